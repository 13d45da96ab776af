// The graph decoder: the kNN graph and the random walker on the GPU against brute force and
// Eigen, and the segmenter's joint solve on scenes whose right answer is plain.
#include <catch2/catch.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <random>

#include "dataset/error.h"
#include "dataset/up_axis.h"
#include "engine/segment/knn_graph.h"
#include "engine/segment/mask_views.h"
#include "engine/segment/random_walker.h"
#include "engine/segment/segmenter.h"
#include "shaders/segment/graph_shared.h"
#include "tests/gpu_fixture.h"
#include "tests/reference/graph_ref.h"
#include "tests/reference/test_scenes.h"

using namespace pg;

namespace {

std::vector<uint32_t> all_of(const data::GaussianCloud& cloud) {
    std::vector<uint32_t> d(cloud.size());
    for (uint32_t i = 0; i < d.size(); ++i) d[i] = i;
    return d;
}

// A scene on the device and its graph over every Gaussian, in scene order.
struct SceneGraph {
    render::GpuScene gpu;
    seg::KnnGraph graph;
    std::vector<uint32_t> domain;
    explicit SceneGraph(const data::GaussianCloud& cloud, const seg::GraphOptions& o = {})
        : gpu(test::gpu(), cloud), graph(test::gpu()), domain(all_of(cloud)) {
        graph.build(gpu, cloud, domain, o);
    }
};

// The GPU's graph as the CPU references take it, so they solve the very same system.
ref::RefGraph as_reference(const seg::KnnGraph& graph) {
    ref::RefGraph rg;
    rg.k = graph.k();
    rg.neighbours = graph.neighbours();
    rg.weights = graph.weights();
    return rg;
}

}  // namespace

TEST_CASE("graph: k nearest neighbours and affinities match a brute-force CPU search") {
    auto scene = ref::random_scene(21, 3000, 1);
    auto& ctx = test::gpu();
    render::GpuScene gpu(ctx, scene.cloud);
    seg::KnnGraph graph(ctx);
    seg::GraphOptions o;
    auto domain = all_of(scene.cloud);
    // A domain in another order than the scene: node i is Gaussian domain[i].
    std::reverse(domain.begin(), domain.end());
    graph.build(gpu, scene.cloud, domain, o);
    REQUIRE(graph.nodes() == domain.size());
    auto nodes = ref::graph_nodes(scene.cloud, domain);
    // The GPU searches the 27 cells around a node: exact for neighbours within one cell side.
    auto want = ref::knn_graph(nodes, o.k, graph.cell_side(), o.colour, o.normal, o.distance);
    auto unbounded = ref::knn_graph(nodes, o.k, 1e9f, o.colour, o.normal, o.distance);
    auto got = graph.neighbours();
    auto weights = graph.weights();
    const size_t k = o.k;
    std::vector<uint8_t> exact(domain.size(), 0);
    for (size_t i = 0; i < domain.size(); ++i) exact[i] = unbounded.distances[i * k + k - 1] <= graph.cell_side() * 0.999f;
    size_t compared = 0, weight_checks = 0;
    for (size_t i = 0; i < domain.size(); ++i) {
        if (!exact[i]) continue;
        ++compared;
        for (size_t t = 0; t < k; ++t) {
            CHECK(got[i * k + t] == want.neighbours[i * k + t]);
            uint32_t j = want.neighbours[i * k + t];
            // A weight depends on both nodes' spacing: compare where both neighbourhoods are exact.
            if (j != 0xFFFFFFFFu && exact[j] && got[i * k + t] == j) {
                CHECK(weights[i * k + t] == Approx(want.weights[i * k + t]).epsilon(1e-4).margin(1e-7));
                ++weight_checks;
            }
        }
    }
    CHECK(compared > domain.size() / 4);
    CHECK(weight_checks > domain.size());
    // Asked to, a sparse node (short of k within one cell side) searches further: it is never an
    // island while another node lies within `shells` cell sides, and its nearest is exact.
    o.shells = seg::gpu::kGraphMaxShells;
    graph.build(gpu, scene.cloud, domain, o);
    got = graph.neighbours();
    size_t isolated_in_27_cells = 0;
    for (size_t i = 0; i < domain.size(); ++i) {
        if (exact[i] || unbounded.distances[i * k] > graph.cell_side() * (float(o.shells) - 0.01f)) continue;
        isolated_in_27_cells += unbounded.distances[i * k] > graph.cell_side() * 1.01f;
        CHECK(got[i * k] == unbounded.neighbours[i * k]);
    }
    CHECK(isolated_in_27_cells > 0);
    // Every weight is an affinity in (0, 1].
    for (float w : weights) CHECK((w >= 0.0f && w <= 1.0f));

    CHECK_THROWS_AS([&] {
        seg::GraphOptions bad;
        bad.k = 17;
        graph.build(gpu, scene.cloud, domain, bad);
    }(), data::InputError);
}

TEST_CASE("graph: thousands of Gaussians collapsed onto one point keep the neighbour search bounded and the rest exact") {
    // Exports that park pruned Gaussians at one point put thousands in one grid cell: past
    // kGraphMaxScan candidates a node keeps the nearest found (all at distance 0 here), so
    // the search stays linear in the nodes; nodes away from that cell are still exact.
    auto scene = ref::random_scene(31, 9000, 1);
    const glm::vec3 point = scene.cloud.mean[0];
    const uint32_t collapsed = 6000;
    REQUIRE(collapsed > seg::gpu::kGraphMaxScan);  // the cap is reached
    for (uint32_t i = 0; i < collapsed; ++i) scene.cloud.mean[i * 3 / 2] = point;  // two of every three
    const seg::GraphOptions o;
    const SceneGraph sg(scene.cloud, o);
    const auto& graph = sg.graph;
    const auto& domain = sg.domain;
    const auto got = graph.neighbours();
    const size_t k = o.k;
    auto nodes = ref::graph_nodes(scene.cloud, domain);
    auto want = ref::knn_graph(nodes, o.k, graph.cell_side(), o.colour, o.normal, o.distance);
    size_t at_point = 0, away = 0;
    for (size_t i = 0; i < domain.size(); ++i) {
        if (scene.cloud.mean[i] == point) {
            ++at_point;
            for (size_t t = 0; t < k; ++t) CHECK((got[i * k + t] < domain.size() && scene.cloud.mean[got[i * k + t]] == point));
        } else if (glm::length(scene.cloud.mean[i] - point) > 4.0f * graph.cell_side()) {
            ++away;
            for (size_t t = 0; t < k; ++t) CHECK(got[i * k + t] == want.neighbours[i * k + t]);
        }
    }
    CHECK(at_point >= collapsed);
    CHECK(away > domain.size() / 10);
}

