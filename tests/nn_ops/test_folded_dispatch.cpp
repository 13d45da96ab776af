// Every dense op on a context whose group-count limit is 3: dispatches fold into 2D grids and
// the shaders must undo it (pg_group_index) and skip the overhang of the last row.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <vector>

#include "engine/vk/context.h"
#include "nn/ops/elementwise.h"
#include "nn/ops/linear.h"
#include "nn/ops/norm.h"
#include "tests/reference/nn_dense_ref.h"

using namespace pg;
using nn::DType;
using nn::Tensor;
namespace ref = pg::test::ref;

namespace {

double worst_error(const std::vector<float>& got, const std::vector<double>& want, double tol) {
    REQUIRE(got.size() == want.size());
    double worst = 0;
    for (size_t i = 0; i < got.size(); ++i)
        worst = std::max(worst, std::fabs(double(got[i]) - want[i]) / (tol * (1.0 + std::fabs(want[i]))));
    return worst;
}

struct PathScope {
    explicit PathScope(nn::ops::GemmPath p) { nn::ops::set_gemm_path(p); }
    ~PathScope() { nn::ops::set_gemm_path(nn::ops::GemmPath::Auto); }
};

}  // namespace

TEST_CASE("dense ops stay correct when dispatches fold over a small group-count limit") {
    vk::ContextOptions o;
    o.validation = true;
    o.quiet = true;
    o.max_group_count_override = 3;
    vk::Context ctx(o);
    auto pool = nn::Pool::create(ctx);
    auto up = [&](const std::vector<float>& v, std::vector<int64_t> shape) {
        return nn::upload_tensor(*pool, v, std::move(shape), DType::F32);
    };

    SECTION("linear and split-K linear, both kernel families") {
        for (auto path : {nn::ops::GemmPath::Lanes, nn::ops::GemmPath::Tiled}) {
            PathScope scope(path);
            for (auto [M, K, N] : {std::tuple<int64_t, int64_t, int64_t>{1000, 64, 100}, {61, 3456, 72}}) {
                INFO((path == nn::ops::GemmPath::Lanes ? "lanes" : "tiled") << " M=" << M << " K=" << K << " N=" << N);
                auto x = ref::random_uniform(size_t(M * K), 1), w = ref::random_uniform(size_t(N * K), 2);
                auto b = ref::random_uniform(size_t(N), 3);
                vk::CommandList cmd(ctx);
                Tensor y = nn::ops::linear(cmd, *pool, up(x, {M, K}), up(w, {N, K}), up(b, {N}));
                cmd.submit_and_wait();
                CHECK(worst_error(nn::download_tensor<float>(ctx, y), ref::linear(x, w, b, {}, M, K, N), 1e-4) <= 1.0);
            }
        }
    }
    SECTION("sparse_conv") {
        const int64_t P = 700, M = 600, T = 27, cin = 32, cout = 64;
        auto x = ref::random_uniform(size_t(P * cin), 4), w = ref::random_uniform(size_t(cout * T * cin), 5);
        std::vector<int32_t> nbr(size_t(M * T));
        for (size_t i = 0; i < nbr.size(); ++i) nbr[i] = i % 3 == 0 ? -1 : int32_t((i * 7919) % size_t(P));
        vk::CommandList cmd(ctx);
        Tensor y = nn::ops::sparse_conv(cmd, *pool, up(x, {P, cin}), nn::upload_tensor(*pool, nbr, {M, T}, DType::I32),
                                        up(w, {cout, T * cin}), {});
        cmd.submit_and_wait();
        const auto a = ref::gather_conv_input(x, nbr, M, T, cin);
        CHECK(worst_error(nn::download_tensor<float>(ctx, y), ref::linear(a, w, {}, {}, M, T * cin, cout), 1e-4) <= 1.0);
    }
    SECTION("norms and elementwise ops") {
        const int64_t M = 1000, C = 32;
        auto x = ref::random_uniform(size_t(M * C), 6, -3.0f, 3.0f), r = ref::random_uniform(size_t(M * C), 7);
        auto g = ref::random_uniform(size_t(C), 8, 0.5f, 1.5f), b = ref::random_uniform(size_t(C), 9);
        auto var = ref::random_uniform(size_t(C), 10, 0.5f, 2.0f);
        std::vector<int32_t> idx(static_cast<size_t>(M));
        for (size_t i = 0; i < idx.size(); ++i) idx[i] = int32_t((i * 31) % size_t(M));
        Tensor tx = up(x, {M, C}), tr = up(r, {M, C}), tg = up(g, {C}), tb = up(b, {C}), tv = up(var, {C});
        Tensor ti = nn::upload_tensor(*pool, idx, {M}, DType::I32);
        vk::CommandList cmd(ctx);
        Tensor ln = nn::ops::layer_norm(cmd, *pool, tx, tg, tb, 1e-5f);
        Tensor bn = nn::ops::batch_norm(cmd, *pool, tx, tb, tv, tg, tb, 1e-3f, true);
        Tensor ge = nn::ops::gelu(cmd, *pool, tx);
        Tensor sum = nn::ops::add(cmd, *pool, tx, tr);
        Tensor ga = nn::ops::gather_rows(cmd, *pool, tx, ti);
        Tensor ag = nn::ops::add_gathered(cmd, *pool, tr, tx, ti);
        cmd.submit_and_wait();
        CHECK(worst_error(nn::download_tensor<float>(ctx, ln), ref::layer_norm(x, g, b, M, C, 1e-5), 1e-5) <= 1.0);
        CHECK(worst_error(nn::download_tensor<float>(ctx, bn), ref::batch_norm(x, b, var, g, b, M, C, 1e-3, true), 1e-5) <=
              1.0);
        std::vector<double> want_gelu(x.size()), want_sum(x.size()), want_gather(x.size());
        for (size_t i = 0; i < x.size(); ++i) {
            want_gelu[i] = ref::gelu(x[i]);
            want_sum[i] = double(x[i]) + r[i];
            want_gather[i] = x[size_t(idx[i / C]) * C + i % C];
        }
        CHECK(worst_error(nn::download_tensor<float>(ctx, ge), want_gelu, 1e-6) <= 1.0);
        CHECK(worst_error(nn::download_tensor<float>(ctx, sum), want_sum, 1e-7) <= 1.0);
        CHECK(worst_error(nn::download_tensor<float>(ctx, ga), want_gather, 1e-12) <= 1.0);
        CHECK(worst_error(nn::download_tensor<float>(ctx, ag), ref::add_gathered(r, x, idx, C), 1e-7) <= 1.0);
    }
    CHECK(vk::Context::validation_message_count() == 0);
}
