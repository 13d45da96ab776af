// LabelColumns (engine/segment/label_columns.h): a walk's per-node label values held whole or,
// past a label count, as each node's largest few; and the walker and the Segmenter with many
// objects held either way.
#include <catch2/catch.hpp>

#include <algorithm>
#include <numeric>

#include "dataset/error.h"
#include "engine/segment/label_columns.h"
#include "engine/segment/random_walker.h"
#include "engine/segment/segmenter.h"
#include "tests/gpu_fixture.h"
#include "tests/reference/test_scenes.h"

using namespace pg;
using seg::LabelColumns;

namespace {

// Node-major values with zeros, negatives and ties, written in column batches of `width`.
std::vector<float> random_values(uint32_t nodes, uint32_t labels, uint64_t seed) {
    ref::Rng rng(seed);
    std::vector<float> x(size_t(nodes) * labels);
    for (auto& v : x) {
        const uint32_t kind = rng.below(10);
        v = kind < 3 ? 0.0f : kind < 4 ? -rng.uniform(0.0f, 0.01f) : kind < 5 ? 0.25f : rng.uniform(0.0f, 1.0f);
    }
    return x;
}

void write_batches(LabelColumns& c, const std::vector<float>& x, uint32_t width) {
    const uint32_t n = c.nodes(), labels = c.labels();
    for (uint32_t base = 0; base < labels; base += width) {
        const uint32_t count = std::min(width, labels - base);
        std::vector<float> batch(size_t(n) * width, 0.0f);
        for (uint32_t i = 0; i < n; ++i)
            for (uint32_t l = 0; l < count; ++l) batch[size_t(i) * width + l] = x[size_t(i) * labels + base + l];
        c.write(base, count, width, batch);
    }
}

}  // namespace

TEST_CASE("label columns: a sparse node keeps its largest values, its most likely label and share are the dense ones") {
    const uint32_t n = 400, labels = 45;
    const auto x = random_values(n, labels, 17);
    LabelColumns dense(n, labels, false), sparse(n, labels, true);
    write_batches(dense, x, 16);
    write_batches(sparse, x, 16);
    CHECK_FALSE(dense.sparse());
    CHECK(sparse.sparse());
    const auto a = dense.most_likely(nullptr), b = sparse.most_likely(nullptr);
    CHECK(a.arg == b.arg);
    CHECK(a.share == b.share);  // the same sums in the same order
    for (uint32_t i = 0; i < n; ++i) {
        // The kKept largest positive values, earlier labels first among equals.
        std::vector<uint32_t> order(labels);
        std::iota(order.begin(), order.end(), 0u);
        std::stable_sort(order.begin(), order.end(),
                         [&](uint32_t p, uint32_t q) { return x[size_t(i) * labels + p] > x[size_t(i) * labels + q]; });
        std::vector<float> want(labels, 0.0f);
        for (uint32_t r = 0; r < LabelColumns::kKept; ++r)
            if (const float v = x[size_t(i) * labels + order[r]]; v > 0) want[order[r]] = v;
        std::vector<float> got(labels);
        for (uint32_t l = 0; l < labels; ++l) got[l] = sparse.at(i, l);
        INFO("node " << i);
        CHECK(got == want);
        CHECK(sparse.any_positive(i) == dense.any_positive(i));
        CHECK(dense.at(i, 7) == x[size_t(i) * labels + 7]);
    }
    // A column batch read back is what at() gives, zero-padded to the width.
    std::vector<float> cols;
    sparse.read(32, 13, 16, cols);
    REQUIRE(cols.size() == size_t(n) * 16);
    for (uint32_t i = 0; i < n; ++i) {
        for (uint32_t l = 0; l < 13; ++l) CHECK(cols[size_t(i) * 16 + l] == sparse.at(i, 32 + l));
        for (uint32_t l = 13; l < 16; ++l) CHECK(cols[size_t(i) * 16 + l] == 0.0f);
    }
    // Nodes set whole or copied keep the same answers; a reached mask leaves the rest unlabelled.
    LabelColumns copy(n, labels, true);
    for (uint32_t i = 0; i < n; ++i) {
        if (i % 2) copy.copy_node(i, sparse, i);
        else copy.set_node(i, &x[size_t(i) * labels]);
    }
    const auto c = copy.most_likely(nullptr);
    CHECK(c.arg == b.arg);
    CHECK(c.share == b.share);
    std::vector<uint8_t> reached(n, 1);
    reached[3] = 0;
    CHECK(sparse.most_likely(&reached).arg[3] == -1);
    CHECK_THROWS_AS(copy.copy_node(0, dense, 0), std::logic_error);
    CHECK_THROWS_AS(LabelColumns::dense(std::vector<float>(10), 3), std::invalid_argument);
    CHECK_THROWS_AS(sparse.take_dense(), std::logic_error);
}

