// The random walker's multigrid preconditioner: the host hierarchy (aggregation, Galerkin
// products, the coarsest pseudo-inverse) against dense brute force, the GPU's V-cycle against
// the CPU reference cycle, and multigrid-preconditioned walks against Eigen.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <map>

#include "engine/segment/knn_graph.h"
#include "engine/segment/random_walker.h"
#include "engine/segment/walk_hierarchy.h"
#include "tests/gpu_fixture.h"
#include "tests/reference/graph_ref.h"
#include "tests/reference/test_scenes.h"
#include "tests/reference/walk_cycle_ref.h"

using namespace pg;

namespace {

// A random symmetric operator D - W: each node joined to a few random others, weights spread
// over three orders of magnitude (as the kNN affinities are), a unary term on some nodes, and
// some nodes out of the system (seeds) with their neighbours' weights toward them 0.
seg::WalkMatrix random_operator(uint32_t n, uint64_t seed) {
    ref::Rng rng(seed);
    std::map<std::pair<uint32_t, uint32_t>, float> w;
    for (uint32_t i = 0; i < n; ++i)
        for (int t = 0; t < 4; ++t) {
            // Mostly near neighbours along a line (a graph with a long diameter), some far.
            uint32_t j = rng.below(5) == 0 ? rng.below(n) : (i + 1 + rng.below(6)) % n;
            if (j == i) continue;
            float v = std::pow(10.0f, rng.uniform(-3.0f, 0.0f));
            w[{std::min(i, j), std::max(i, j)}] = v;
        }
    std::vector<uint8_t> out(n, 0);
    for (int s = 0; s < 6; ++s) out[rng.below(n)] = 1;
    std::vector<std::vector<std::pair<uint32_t, float>>> adj(n);
    std::vector<double> degree(n, 0.0);
    for (auto& [e, v] : w) {
        adj[e.first].push_back({e.second, out[e.second] ? 0.0f : v});
        adj[e.second].push_back({e.first, out[e.first] ? 0.0f : v});
        degree[e.first] += v, degree[e.second] += v;
    }
    seg::WalkMatrix a;
    a.rows.push_back(0);
    for (uint32_t i = 0; i < n; ++i) {
        for (auto [j, v] : adj[i]) a.columns.push_back(j), a.weights.push_back(v);
        a.rows.push_back(uint32_t(a.columns.size()));
        const float gamma = rng.below(4) == 0 ? rng.uniform(0.0f, 0.5f) : 0.0f;
        a.diagonal.push_back(out[i] ? 0.0f : float(degree[i]) + gamma);
    }
    return a;
}

std::vector<double> dense(const seg::WalkMatrix& a) {
    const size_t n = a.size();
    std::vector<double> m(n * n, 0.0);
    for (size_t i = 0; i < n; ++i) {
        if (a.diagonal[i] <= 0.0f) continue;  // out of the system: no row
        m[i * n + i] = a.diagonal[i];
        for (uint32_t s = a.rows[i]; s < a.rows[i + 1]; ++s) m[i * n + a.columns[s]] -= a.weights[s];
    }
    return m;
}

// The reference's copy of a GPU graph.
ref::RefGraph ref_graph(const seg::KnnGraph& graph) {
    ref::RefGraph rg;
    rg.k = graph.k();
    rg.neighbours = graph.neighbours();
    rg.weights = graph.weights();
    return rg;
}

std::vector<uint32_t> all_of(const data::GaussianCloud& cloud) {
    std::vector<uint32_t> d(cloud.size());
    for (uint32_t i = 0; i < d.size(); ++i) d[i] = i;
    return d;
}

}  // namespace

