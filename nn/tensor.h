#pragma once
// Device tensors: a shape, an element type and a buffer taken from a Pool. A tensor's buffer
// goes back to its pool when the last copy of the tensor is dropped, and the next tensor of
// a fitting size reuses it. Reuse inside one command stream is safe: the CommandList puts a
// barrier before any command that touches a buffer already touched since the last barrier.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "engine/vk/buffer.h"
#include "engine/vk/commands.h"

namespace pg::nn {

enum class DType { F32, I32, U32, U64 };

size_t dtype_size(DType t);
const char* dtype_name(DType t);

class Pool;

std::string shape_string(const std::vector<int64_t>& shape);  // "[2,3]"

struct Tensor {
    std::shared_ptr<vk::Buffer> buffer;
    std::vector<int64_t> shape;
    DType dtype = DType::F32;

    bool defined() const { return buffer != nullptr; }
    int64_t numel() const;
    int64_t dim(int i) const { return shape.at(i < 0 ? shape.size() + i : i); }
    uint64_t bytes() const { return uint64_t(numel()) * dtype_size(dtype); }
    std::string shape_string() const;
    operator vk::BufferRange() const { return vk::BufferRange(*buffer); }  // NOLINT: binds as a whole buffer
};

// The same buffer viewed with another shape of as many elements (e.g. conv weights
// [O,k,k,k,I] as [O, k^3 I]); no copy, no check.
inline Tensor reshaped(const Tensor& t, std::vector<int64_t> shape) {
    Tensor r = t;
    r.shape = std::move(shape);
    return r;
}

// Buffers of dropped tensors, kept for reuse (best fit by size). Sizes are rounded up to
// powers of two above 4 KiB so layers of similar size share buffers.
class Pool : public std::enable_shared_from_this<Pool> {
public:
    static std::shared_ptr<Pool> create(vk::Context& ctx) { return std::shared_ptr<Pool>(new Pool(ctx)); }
    Tensor empty(std::vector<int64_t> shape, DType dtype = DType::F32);
    vk::Context& context() { return ctx_; }

    uint64_t live_bytes() const { return live_; }
    uint64_t peak_bytes() const { return peak_; }
    uint64_t reserved_bytes() const { return reserved_; }
    void reset_peak() { peak_ = live_; }
    // Frees every idle buffer (e.g. between forwards of very different sizes).
    void trim();

private:
    explicit Pool(vk::Context& ctx) : ctx_(ctx) {}
    void give_back(vk::Buffer* b);
    vk::Context& ctx_;
    std::vector<std::unique_ptr<vk::Buffer>> idle_;
    uint64_t live_ = 0, peak_ = 0, reserved_ = 0;
};

// Host <-> tensor copies. They act at once, not in a stream: while a CommandList is recording,
// a fresh tensor may reuse a buffer its earlier commands still use, so upload small data
// there with cmd.update instead.
Tensor upload_tensor(Pool& pool, const void* data, std::vector<int64_t> shape, DType dtype);
template <class T> Tensor upload_tensor(Pool& pool, const std::vector<T>& v, std::vector<int64_t> shape, DType dtype) {
    return upload_tensor(pool, v.data(), std::move(shape), dtype);
}
template <class T> std::vector<T> download_tensor(vk::Context& ctx, const Tensor& t) {
    std::vector<T> v(t.bytes() / sizeof(T));
    if (!v.empty()) vk::download(ctx, *t.buffer, v.data(), t.bytes());
    return v;
}

}  // namespace pg::nn
