#include "nn/tensor.h"

#include <algorithm>
#include <bit>
#include <stdexcept>

namespace pg::nn {

size_t dtype_size(DType t) {
    switch (t) {
    case DType::F32:
    case DType::I32:
    case DType::U32: return 4;
    case DType::U64: return 8;
    }
    return 4;
}

const char* dtype_name(DType t) {
    switch (t) {
    case DType::F32: return "f32";
    case DType::I32: return "i32";
    case DType::U32: return "u32";
    case DType::U64: return "u64";
    }
    return "?";
}

int64_t Tensor::numel() const {
    int64_t n = 1;
    for (int64_t s : shape) n *= s;
    return n;
}

std::string Tensor::shape_string() const { return nn::shape_string(shape); }

std::string shape_string(const std::vector<int64_t>& shape) {
    std::string s = "[";
    for (size_t i = 0; i < shape.size(); ++i) {
        if (i) s += ',';
        s += std::to_string(shape[i]);
    }
    s += ']';
    return s;
}

Tensor Pool::empty(std::vector<int64_t> shape, DType dtype) {
    Tensor t;
    t.shape = std::move(shape);
    t.dtype = dtype;
    for (int64_t s : t.shape)
        if (s < 0) throw std::invalid_argument("nn::Pool: negative tensor dimension " + t.shape_string());
    uint64_t need = std::max<uint64_t>(t.bytes(), 16);
    if (need > 4096) need = std::bit_ceil(need);
    // Best fit among idle buffers, within 2x so small tensors do not pin big buffers.
    auto best = idle_.end();
    for (auto it = idle_.begin(); it != idle_.end(); ++it) {
        uint64_t sz = (*it)->size();
        if (sz >= need && sz <= 2 * need && (best == idle_.end() || sz < (*best)->size())) best = it;
    }
    vk::Buffer* raw;
    if (best != idle_.end()) {
        raw = best->release();
        idle_.erase(best);
    } else {
        raw = new vk::Buffer(ctx_, need, vk::MemoryUse::Device, "nn tensor");
        reserved_ += raw->size();
    }
    live_ += raw->size();
    peak_ = std::max(peak_, live_);
    std::weak_ptr<Pool> self = weak_from_this();
    t.buffer = std::shared_ptr<vk::Buffer>(raw, [self](vk::Buffer* b) {
        if (auto pool = self.lock()) pool->give_back(b);
        else delete b;
    });
    return t;
}

void Pool::give_back(vk::Buffer* b) {
    live_ -= b->size();
    idle_.emplace_back(b);
}

void Pool::trim() {
    for (auto& b : idle_) reserved_ -= b->size();
    idle_.clear();
}

Tensor upload_tensor(Pool& pool, const void* data, std::vector<int64_t> shape, DType dtype) {
    Tensor t = pool.empty(std::move(shape), dtype);
    if (t.bytes()) vk::upload(pool.context(), *t.buffer, data, t.bytes());
    return t;
}

}  // namespace pg::nn
