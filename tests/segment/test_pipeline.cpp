// The segmentation stages around the network, each against a plain CPU computation.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <set>

#include "dataset/error.h"
#include "dataset/orbit.h"
#include "dataset/up_axis.h"
#include "engine/segment/partition.h"
#include "engine/segment/prompt_encoder.h"
#include "engine/segment/segmenter.h"
#include "tests/gpu_fixture.h"
#include "tests/reference/cpu_rasterizer.h"
#include "tests/reference/pixel_pick.h"
#include "tests/reference/test_scenes.h"

using namespace pg;

TEST_CASE("partition: disjoint batches of at most N_max covering the ROI, seeded") {
    for (uint32_t n : {0u, 1u, 8192u, 8193u, 20000u, 50001u}) {
        std::vector<uint32_t> roi(n);
        for (uint32_t i = 0; i < n; ++i) roi[i] = 3 * i + 1;
        auto batches = seg::partition_roi(roi, 8192, 7);
        CHECK(batches.size() == (n + 8191) / 8192);
        std::vector<uint32_t> all;
        size_t smallest = SIZE_MAX, largest = 0;
        for (auto& b : batches) {
            CHECK(b.size() <= 8192);
            CHECK(std::is_sorted(b.begin(), b.end()));
            smallest = std::min(smallest, b.size());
            largest = std::max(largest, b.size());
            all.insert(all.end(), b.begin(), b.end());
        }
        if (!batches.empty()) CHECK(largest - smallest <= 1);
        std::sort(all.begin(), all.end());
        CHECK(all == roi);  // disjoint and complete
        CHECK(seg::partition_roi(roi, 8192, 7) == batches);
        if (batches.size() > 1) {
            CHECK(seg::partition_roi(roi, 8192, 8) != batches);
            // Each batch spans the ROI rather than one end of it.
            for (auto& b : batches) CHECK(b.back() - b.front() > 3 * n * 3 / 4);
        }
    }
}

TEST_CASE("up axis: from cameras, from a ground plane, never assumed") {
    auto scene = ref::random_scene(2, 200, 0);
    data::OrbitOptions ring;
    ring.count = 12;
    ring.elevation_degrees = 35;  // tilted cameras: their ups cancel around the ring
    for (glm::dvec3 world_up : {glm::dvec3(0, -1, 0), glm::dvec3(0, 0, 1)}) {
        auto cams = data::orbit_cameras(scene.cloud, world_up, ring);
        CHECK(glm::length(cams[0].up() - world_up) > 0.1);
        CHECK(glm::length(data::up_from_cameras(cams) - world_up) < 1e-6);
    }
    CHECK_THROWS_AS(data::up_from_cameras({}), data::InputError);

    // A ground plane z = 0 with objects above it: up = +z. The same scene y-down: up = -y.
    for (int variant = 0; variant < 2; ++variant) {
        data::GaussianCloud cloud;
        ref::Rng rng(3);
        auto place = [&](glm::vec3 p) {
            if (variant == 1) p = glm::vec3(p.x, -p.z, p.y);
            ref::add_gaussian(cloud, p, glm::vec3(-4.0f), glm::vec4(1, 0, 0, 0), 2.0f, glm::vec3(0.0f));
        };
        for (int i = 0; i < 3000; ++i) place({rng.uniform(-5, 5), rng.uniform(-5, 5), 0.0f});
        for (int i = 0; i < 1500; ++i) place({rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(0.2f, 2.0f)});
        auto g = data::up_from_ground_plane(cloud);
        glm::dvec3 expected = variant == 0 ? glm::dvec3(0, 0, 1) : glm::dvec3(0, -1, 0);
        CHECK(glm::dot(g, expected) > 0.99);
    }
    glm::dvec3 a, b;
    for (glm::dvec3 u : {glm::dvec3(0, -1, 0), glm::dvec3(0, 0, 1), glm::normalize(glm::dvec3(1, 2, 3))}) {
        data::horizontal_axes(u, a, b);
        CHECK(std::abs(glm::dot(a, u)) < 1e-12);
        CHECK(std::abs(glm::dot(b, u)) < 1e-12);
        CHECK(std::abs(glm::dot(a, b)) < 1e-12);
        CHECK(glm::length(a) == Approx(1.0));
    }
}

