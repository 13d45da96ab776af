#include "nn/train/grad_reduce.h"

#include <algorithm>
#include <stdexcept>

#include "nn/ops/linear.h"
#include "shaders/nn/grad_shared.glsl"

namespace pg::nn::grad::detail {

using vk::ceil_div;

void expect(const char* op, const char* name, const Tensor& t, DType dtype, std::vector<int64_t> shape) {
    bool ok = t.defined() && t.dtype == dtype && t.shape.size() == shape.size();
    for (size_t i = 0; ok && i < shape.size(); ++i) ok = shape[i] < 0 || t.shape[i] == shape[i];
    if (ok) return;
    std::string want = "[";
    for (size_t i = 0; i < shape.size(); ++i)
        want += (i ? ", " : "") + (shape[i] < 0 ? std::string("*") : std::to_string(shape[i]));
    want += "]";
    throw std::invalid_argument(std::string(op) + ": " + name + " " +
                                (t.defined() ? t.shape_string() + " " + dtype_name(t.dtype) : std::string("(none)")) +
                                " must be " + dtype_name(dtype) + " " + want);
}

void expect_small(const char* op, uint64_t n) {
    if (n > 0xFFFFFFFFull) throw std::invalid_argument(std::string(op) + ": tensor too large for 32-bit indexing");
}

uint32_t rows_per_chunk(uint64_t rows) { return uint32_t(std::max<uint64_t>(64, ceil_div(rows, 256))); }

Tensor column_sums(vk::CommandList& cmd, Pool& pool, uint32_t mode, const Tensor& a, const Tensor& b, const Tensor& v,
                   uint64_t rows, uint64_t cols, float scale) {
    Tensor out = pool.empty({int64_t(cols)});
    if (cols == 0) return out;
    if (rows == 0) {
        cmd.fill(*out.buffer, 0u);
        return out;
    }
    const uint32_t per = rows_per_chunk(rows);
    const uint64_t chunks = ceil_div(rows, per);
    // CPU devices: one pass, bit-identical to the two below (nn/grad_column_sums); a dispatch's
    // fixed cost there outweighs the work of the narrow columns of a training step.
    if (ops::detail::use_lanes(pool.context())) {
        gpu::ColumnSumsPush push{uint32_t(rows), uint32_t(cols), mode, per, scale, 0, 0, 0};
        cmd.dispatch("nn/grad_column_sums", {a, b, v, out}, push, ceil_div(cols, PG_COLSUM_THREADS));
        return out;
    }
    Tensor part = pool.empty({int64_t(chunks), int64_t(cols)});
    gpu::ColumnPartialsPush push{uint32_t(rows), uint32_t(cols), mode, per};
    cmd.dispatch("nn/grad_column_partials", {a, b, v, part}, push, ceil_div(chunks * cols, PG_GRAD_THREADS));
    sum_partials(cmd, part, out, cols, chunks, scale);
    return out;
}

void sum_partials(vk::CommandList& cmd, const Tensor& part, const Tensor& out, uint64_t len, uint64_t splits,
                  float scale) {
    gpu::SumPartialsPush push{uint32_t(len), uint32_t(splits), scale, 0};
    cmd.dispatch("nn/grad_sum_partials", {part, out}, push, ceil_div(len, PG_GRAD_THREADS));
}

}  // namespace pg::nn::grad::detail
