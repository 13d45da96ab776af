// The graph decoder's ROI scales: boundary_contrast on graphs whose right answer is plain, and
// the segmenter keeping the answer whose boundary is weakest where the object outgrows its ROI.
#include <catch2/catch.hpp>

#include <cmath>

#include "dataset/formats/camera_io.h"
#include "dataset/formats/scene_io.h"
#include "dataset/prompts.h"
#include "dataset/up_axis.h"
#include "engine/segment/boundary_contrast.h"
#include "engine/segment/segmenter.h"
#include "tests/gpu_fixture.h"
#include "tests/reference/test_scenes.h"
#include "tests/test_paths.h"

using namespace pg;

namespace {

// A symmetric adjacency from undirected edges (i, j, w).
seg::HostAdjacency adjacency(uint32_t nodes, const std::vector<std::tuple<uint32_t, uint32_t, float>>& edges) {
    std::vector<std::vector<std::pair<uint32_t, float>>> rows(nodes);
    for (auto [i, j, w] : edges) rows[i].push_back({j, w}), rows[j].push_back({i, w});
    seg::HostAdjacency a;
    a.rows.push_back(0);
    for (auto& r : rows) {
        for (auto [j, w] : r) a.columns.push_back(j), a.weights.push_back(w);
        a.rows.push_back(uint32_t(a.columns.size()));
    }
    return a;
}

}  // namespace

TEST_CASE("boundary contrast: a cut along a weak edge scores its weakness, one through an even chain scores 1") {
    // Two triangles of weight 1 joined by one edge of weight 0.05, then an even chain of 6 nodes.
    std::vector<std::tuple<uint32_t, uint32_t, float>> e = {{0, 1, 1}, {1, 2, 1}, {0, 2, 1}, {3, 4, 1}, {4, 5, 1},
                                                            {3, 5, 1}, {2, 3, 0.05f}};
    for (uint32_t i = 6; i < 11; ++i) e.push_back({i, i + 1, 0.5f});
    const auto g = adjacency(12, e);
    std::vector<int32_t> label(12, 0);
    label[0] = label[1] = label[2] = 1;          // one triangle: cut on the weak edge
    label[6] = label[7] = label[8] = 2;          // half the chain: cut between equals
    const auto c = seg::boundary_contrast(g, label, 4);
    REQUIRE(c.size() == 4);
    CHECK(c[0] == 0.0);
    CHECK(c[1] == Approx(0.05));
    CHECK(c[2] == Approx(1.0));
    CHECK(c[3] == 0.0);  // no node
    // Both triangles together: nothing leaves them but that weak edge, now inside.
    label[3] = label[4] = label[5] = 1;
    CHECK(seg::boundary_contrast(g, label, 4)[1] == 0.0);
    // A label past `labels` and unlabelled nodes count as outside, never as a label.
    label[9] = 7;
    CHECK(seg::boundary_contrast(g, label, 4)[2] == Approx(1.0));
}