TEST_CASE("prompt encoder: click weights and the ROI column match a CPU computation") {
    auto scene = ref::random_scene(4, 5000, 0);
    auto& ctx = test::gpu();
    render::GpuScene gpu(ctx, scene.cloud);
    seg::PromptEncoder encoder(ctx);
    std::vector<seg::Anchor> anchors = {{{0.1, 0.2, 0.0}, true, -1}, {{-0.3, 0.1, 0.2}, false, -1},
                                        {{0.2, -0.1, 0.1}, true, -1}};
    seg::RoiBox roi;
    roi.centre = anchors[0].position;
    data::horizontal_axes(glm::dvec3(0, -1, 0), roi.length_axis, roi.width_axis);
    roi.length = 0.8;
    roi.width = 0.5;
    const double sigma = 0.15;
    auto out = encoder.encode(gpu, anchors, sigma, roi);

    std::vector<uint32_t> expected;
    for (uint32_t i = 0; i < scene.cloud.size(); ++i) {
        glm::dvec3 rel = glm::dvec3(scene.cloud.mean[i]) - roi.centre;
        double l = std::abs(glm::dot(rel, roi.length_axis)), w = std::abs(glm::dot(rel, roi.width_axis));
        if (std::abs(l - roi.length / 2) < 1e-5 || std::abs(w - roi.width / 2) < 1e-5) continue;  // on the edge
        if (l <= roi.length / 2 && w <= roi.width / 2) expected.push_back(i);
    }
    REQUIRE(expected.size() > 100);
    REQUIRE(expected.size() < scene.cloud.size());  // the column cuts
    std::set<uint32_t> got(out.indices.begin(), out.indices.end());
    CHECK(std::is_sorted(out.indices.begin(), out.indices.end()));
    for (uint32_t i : expected) CHECK(got.count(i) == 1);
    CHECK(out.indices.size() <= expected.size() + 2);
    for (size_t k = 0; k < out.indices.size(); ++k) {
        glm::dvec3 mu(scene.cloud.mean[out.indices[k]]);
        double pos = 0, neg = 0;
        for (auto& a : anchors) {
            double v = std::exp(-glm::dot(mu - a.position, mu - a.position) / (2 * sigma * sigma));
            (a.positive ? pos : neg) = std::max(a.positive ? pos : neg, v);
        }
        CHECK(out.weights[k].x == Approx(pos).margin(1e-5));
        CHECK(out.weights[k].y == Approx(neg).margin(1e-5));
    }
}

namespace {
// A 64 x 48 camera at the origin looking down +z.
data::Camera front_camera() {
    data::Camera cam;
    cam.name = "front";
    cam.width = 64;
    cam.height = 48;
    cam.fx = cam.fy = 60;
    cam.cx = 32;
    cam.cy = 24;
    return cam;
}

// A wall at z = 2 of small Gaussians that cover a pixel to about 0.6 only, and behind it one
// large opaque Gaussian (the ground, last in the cloud) at depth `z`, `thickness` along the ray.
data::GaussianCloud wall_before_ground(float z, float thickness) {
    data::GaussianCloud cloud;
    for (int y = -8; y <= 8; ++y)
        for (int x = -8; x <= 8; ++x)
            ref::add_gaussian(cloud, glm::vec3(x * 0.05f, y * 0.05f, 2.0f), glm::vec3(std::log(0.03f), std::log(0.03f), -6.0f),
                              glm::vec4(1, 0, 0, 0), -1.2f, glm::vec3(0.0f));
    ref::add_gaussian(cloud, glm::vec3(0.0f, 0.0f, z), glm::vec3(std::log(2.0f), std::log(2.0f), std::log(thickness)),
                      glm::vec4(1, 0, 0, 0), 6.0f, glm::vec3(0.0f));
    return cloud;
}

// wall_before_ground on the device, seen by front_camera, and the CPU reference's pick at the
// pixel (33, 25) both lifting tests click.
struct WallBeforeGround {
    data::GaussianCloud cloud;
    int32_t ground;
    data::Camera cam = front_camera();
    render::GpuScene gpu;
    render::Renderer renderer;
    ref::RefPick want;
    WallBeforeGround(float z, float thickness)
        : cloud(wall_before_ground(z, thickness)), ground(int32_t(cloud.size()) - 1), gpu(test::gpu(), cloud),
          renderer(test::gpu()), want(ref::pick_reference(cloud, cam, 33, 25)) {}
    seg::Anchor lift(seg::LiftRule rule) { return seg::lift_click(renderer, gpu, cam, 33, 25, true, {}, rule, "click"); }
};

}  // namespace