TEST_CASE("graph: the adjacency is W + W^T with each pair once, every row in slot order, hubs included") {
    // A random scene with hubs: 300 Gaussians parked at one point (as some exports park pruned
    // ones) all list the same few of them (ties go to the smaller id), whose rows then receive
    // hundreds of slots from the reverse half, placed by atomics in any order.
    auto scene = ref::random_scene(41, 3000, 1);
    const glm::vec3 point = scene.cloud.mean[0];
    for (uint32_t i = 1; i <= 300; ++i) scene.cloud.mean[i * 7] = point;
    const SceneGraph sg(scene.cloud);
    const auto& graph = sg.graph;
    const uint32_t n = graph.nodes(), k = graph.k();
    const auto nbr = graph.neighbours();
    const auto w = graph.weights();
    const seg::HostAdjacency& a = graph.host_adjacency();
    REQUIRE(a.rows.size() == n + 1);
    auto lists = [&](uint32_t i, uint32_t j) {
        for (uint32_t t = 0; t < k; ++t)
            if (nbr[size_t(i) * k + t] == j) return int(t);
        return -1;
    };
    size_t most_reverse = 0, mismatches = 0;
    for (uint32_t i = 0; i < n; ++i) {
        // Expected row: own filled slots in order (a mutual pair weighs both slots), then the slots
        // of nodes that list i and that i does not list, by slot id.
        std::vector<std::pair<uint32_t, float>> want;
        for (uint32_t t = 0; t < k; ++t) {
            const uint32_t j = nbr[size_t(i) * k + t];
            if (j == seg::gpu::kGraphNone) continue;
            const int back = lists(j, i);
            want.push_back({j, back < 0 ? w[size_t(i) * k + t] : w[size_t(i) * k + t] + w[size_t(j) * k + uint32_t(back)]});
        }
        size_t reverse = 0;
        for (uint32_t slot = 0; slot < n * k; ++slot)
            if (nbr[slot] == i && lists(i, slot / k) < 0) want.push_back({slot / k, w[slot]}), ++reverse;
        most_reverse = std::max(most_reverse, reverse);
        REQUIRE(a.rows[i + 1] - a.rows[i] == want.size());
        float degree = 0;
        for (size_t e = 0; e < want.size(); ++e) {
            const uint32_t s = a.rows[i] + uint32_t(e);
            mismatches += a.columns[s] != want[e].first || a.weights[s] != want[e].second;
            degree += a.weights[s];
        }
        CHECK(a.degree[i] == Approx(degree).epsilon(1e-5));
    }
    CHECK(mismatches == 0);
    CHECK(most_reverse >= 250);  // a hub's row
    // Symmetric to the bit: A[i][j] == A[j][i].
    size_t asymmetric = 0;
    for (uint32_t i = 0; i < n; ++i)
        for (uint32_t s = a.rows[i]; s < a.rows[i + 1]; ++s) {
            const uint32_t j = a.columns[s];
            bool found = false;
            for (uint32_t e = a.rows[j]; e < a.rows[j + 1]; ++e) found |= a.columns[e] == i && a.weights[e] == a.weights[s];
            asymmetric += !found;
        }
    CHECK(asymmetric == 0);
}

TEST_CASE("graph: the order a domain lists its Gaussians in changes no spacing, cell or neighbour") {
    // The segmenter numbers nodes in Morton order (for the passes' memory access), so the graph
    // must be the same graph whatever the numbering: the median spacing (hence the cell side
    // and every sparse node's search) is sampled in scene order.
    auto scene = ref::random_scene(33, 3000, 1);
    auto& ctx = test::gpu();
    render::GpuScene gpu(ctx, scene.cloud);
    seg::GraphOptions o;
    auto forward = all_of(scene.cloud), shuffled = forward;
    std::mt19937 rng(5);
    std::shuffle(shuffled.begin(), shuffled.end(), rng);
    seg::KnnGraph a(ctx), b(ctx);
    a.build(gpu, scene.cloud, forward, o);
    b.build(gpu, scene.cloud, shuffled, o);
    CHECK(a.median_spacing() == b.median_spacing());
    CHECK(a.cell_side() == b.cell_side());
    // The same neighbours (as Gaussians, nearest first) for every Gaussian.
    const auto na = a.neighbours(), nb = b.neighbours();
    std::vector<uint32_t> node_in_b(scene.cloud.size());
    for (uint32_t i = 0; i < shuffled.size(); ++i) node_in_b[shuffled[i]] = i;
    auto gaussian = [](const std::vector<uint32_t>& d, uint32_t node) { return node < d.size() ? d[node] : node; };
    size_t differ = 0;
    for (uint32_t g = 0; g < forward.size(); ++g)
        for (uint32_t t = 0; t < o.k; ++t)
            differ += gaussian(forward, na[size_t(g) * o.k + t]) != gaussian(shuffled, nb[size_t(node_in_b[g]) * o.k + t]);
    CHECK(differ == 0);
}

TEST_CASE("graph decoder: a click seeds the node whose centre is nearest, however far and however many clicks") {
    // The scan (a few clicks) and the hash grid (many) must agree with brute force everywhere: far
    // outside the nodes (past any ring limit), on duplicated centres (the lowest node wins) and
    // on a grid cell much smaller than the spacing.
    data::GaussianCloud cloud;
    seg::GraphDomain d;
    seg::DomainNodes nodes(cloud, d, false);
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int i = 0; i < 3000; ++i) nodes.position.push_back(glm::vec3(u(rng), u(rng), 0.1f * u(rng)));
    for (int i = 0; i < 200; ++i) nodes.position.push_back(nodes.position[size_t(i) * 7]);  // duplicates, higher numbers
    auto brute = [&](glm::vec3 p) {
        uint32_t best = 0;
        double bd = 1e300;
        for (uint32_t i = 0; i < nodes.position.size(); ++i) {
            const glm::dvec3 e = glm::dvec3(nodes.position[i]) - glm::dvec3(p);
            if (const double d2 = glm::dot(e, e); d2 < bd) bd = d2, best = i;
        }
        return best;
    };
    for (size_t count : {5u, 200u})
        for (float cell : {0.002f, 0.05f}) {
            std::vector<glm::vec3> points;
            for (size_t c = 0; c < count; ++c) {
                const float far = c % 5 == 0 ? 20.0f : 1.0f;  // every fifth far away
                points.push_back(c % 3 == 0 ? nodes.position[c * 7] : glm::vec3(far * u(rng), far * u(rng), u(rng)));
            }
            const auto got = nodes.nearest(points, cell);
            REQUIRE(got.size() == count);
            size_t wrong = 0;
            for (size_t c = 0; c < count; ++c) wrong += got[c] != brute(points[c]);
            INFO("clicks " << count << ", cell " << cell);
            CHECK(wrong == 0);
        }
}