TEST_CASE("graph decoder: a rod longer than its click's ROI comes out whole at the larger ROI scale and says so, one within it is solved once, and past the node limit or the budget the margin narrows, then the larger scale is left out") {
    // An orange rod 1.2 long held 0.05 above a grey floor (on supports out of the picture),
    // clicked 0.1 from one end. The ROI at scale 1
    // (1.25 wide about the click) ends halfway along the rod: the margin's background seeds lie
    // on it and cut it through strong edges. At scale 2 the ROI holds the rod and its boundary
    // is the gap between rod and floor, far weaker: that answer stands.
    ref::TestScene s;
    std::vector<int32_t> truth;
    ref::Rng rng(5);
    for (int i = 0; i < 6000; ++i) {
        // The rod's surface: a box 1.2 x 0.15 x 0.15 (y down).
        const int face = int(rng.below(4));
        const float x = rng.uniform(-0.6f, 0.6f), t = rng.uniform(-0.075f, 0.075f);
        glm::vec3 p = face == 0 ? glm::vec3(x, -0.2f, t) : face == 1 ? glm::vec3(x, -0.125f + t, -0.075f)
                    : face == 2 ? glm::vec3(x, -0.125f + t, 0.075f) : glm::vec3(x, -0.05f, t);
        // Flat along the face's normal, as a trained scene's surface Gaussians are.
        const glm::vec3 scale = face == 1 || face == 2 ? glm::vec3(0.01f, 0.01f, 0.001f) : glm::vec3(0.01f, 0.001f, 0.01f);
        ref::add_gaussian(s.cloud, p, glm::log(scale), glm::vec4(1, 0, 0, 0), 4.0f, ref::dc_from_rgb({0.9f, 0.5f, 0.1f}));
        truth.push_back(1);
    }
    for (int i = 0; i < 12000; ++i) {
        ref::add_gaussian(s.cloud, glm::vec3(rng.uniform(-2.5f, 2.5f), 0.01f, rng.uniform(-1.5f, 1.5f)),
                          glm::vec3(std::log(0.03f), std::log(0.003f), std::log(0.03f)), glm::vec4(1, 0, 0, 0), 4.0f,
                          ref::dc_from_rgb(glm::vec3(0.5f)));
        truth.push_back(0);
    }
    s.cameras.push_back(ref::look_at_camera("front", {0, -1.5, -4}, {0, 0, 0}, {0, -1, 0}, 160, 120, 150, 150, 80, 60));
    auto& ctx = test::gpu();
    render::GpuScene gpu(ctx, s.cloud);
    seg::Segmenter segmenter(ctx, s.cloud, gpu, s.cameras);
    seg::SegmentOptions o;
    o.up = {0, -1, 0};
    o.scale = 0.5;  // ROI columns 1.25 wide about the click
    o.graph = seg::GraphUse::Alone;
    data::Prompts p;
    data::PromptClick click;
    click.point = glm::dvec3(-0.5, -0.2, 0.0);
    p.objects.push_back({"rod", 1, {click}});
    auto rod_iou = [&](const seg::SegmentResult& r) {
        size_t inter = 0, uni = 0;
        for (size_t i = 0; i < truth.size(); ++i) {
            inter += r.labels[i] == 1 && truth[i] == 1;
            uni += r.labels[i] == 1 || truth[i] == 1;
        }
        return double(inter) / double(uni);
    };
    o.graph_scales = {1.0};
    const auto cut = segmenter.segment(p, o);
    REQUIRE(cut.failed() == 0);
    CHECK(rod_iou(cut) < 0.75);
    CHECK(cut.objects[0].graph_scale == 1.0);
    o.graph_scales = {1.0, 2.0};
    const auto whole = segmenter.segment(p, o);
    REQUIRE(whole.failed() == 0);
    CHECK(rod_iou(whole) > 0.95);
    CHECK(whole.objects[0].graph_scale == 2.0);
    CHECK(whole.objects[0].boundary_contrast < 0.1);
    REQUIRE(whole.objects[0].scale_answers.size() == 2);  // the answer at 2 reached past the ROI at 1
    // Clicked at its middle, the rod lies within the ROI at scale 1: the answer at scale 2 fits
    // there, a smaller margin could only cut it, so scale 1 is not solved.
    p.objects[0].clicks[0].point = glm::dvec3(0.0, -0.2, 0.0);
    const auto middle = segmenter.segment(p, o);
    REQUIRE(middle.failed() == 0);
    CHECK(rod_iou(middle) > 0.95);
    CHECK(middle.objects[0].scale_answers.size() == 1);
    CHECK(middle.objects[0].graph_scale == 2.0);
    // Past the graph's node limit or a click's budget, before any decimation: the margin narrows
    // first, and the larger scale stays while that fits (the rod whole); below that the larger
    // scale is left out too: every node at scale 1 rather than every n-th at scale 2.
    o.graph_scales = {1.0};
    const auto one = segmenter.segment(p, o);
    o.graph_scales = {1.0, 2.0};
    o.graph_margin = seg::kNarrowMargin;
    const auto narrow = segmenter.segment(p, o);
    o.graph_margin = 0.5;
    REQUIRE(one.graph);
    REQUIRE(middle.graph);
    REQUIRE(narrow.graph);
    const size_t small_domain = one.graph->domain, large_domain = middle.graph->domain;
    REQUIRE(large_domain > small_domain);
    CHECK(double(narrow.graph->domain) < 0.8 * double(large_domain));  // the floor past the ROI at 2 left out
    CHECK(middle.graph->margin == 0.5);
    CHECK(rod_iou(narrow) > 0.95);
    for (bool budget : {false, true}) {
        INFO((budget ? "a click's budget" : "the node limit"));
        uint64_t& limit = budget ? o.graph_budget : o.graph_max_nodes;
        const uint64_t before = limit;
        limit = narrow.graph->domain;
        const auto fitted = segmenter.segment(p, o);
        REQUIRE(fitted.failed() == 0);
        REQUIRE(fitted.graph);
        CHECK(fitted.graph->stride == 1);
        CHECK(fitted.graph->domain == narrow.graph->domain);
        CHECK(fitted.graph->margin == seg::kNarrowMargin);  // report.json says why the domain is smaller
        CHECK(fitted.objects[0].graph_scale == 2.0);
        CHECK(fitted.labels == narrow.labels);
        limit = narrow.graph->domain - 1;
        const auto tight = segmenter.segment(p, o);
        REQUIRE(tight.failed() == 0);
        REQUIRE(tight.graph);
        CHECK(tight.graph->stride == 1);
        CHECK(tight.graph->domain < small_domain);  // scale 1 with the narrow margin
        CHECK(tight.objects[0].graph_scale == 1.0);
        limit = before;
    }
}

