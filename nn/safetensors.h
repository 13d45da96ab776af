#pragma once
// The .safetensors format: an 8-byte little-endian header length, a JSON header mapping
// names to {dtype, shape, data_offsets} (plus an optional "__metadata__" of strings), then
// the raw little-endian data. Model files and golden fixtures use it.
#include <cstdint>
#include <filesystem>
#include <map>
#include <span>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace pg::nn {

// A malformed or unexpected file; the message names the file and the reason.
class FormatError : public std::runtime_error {
public:
    FormatError(const std::string& where, const std::string& reason) : std::runtime_error(where + ": " + reason) {}
};

struct SafeTensorInfo {
    std::string dtype;  // "F32", "F16", "BF16", "F64", "I64", "I32", "U8", ...
    std::vector<int64_t> shape;
    uint64_t begin = 0, end = 0;  // byte range in the data section
    int64_t numel() const;
};

class SafeTensors {
public:
    // Reads and validates the whole file (offsets in range, sizes agree with dtype x shape).
    static SafeTensors load(const std::filesystem::path& path);

    const std::filesystem::path& path() const { return path_; }
    const std::map<std::string, std::string>& metadata() const { return metadata_; }
    const std::map<std::string, SafeTensorInfo>& tensors() const { return tensors_; }
    bool contains(const std::string& name) const { return tensors_.count(name) != 0; }
    const SafeTensorInfo& info(const std::string& name) const;
    std::span<const uint8_t> bytes(const std::string& name) const;

    // Values converted to float (from F32, F16, BF16 or F64) or to int64 (from any integer type).
    std::vector<float> f32(const std::string& name) const;
    std::vector<int64_t> i64(const std::string& name) const;

private:
    std::filesystem::path path_;
    std::map<std::string, std::string> metadata_;
    std::map<std::string, SafeTensorInfo> tensors_;
    std::vector<uint8_t> data_;
};

struct SafeTensorEntry {
    std::string name;
    std::string dtype;  // "F32", "I64", "I32"
    std::vector<int64_t> shape;
    std::vector<uint8_t> data;
};
template <class T> SafeTensorEntry make_entry(std::string name, std::string dtype, std::vector<int64_t> shape,
                                              const std::vector<T>& values) {
    SafeTensorEntry e{std::move(name), std::move(dtype), std::move(shape), {}};
    e.data.resize(values.size() * sizeof(T));
    if (!values.empty()) std::memcpy(e.data.data(), values.data(), e.data.size());
    return e;
}

// Writes atomically (temporary file + rename); tensors are stored in the given order.
void write_safetensors(const std::filesystem::path& path, const std::vector<SafeTensorEntry>& entries,
                       const std::map<std::string, std::string>& metadata = {});

}  // namespace pg::nn