TEST_CASE("random walker: the GPU's conjugate gradient matches Eigen's on the same systems") {
    auto scene = ref::random_scene(22, 1500, 0);
    auto& ctx = test::gpu();
    const SceneGraph sg(scene.cloud);
    const auto& graph = sg.graph;
    const auto& domain = sg.domain;
    const auto rg = as_reference(graph);
    seg::RandomWalker walker(ctx);
    seg::WalkOptions wo;
    wo.tolerance = 1e-6f;
    wo.max_iterations = 4000;
    ref::Rng rng(5);
    // 3 labels (one solve) and 19 (two solves of 16 columns); seeds, and unary terms on a third of the nodes.
    for (uint32_t labels : {3u, 19u}) {
        seg::WalkProblem pr;
        pr.labels = labels;
        pr.seed.assign(domain.size(), -1);
        for (uint32_t l = 0; l < labels; ++l)
            for (int s = 0; s < 3; ++s) pr.seed[rng.below(uint32_t(domain.size()))] = int32_t(l);
        pr.gamma.assign(domain.size(), 0.0f);
        pr.prior.assign(domain.size() * labels, 0.0f);
        for (size_t i = 0; i < domain.size(); ++i)
            if (rng.below(3) == 0) {
                pr.gamma[i] = rng.uniform(0.0f, 2.0f);
                pr.prior[i * labels + rng.below(labels)] = 1.0f;
            }
        auto got = walker.solve(graph, pr, wo);
        auto want = ref::random_walk(rg, labels, pr.seed, pr.gamma, pr.prior);
        REQUIRE(got.x.size() == want.size());
        double worst = 0;
        for (size_t i = 0; i < want.size(); ++i) worst = std::max(worst, std::abs(double(got.x[i]) - want[i]));
        INFO("labels " << labels << ", iterations " << got.iterations << ", residual " << got.residual);
        CHECK(worst < 2e-3);
        CHECK(got.residual <= 1e-6);
        // Warm start from the answer: nothing left to do.
        pr.start = got.x;
        auto again = walker.solve(graph, pr, wo);
        CHECK(again.iterations < got.iterations / 4);
    }
    seg::WalkProblem bad;
    bad.labels = 2;
    bad.seed.assign(domain.size(), 2);  // a label out of range
    CHECK_THROWS_AS(walker.solve(graph, bad), data::InputError);
}

TEST_CASE("seeded forest: the GPU's widest-path rounds and the host's flood give Kruskal's seeded maximum spanning forest") {
    auto scene = ref::random_scene(23, 2000, 0);
    auto& ctx = test::gpu();
    const SceneGraph sg(scene.cloud);
    const auto& graph = sg.graph;
    const auto& domain = sg.domain;
    const auto rg = as_reference(graph);
    seg::SeededForest forest(ctx);
    ref::Rng rng(6);
    // 2 and 40 labels of two seeds each; then most nodes seeded, as after a walk (the host's
    // flood by default), each solved both ways.
    for (uint32_t labels : {2u, 40u, 1000u}) {
        std::vector<int32_t> seed(domain.size(), -1);
        for (uint32_t l = 0; l < labels; ++l)
            for (int s = 0; s < 2; ++s) seed[rng.below(uint32_t(domain.size()))] = int32_t(labels > 100 ? l % 3 : l);
        const auto want = ref::seeded_forest(rg, seed);
        for (float host_below : {0.0f, 1.0f}) {
            seg::ForestOptions options;
            options.host_below = host_below;
            auto got = forest.solve(graph, seed, options);
            INFO("labels " << labels << ", host " << host_below << ", rounds " << got.rounds);
            CHECK(got.converged);
            CHECK((got.rounds == 0) == (host_below > 0));
            size_t same = 0, reached = 0;
            for (size_t i = 0; i < domain.size(); ++i) {
                CHECK(got.width[i] == want.width[i]);
                CHECK((got.label[i] < 0) == (want.label[i] < 0));
                same += got.label[i] == want.label[i];
                reached += want.label[i] >= 0;
            }
            // Only a tie of two distinct edges of exactly equal weight may go either way.
            CHECK(same >= domain.size() * 999 / 1000);
            CHECK(reached > domain.size() / 2);
        }
    }
    std::vector<int32_t> bad(domain.size(), -1);
    bad[0] = -2;
    CHECK_THROWS_AS(forest.solve(graph, bad), data::InputError);
}