TEST_CASE("walk hierarchy: a Galerkin product large enough for threads is the sequential sum, bit for bit") {
    // Past 8192 aggregates the coarse rows are built by several threads; each entry must still be
    // the same sum in the same order: fine nodes ascending, their edges in order.
    const auto a = random_operator(120000, 77);
    seg::HierarchyOptions o;
    uint32_t coarse = 0;
    const auto parent = seg::aggregate_nodes(a, o, coarse);
    REQUIRE(coarse >= 8192);
    std::vector<std::map<uint32_t, double>> sums(coarse);
    std::vector<double> excess(coarse, 0.0);
    for (uint32_t i = 0; i < a.size(); ++i) {
        const uint32_t p = parent[i];
        if (p == seg::kHierarchyNone || a.diagonal[i] <= 0.0f) continue;
        double e = a.diagonal[i];
        for (uint32_t s = a.rows[i]; s < a.rows[i + 1]; ++s) e -= a.weights[s];
        if (e > 1e-6 * a.diagonal[i]) excess[p] += e;
    }
    for (uint32_t i = 0; i < a.size(); ++i) {
        const uint32_t p = parent[i];
        if (p == seg::kHierarchyNone) continue;
        for (uint32_t s = a.rows[i]; s < a.rows[i + 1]; ++s) {
            const uint32_t q = parent[a.columns[s]];
            if (a.weights[s] != 0.0f && q != seg::kHierarchyNone && q != p) sums[p][q] += a.weights[s];
        }
    }
    std::vector<float> diagonal(coarse);
    for (uint32_t p = 0; p < coarse; ++p) {
        double d = excess[p];
        for (auto& [q, w] : sums[p]) d += w;
        diagonal[p] = float(d);
    }
    const auto c = seg::galerkin(a, parent, coarse);
    REQUIRE(c.size() == coarse);
    size_t mismatched = 0;
    for (uint32_t p = 0; p < coarse; ++p) {
        mismatched += c.diagonal[p] != diagonal[p];
        std::vector<std::pair<uint32_t, float>> want;
        if (diagonal[p] > 0.0f)
            for (auto& [q, w] : sums[p])
                if (diagonal[q] > 0.0f) want.push_back({q, float(w)});
        std::vector<std::pair<uint32_t, float>> got;
        for (uint32_t s = c.rows[p]; s < c.rows[p + 1]; ++s) got.push_back({c.columns[s], c.weights[s]});
        mismatched += got != want;
    }
    CHECK(mismatched == 0);
}

TEST_CASE("walk hierarchy: aggregates and the Galerkin product P^T A P match a dense brute force") {
    const auto a = seg::WalkMatrix(random_operator(400, 31));
    const uint32_t n = a.size();
    seg::HierarchyOptions o;
    uint32_t coarse = 0;
    auto parent = seg::aggregate_nodes(a, o, coarse);
    REQUIRE(parent.size() == n);
    // Every node in the system has an aggregate, none out of it does; aggregates shrink the level.
    std::vector<uint32_t> size(coarse, 0);
    for (uint32_t i = 0; i < n; ++i) {
        CHECK((a.diagonal[i] > 0.0f) == (parent[i] != seg::kHierarchyNone));
        if (parent[i] != seg::kHierarchyNone) {
            REQUIRE(parent[i] < coarse);
            ++size[parent[i]];
        }
    }
    for (uint32_t s : size) CHECK(s > 0);
    CHECK(coarse < n / 2);
    CHECK(*std::max_element(size.begin(), size.end()) <= 4 * o.aggregate);

    auto c = seg::galerkin(a, parent, coarse);
    REQUIRE(c.size() == coarse);
    REQUIRE(c.rows.size() == coarse + 1);
    const auto fine = dense(a);
    std::vector<double> want(size_t(coarse) * coarse, 0.0);
    for (uint32_t i = 0; i < n; ++i)
        for (uint32_t j = 0; j < n; ++j)
            if (parent[i] != seg::kHierarchyNone && parent[j] != seg::kHierarchyNone)
                want[size_t(parent[i]) * coarse + parent[j]] += fine[size_t(i) * n + j];
    const auto got = dense(c);
    double worst = 0, scale = 0;
    for (size_t t = 0; t < want.size(); ++t) {
        worst = std::max(worst, std::abs(got[t] - want[t]));
        scale = std::max(scale, std::abs(want[t]));
    }
    CHECK(worst <= 1e-5 * scale);
    // Symmetric, sorted rows without self entries; each row's excess over its weights (the
    // unary terms and the couplings to nodes out of the system) is its aggregate's.
    for (uint32_t p = 0; p < coarse; ++p) {
        double weights = 0;
        for (uint32_t s = c.rows[p]; s < c.rows[p + 1]; ++s) {
            const uint32_t q = c.columns[s];
            CHECK(q != p);
            if (s > c.rows[p]) CHECK(c.columns[s - 1] < q);
            CHECK(got[size_t(q) * coarse + p] == got[size_t(p) * coarse + q]);
            weights += c.weights[s];
        }
        double excess = 0;
        for (uint32_t i = 0; i < n; ++i)
            if (parent[i] == p) {
                excess += a.diagonal[i];
                for (uint32_t s = a.rows[i]; s < a.rows[i + 1]; ++s) excess -= a.weights[s];
            }
        CHECK(c.diagonal[p] - weights == Approx(excess).margin(1e-4 * c.diagonal[p]));
    }
}

