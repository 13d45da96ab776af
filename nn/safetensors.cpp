#include "nn/safetensors.h"

#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>

#include <nlohmann/json.hpp>

#include "dataset/atomic_file.h"

namespace pg::nn {
namespace {

uint64_t dtype_bytes(const std::string& d) {
    if (d == "F64" || d == "I64" || d == "U64") return 8;
    if (d == "F32" || d == "I32" || d == "U32") return 4;
    if (d == "F16" || d == "BF16" || d == "I16" || d == "U16") return 2;
    if (d == "I8" || d == "U8" || d == "BOOL") return 1;
    return 0;
}

float half_to_float(uint16_t h) {
    uint32_t sign = uint32_t(h >> 15) << 31, exp = (h >> 10) & 31, man = h & 1023;
    if (exp == 0) {
        float v = std::ldexp(float(man), -24);
        return sign ? -v : v;
    }
    uint32_t bits = exp == 31 ? (sign | 0x7f800000u | (man << 13)) : (sign | ((exp + 112) << 23) | (man << 13));
    return std::bit_cast<float>(bits);
}

}  // namespace

int64_t SafeTensorInfo::numel() const {
    int64_t n = 1;
    for (int64_t s : shape) n *= s;
    return n;
}

SafeTensors SafeTensors::load(const std::filesystem::path& path) {
    const std::string where = path.string();
    std::ifstream in(path, std::ios::binary);
    if (!in) throw FormatError(where, "cannot open file");
    in.seekg(0, std::ios::end);
    const uint64_t size = uint64_t(in.tellg());
    in.seekg(0);
    uint64_t header_len = 0;
    if (size < 8 || !in.read(reinterpret_cast<char*>(&header_len), 8))
        throw FormatError(where, "not a safetensors file (shorter than its 8-byte header length)");
    if (header_len > size - 8 || header_len > (100u << 20))
        throw FormatError(where, "not a safetensors file (header length " + std::to_string(header_len) +
                                     " exceeds the file size)");
    std::string header(header_len, '\0');
    in.read(header.data(), std::streamsize(header_len));
    SafeTensors st;
    st.path_ = path;
    st.data_.resize(size - 8 - header_len);
    if (!st.data_.empty()) in.read(reinterpret_cast<char*>(st.data_.data()), std::streamsize(st.data_.size()));
    if (!in) throw FormatError(where, "truncated while reading");

    nlohmann::json j;
    try {
        j = nlohmann::json::parse(header);
    } catch (const std::exception& e) {
        throw FormatError(where, std::string("header is not valid JSON (") + e.what() + ")");
    }
    if (!j.is_object()) throw FormatError(where, "header is not a JSON object");
    for (auto& [name, v] : j.items()) {
        if (name == "__metadata__") {
            if (!v.is_object()) throw FormatError(where, "__metadata__ is not an object");
            for (auto& [k, s] : v.items()) {
                if (!s.is_string()) throw FormatError(where, "__metadata__." + k + " is not a string");
                st.metadata_[k] = s.get<std::string>();
            }
            continue;
        }
        const std::string what = "tensor '" + name + "'";
        if (!v.is_object() || !v.contains("dtype") || !v.contains("shape") || !v.contains("data_offsets") ||
            !v["dtype"].is_string() || !v["shape"].is_array() || !v["data_offsets"].is_array() ||
            v["data_offsets"].size() != 2)
            throw FormatError(where, what + " lacks dtype, shape or data_offsets");
        SafeTensorInfo info;
        info.dtype = v["dtype"].get<std::string>();
        const uint64_t elem = dtype_bytes(info.dtype);
        if (!elem) throw FormatError(where, what + " has unknown dtype " + info.dtype);
        for (auto& d : v["shape"]) {
            if (!d.is_number_integer() || d.get<int64_t>() < 0) throw FormatError(where, what + " has a bad shape");
            info.shape.push_back(d.get<int64_t>());
        }
        for (auto& o : v["data_offsets"])
            if (!o.is_number_unsigned()) throw FormatError(where, what + " has bad data_offsets");
        info.begin = v["data_offsets"][0].get<uint64_t>();
        info.end = v["data_offsets"][1].get<uint64_t>();
        if (info.begin > info.end || info.end > st.data_.size())
            throw FormatError(where, what + " data_offsets lie outside the file");
        if (info.end - info.begin != uint64_t(info.numel()) * elem)
            throw FormatError(where, what + " holds " + std::to_string(info.end - info.begin) + " bytes, its " +
                                         info.dtype + " shape needs " + std::to_string(uint64_t(info.numel()) * elem));
        st.tensors_[name] = std::move(info);
    }
    return st;
}

const SafeTensorInfo& SafeTensors::info(const std::string& name) const {
    auto it = tensors_.find(name);
    if (it == tensors_.end()) throw FormatError(path_.string(), "no tensor named '" + name + "'");
    return it->second;
}

std::span<const uint8_t> SafeTensors::bytes(const std::string& name) const {
    const auto& i = info(name);
    return {data_.data() + i.begin, size_t(i.end - i.begin)};
}

std::vector<float> SafeTensors::f32(const std::string& name) const {
    const auto& i = info(name);
    auto b = bytes(name);
    std::vector<float> out(size_t(i.numel()));
    for (size_t k = 0; k < out.size(); ++k) {
        if (i.dtype == "F32") std::memcpy(&out[k], b.data() + 4 * k, 4);
        else if (i.dtype == "F64") {
            double d;
            std::memcpy(&d, b.data() + 8 * k, 8);
            out[k] = float(d);
        } else if (i.dtype == "F16" || i.dtype == "BF16") {
            uint16_t h;
            std::memcpy(&h, b.data() + 2 * k, 2);
            out[k] = i.dtype == "F16" ? half_to_float(h) : std::bit_cast<float>(uint32_t(h) << 16);
        } else
            throw FormatError(path_.string(), "tensor '" + name + "' is " + i.dtype + ", expected a float type");
    }
    return out;
}

std::vector<int64_t> SafeTensors::i64(const std::string& name) const {
    const auto& i = info(name);
    auto b = bytes(name);
    std::vector<int64_t> out(size_t(i.numel()));
    const uint64_t elem = dtype_bytes(i.dtype);
    const bool is_signed = i.dtype[0] == 'I';
    if (i.dtype[0] != 'I' && i.dtype[0] != 'U')
        throw FormatError(path_.string(), "tensor '" + name + "' is " + i.dtype + ", expected an integer type");
    for (size_t k = 0; k < out.size(); ++k) {
        uint64_t raw = 0;
        std::memcpy(&raw, b.data() + elem * k, elem);
        if (is_signed && elem < 8 && (raw >> (8 * elem - 1)) & 1) raw |= ~uint64_t(0) << (8 * elem);
        out[k] = int64_t(raw);
    }
    return out;
}

void write_safetensors(const std::filesystem::path& path, const std::vector<SafeTensorEntry>& entries,
                       const std::map<std::string, std::string>& metadata) {
    nlohmann::ordered_json h = nlohmann::ordered_json::object();
    if (!metadata.empty()) h["__metadata__"] = metadata;
    uint64_t off = 0;
    for (const auto& e : entries) {
        h[e.name] = {{"dtype", e.dtype}, {"shape", e.shape}, {"data_offsets", {off, off + e.data.size()}}};
        off += e.data.size();
    }
    std::string header = h.dump();
    while ((header.size() + 8) % 8) header += ' ';  // data starts 8-byte aligned
    // Whole or not at all (and removed if the process is interrupted): a checkpoint written
    // while a training run is stopped must not replace the last good one with half a file.
    data::write_atomically(path, [&](std::ostream& out) {
        uint64_t n = header.size();
        out.write(reinterpret_cast<const char*>(&n), 8);
        out.write(header.data(), std::streamsize(header.size()));
        for (const auto& e : entries) out.write(reinterpret_cast<const char*>(e.data.data()), std::streamsize(e.data.size()));
    });
}

}  // namespace pg::nn