namespace {

// Three balls of distinct colours standing apart on a grey floor (y-down world, floor at y = 0).
struct BallsScene {
    data::GaussianCloud cloud;
    std::vector<int32_t> ball;  // 1..3 per Gaussian, 4 a floating cluster, 0 the floor
    std::vector<data::Camera> cameras;
};

BallsScene balls_scene() {
    BallsScene s;
    ref::Rng rng(9);
    const glm::vec3 colours[3] = {{0.9f, 0.1f, 0.1f}, {0.1f, 0.8f, 0.2f}, {0.1f, 0.2f, 0.9f}};
    for (int b = 0; b < 3; ++b)
        for (int i = 0; i < 900; ++i) {
            glm::vec3 d(rng.normal(), rng.normal(), rng.normal());
            d = glm::normalize(d) * 0.25f;
            ref::add_gaussian(s.cloud, glm::vec3(float(b - 1), -0.26f, 0.0f) + d, glm::vec3(std::log(0.02f)),
                              glm::vec4(1, 0, 0, 0), 4.0f, ref::dc_from_rgb(colours[b]));
            s.ball.push_back(b + 1);
        }
    // A floating cluster high above the left ball: in its ROI column, joined to nothing.
    for (int i = 0; i < 60; ++i) {
        ref::add_gaussian(s.cloud, glm::vec3(-1.0f + rng.uniform(-0.05f, 0.05f), -2.5f, rng.uniform(-0.05f, 0.05f)),
                          glm::vec3(std::log(0.01f)), glm::vec4(1, 0, 0, 0), 4.0f, ref::dc_from_rgb(glm::vec3(0.9f)));
        s.ball.push_back(4);
    }
    for (int i = 0; i < 5000; ++i) {
        ref::add_gaussian(s.cloud, glm::vec3(rng.uniform(-2, 2), 0.0f, rng.uniform(-1, 1)),
                          glm::vec3(std::log(0.03f), std::log(0.003f), std::log(0.03f)), glm::vec4(1, 0, 0, 0), 4.0f,
                          ref::dc_from_rgb(glm::vec3(0.5f)));
        s.ball.push_back(0);
    }
    s.cameras.push_back(ref::look_at_camera("front", {0, -1.5, -4}, {0, -0.25, 0}, {0, -1, 0}, 160, 120, 150, 150, 80, 60));
    return s;
}

data::PromptClick point_click(glm::dvec3 p, bool positive = true) {
    data::PromptClick c;
    c.point = p;
    c.positive = positive;
    return c;
}

double iou(const std::vector<int32_t>& labels, int id, const std::vector<int32_t>& truth, int truth_id) {
    size_t inter = 0, uni = 0;
    for (size_t i = 0; i < labels.size(); ++i) {
        bool a = labels[i] == id, b = truth[i] == truth_id;
        inter += a && b;
        uni += a || b;
    }
    return uni ? double(inter) / double(uni) : 0.0;
}

// What the balls-scene tests share: the graph alone, y-down, ROI columns 1.25 wide per click.
seg::SegmentOptions balls_options() {
    seg::SegmentOptions o;
    o.up = {0, -1, 0};
    o.scale = 0.5;
    o.graph = seg::GraphUse::Alone;
    return o;
}

// A 3D click on top of the left ball (object 1) and one on the middle ball's front (object 2).
data::Prompts left_and_middle() {
    data::Prompts p;
    p.objects.push_back({"left", 1, {point_click({-1.0, -0.51, 0.0})}});
    p.objects.push_back({"middle", 2, {point_click({0.0, -0.26, -0.25})}});
    return p;
}

}  // namespace

TEST_CASE("graph decoder: each object's click takes its own object, unclicked content stays unlabelled") {
    auto s = balls_scene();
    auto& ctx = test::gpu();
    render::GpuScene gpu(ctx, s.cloud);
    seg::Segmenter segmenter(ctx, s.cloud, gpu, s.cameras);  // no network
    for (auto solver : {seg::GraphSolver::Walk, seg::GraphSolver::Forest, seg::GraphSolver::WalkForest})
        for (float colour : {3.0f, 10.0f}) {
            // Flat colours on flat colours: the scene's boundaries are its colours. At the
            // default contrast (3) a single click's walk leaks over the floor (ball IoU 0.3-0.5);
            // the forest has no such bias towards the many background seeds.
            if (solver == seg::GraphSolver::Walk && colour == 3.0f) continue;
            INFO("solver " << seg::graph_solver_name(solver) << ", colour contrast " << colour);
            seg::SegmentOptions o;
            o.up = {0, -1, 0};
            o.scale = 0.5;  // ROI columns 1.25 wide around each click
            o.graph = seg::GraphUse::Alone;
            o.solver = solver;
            o.graph_options.colour = colour;
            data::Prompts p;
            p.objects.push_back({"left", 1, {point_click({-1.0, -0.51, 0.0})}});
            p.objects.push_back({"middle", 2, {point_click({0.0, -0.26, -0.25})}});
            auto r = segmenter.segment(p, o);
            REQUIRE(r.graph);
            CHECK(r.graph->solver == solver);
            CHECK(r.failed() == 0);
            CHECK(iou(r.labels, 1, s.ball, 1) > 0.9);
            CHECK(iou(r.labels, 2, s.ball, 2) > 0.9);
            // The floating cluster's component holds no seed: unlabelled, and counted.
            CHECK(r.graph->unreached_components >= 1);
            CHECK(r.graph->unreached >= 60);
            size_t right = 0, floor_labelled = 0, floor = 0;
            for (size_t i = 0; i < s.ball.size(); ++i) {
                right += (s.ball[i] == 3 || s.ball[i] == 4) && r.labels[i] != 0;
                floor += s.ball[i] == 0;
                floor_labelled += s.ball[i] == 0 && r.labels[i] != 0;
            }
            CHECK(right == 0);
            CHECK(floor_labelled < floor / 20);
            // The network decoders need a network.
            o.graph = seg::GraphUse::Unary;
            CHECK_THROWS_AS(segmenter.segment(p, o), data::InputError);

            // A further click reuses the graph (the walk starts from its last solution).
            o.graph = seg::GraphUse::Alone;
            p.objects[0].clicks.push_back(point_click({-1.25, -0.26, 0.0}));
            auto r2 = segmenter.segment(p, o);
            if (solver == seg::GraphSolver::Walk) CHECK(r2.graph->iterations <= r.graph->iterations);
            CHECK(iou(r2.labels, 1, s.ball, 1) > 0.9);
        }
}