TEST_CASE("walk hierarchy: every level stays a diagonally dominant operator, down to a dense coarsest") {
    // Bare Laplacian rows (no unary, no seed next to them) are most of a walk's rows: a coarse
    // diagonal taken as a difference of sums would lose their aggregates' small excess to
    // rounding (even turn it negative), and the coarsest inverse would blow up.
    const auto a = random_operator(6000, 32);
    seg::HierarchyOptions o;
    const auto h = seg::build_walk_hierarchy(a, o);
    REQUIRE(h.levels.size() >= 3);
    CHECK(h.levels.back().matrix.size() <= o.coarsest);
    CHECK(h.coarse_inverse.size() == size_t(h.levels.back().matrix.size()) * h.levels.back().matrix.size());
    for (size_t l = 0; l < h.levels.size(); ++l) {
        const auto& m = h.levels[l].matrix;
        INFO("level " << l << " of " << h.levels.size() << ", " << m.size() << " nodes");
        if (l > 0) CHECK(m.size() < h.levels[l - 1].matrix.size() / 2);
        size_t worse = 0;
        for (uint32_t i = 0; i < m.size(); ++i) {
            double sum = 0;
            for (uint32_t s = m.rows[i]; s < m.rows[i + 1]; ++s) sum += m.weights[s];
            worse += m.diagonal[i] > 0.0f && m.diagonal[i] < sum * (1.0 - 1e-6);
            CHECK(h.levels[l].smoother[i] == (m.diagonal[i] > 0.0f ? o.omega / m.diagonal[i] : 0.0f));
        }
        CHECK(worse == 0);
    }
}