TEST_CASE("click lifting: by the tau rule the anchor lies where opacity reaches tau, and bad clicks are named") {
    // An opaque wall of overlapping Gaussians at z = 2 in front of a camera at the origin.
    data::GaussianCloud cloud;
    for (int y = -20; y <= 20; ++y)
        for (int x = -20; x <= 20; ++x)
            ref::add_gaussian(cloud, glm::vec3(x * 0.05f, y * 0.05f, 2.0f), glm::vec3(std::log(0.04f), std::log(0.04f), -6.0f),
                              glm::vec4(1, 0, 0, 0), 6.0f, glm::vec3(0.0f));
    const data::Camera cam = front_camera();
    auto& ctx = test::gpu();
    render::GpuScene gpu(ctx, cloud);
    render::Renderer renderer(ctx);
    auto a = seg::lift_click(renderer, gpu, cam, 40, 10, true, {}, seg::LiftRule::Tau, "click 0");
    CHECK(a.position.z == Approx(2.0).margin(1e-4));
    // On the pixel's ray: x / z = (u + 0.5 - cx) / fx.
    CHECK(a.position.x / a.position.z == Approx((40.5 - 32) / 60.0).margin(1e-5));
    CHECK(a.position.y / a.position.z == Approx((10.5 - 24) / 60.0).margin(1e-5));
    CHECK(a.gaussian >= 0);
    try {
        seg::lift_click(renderer, gpu, cam, 64, 3, true, {}, seg::LiftRule::Tau, "prompts: click 7");
        FAIL("expected an error");
    } catch (const data::InputError& e) {
        CHECK(std::string(e.what()).find("click 7") != std::string::npos);
        CHECK(std::string(e.what()).find("off the") != std::string::npos);
    }
    // Looking away from the wall: opacity never reaches tau.
    data::Camera away = cam;
    away.R = glm::dmat3(-1, 0, 0, 0, 1, 0, 0, 0, -1);
    CHECK_THROWS_AS(seg::lift_click(renderer, gpu, away, 30, 20, true, {}, seg::LiftRule::Tau, "click"), data::InputError);
}

TEST_CASE("click lifting: a click on an object lifts onto it, though the ground behind its edge reaches tau") {
    // The object: a wall at z = 2 of small Gaussians that cover a pixel to about 0.6 only; the
    // ground: one large opaque Gaussian at z = 5 behind it, which completes the pixel.
    WallBeforeGround s(5.0f, 0.05f);
    const auto& want = s.want;
    INFO("opacity " << want.opacity << ", surface weight " << want.surface_weight << ", tau depth " << want.tau_depth);
    REQUIRE(want.opacity > 0.9f);
    REQUIRE(want.tau_id == s.ground);  // the wall alone never reaches tau here
    auto tau = s.lift(seg::LiftRule::Tau);
    CHECK(tau.gaussian == s.ground);
    CHECK(tau.position.z == Approx(5.0).margin(1e-3));
    auto surface = s.lift(seg::LiftRule::Surface);
    CHECK(surface.gaussian == want.surface_id);
    CHECK(surface.gaussian != s.ground);
    CHECK(surface.position.z == Approx(2.0).margin(1e-3));
    CHECK(surface.position.x / surface.position.z == Approx((33.5 - 32) / 60.0).margin(1e-5));
}