TEST_CASE("graph decoder: a click on the same objects reuses their domain, other objects take their own, and either gives a fresh segmenter's labels") {
    // One segmenter asked in turn about one pair of objects, another object, and the pair again
    // (a further click and a changed option): each answer equals a new segmenter's (the further
    // click's, warm-started, within the walk's tolerance), so the kept domain is the one the
    // question's ROI boxes and options make.
    auto s = balls_scene();
    auto& ctx = test::gpu();
    render::GpuScene gpu(ctx, s.cloud);
    seg::Segmenter kept(ctx, s.cloud, gpu, s.cameras);
    seg::SegmentOptions o;
    o.up = {0, -1, 0};
    o.scale = 0.5;
    o.graph = seg::GraphUse::Alone;
    data::Prompts pair, other, pair_further;
    pair.objects.push_back({"left", 1, {point_click({-1.0, -0.51, 0.0})}});
    pair.objects.push_back({"middle", 2, {point_click({0.0, -0.26, -0.25})}});
    other.objects.push_back({"right", 1, {point_click({1.0, -0.26, 0.0})}});
    pair_further = pair;
    pair_further.objects[0].clicks.push_back(point_click({-1.25, -0.26, 0.0}));
    auto fresh = [&](const data::Prompts& p, const seg::SegmentOptions& opt) {
        seg::Segmenter one(ctx, s.cloud, gpu, s.cameras);
        return one.segment(p, opt);
    };
    seg::SegmentOptions narrow = o;
    narrow.graph_margin = seg::kNarrowMargin;
    // `warm`: a further click on the same objects and options, which starts the walk from the
    // last answer while a fresh segmenter starts cold. Both stop at the walk's tolerance, so a few
    // nodes at a tie may fall either way (7 of 7,760 with one spacing sample tried).
    struct Ask {
        const data::Prompts* prompts;
        const seg::SegmentOptions* options;
        bool warm;
    };
    const std::vector<Ask> asks{{&pair, &o, false},         {&other, &o, false},          {&pair, &o, false},
                                {&pair_further, &o, true}, {&pair_further, &narrow, false}, {&pair, &o, false}};
    size_t step = 0;
    for (auto [p, opt, warm] : asks) {
        INFO("question " << step++);
        const auto got = kept.segment(*p, *opt);
        const auto want = fresh(*p, *opt);
        REQUIRE(got.graph);
        REQUIRE(want.graph);
        CHECK(got.graph->domain == want.graph->domain);
        CHECK(got.graph->margin == want.graph->margin);
        if (warm) {
            size_t differ = 0;
            for (size_t i = 0; i < got.labels.size(); ++i) differ += got.labels[i] != want.labels[i];
            CHECK(differ * 200 <= got.labels.size());
        } else {
            CHECK(got.labels == want.labels);
        }
    }
}

TEST_CASE("graph decoder: a piece split off an object's graph follows the object it is bridged to, a far one stays unlabelled") {
    // A dense pebble of the left ball's colour 0.12 beside it: every node's neighbours lie inside
    // it, so it is a component no seed reaches; its bridges (its nodes' nearest seeded nodes, all
    // on the ball) carry the ball's answer over. The floating cluster is beyond any bridge's reach.
    auto s = balls_scene();
    ref::Rng rng(12);
    const uint32_t pebble_first = uint32_t(s.cloud.size());
    for (int i = 0; i < 80; ++i) {
        ref::add_gaussian(s.cloud, glm::vec3(-1.37f + rng.uniform(-0.01f, 0.01f), -0.26f + rng.uniform(-0.01f, 0.01f),
                                             rng.uniform(-0.01f, 0.01f)),
                          glm::vec3(std::log(0.005f)), glm::vec4(1, 0, 0, 0), 4.0f, ref::dc_from_rgb({0.9f, 0.1f, 0.1f}));
        s.ball.push_back(5);
    }
    auto& ctx = test::gpu();
    render::GpuScene gpu(ctx, s.cloud);
    seg::Segmenter segmenter(ctx, s.cloud, gpu, s.cameras);
    seg::SegmentOptions o = balls_options();
    data::Prompts p = left_and_middle();
    auto r = segmenter.segment(p, o);
    REQUIRE(r.graph);
    CHECK(iou(r.labels, 1, s.ball, 1) > 0.9);
    size_t pebble_left = 0, floating_labelled = 0;
    for (size_t i = 0; i < s.ball.size(); ++i) {
        pebble_left += i >= pebble_first && r.labels[i] == 1;
        floating_labelled += s.ball[i] == 4 && r.labels[i] != 0;
    }
    CHECK(pebble_left == 80);
    CHECK(floating_labelled == 0);
    CHECK(r.graph->unreached >= 60);  // the floating cluster, counted

    // A further click and a negative one on the middle ball's object: the bridges kept from the
    // first solve (the same components hold seeds) carry the new answers as a new segmenter's do
    // (up to the walk's tolerance: this one starts from its last answer, a new one from nothing).
    p.objects[0].clicks.push_back(point_click({-1.25, -0.26, 0.0}));
    for (int step = 0; step < 2; ++step) {
        INFO("further click " << step);
        if (step == 1) p.objects[1].clicks.push_back(point_click({0.0, -0.01, 0.5}, false));
        const auto again = segmenter.segment(p, o);
        seg::Segmenter fresh(ctx, s.cloud, gpu, s.cameras);
        const auto want = fresh.segment(p, o);
        size_t differ = 0;
        for (size_t i = 0; i < want.labels.size(); ++i) differ += again.labels[i] != want.labels[i];
        INFO(differ << " labels differ");
        CHECK(differ * 100 <= want.labels.size());
        size_t pebble = 0;
        for (size_t i = pebble_first; i < s.ball.size(); ++i) pebble += again.labels[i] == 1;
        CHECK(pebble == 80);
    }
}

