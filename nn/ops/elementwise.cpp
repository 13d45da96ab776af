#include "nn/ops/elementwise.h"

#include <stdexcept>
#include <string>

#include "shaders/nn/elementwise_shared.glsl"

namespace pg::nn::ops {

namespace {

using vk::ceil_div;

void expect(bool ok, const std::string& message) {
    if (!ok) throw std::invalid_argument(message);
}

void expect_small(uint64_t n, const char* op) {
    expect(n <= 0xFFFFFFFFull, std::string(op) + ": tensor too large for 32-bit indexing");
}

// Elements (or 32-bit words) per row of x, for a gather along dim 0.
uint64_t row_size(const Tensor& x) { return x.shape.empty() || x.dim(0) == 0 ? 0 : uint64_t(x.numel() / x.dim(0)); }

void check_index(const char* op, const Tensor& idx) {
    expect(idx.dtype == DType::I32 && idx.shape.size() == 1,
           std::string(op) + ": index " + idx.shape_string() + " must be i32 [R]");
}

// nn/gelu computes GELU or, with `erf_only`, erf itself.
Tensor gelu_or_erf(vk::CommandList& cmd, Pool& pool, const Tensor& x, bool erf_only) {
    const char* op = erf_only ? "erf" : "gelu";
    expect(x.dtype == DType::F32, std::string(op) + ": x must be f32");
    const uint64_t n = uint64_t(x.numel());
    expect_small(n, op);
    Tensor y = pool.empty(x.shape);
    if (n == 0) return y;
    const bool wide = n % 8 == 0;
    const gpu::GeluPush push{uint32_t(n), wide, erf_only};
    cmd.dispatch("nn/gelu", {x, x, y, y}, push, ceil_div(wide ? n / 8 : n, PG_ELEMENTWISE_THREADS));
    return y;
}

}  // namespace

Tensor gelu(vk::CommandList& cmd, Pool& pool, const Tensor& x) { return gelu_or_erf(cmd, pool, x, false); }

Tensor erf(vk::CommandList& cmd, Pool& pool, const Tensor& x) { return gelu_or_erf(cmd, pool, x, true); }

Tensor add(vk::CommandList& cmd, Pool& pool, const Tensor& a, const Tensor& b) {
    expect(a.dtype == DType::F32 && b.dtype == DType::F32, "add: a and b must be f32");
    expect(a.shape == b.shape, "add: shapes " + a.shape_string() + " and " + b.shape_string() + " differ");
    const uint64_t n = uint64_t(a.numel());
    expect_small(n, "add");
    Tensor y = pool.empty(a.shape);
    if (n == 0) return y;
    const bool wide = n % 8 == 0;
    const gpu::AddPush push{uint32_t(n), wide};
    cmd.dispatch("nn/add", {a, a, b, b, y, y}, push, ceil_div(wide ? n / 8 : n, PG_ELEMENTWISE_THREADS));
    return y;
}

Tensor gather_rows(vk::CommandList& cmd, Pool& pool, const Tensor& x, const Tensor& idx) {
    check_index("gather_rows", idx);
    expect(!x.shape.empty(), "gather_rows: x must have at least one dimension");
    std::vector<int64_t> shape = x.shape;
    shape[0] = idx.dim(0);
    Tensor y = pool.empty(shape, x.dtype);
    const uint64_t rows = uint64_t(idx.dim(0));
    const uint64_t words = row_size(x) * dtype_size(x.dtype) / 4;
    expect_small(rows * words, "gather_rows");
    if (rows == 0 || words == 0) return y;
    expect(x.dim(0) > 0, "gather_rows: x " + x.shape_string() + " has no rows to gather");
    const bool wide = words % 8 == 0;
    const gpu::GatherRowsPush push{uint32_t(rows), uint32_t(words), wide};
    cmd.dispatch("nn/gather_rows", {x, x, idx, y, y}, push,
                 ceil_div(rows * (wide ? words / 8 : words), PG_ELEMENTWISE_THREADS));
    return y;
}

Tensor add_gathered(vk::CommandList& cmd, Pool& pool, const Tensor& a, const Tensor& x, const Tensor& idx) {
    check_index("add_gathered", idx);
    expect(a.dtype == DType::F32 && x.dtype == DType::F32, "add_gathered: a and x must be f32");
    expect(a.shape.size() == 2 && x.shape.size() == 2 && a.dim(1) == x.dim(1) && a.dim(0) == idx.dim(0),
           "add_gathered: a " + a.shape_string() + ", x " + x.shape_string() + " and index " + idx.shape_string() +
               " must be [R, C], [P, C] and [R]");
    Tensor y = pool.empty(a.shape);
    const uint64_t rows = uint64_t(a.dim(0)), c = uint64_t(a.dim(1));
    expect_small(rows * c, "add_gathered");
    if (rows == 0 || c == 0) return y;
    expect(x.dim(0) > 0, "add_gathered: x " + x.shape_string() + " has no rows to gather");
    const bool wide = c % 8 == 0;
    const gpu::AddGatheredPush push{uint32_t(rows), uint32_t(c), wide};
    cmd.dispatch("nn/add_gathered", {a, a, x, x, idx, y, y}, push,
                 ceil_div(rows * (wide ? c / 8 : c), PG_ELEMENTWISE_THREADS));
    return y;
}

}  // namespace pg::nn::ops