TEST_CASE("click lifting: a thin object that chains in depth into a large opaque Gaussian behind it keeps the click") {
    // The object: the same partly transparent wall at z = 2; right behind it, a large opaque
    // Gaussian 0.15 thick along the ray (a road under a car's body at a grazing view), near
    // enough that the two make one surface. That Gaussian alone outweighs each of the wall's, but
    // the wall holds most of the surface's weight: the surface's median, not its heaviest
    // Gaussian, stands for it.
    WallBeforeGround s(2.3f, 0.15f);
    const auto& want = s.want;
    INFO("opacity " << want.opacity << ", surface weight " << want.surface_weight << ", surface " << want.surface_id);
    REQUIRE(want.surface_weight > 0.9f);  // wall and ground are one surface
    CHECK(want.surface_id != s.ground);
    auto surface = s.lift(seg::LiftRule::Surface);
    CHECK(surface.gaussian == want.surface_id);
    CHECK(surface.gaussian != s.ground);
    CHECK(surface.position.z == Approx(2.0).margin(1e-3));
}

TEST_CASE("pixel picking matches the CPU reference: dominant surface, tau Gaussian, opacity") {
    auto scene = ref::random_scene(21, 3000, 1);
    auto& ctx = test::gpu();
    render::GpuScene gpu(ctx, scene.cloud);
    render::Renderer renderer(ctx);
    size_t picked = 0, same_surface = 0, same_tau = 0;
    for (size_t v = 0; v < 2; ++v) {
        const auto& cam = scene.cameras[v];
        renderer.render(gpu, cam, {});
        for (int y = 1; y < cam.height; y += 9)
            for (int x = 2; x < cam.width; x += 11) {
                const auto want = ref::pick_reference(scene.cloud, cam, x, y);
                const auto got = renderer.pick(x, y);
                CHECK(got.opacity == Approx(want.opacity).margin(1e-4));
                if (want.opacity < 0.05f) continue;
                ++picked;
                same_surface += got.surface_id == want.surface_id;
                same_tau += got.tau_id == want.tau_id;
                if (got.surface_id == want.surface_id) {
                    CHECK(got.surface_depth == Approx(want.surface_depth).margin(1e-4));
                    CHECK(got.surface_weight == Approx(want.surface_weight).margin(1e-3));
                }
                if (got.tau_id == want.tau_id) CHECK(got.tau == Approx(want.tau).margin(1e-4));
            }
    }
    INFO("picked " << picked << ", same surface " << same_surface << ", same tau Gaussian " << same_tau);
    REQUIRE(picked > 100);
    CHECK(double(same_surface) >= 0.98 * double(picked));
    CHECK(double(same_tau) >= 0.98 * double(picked));
    CHECK_THROWS_AS(renderer.pick(-1, 0), std::out_of_range);
}

TEST_CASE("pixel picking walks a tile of 300k Gaussians to its end like the CPU reference") {
    // One invocation walks the tile's list twice where tau is not reached: on lavapipe that
    // ran past its loop limit until the walks went window by window.
    const auto scene = ref::crowded_tile_scene(300000);
    const auto& cam = scene.cameras[0];
    auto& ctx = test::gpu();
    render::GpuScene gpu(ctx, scene.cloud);
    render::Renderer renderer(ctx);
    renderer.render(gpu, cam, {});
    REQUIRE(renderer.tile_windows() > 1);
    size_t picks = 0, same_surface = 0, same_tau = 0, second_walks = 0;
    for (int y = 8; y < 16; y += 3)
        for (int x = 8; x < 16; x += 3) {
            const auto want = ref::pick_reference(scene.cloud, cam, x, y);
            const auto got = renderer.pick(x, y);
            CAPTURE(x, y);
            // Each splat is faint (alpha <= 0.0045) and at the 1/255 cut: one may tip either way.
            CHECK(got.opacity == Approx(want.opacity).margin(5e-3));
            ++picks;
            same_surface += got.surface_id == want.surface_id;
            same_tau += got.tau_id == want.tau_id;
            second_walks += want.tau < 0.9f;
        }
    CHECK(same_surface >= picks - 1);
    CHECK(same_tau >= picks - 1);
    WARN("picks " << picks << ", of them below tau " << second_walks);
}

TEST_CASE("objects: a Gaussian claimed twice goes to the higher probability, removal reassigns it") {
    seg::SegmentResult r;
    seg::ObjectResult a, b;
    a.id = 1;
    a.claims = {{0, 0.9f}, {1, 0.6f}, {2, 0.7f}};
    b.id = 2;
    b.claims = {{1, 0.8f}, {2, 0.7f}, {3, 0.55f}};
    r.objects = {a, b};
    r.assemble(5);
    CHECK(r.labels == std::vector<int32_t>{1, 2, 1, 2, 0});  // ties go to the earlier object
    CHECK(r.objects[0].labelled == 2);
    CHECK(r.remove_object(1));
    CHECK(r.labels == std::vector<int32_t>{0, 2, 2, 2, 0});
    CHECK_FALSE(r.remove_object(9));
}