TEST_CASE("graph decoder: a click on a fragment of the surface it hit seeds the surface about it too") {
    // A blue wall 1.2 x 1 (z = 0, y down) with a hole of radius 0.12, in which lies one large flat
    // Gaussian (sigma 0.06) of the wall's colour: a real capture's sparse splat, beyond the
    // neighbour search's reach of the wall, so a piece of the graph of its own. A click on it holds
    // its object to that one node unless it also seeds the wall within the Gaussian's extent.
    seg::SegmentOptions o = balls_options();
    ref::TestScene s;
    std::vector<int32_t> wall;
    ref::Rng rng(3);
    while (s.cloud.size() < 5000) {
        const float x = rng.uniform(-0.6f, 0.6f), y = rng.uniform(-1.1f, -0.1f);
        if (x * x + (y + 0.6f) * (y + 0.6f) < 0.12f * 0.12f) continue;
        ref::add_gaussian(s.cloud, glm::vec3(x, y, 0.0f), glm::log(glm::vec3(0.01f, 0.01f, 0.001f)), glm::vec4(1, 0, 0, 0), 4.0f,
                          ref::dc_from_rgb({0.3f, 0.5f, 0.7f}));
        wall.push_back(1);
    }
    ref::add_gaussian(s.cloud, glm::vec3(0.0f, -0.6f, 0.0f), glm::log(glm::vec3(0.06f, 0.06f, 0.0005f)), glm::vec4(1, 0, 0, 0), 4.0f,
                      ref::dc_from_rgb({0.3f, 0.5f, 0.7f}));
    wall.push_back(1);
    for (int i = 0; i < 6000; ++i) {
        ref::add_gaussian(s.cloud, glm::vec3(rng.uniform(-1.5f, 1.5f), 0.01f, rng.uniform(-1.0f, 1.0f)),
                          glm::log(glm::vec3(0.03f, 0.003f, 0.03f)), glm::vec4(1, 0, 0, 0), 4.0f, ref::dc_from_rgb(glm::vec3(0.5f)));
        wall.push_back(0);
    }
    s.cameras.push_back(ref::look_at_camera("front", {0, -0.6, -4}, {0, -0.6, 0}, {0, -1, 0}, 320, 240, 300, 300, 160, 120));
    auto& ctx = test::gpu();
    render::GpuScene gpu(ctx, s.cloud);
    seg::Segmenter segmenter(ctx, s.cloud, gpu, s.cameras);
    data::Prompts p;
    p.objects.push_back({"wall", 1, {point_click({0.02, -0.6, 0.0})}});
    for (auto solver : {seg::GraphSolver::WalkForest, seg::GraphSolver::Forest}) {
        INFO("solver " << seg::graph_solver_name(solver));
        o.solver = solver;
        const auto r = segmenter.segment(p, o);
        REQUIRE(r.failed() == 0);
        REQUIRE(r.graph);
        CHECK(r.graph->widened_clicks == 1);
        CHECK(r.objects[0].anchors[0].gaussian == 5000);  // the click did land on the fragment
        CHECK(iou(r.labels, 1, wall, 1) > 0.95);
    }
    // A click on the wall itself is not widened.
    p.objects[0].clicks[0] = point_click({0.4, -0.3, 0.0});
    const auto plain = segmenter.segment(p, o);
    REQUIRE(plain.graph);
    CHECK(plain.graph->widened_clicks == 0);
    CHECK(iou(plain.labels, 1, wall, 1) > 0.95);
}

TEST_CASE("segmenter: an object whose clicks cannot be lifted fails alone, the others are segmented") {
    auto s = balls_scene();
    auto& ctx = test::gpu();
    render::GpuScene gpu(ctx, s.cloud);
    seg::Segmenter segmenter(ctx, s.cloud, gpu, s.cameras);
    seg::SegmentOptions o = balls_options();
    o.graph_options.colour = 10.0f;
    data::Prompts p;
    p.objects.push_back({"off", 1, {{"front", 500.0, 10.0, std::nullopt, true}}});        // off the image
    p.objects.push_back({"good", 2, {point_click({0.0, -0.26, -0.25})}});
    p.objects.push_back({"sky", 3, {{"front", 80.0, 2.0, std::nullopt, true}}});          // an empty pixel
    p.objects.push_back({"negative", 4, {point_click({1.0, -0.26, -0.25}, false)}});     // no positive click
    auto r = segmenter.segment(p, o);
    REQUIRE(r.objects.size() == 4);
    CHECK(r.failed() == 3);
    CHECK(r.objects[0].error.find("off the") != std::string::npos);
    CHECK(r.objects[1].error.empty());
    CHECK(r.objects[2].error.find("nearly empty") != std::string::npos);
    CHECK(r.objects[3].error.find("no positive click") != std::string::npos);
    CHECK(iou(r.labels, 2, s.ball, 2) > 0.9);
    for (int id : {1, 3, 4}) CHECK(std::count(r.labels.begin(), r.labels.end(), id) == 0);
    o.strict = true;
    CHECK_THROWS_AS(segmenter.segment(p, o), data::InputError);
}

TEST_CASE("a streamed scene segments like the resident one: lifts, ROI, graph and walk") {
    // Slabs of 4096 Gaussians (the splats are the widest array): the balls scene takes two.
    auto s = balls_scene();
    auto& ctx = test::gpu();
    render::SceneBudget budget;
    budget.max_binding_bytes = 4096 * 48;
    render::GpuScene resident(ctx, s.cloud), streamed(ctx, s.cloud, budget);
    REQUIRE(streamed.streamed());
    seg::Segmenter a(ctx, s.cloud, resident, s.cameras), b(ctx, s.cloud, streamed, s.cameras);
    seg::SegmentOptions o = balls_options();
    o.graph_options.colour = 10.0f;
    // Pixel clicks (lifted through a render) on the left and middle balls, a 3D one on the right.
    const data::Camera& cam = s.cameras[0];
    auto pixel_of = [&](glm::dvec3 p) {
        const glm::dvec3 c = cam.R * p + cam.t;
        return glm::dvec2(cam.fx * c.x / c.z + cam.cx, cam.fy * c.y / c.z + cam.cy);
    };
    const glm::dvec2 left = pixel_of({-1.0, -0.26, -0.2}), middle = pixel_of({0.0, -0.26, -0.2});
    data::Prompts p;
    p.objects.push_back({"left", 1, {{"front", left.x, left.y, std::nullopt, true}}});
    p.objects.push_back({"middle", 2, {{"front", middle.x, middle.y, std::nullopt, true}}});
    p.objects.push_back({"right", 3, {point_click({1.0, -0.26, -0.25})}});
    for (auto solver : {seg::GraphSolver::Walk, seg::GraphSolver::Forest}) {
        o.solver = solver;
        const auto ra = a.segment(p, o), rb = b.segment(p, o);
        REQUIRE(ra.failed() == 0);
        REQUIRE(rb.failed() == 0);
        for (size_t j = 0; j < ra.objects.size(); ++j) {
            CHECK(ra.objects[j].anchors.size() == rb.objects[j].anchors.size());
            for (size_t c = 0; c < ra.objects[j].anchors.size(); ++c)
                CHECK(ra.objects[j].anchors[c].gaussian == rb.objects[j].anchors[c].gaussian);
        }
        CHECK(ra.labels == rb.labels);
        for (int id : {1, 2, 3}) CHECK(iou(rb.labels, id, s.ball, id) > 0.9);
    }
    // Masks: each slab's labels rasterized over the last slab's pixel state, in both modes.
    seg::MaskViews ma(ctx, resident, s.ball), mb(ctx, streamed, s.ball);
    for (auto mode : {seg::LabelMode::Occlusion, seg::LabelMode::Paper}) {
        INFO("mode " << seg::label_mode_name(mode));
        seg::MaskViewsOptions mo;
        mo.mode = mode;
        mo.refine = false;
        const auto va = ma.render(cam, mo, false), vb = mb.render(cam, mo, false);
        size_t differ = 0, labelled = 0;
        for (size_t i = 0; i < va.labels.size(); ++i) {
            differ += va.labels[i] != vb.labels[i];
            labelled += va.labels[i] != 0;
        }
        CHECK(labelled > va.labels.size() / 20);
        CHECK(differ == 0);
    }
}

