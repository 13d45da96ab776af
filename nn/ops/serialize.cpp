#include "nn/ops/serialize.h"

#include <map>
#include <memory>
#include <stdexcept>
#include <string>

#include "engine/vk/context.h"

#include "shaders/nn/index_shared.glsl"

namespace pg::nn::ops {

namespace detail {

IndexState::IndexState(vk::Context& ctx)
    : sort(ctx), scan(ctx), readback(ctx, PG_INFO_WORDS * 4, vk::MemoryUse::Readback, "nn index readback") {}

IndexState& index_state(vk::Context& ctx) { return ctx.attachment<IndexState>("nn.index"); }

void expect(const char* op, const char* name, const Tensor& t, DType dtype, std::initializer_list<int64_t> shape) {
    bool ok = t.defined() && t.dtype == dtype && t.shape.size() == shape.size();
    if (ok) {
        size_t i = 0;
        for (int64_t s : shape) {
            ok = ok && (s < 0 || t.shape[i] == s);
            ++i;
        }
    }
    if (ok) return;
    std::string want = "[";
    for (int64_t s : shape) {
        if (want.size() > 1) want += ',';
        want += s < 0 ? std::string("*") : std::to_string(s);
    }
    want += ']';
    throw std::invalid_argument(std::string(op) + ": " + name + " must be " + dtype_name(dtype) + " " + want +
                                ", got " + (t.defined() ? std::string(dtype_name(t.dtype)) + " " + t.shape_string()
                                                        : std::string("an undefined tensor")));
}

uint64_t groups(uint64_t threads) { return vk::ceil_div(threads, PG_INDEX_THREADS); }

Tensor info_tensor(vk::CommandList& cmd, Pool& pool) {
    Tensor info = pool.empty({PG_INFO_WORDS}, DType::U32);
    cmd.fill(*info.buffer, 0, 0, PG_INFO_WORDS * 4);
    return info;
}

std::vector<uint32_t> submit_and_read_info(vk::CommandList& cmd, IndexState& state, const Tensor& info) {
    cmd.copy(*info.buffer, state.readback, PG_INFO_WORDS * 4);
    cmd.submit_and_wait();
    const uint32_t* words = state.readback.as<uint32_t>();
    return std::vector<uint32_t>(words, words + PG_INFO_WORDS);
}

}  // namespace detail

void release_index_state(vk::Context& ctx) { ctx.detach("nn.index"); }

Tensor serialize_codes(vk::CommandList& cmd, Pool& pool, const Tensor& grid, const Tensor& batch, Order order,
                       int depth) {
    detail::expect("serialize_codes", "grid", grid, DType::I32, {-1, 3});
    const int64_t n = grid.dim(0);
    detail::expect("serialize_codes", "batch", batch, DType::I32, {n});
    if (depth < 0 || depth > 21)
        throw std::invalid_argument("serialize_codes: depth " + std::to_string(depth) +
                                    " is outside [0, 21] (3 bits per level in a 64-bit code)");
    Tensor codes = pool.empty({n}, DType::U64);
    if (n == 0) return codes;
    const bool swap = order == Order::ZTrans || order == Order::HilbertTrans;
    const bool hilbert = order == Order::Hilbert || order == Order::HilbertTrans;
    cmd.dispatch("nn/serialize_codes", {grid, batch, codes},
                 gpu::SerializePush{uint32_t(n), uint32_t(depth), swap ? 1u : 0u, hilbert ? 1u : 0u},
                 detail::groups(uint64_t(n)));
    return codes;
}

Sorted sort_codes(vk::CommandList& cmd, Pool& pool, const Tensor& codes, int key_bits) {
    detail::expect("sort_codes", "codes", codes, DType::U64, {-1});
    if (key_bits < 0 || key_bits > 64)
        throw std::invalid_argument("sort_codes: key_bits " + std::to_string(key_bits) + " is outside [0, 64]");
    const int64_t n = codes.dim(0);
    Sorted s{pool.empty({n}, DType::I32), pool.empty({n}, DType::I32)};
    if (n == 0) return s;
    // The sort works in place: sort a copy of the codes.
    Tensor keys = pool.empty({n}, DType::U64);
    cmd.dispatch("nn/serialize_keys", {codes, keys, s.order}, gpu::ShiftPush{uint32_t(n), 0, 1, 0},
                 detail::groups(uint64_t(n)));
    detail::index_state(pool.context())
        .sort.sort(cmd, *keys.buffer, *s.order.buffer, uint32_t(n), uint32_t(key_bits), sort::KeyWidth::Bits64);
    cmd.dispatch("nn/serialize_inverse", {s.order, s.inverse}, gpu::CountPush{uint32_t(n)},
                 detail::groups(uint64_t(n)));
    return s;
}

}  // namespace pg::nn::ops