TEST_CASE("random walker: past dense_labels the answer is held sparse and labels as the dense one") {
    auto& ctx = test::gpu();
    const auto cloud = ref::random_scene(41, 2000, 0).cloud;
    render::GpuScene gpu(ctx, cloud);
    seg::KnnGraph graph(ctx);
    std::vector<uint32_t> domain(cloud.size());
    std::iota(domain.begin(), domain.end(), 0u);
    graph.build(gpu, cloud, domain, seg::GraphOptions{});
    const uint32_t n = graph.nodes(), labels = 40;  // three column batches
    ref::Rng rng(8);
    seg::WalkProblem pr;
    pr.labels = labels;
    pr.seed.assign(n, -1);
    for (uint32_t l = 0; l < labels; ++l)
        for (int s = 0; s < 3; ++s) pr.seed[rng.below(n)] = int32_t(l);
    seg::RandomWalker walker(ctx);
    seg::WalkOptions wo;
    wo.tolerance = 1e-5f;
    const auto dense = walker.solve(graph, pr, wo);  // the node-major API: always dense
    LabelColumns sparse;
    const auto cold = walker.solve(graph, pr, sparse, wo);
    REQUIRE(sparse.sparse());
    CHECK(cold.x.empty());
    CHECK(cold.iterations == dense.iterations);  // the same solve from the same start
    const auto want = LabelColumns::dense(dense.x, labels).most_likely(nullptr);
    const auto got = sparse.most_likely(nullptr);
    CHECK(got.arg == want.arg);
    CHECK(got.share == want.share);
    for (uint32_t i = 0; i < n; i += 7)
        for (uint32_t l = 0; l < labels; ++l)
            if (const float v = sparse.at(i, l); v != 0.0f) CHECK(v == dense.x[size_t(i) * labels + l]);

    // A warm start from the sparse answer (its largest values only) solves to the same labels.
    pr.seed[rng.below(n)] = 5;
    const auto again_dense = walker.solve(graph, pr, wo);
    const auto warm = walker.solve(graph, pr, sparse, wo);
    const auto want2 = LabelColumns::dense(again_dense.x, labels).most_likely(nullptr);
    const auto got2 = sparse.most_likely(nullptr);
    size_t same = 0;
    for (uint32_t i = 0; i < n; ++i) same += got2.arg[i] == want2.arg[i];
    INFO("warm: " << warm.iterations << " iterations, cold " << again_dense.iterations << "; same label on " << same
                  << " of " << n);
    CHECK(same >= n - n / 500);
    CHECK(warm.iterations <= again_dense.iterations);
    // A dense walk can start from it too, and a start of the wrong size is refused.
    LabelColumns wrong(n + 1, labels, true);
    CHECK_THROWS_AS(walker.solve(graph, pr, wrong, wo), data::InputError);
}

TEST_CASE("segmenter: 40 objects held sparse label every Gaussian as held dense") {
    auto scene = ref::random_scene(43, 6000, 0);
    auto& ctx = test::gpu();
    render::GpuScene gpu(ctx, scene.cloud);
    data::Prompts p;
    ref::Rng rng(12);
    for (int j = 0; j < 40; ++j) {
        const glm::vec3 at = scene.cloud.mean[rng.below(uint32_t(scene.cloud.size()))];
        data::PromptClick c;
        c.positive = true;
        c.point = glm::dvec3(at);
        p.objects.push_back({"o" + std::to_string(j + 1), j + 1, {c}});
    }
    seg::SegmentOptions o;
    o.up = {0, -1, 0};
    o.scale = 0.6;
    o.graph = seg::GraphUse::Alone;
    REQUIRE(p.objects.size() + 1 > o.walk.dense_labels);
    seg::Segmenter held_sparse(ctx, scene.cloud, gpu, scene.cameras), held_dense(ctx, scene.cloud, gpu, scene.cameras);
    const auto a = held_sparse.segment(p, o);
    o.walk.dense_labels = 1000;
    const auto b = held_dense.segment(p, o);
    size_t same = 0, labelled = 0;
    for (size_t i = 0; i < a.labels.size(); ++i) same += a.labels[i] == b.labels[i], labelled += b.labels[i] > 0;
    INFO("same label on " << same << " of " << a.labels.size() << ", labelled " << labelled);
    CHECK(labelled > a.labels.size() / 4);
    CHECK(same >= a.labels.size() - a.labels.size() / 1000);
}