TEST_CASE("graph decoder: a domain past the graph's node limit is solved on every n-th node, each object still found") {
    // What a click in a scene of millions meets once the domain's graph would pass the device's
    // largest binding (about 1.6 M nodes on lavapipe), forced here by a small limit.
    auto s = balls_scene();
    auto& ctx = test::gpu();
    render::GpuScene gpu(ctx, s.cloud);
    seg::Segmenter segmenter(ctx, s.cloud, gpu, s.cameras);
    seg::SegmentOptions o = balls_options();
    o.graph_options.colour = 10.0f;
    o.graph_scales = {1.0};  // one ROI scale and the narrow margin: past the limit a larger one
    o.graph_margin = seg::kNarrowMargin;  // is left out and the margin narrowed first (test_graph_scales)
    data::Prompts p = left_and_middle();
    for (auto solver : {seg::GraphSolver::Walk, seg::GraphSolver::Forest, seg::GraphSolver::WalkForest}) {
        INFO("solver " << seg::graph_solver_name(solver));
        o.solver = solver;
        o.graph_max_nodes = 0;
        const auto full = segmenter.segment(p, o);
        REQUIRE(full.graph);
        CHECK(full.graph->stride == 1);
        CHECK(full.graph->nodes == full.graph->domain);
        o.graph_max_nodes = full.graph->domain / 3;
        const auto r = segmenter.segment(p, o);
        REQUIRE(r.graph);
        CHECK(r.failed() == 0);
        CHECK(r.graph->stride >= 3);
        CHECK(r.graph->domain == full.graph->domain);
        CHECK(r.graph->nodes <= o.graph_max_nodes);
        CHECK(iou(r.labels, 1, s.ball, 1) > 0.85);
        CHECK(iou(r.labels, 2, s.ball, 2) > 0.85);
        // Unclicked content stays unlabelled: the right balls, the floating cluster (counted).
        size_t right = 0, agree = 0;
        for (size_t i = 0; i < s.ball.size(); ++i) {
            right += (s.ball[i] == 3 || s.ball[i] == 4) && r.labels[i] != 0;
            agree += r.labels[i] == full.labels[i];
        }
        CHECK(right == 0);
        CHECK(r.graph->unreached >= 60);
        CHECK(agree >= s.ball.size() * 95 / 100);
        // The next click builds its graph again (the subsample's is not the domain's).
        o.graph_max_nodes = 0;
        CHECK(segmenter.segment(p, o).labels == full.labels);
    }
    // A limit that leaves no room beside the clicked nodes: one clear error.
    o.graph_max_nodes = 10;
    CHECK_THROWS_WITH(segmenter.segment(p, o), Catch::Matchers::Contains("graph of at most 10 nodes"));
}

TEST_CASE("graph decoder: a cold solve hands over a coarse answer first, and a cancelled one leaves nothing stale") {
    auto s = balls_scene();
    auto& ctx = test::gpu();
    render::GpuScene gpu(ctx, s.cloud);
    seg::SegmentOptions o = balls_options();
    o.graph_options.colour = 10.0f;
    REQUIRE(s.cloud.size() >= 64 * o.coarse_stride);  // big enough for a coarse graph
    data::Prompts p = left_and_middle();

    seg::Segmenter first(ctx, s.cloud, gpu, s.cameras);
    int answers = 0;
    std::vector<int32_t> coarse;
    o.on_coarse = [&](const seg::SegmentResult& r) {
        ++answers;
        coarse = r.labels;
    };
    const auto full = first.segment(p, o);
    CHECK(answers == 1);
    REQUIRE(coarse.size() == s.cloud.size());
    // Rough, but already each click's own ball.
    CHECK(iou(coarse, 1, s.ball, 1) > 0.7);
    CHECK(iou(coarse, 2, s.ball, 2) > 0.7);
    CHECK(iou(full.labels, 1, s.ball, 1) > 0.9);
    first.segment(p, o);  // warm: it starts from the last solution, no coarse answer
    CHECK(answers == 1);

    // A flag already set stops the run before any work.
    std::atomic<bool> cancel{true};
    o.cancel = &cancel;
    seg::Segmenter second(ctx, s.cloud, gpu, s.cameras);
    CHECK_THROWS_AS(second.segment(p, o), seg::Cancelled);
    // Set while the coarse answer is shown (a newer click): the fine solve stops; the next run
    // gives what a segmenter that was never interrupted gives.
    cancel = false;
    o.on_coarse = [&](const seg::SegmentResult&) { cancel = true; };
    CHECK_THROWS_AS(second.segment(p, o), seg::Cancelled);
    cancel = false;
    o.on_coarse = nullptr;
    const auto again = second.segment(p, o);
    CHECK(again.labels == full.labels);
}