TEST_CASE("ground-truth decoder: foreground is the instance under the positive clicks") {
    seg::GroundTruthDecoder d({0, 3, 3, 5, 3, 0});
    seg::DecoderBatch batch;
    batch.gaussians = {0, 1, 2, 3, 4, 5};
    batch.features.assign(6, glm::vec2(0.0f));
    batch.click_gaussians = {2, 4, 3};
    CHECK(d.predict(batch) == std::vector<float>{0, 1, 1, 0, 1, 0});
    batch.click_gaussians = {0};  // a click on background with nothing labelled near it
    CHECK(d.predict(batch) == std::vector<float>(6, 0.0f));
    // The click's own Gaussian is background (a floater), but its neighbours are instance 5.
    batch.features[3] = glm::vec2(0.9f, 0.0f);
    CHECK(d.predict(batch) == std::vector<float>{0, 0, 0, 1, 0, 0});
}

TEST_CASE("segmenter: clicks in the same view give the same anchors whether or not the view is re-rendered") {
    auto scene = ref::random_scene(9, 4000, 0);
    std::vector<int32_t> labels(scene.cloud.size());
    for (size_t i = 0; i < labels.size(); ++i) labels[i] = int32_t(i % 3);
    auto& ctx = test::gpu();
    render::GpuScene gpu(ctx, scene.cloud);
    seg::GroundTruthDecoder decoder(labels);
    const auto& cam = scene.cameras[0];
    // Find two pixels that reach tau.
    render::Renderer probe(ctx);
    probe.render(gpu, cam, {});
    auto img = probe.read();
    std::vector<std::pair<int, int>> hits;
    for (int y = 0; y < img.height && hits.size() < 2; y += 7)
        for (int x = 0; x < img.width && hits.size() < 2; x += 5)
            if (img.tau_id[size_t(y) * img.width + x] >= 0) hits.push_back({x, y});
    REQUIRE(hits.size() == 2);
    data::Prompts p;
    p.objects.push_back({"a", 1, {{cam.name, double(hits[0].first), double(hits[0].second), std::nullopt, true},
                                  {cam.name, double(hits[1].first), double(hits[1].second), std::nullopt, false}}});
    seg::SegmentOptions o;
    o.scale = 0.5;
    o.lift = seg::LiftRule::Tau;  // the anchors' Gaussians are then the frame's tau ids
    seg::Segmenter twice(ctx, scene.cloud, gpu, scene.cameras, decoder);
    auto r1 = twice.segment(p, o);
    auto r2 = twice.segment(p, o);  // second run reuses the rendered view
    REQUIRE(r1.objects[0].anchors.size() == 2);
    for (size_t k = 0; k < 2; ++k) {
        CHECK(r1.objects[0].anchors[k].gaussian == img.tau_id[size_t(hits[k].second) * img.width + hits[k].first]);
        CHECK(r1.objects[0].anchors[k].gaussian == r2.objects[0].anchors[k].gaussian);
        CHECK(glm::length(r1.objects[0].anchors[k].position - r2.objects[0].anchors[k].position) == 0.0);
    }
    CHECK(r1.labels == r2.labels);
}