TEST_CASE("walk hierarchy: the coarsest level's pseudo-inverse, and a closed component without seeds left out") {
    // Two components: one with a unary term (invertible), one a bare Laplacian (singular).
    seg::WalkMatrix a;
    const uint32_t n = 12;
    std::vector<std::vector<std::pair<uint32_t, float>>> adj(n);
    ref::Rng rng(7);
    for (uint32_t i = 0; i < n; ++i)
        for (uint32_t j = i + 1; j < n; ++j)
            if ((i < 6) == (j < 6) && rng.below(2) == 0) {
                float v = rng.uniform(0.1f, 1.0f);
                adj[i].push_back({j, v}), adj[j].push_back({i, v});
            }
    for (uint32_t i = 0; i + 1 < n; ++i)
        if ((i < 6) == (i + 1 < 6)) adj[i].push_back({i + 1, 0.05f}), adj[i + 1].push_back({i, 0.05f});  // connected
    a.rows.push_back(0);
    for (uint32_t i = 0; i < n; ++i) {
        double d = i == 2 ? 0.3 : 0.0;
        for (auto [j, v] : adj[i]) a.columns.push_back(j), a.weights.push_back(v), d += v;
        a.rows.push_back(uint32_t(a.columns.size()));
        a.diagonal.push_back(float(d));
    }
    const auto inv = seg::dense_pseudo_inverse(a);
    const auto m = dense(a);
    // A A^+ A = A, and A^+ is symmetric.
    double worst = 0;
    for (uint32_t i = 0; i < n; ++i)
        for (uint32_t j = 0; j < n; ++j) {
            double v = 0;
            for (uint32_t p = 0; p < n; ++p)
                for (uint32_t q = 0; q < n; ++q) v += m[i * n + p] * inv[p * n + q] * m[q * n + j];
            worst = std::max(worst, std::abs(v - m[i * n + j]));
            CHECK(inv[i * n + j] == Approx(inv[j * n + i]).margin(1e-4));
        }
    CHECK(worst < 1e-3);
    // On the invertible component A^+ is the inverse.
    for (uint32_t i = 0; i < 6; ++i) {
        double v = 0;
        for (uint32_t p = 0; p < 6; ++p) v += inv[i * n + p] * m[p * n + i];
        CHECK(v == Approx(1.0).margin(1e-3));
    }
    // Aggregated whole, the singular component's coarse node leaves the system.
    std::vector<uint32_t> parent(n);
    for (uint32_t i = 0; i < n; ++i) parent[i] = i < 6 ? 0 : 1;
    auto c = seg::galerkin(a, parent, 2);
    CHECK(c.diagonal[0] == Approx(0.3f).epsilon(1e-3));
    CHECK(c.diagonal[1] == 0.0f);
}

TEST_CASE("walk multigrid: the GPU's V-cycle matches the CPU reference cycle") {
    auto scene = ref::random_scene(24, 3000, 0);
    auto& ctx = test::gpu();
    render::GpuScene gpu(ctx, scene.cloud);
    seg::KnnGraph graph(ctx);
    auto domain = all_of(scene.cloud);
    graph.build(gpu, scene.cloud, domain, seg::GraphOptions{});
    seg::RandomWalker walker(ctx);
    ref::Rng rng(8);
    for (uint32_t labels : {3u, 13u}) {
        seg::WalkProblem pr;
        pr.labels = labels;
        pr.seed.assign(domain.size(), -1);
        for (uint32_t l = 0; l < labels; ++l)
            for (int s = 0; s < 3; ++s) pr.seed[rng.below(uint32_t(domain.size()))] = int32_t(l);
        pr.gamma.assign(domain.size(), 0.0f);
        for (auto& g : pr.gamma)
            if (rng.below(3) == 0) g = rng.uniform(0.0f, 2.0f);
        std::vector<float> r(domain.size() * labels);
        for (auto& v : r) v = rng.uniform(-1.0f, 1.0f);
        seg::WalkOptions o;
        o.coarse_scale = 1.5f;
        o.hierarchy.coarsest = 100;  // more levels to cross
        auto got = walker.cycle(graph, pr, r, o);
        const auto& h = walker.hierarchy();
        INFO("labels " << labels << ", levels " << h.levels.size());
        REQUIRE(h.levels.size() >= 3);
        // The reference takes r with `width` columns, as the GPU holds it.
        const uint32_t width = (labels + 3) / 4 * 4;
        std::vector<double> rw(domain.size() * width, 0.0);
        for (size_t i = 0; i < domain.size(); ++i)
            for (uint32_t l = 0; l < labels; ++l) rw[i * width + l] = r[i * labels + l];
        auto want = ref::walk_cycle(h, o.coarse_scale, width, rw);
        double worst = 0, scale = 0;
        for (size_t i = 0; i < domain.size(); ++i)
            for (uint32_t l = 0; l < labels; ++l) {
                worst = std::max(worst, std::abs(double(got[i * labels + l]) - want[i * width + l]));
                scale = std::max(scale, std::abs(want[i * width + l]));
            }
        CHECK(scale > 0);
        CHECK(worst <= 1e-4 * scale);
        // Seeds are out of the system: their z stays 0.
        for (size_t i = 0; i < domain.size(); ++i)
            if (pr.seed[i] >= 0)
                for (uint32_t l = 0; l < labels; ++l) CHECK(got[i * labels + l] == 0.0f);
    }
}