TEST_CASE("ptv3+graph: the network's answer stands where it cuts the graph no harder than the graph's own, on the whole domain and on every n-th node") {
    auto s = balls_scene();
    auto& ctx = test::gpu();
    render::GpuScene gpu(ctx, s.cloud);
    data::Prompts p = left_and_middle();
    seg::SegmentOptions o = balls_options();
    o.graph = seg::GraphUse::Unary;
    o.graph_scales = {1.0};
    // The same rule where the domain is solved on every n-th node (past the node limit): the
    // same choice, and both balls found.
    auto decimated = [&](seg::Segmenter& segmenter, const seg::SegmentResult& whole) {
        REQUIRE(whole.graph);
        auto limited = o;
        limited.graph_max_nodes = whole.graph->domain / 4;
        auto dec = segmenter.segment(p, limited);
        REQUIRE(dec.graph);
        CHECK(dec.graph->stride >= 2);
        CHECK(iou(dec.labels, 1, s.ball, 1) > 0.85);
        CHECK(iou(dec.labels, 2, s.ball, 2) > 0.85);
        return dec;
    };
    // The segmenter's answer for the prompts: whether the network's answer stood (also on every
    // n-th node), the network trusted, both balls found to `floor`.
    auto check_choice = [&](seg::Segmenter& segmenter, bool network_answer, double floor) {
        const auto r = segmenter.segment(p, o);
        CHECK(r.objects[0].network_answer == network_answer);
        CHECK(r.objects[0].network_trusted);
        CHECK(iou(r.labels, 1, s.ball, 1) > floor);
        CHECK(iou(r.labels, 2, s.ball, 2) > floor);
        CHECK(decimated(segmenter, r).objects[0].network_answer == network_answer);
    };
    {
        // A leaky graph (the walk alone at colour contrast 3 floods the floor from one click):
        // a network that knows the balls cuts them at their colour edge, a cleaner cut than the
        // graph's through the even floor, so its answer stands.
        o.solver = seg::GraphSolver::Walk;
        seg::GroundTruthDecoder network(s.ball);
        seg::Segmenter segmenter(ctx, s.cloud, gpu, s.cameras, network);
        auto alone = o;
        alone.graph = seg::GraphUse::Alone;
        const auto graph = segmenter.segment(p, alone);
        CHECK(iou(graph.labels, 1, s.ball, 1) < 0.9);
        check_choice(segmenter, true, 0.95);
    }
    {
        // A network that takes only the left ball's top half (a cut through its even colour) while
        // the graph finds the ball whole at its colour edge: the graph's answer stands for it.
        o.solver = seg::GraphSolver::WalkForest;
        o.graph_options.colour = 10.0f;
        std::vector<int32_t> half = s.ball;
        for (size_t i = 0; i < half.size(); ++i)
            if (half[i] == 1 && s.cloud.mean[i].y > -0.26f) half[i] = 0;
        seg::GroundTruthDecoder network(half);
        seg::Segmenter segmenter(ctx, s.cloud, gpu, s.cameras, network);
        check_choice(segmenter, false, 0.9);
    }
}

TEST_CASE("ptv3+graph: where the graph's answer is a whole component, the network's clean cut stands") {
    // A red ball with a blue one resting against it, floating alone: one graph component and no
    // background seed anywhere, so the graph alone gives the click both balls and cuts no edge
    // (contrast 0), as a house with the car parked against it and the trees over its roof.
    data::GaussianCloud cloud;
    std::vector<int32_t> truth;
    ref::Rng rng(17);
    const glm::vec3 colours[2] = {{0.9f, 0.1f, 0.1f}, {0.1f, 0.2f, 0.9f}};
    for (int b = 0; b < 2; ++b)
        for (int i = 0; i < 900; ++i) {
            glm::vec3 d = glm::normalize(glm::vec3(rng.normal(), rng.normal(), rng.normal())) * 0.12f;
            ref::add_gaussian(cloud, glm::vec3(0.23f * float(b), -1.0f, 0.0f) + d, glm::vec3(std::log(0.01f)),
                              glm::vec4(1, 0, 0, 0), 4.0f, ref::dc_from_rgb(colours[b]));
            truth.push_back(b + 1);
        }
    std::vector<data::Camera> cameras{ref::look_at_camera("front", {0.2, -1.5, -4}, {0.2, -1.0, 0}, {0, -1, 0}, 160, 120, 150, 150, 80, 60)};
    auto& ctx = test::gpu();
    render::GpuScene gpu(ctx, cloud);
    data::Prompts p;
    p.objects.push_back({"red", 1, {point_click({-0.12, -1.0, 0.0})}});
    seg::SegmentOptions o = balls_options();
    o.graph_scales = {1.0};
    auto solve = [&](const std::vector<int32_t>& network_truth, seg::GraphUse use, double clean, uint64_t max_nodes = 0) {
        seg::GroundTruthDecoder network(network_truth);
        seg::Segmenter segmenter(ctx, cloud, gpu, cameras, network);
        auto with = o;
        with.graph = use;
        with.unary_clean = clean;
        with.graph_max_nodes = max_nodes;
        return segmenter.segment(p, with);
    };
    std::vector<int32_t> red_only = truth;
    for (auto& t : red_only) t = t == 1 ? 1 : 0;
    const seg::SegmentOptions defaults;
    const double bound = defaults.unary_clean;
    const auto graph = solve(red_only, seg::GraphUse::Alone, bound);
    REQUIRE(graph.objects.size() == 1);
    CHECK(graph.objects[0].boundary_contrast == 0.0);
    CHECK(iou(graph.labels, 1, truth, 1) < 0.6);  // both balls
    // The network cuts at the colour edge between the balls: its answer stands, the red ball alone.
    const auto clean = solve(red_only, seg::GraphUse::Unary, bound);
    CHECK(clean.objects[0].network_answer);
    CHECK(clean.objects[0].boundary_contrast > 0.0);
    CHECK(clean.objects[0].boundary_contrast < bound);
    CHECK(iou(clean.labels, 1, truth, 1) > 0.95);
    // The same where the domain is solved on every n-th node (past the node limit).
    const auto decimated = solve(red_only, seg::GraphUse::Unary, bound, cloud.size() / 4);
    REQUIRE(decimated.graph);
    CHECK(decimated.graph->stride >= 2);
    CHECK(decimated.objects[0].network_answer);
    CHECK(iou(decimated.labels, 1, truth, 1) > 0.9);
    // Off (0), the graph's answer stands as before.
    const auto off = solve(red_only, seg::GraphUse::Unary, 0.0);
    CHECK_FALSE(off.objects[0].network_answer);
    CHECK(off.labels == graph.labels);
    // A network that takes half the red ball cuts through its even colour: not clean,
    // the graph's whole answer stands.
    std::vector<int32_t> half = red_only;
    for (size_t i = 0; i < half.size(); ++i)
        if (half[i] == 1 && cloud.mean[i].x > 0.0f) half[i] = 0;
    const auto inside = solve(half, seg::GraphUse::Unary, bound);
    CHECK(inside.objects[0].network_trusted);
    CHECK_FALSE(inside.objects[0].network_answer);
    CHECK(inside.labels == graph.labels);
    // (Its answer, let through by any bound: the half ball, its cut far above a clean one's.)
    const auto through = solve(half, seg::GraphUse::Unary, 10.0);
    CHECK(through.objects[0].network_answer);
    CHECK(through.objects[0].boundary_contrast > 2.0 * bound);
    CHECK(iou(through.labels, 1, half, 1) > 0.9);
}