TEST_CASE("click lifting: a translucent surface lifts where opacity reaches tau x its final value") {
    // Two sparse translucent walls (z = 2 and z = 2.6): no pixel reaches tau = 0.9, many are clearly covered.
    data::GaussianCloud cloud;
    for (int layer = 0; layer < 2; ++layer)
        for (int y = -12; y <= 12; ++y)
            for (int x = -12; x <= 12; ++x)
                ref::add_gaussian(cloud, glm::vec3(x * 0.08f, y * 0.08f, 2.0f + 0.6f * float(layer)),
                                  glm::vec3(std::log(0.05f), std::log(0.05f), -6.0f), glm::vec4(1, 0, 0, 0),
                                  layer == 0 ? 0.0f : -0.5f, glm::vec3(0.0f));
    const data::Camera cam = front_camera();
    auto plain = ref::render_reference(cloud, cam);
    auto& ctx = test::gpu();
    render::GpuScene gpu(ctx, cloud);
    render::Renderer renderer(ctx);
    size_t fallbacks = 0;
    for (int py = 4; py < cam.height; py += 9)
        for (int px = 3; px < cam.width; px += 7) {
            const size_t at = size_t(py) * cam.width + px;
            const float alpha = plain.alpha[at];
            if (plain.tau_id[at] >= 0 || std::abs(alpha - seg::kMinLiftCoverage) < 0.02f) continue;
            if (alpha < seg::kMinLiftCoverage) {
                try {
                    seg::lift_click(renderer, gpu, cam, px, py, true, {}, seg::LiftRule::Tau, "click 3");
                    FAIL("expected an error");
                } catch (const data::InputError& e) {
                    CHECK(std::string(e.what()).find("nearly empty") != std::string::npos);
                    CHECK(std::string(e.what()).find("click 3") != std::string::npos);
                }
                continue;
            }
            // The reference: the depth where the ray's opacity reaches 0.9 x alpha.
            ref::RefOptions ro;
            ro.tau = 0.9f * alpha;
            auto want = ref::render_reference(cloud, cam, ro);
            auto a = seg::lift_click(renderer, gpu, cam, px, py, true, {}, seg::LiftRule::Tau, "click");
            CHECK(a.fallback);
            CHECK(a.coverage == Approx(alpha).margin(1e-4));
            CHECK(a.gaussian == want.tau_id[at]);
            CHECK(a.position.z == Approx(want.tau_depth[at]).margin(1e-4));
            ++fallbacks;
        }
    CHECK(fallbacks >= 5);
}

TEST_CASE("click lifting: the lift's own few-Gaussian scene picks what a frame of the whole scene picks") {
    // Scenes that test the host's bound on each footprint: random sizes, rotations and opacities,
    // Gaussians behind and straddling the near plane, degenerate and edge-on ones, and one large
    // enough to cover every pixel.
    auto& ctx = test::gpu();
    render::Renderer lift(ctx), whole(ctx);
    size_t lifted = 0, empty = 0;
    for (const auto& scene : {ref::random_scene(4242, 600, 3), ref::behind_camera_scene(), ref::near_plane_scene(),
                              ref::fullscreen_scene(), ref::degenerate_scales_scene(), ref::flat_2dgs_scene()}) {
        render::GpuScene gpu(ctx, scene.cloud);
        for (size_t c = 0; c < std::min<size_t>(1, scene.cameras.size()); ++c) {
            const data::Camera& cam = scene.cameras[c];
            for (int py = 1; py < cam.height; py += 21)
                for (int px = 2; px < cam.width; px += 27)
                    for (auto rule : {seg::LiftRule::Surface, seg::LiftRule::Tau}) {
                        render::RenderSettings s;
                        s.window = glm::ivec4(px, py, px + 1, py + 1);
                        s.lists_only = true;
                        whole.render(gpu, cam, s);
                        const render::PixelPick want = whole.pick(px, py);
                        if (!(want.opacity >= seg::kMinLiftCoverage)) {
                            CHECK_THROWS_AS(seg::lift_click(lift, gpu, cam, px, py, true, {}, rule, "click"), data::InputError);
                            ++empty;
                            continue;
                        }
                        const seg::Anchor a = seg::lift_click(lift, gpu, cam, px, py, true, {}, rule, "click");
                        // The lift's own scene is gone: its renderer has no frame to pick from.
                        if (lifted == 0) CHECK_THROWS_AS(lift.pick(px, py), std::logic_error);
                        CHECK(a.gaussian == (rule == seg::LiftRule::Surface ? want.surface_id : want.tau_id));
                        CHECK(a.fallback == (want.opacity < s.tau));
                        const double z = rule == seg::LiftRule::Surface ? want.surface_depth : want.tau_depth;
                        CHECK((cam.R * a.position + cam.t).z == Approx(z).margin(1e-5));
                        ++lifted;
                    }
        }
    }
    INFO(lifted << " lifted, " << empty << " empty");
    CHECK(lifted >= 200);
    CHECK(empty >= 20);
}