TEST_CASE("graph decoder: the budget's narrow margin answers the sample as well as the default one") {
    // Every node in the margin seeds the background, and the walk's answer inside the ROI depends
    // on the seeds next to it, not on how far the ring reaches: a ring a fifth as wide answers the
    // sample's ten first clicks as well (the graph's grid cell follows the domain's spacing, so a
    // near tie may still flip: not the same labels, the same quality).
    const auto dir = test::source_dir() / "assets" / "sample" / "desk_000";
    const auto cloud = data::load_scene(dir / "scene.ply");
    const auto cameras = data::load_cameras(dir / "cameras.json");
    auto prompts = data::read_prompts(dir / "prompts.json");
    for (auto& obj : prompts.objects) obj.clicks.resize(1);
    const auto truth = cloud.int_property("instance");
    REQUIRE(truth);
    auto& ctx = test::gpu();
    render::GpuScene gpu(ctx, cloud);
    seg::Segmenter segmenter(ctx, cloud, gpu, cameras);
    seg::SegmentOptions o;
    o.up = data::up_from_cameras(cameras);
    o.graph = seg::GraphUse::Alone;
    auto mean_iou = [&](const seg::SegmentResult& r) {
        double sum = 0;
        for (auto& obj : prompts.objects) {
            size_t inter = 0, uni = 0;
            for (size_t i = 0; i < r.labels.size(); ++i) {
                const bool a = r.labels[i] == obj.id, b = (*truth)[i] == obj.id;
                inter += a && b, uni += a || b;
            }
            sum += uni ? double(inter) / double(uni) : 0.0;
        }
        return sum / double(prompts.objects.size());
    };
    o.graph_margin = seg::kNarrowMargin;
    const auto thin = segmenter.segment(prompts, o);
    o.graph_margin = 0.5;
    const auto wide = segmenter.segment(prompts, o);
    REQUIRE(thin.failed() == 0);
    REQUIRE(wide.failed() == 0);
    REQUIRE(thin.graph);
    REQUIRE(wide.graph);
    CHECK(thin.graph->domain <= wide.graph->domain);
    const double a = mean_iou(thin), b = mean_iou(wide);
    INFO("mean 3D IoU, margin 0.1: " << a << ", 0.5: " << b);
    CHECK(b > 0.85);
    CHECK(a >= b - 0.02);
}