namespace {

// A long strip of Gaussians (a graph with a long diameter, where Jacobi needs many iterations),
// its colour changing in bands (weak edges across them).
data::GaussianCloud strip_cloud() {
    data::GaussianCloud cloud;
    ref::Rng rng(12);
    for (int x = 0; x < 150; ++x)
        for (int z = 0; z < 16; ++z) {
            glm::vec3 p(0.02f * (float(x) + rng.uniform(-0.3f, 0.3f)), 0.002f * rng.uniform(-1.0f, 1.0f),
                        0.02f * (float(z) + rng.uniform(-0.3f, 0.3f)));
            const float band = float((x / 30) % 2);
            ref::add_gaussian(cloud, p, glm::vec3(std::log(0.01f)), glm::vec4(1, 0, 0, 0), 4.0f,
                              ref::dc_from_rgb(glm::vec3(0.3f + 0.4f * band, 0.5f, 0.6f - 0.3f * band)));
        }
    return cloud;
}

}  // namespace

TEST_CASE("walk multigrid: the preconditioned walk matches Eigen's, on a long graph in a fraction of Jacobi's iterations") {
    auto& ctx = test::gpu();
    seg::RandomWalker walker(ctx);
    ref::Rng rng(5);
    // A random cloud with 3 and 19 labels (two column batches), seeds and unary terms; a strip
    // with 3 labels, seeds at its ends and middle only.
    struct Case {
        data::GaussianCloud cloud;
        uint32_t labels;
        bool strip;
        bool start = false;
    };
    std::vector<Case> cases;
    cases.push_back({ref::random_scene(22, 1500, 0).cloud, 3, false});
    cases.push_back({ref::random_scene(22, 1500, 0).cloud, 19, false});
    cases.push_back({strip_cloud(), 3, true});
    cases.push_back({ref::random_scene(22, 1500, 0).cloud, 11, false, true});
    cases.push_back({ref::random_scene(22, 1500, 0).cloud, 19, false, true});
    for (const auto& c : cases) {
        render::GpuScene gpu(ctx, c.cloud);
        seg::KnnGraph graph(ctx);
        auto domain = all_of(c.cloud);
        graph.build(gpu, c.cloud, domain, seg::GraphOptions{});
        const ref::RefGraph rg = ref_graph(graph);
        const uint32_t labels = c.labels, n = uint32_t(domain.size());
        seg::WalkProblem pr;
        pr.labels = labels;
        pr.seed.assign(n, -1);
        if (c.strip) {
            for (uint32_t z = 0; z < 16; z += 5) pr.seed[z] = 0, pr.seed[75 * 16 + z] = 1, pr.seed[149 * 16 + z] = 2;
        } else {
            for (uint32_t l = 0; l < labels; ++l)
                for (int s = 0; s < 3; ++s) pr.seed[rng.below(n)] = int32_t(l);
            pr.gamma.assign(n, 0.0f);
            pr.prior.assign(size_t(n) * labels, 0.0f);
            for (size_t i = 0; i < n; ++i)
                if (rng.below(3) == 0) {
                    pr.gamma[i] = rng.uniform(0.0f, 2.0f);
                    pr.prior[i * labels + rng.below(labels)] = 1.0f;
                }
        }
        const auto want = ref::random_walk(rg, labels, pr.seed, pr.gamma, pr.prior);
        if (c.start) {
            pr.start.resize(size_t(n) * labels);
            for (auto& v : pr.start) v = rng.uniform(0.0f, 1.0f);
        }
        std::map<seg::WalkPreconditioner, seg::WalkResult> got;
        for (auto pc : {seg::WalkPreconditioner::Jacobi, seg::WalkPreconditioner::Multigrid}) {
            seg::WalkOptions wo;
            wo.tolerance = 1e-6f;
            wo.max_iterations = 4000;
            wo.check_every = 5;
            wo.preconditioner = pc;
            got[pc] = walker.solve(graph, pr, wo);
            double worst = 0;
            for (size_t i = 0; i < want.size(); ++i) worst = std::max(worst, std::abs(double(got[pc].x[i]) - want[i]));
            INFO("labels " << labels << ", strip " << c.strip << ", multigrid " << (pc == seg::WalkPreconditioner::Multigrid)
                           << ", iterations " << got[pc].iterations << ", residual " << got[pc].residual);
            CHECK(worst < 2e-3);
            CHECK(got[pc].residual <= 1e-6);
            CHECK(got[pc].levels == (pc == seg::WalkPreconditioner::Multigrid ? walker.hierarchy().levels.size() : 0));
        }
        const auto& jacobi = got[seg::WalkPreconditioner::Jacobi];
        const auto& multigrid = got[seg::WalkPreconditioner::Multigrid];
        INFO("labels " << labels << ", strip " << c.strip << ": Jacobi " << jacobi.iterations << " iterations, multigrid "
                       << multigrid.iterations);
        CHECK(multigrid.levels >= 2);
        CHECK(multigrid.iterations <= jacobi.iterations);
        // Where Jacobi is slow (the strip), multigrid needs a small fraction of its iterations.
        if (c.strip) CHECK(multigrid.iterations * 4 < jacobi.iterations);
        if (c.start) {
            // The start handed over as the answer's storage (read a column batch at a time before
            // that batch's answer overwrites it): the same answer as from a copy of it.
            seg::WalkProblem moved = pr;
            seg::WalkOptions wo;
            wo.tolerance = 1e-6f;
            wo.max_iterations = 4000;
            wo.check_every = 5;
            const auto in_place = walker.solve(graph, std::move(moved), wo);
            CHECK(moved.start.empty());
            CHECK(in_place.x == multigrid.x);
        }
    }
}

TEST_CASE("walk multigrid: a nearly singular walk (few seeds in a large graph) converges without falling back to Jacobi") {
    // As on a real capture with a click per object: a few seeds in tens of thousands of nodes.
    // The operator's product is then a small difference of large sums; computed as
    // degree x_i - sum w x_j its float rounding, new at every product, stalled the multigrid
    // CG near a relative residual of 1e-2 and then blew it up.
    auto& ctx = test::gpu();
    seg::RandomWalker walker(ctx);
    data::GaussianCloud cloud;
    ref::Rng rng(31);
    for (int x = 0; x < 96; ++x)
        for (int y = 0; y < 96; ++y)
            for (int z = 0; z < 4; ++z) {
                glm::vec3 p(0.02f * (float(x) + rng.uniform(-0.3f, 0.3f)), 0.02f * (float(y) + rng.uniform(-0.3f, 0.3f)),
                            0.02f * (float(z) + rng.uniform(-0.3f, 0.3f)));
                // Quadrants of contrasting colour: weak edges between them, and two without a seed
                // of their own hang on those alone (the operator's nearly singular modes).
                const float q = float((x / 48) + 2 * (y / 48));
                const glm::vec3 rgb = q == 0 ? glm::vec3(0.0f) : q == 1 ? glm::vec3(1.0f, 0.0f, 0.0f)
                                    : q == 2 ? glm::vec3(0.0f, 1.0f, 1.0f) : glm::vec3(1.0f);
                // Opacities and colours spread: affinities over orders of magnitude.
                ref::add_gaussian(cloud, p, glm::vec3(std::log(0.01f)), glm::vec4(1, 0, 0, 0), 4.0f - 8.0f * rng.uniform(0.0f, 1.0f),
                                  ref::dc_from_rgb(rgb + 0.5f * glm::vec3(rng.uniform(0.0f, 1.0f), rng.uniform(0.0f, 1.0f), rng.uniform(0.0f, 1.0f))));
            }
    render::GpuScene gpu(ctx, cloud);
    seg::KnnGraph graph(ctx);
    auto domain = all_of(cloud);
    graph.build(gpu, cloud, domain, seg::GraphOptions{});
    const uint32_t n = uint32_t(domain.size()), labels = 2;
    seg::WalkProblem pr;
    pr.labels = labels;
    pr.seed.assign(n, -1);
    auto at = [](int x, int y, int z) { return uint32_t((x * 96 + y) * 4 + z); };
    pr.seed[at(3, 3, 0)] = 0, pr.seed[at(3, 3, 1)] = 0;
    pr.seed[at(92, 90, 2)] = 1;
    const ref::RefGraph rg = ref_graph(graph);
    const auto want = ref::random_walk(rg, labels, pr.seed, {}, {});
    auto worst_of = [&](const seg::WalkResult& got) {
        double worst = 0;
        for (size_t i = 0; i < want.size(); ++i) worst = std::max(worst, std::abs(double(got.x[i]) - want[i]));
        return worst;
    };
    {
        seg::WalkOptions wo;
        wo.tolerance = 1e-3f;
        const auto got = walker.solve(graph, pr, wo);
        INFO("iterations " << got.iterations << ", residual " << got.residual << ", retries " << got.jacobi_retries);
        CHECK(got.jacobi_retries == 0);
        CHECK(got.residual <= 1e-3);
        CHECK(got.iterations <= 60);
        CHECK(worst_of(got) < 2e-3);
    }
    {
        // From a start far from the answer (x = 10), to 1e-5: the answer is as exact as asked.
        // With the product's rounding, A x0 carried ~1e-6 x degree of noise per node, which the
        // nearly singular operator turns into errors of 5e-4 however long the solve runs.
        pr.start.assign(size_t(n) * labels, 10.0f);
        seg::WalkOptions wo;
        wo.tolerance = 1e-5f;
        const auto got = walker.solve(graph, pr, wo);
        INFO("iterations " << got.iterations << ", residual " << got.residual);
        CHECK(got.residual <= 1e-5);
        CHECK(worst_of(got) < 5e-5);
    }
}

TEST_CASE("walk hierarchy: a component that no seed or unary term anchors leaves the system") {
    // Nodes 0-3 a chain coupled to a seed at node 0 (its excess), 4-7 a bare chain, 8 alone.
    seg::WalkMatrix a;
    a.rows.push_back(0);
    for (uint32_t i = 0; i < 9; ++i) {
        double d = i == 0 ? 0.5 : 0.0;
        for (uint32_t j : {i - 1, i + 1})
            if (i < 8 && j < 8 && (i < 4) == (j < 4)) a.columns.push_back(j), a.weights.push_back(0.25f), d += 0.25;
        a.rows.push_back(uint32_t(a.columns.size()));
        a.diagonal.push_back(float(d));
    }
    CHECK(seg::drop_unanchored(a) == 4);
    for (uint32_t i = 0; i < 4; ++i) CHECK(a.diagonal[i] > 0.0f);
    for (uint32_t i = 4; i < 8; ++i) CHECK(a.diagonal[i] == 0.0f);
    CHECK(a.diagonal[8] == 0.0f);  // was already out
}

TEST_CASE("walk: values far outside [0, 1] are found, solved again with Jacobi, and what stays outside is clamped and counted") {
    // The maximum principle, checked on a hand-made answer: seeds and in-range values pass, a
    // value past the slack or NaN does not.
    {
        const std::vector<int32_t> seed = {-1, 0, -1};
        std::vector<float> columns = {1.04f, -0.04f, 0.0f, 0.0f,   // free, within the slack
                                      7.0f, -3.0f, 0.0f, 0.0f,     // a seed: not checked
                                      1.2f, NAN, 0.5f, -0.1f};     // free: 1.2 and NaN; -0.1 in an unused column
        CHECK(seg::walk_values_outside(columns, seed, 4, 3) == 1);  // the solver's slack, 1: NaN only
        CHECK(seg::walk_values_outside(columns, seed, 4, 3, 0.05f) == 2);
        CHECK(seg::clamp_walk_values(columns, seed, 4, 3, 0.05f) == 2);
        CHECK(columns[8] == 1.0f);
        CHECK(columns[9] == 0.0f);
        CHECK(columns[0] == 1.04f);  // inside the slack: left as it is
        CHECK(seg::walk_values_outside(columns, seed, 4, 3, 0.05f) == 0);
    }
    // In a solve: a piece no seed reaches keeps its start, here 1e6 (a start the walk cannot
    // correct; multigrid's small residual does not see it). Multigrid's answer is solved again
    // with Jacobi, which keeps it too; it is clamped and counted, and the reached nodes hold the
    // reference's answer.
    auto& ctx = test::gpu();
    seg::RandomWalker walker(ctx);
    data::GaussianCloud cloud = ref::random_scene(22, 1500, 0).cloud;
    const uint32_t main_n = uint32_t(cloud.size()), far_n = 40;
    cloud.resize(main_n + far_n);
    for (uint32_t i = 0; i < far_n; ++i) {
        const uint32_t j = main_n + i;
        cloud.mean[j] = cloud.mean[i] + glm::vec3(1000.0f, 0.0f, 0.0f);
        cloud.log_scale[j] = cloud.log_scale[i];
        cloud.rotation[j] = cloud.rotation[i];
        cloud.opacity_logit[j] = cloud.opacity_logit[i];
        for (int c = 0; c < 3 * cloud.coeffs(); ++c) cloud.sh[size_t(j) * 3 * cloud.coeffs() + c] = cloud.sh[size_t(i) * 3 * cloud.coeffs() + c];
    }
    render::GpuScene gpu(ctx, cloud);
    seg::KnnGraph graph(ctx);
    auto domain = all_of(cloud);
    graph.build(gpu, cloud, domain, seg::GraphOptions{});
    const uint32_t n = uint32_t(domain.size()), labels = 3;
    seg::WalkProblem pr;
    pr.labels = labels;
    pr.seed.assign(n, -1);
    ref::Rng rng(9);
    for (uint32_t l = 0; l < labels; ++l)
        for (int s = 0; s < 3; ++s) pr.seed[rng.below(main_n)] = int32_t(l);
    pr.start.assign(size_t(n) * labels, 0.0f);
    for (uint32_t i = main_n; i < n; ++i)
        for (uint32_t l = 0; l < labels; ++l) pr.start[size_t(i) * labels + l] = 1e6f;
    seg::WalkOptions wo;
    wo.tolerance = 1e-5f;
    wo.max_iterations = 4000;
    const auto got = walker.solve(graph, pr, wo);
    CHECK(got.levels >= 2);  // multigrid answered first
    CHECK(got.range_retries == 1);
    CHECK(got.out_of_range == uint64_t(far_n) * labels);
    for (float v : got.x) CHECK((v >= 0.0f && v <= 1.0f));
    const ref::RefGraph rg = ref_graph(graph);
    const auto want = ref::random_walk(rg, labels, pr.seed, pr.gamma, pr.prior);
    double worst = 0;
    for (size_t i = 0; i < size_t(main_n) * labels; ++i) worst = std::max(worst, std::abs(double(got.x[i]) - want[i]));
    CHECK(worst < 2e-3);
    // A start in range: nothing to retry or clamp.
    for (uint32_t i = main_n; i < n; ++i)
        for (uint32_t l = 0; l < labels; ++l) pr.start[size_t(i) * labels + l] = 0.0f;
    const auto clean = walker.solve(graph, pr, wo);
    CHECK(clean.range_retries == 0);
    CHECK(clean.out_of_range == 0);
}
