// The GPU label rasterizer against the CPU reference (tests/reference/label_raster_ref.h),
// plus hand-made cases whose answer is known without either.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "engine/render/renderer.h"
#include "engine/segment/label_raster.h"
#include "tests/gpu_fixture.h"
#include "tests/reference/label_raster_ref.h"
#include "tests/reference/test_scenes.h"

using namespace pg;

namespace {

ref::LabelMode ref_mode(seg::LabelMode m) {
    return m == seg::LabelMode::Paper ? ref::LabelMode::Paper : ref::LabelMode::Occlusion;
}

// `fraction` of the Gaussians get a label in 1..classes, the rest 0.
std::vector<uint32_t> random_labels(size_t n, float fraction, uint32_t classes, uint64_t seed) {
    ref::Rng rng(seed);
    std::vector<uint32_t> labels(n);
    for (auto& l : labels) {
        const bool labelled = fraction >= 1.0f || rng.uniform() < fraction;
        l = labelled ? 1 + rng.below(classes) : 0;
    }
    return labels;
}

// GPU and CPU label images agree on at least 99.9% of the pixels of every camera, label
// density and mode. The remaining pixels, if any, sit on a threshold that the GPU's exp()
// and log() (a few ulp off std::exp/log, and fused multiply-adds in the projection) can
// tip: alpha at 1/255, T at 1e-4, 1 - T at 0.5, two labels' weights within rounding, a
// tile-test or rho^2 = 4 px^2 boundary.
void check_scene(const ref::TestScene& scene, uint64_t seed) {
    auto& ctx = test::gpu();
    render::GpuScene gpu_scene(ctx, scene.cloud);
    render::Renderer renderer(ctx);
    seg::LabelRasterizer raster(ctx);
    struct Density {
        float fraction;
        uint32_t classes;
    };
    // 100% labelled with 12 classes overflows the 8 slots on deep pixels.
    const Density densities[] = {{0.1f, 3}, {0.5f, 5}, {1.0f, 12}};
    std::vector<std::vector<uint32_t>> labels;
    std::vector<vk::Buffer> buffers;
    for (const Density& d : densities) {
        labels.push_back(random_labels(scene.cloud.size(), d.fraction, d.classes, seed++));
        buffers.push_back(vk::upload_vector(ctx, labels.back(), "labels"));
    }
    size_t labelled_pixels[2] = {0, 0}, overflow_pixels = 0, differing = 0, total = 0;
    for (const auto& cam : scene.cameras) {
        renderer.render(gpu_scene, cam, {});
        for (size_t k = 0; k < labels.size(); ++k) {
            for (seg::LabelMode mode : {seg::LabelMode::Paper, seg::LabelMode::Occlusion}) {
                auto gpu = raster.rasterize_and_read(renderer, buffers[k], mode);
                ref::LabelStats stats;
                auto cpu = ref::label_reference(scene.cloud, cam, labels[k], ref_mode(mode), {}, &stats);
                REQUIRE(gpu.size() == cpu.size());
                size_t same = 0, labelled = 0;
                std::ostringstream diffs;
                for (size_t p = 0; p < gpu.size(); ++p) {
                    same += gpu[p] == cpu[p];
                    labelled += cpu[p] != 0;
                    if (gpu[p] != cpu[p] && diffs.tellp() < 400)
                        diffs << " (" << p % cam.width << "," << p / cam.width << "): gpu " << gpu[p] << " cpu "
                              << cpu[p];
                }
                labelled_pixels[mode == seg::LabelMode::Paper ? 0 : 1] += labelled;
                overflow_pixels += stats.overflow_pixels;
                differing += gpu.size() - same;
                total += gpu.size();
                const double agreement = double(same) / double(gpu.size());
                INFO("camera " << cam.name << ", " << seg::label_mode_name(mode) << ", "
                               << densities[k].fraction * 100 << "% labelled: agreement " << agreement << ", "
                               << labelled << " labelled pixels;" << diffs.str());
                CHECK(agreement >= 0.999);
            }
        }
    }
    // Not vacuous: both modes produced labels somewhere.
    CHECK(labelled_pixels[0] > 0);
    CHECK(labelled_pixels[1] > 0);
    WARN("labelled pixels: paper " << labelled_pixels[0] << ", occlusion " << labelled_pixels[1]
                                   << "; pixels past 8 labels " << overflow_pixels << "; GPU != CPU on " << differing
                                   << " of " << total << " pixels");
}

// Frontal camera at (0, 0, -3) looking down +z with R = identity: a world point (x, y, z)
// lands at pixel coordinates (100 x / (z + 3) + 32, 100 y / (z + 3) + 24).
data::Camera hand_camera() {
    return ref::look_at_camera("hand", glm::dvec3(0, 0, -3), glm::dvec3(0.0), glm::dvec3(0, -1, 0), 64, 48, 100, 100,
                               32, 24);
}

// The world point at world z (view z = z + 3) that projects to pixel coordinates (u, v).
glm::vec3 at_pixel(float u, float v, float z) { return {(u - 32.0f) * (z + 3.0f) / 100.0f, (v - 24.0f) * (z + 3.0f) / 100.0f, z}; }

struct HandResult {
    std::vector<uint32_t> paper, occlusion;
    uint32_t paper_at(int x, int y) const { return paper[size_t(y) * 64 + x]; }
    uint32_t occlusion_at(int x, int y) const { return occlusion[size_t(y) * 64 + x]; }
};

// Renders a hand-made cloud, rasterizes both modes and checks them against the reference too.
HandResult run_hand(const data::GaussianCloud& cloud, const std::vector<uint32_t>& labels) {
    auto& ctx = test::gpu();
    render::GpuScene gpu_scene(ctx, cloud);
    render::Renderer renderer(ctx);
    seg::LabelRasterizer raster(ctx);
    const auto cam = hand_camera();
    renderer.render(gpu_scene, cam, {});
    auto buffer = vk::upload_vector(ctx, labels, "labels");
    HandResult r{raster.rasterize_and_read(renderer, buffer, seg::LabelMode::Paper),
                 raster.rasterize_and_read(renderer, buffer, seg::LabelMode::Occlusion)};
    CHECK(r.paper == ref::label_reference(cloud, cam, labels, ref::LabelMode::Paper));
    CHECK(r.occlusion == ref::label_reference(cloud, cam, labels, ref::LabelMode::Occlusion));
    return r;
}

const glm::vec4 kIdentity(1, 0, 0, 0);
const glm::vec3 kGrey = ref::dc_from_rgb({0.5f, 0.5f, 0.5f});

}  // namespace

TEST_CASE("label raster matches the reference on a random scene") { check_scene(ref::random_scene(11, 2000, 1), 100); }
TEST_CASE("label raster matches the reference with SH degree 0") { check_scene(ref::sh0_scene(), 200); }
TEST_CASE("label raster matches the reference on a dense scene") { check_scene(ref::dense_scene(), 300); }
TEST_CASE("label raster matches the reference with a full-screen Gaussian") { check_scene(ref::fullscreen_scene(), 400); }
TEST_CASE("label raster matches the reference on flat 2DGS surfels") { check_scene(ref::flat_2dgs_scene(), 500); }
TEST_CASE("label raster matches the reference with degenerate scales") { check_scene(ref::degenerate_scales_scene(), 600); }

TEST_CASE("label raster walks a tile of 200k Gaussians window by window like the reference") {
    check_scene(ref::crowded_tile_scene(200000), 700);
}

TEST_CASE("label raster of a streamed tile of 200k Gaussians: windows inside slabs, as the resident frame") {
    const auto scene = ref::crowded_tile_scene(200000);
    const auto& cam = scene.cameras[0];
    auto& ctx = test::gpu();
    render::SceneBudget budget;
    budget.max_binding_bytes = uint64_t(70000) * 48;  // slabs of about 70 k Gaussians
    render::GpuScene resident(ctx, scene.cloud), streamed(ctx, scene.cloud, budget);
    REQUIRE(streamed.streamed());
    const auto labels = random_labels(scene.cloud.size(), 0.9f, 3, 800);
    const auto buffer = vk::upload_vector(ctx, labels, "labels");
    render::Renderer a(ctx), b(ctx);
    seg::LabelRasterizer ra(ctx), rb(ctx);
    a.render(resident, cam, {});
    REQUIRE(a.tile_windows() > 1);
    for (seg::LabelMode mode : {seg::LabelMode::Paper, seg::LabelMode::Occlusion}) {
        const auto want = ra.rasterize_and_read(a, buffer, mode);
        vk::Buffer image;
        vk::CommandList cmd(ctx);
        uint32_t most_windows = 0;  // a slab is recorded again when it needs more windows than planned
        b.render(streamed, cam, {}, nullptr, [&](vk::CommandList& c, const render::SlabPass& slab) {
            most_windows = std::max(most_windows, slab.windows);
            rb.rasterize_slab(c, b, slab, buffer, image, mode);
        });
        CHECK(b.slabs() >= 3);
        CHECK(most_windows > 1);
        CHECK(vk::download_vector<uint32_t>(ctx, image, want.size()) == want);
        CHECK(std::count(want.begin(), want.end(), 0u) < long(want.size()) - 48);  // most of the 8x8 crowd
    }
}

TEST_CASE("the one-pixel and the column occlusion label passes give the same images, bit for bit, as the reference does") {
    // The renderer's blend kernel picks the label pass's (a column of two on CPU devices, one
    // pixel on GPUs). Frames not a multiple of the tile, early termination, more labels than
    // slots, and a tile walked in windows (carried state).
    auto odd = ref::random_scene(23, 2000, 1);
    for (auto& c : odd.cameras) c = c.resized(c.width / 2 + 5, c.height / 2 + 3);
    const std::vector<ref::TestScene> scenes = {odd, ref::dense_scene(), ref::crowded_tile_scene(40000)};
    auto& ctx = test::gpu();
    render::Renderer renderer(ctx);
    seg::LabelRasterizer raster(ctx);
    uint64_t seed = 900;
    for (const auto& scene : scenes) {
        render::GpuScene gpu_scene(ctx, scene.cloud);
        const auto labels = random_labels(scene.cloud.size(), 1.0f, 12, seed++);
        const auto buffer = vk::upload_vector(ctx, labels, "labels");
        for (const auto& cam : scene.cameras) {
            std::vector<uint32_t> images[2];
            const render::BlendKernel kernels[2] = {render::BlendKernel::Pixel, render::BlendKernel::Column};
            for (int k = 0; k < 2; ++k) {
                render::RenderSettings s;
                s.blend_kernel = kernels[k];
                renderer.render(gpu_scene, cam, s);
                REQUIRE(renderer.blend_kernel() == kernels[k]);
                images[k] = raster.rasterize_and_read(renderer, buffer, seg::LabelMode::Occlusion);
            }
            const auto cpu = ref::label_reference(scene.cloud, cam, labels, ref::LabelMode::Occlusion);
            size_t same = 0, labelled = 0;
            for (size_t p = 0; p < cpu.size(); ++p) {
                same += images[1][p] == cpu[p];
                labelled += cpu[p] != 0;
            }
            INFO("camera " << cam.name << " " << cam.width << "x" << cam.height << ", " << renderer.tile_windows()
                           << " windows, " << labelled << " labelled pixels");
            CHECK(labelled > 0);
            CHECK(double(same) / double(cpu.size()) >= 0.999);
            CHECK(images[0] == images[1]);
        }
    }
}

TEST_CASE("paper mode takes a labelled centre behind an opaque unlabelled Gaussian, occlusion mode hides it") {
    data::GaussianCloud cloud;
    cloud.sh_degree = 0;
    // In front: a wide, opaque, unlabelled Gaussian centred on pixel (31, 23).
    ref::add_gaussian(cloud, at_pixel(31.5f, 23.5f, 0.0f), glm::vec3(std::log(0.1f)), kIdentity, 8.0f, kGrey);
    // Behind it: a small labelled one, its centre 0.3 px right of pixel (31, 23)'s centre.
    ref::add_gaussian(cloud, at_pixel(31.8f, 23.5f, 1.0f), glm::vec3(std::log(0.02f)), kIdentity, 8.0f, kGrey);
    auto r = run_hand(cloud, {0, 7});
    CHECK(r.paper_at(31, 23) == 7);
    CHECK(r.paper_at(33, 23) == 7);  // 1.7 px from the centre
    CHECK(r.paper_at(34, 23) == 0);  // 2.7 px
    CHECK(r.paper_at(31, 21) == 0);  // 2 px up, 0.3 px across: rho^2 = 4.09
    CHECK(r.occlusion_at(31, 23) == 0);
    CHECK(r.occlusion_at(33, 23) == 0);
}

TEST_CASE("occlusion mode labels the footprint of an opaque labelled Gaussian in front") {
    data::GaussianCloud cloud;
    cloud.sh_degree = 0;
    ref::add_gaussian(cloud, at_pixel(31.5f, 23.5f, 0.0f), glm::vec3(std::log(0.1f)), kIdentity, 8.0f, kGrey);
    ref::add_gaussian(cloud, at_pixel(31.8f, 23.5f, 1.0f), glm::vec3(std::log(0.02f)), kIdentity, 8.0f, kGrey);
    auto r = run_hand(cloud, {4, 0});
    // sigma^2 = (100 * 0.1 / 3)^2 + 0.3 = 11.4 px^2: alpha = 0.99 exp(-d^2 / 22.8) is 0.67 at
    // d = 3 px and 0.2 < 0.5 at d = 6 px.
    CHECK(r.occlusion_at(31, 23) == 4);
    CHECK(r.occlusion_at(34, 23) == 4);
    CHECK(r.occlusion_at(37, 23) == 0);
    CHECK(r.paper_at(31, 23) == 4);
    CHECK(r.paper_at(34, 23) == 0);  // 3 px: too far for the paper's rule, however opaque
}

TEST_CASE("paper mode gives 0 to a pixel 2.1 px from the only centre") {
    data::GaussianCloud cloud;
    cloud.sh_degree = 0;
    // Centre at (31.4, 23.5), in tile column 1; pixel (33, 23) of tile column 2 is 2.1 px away.
    ref::add_gaussian(cloud, at_pixel(31.4f, 23.5f, 0.0f), glm::vec3(std::log(0.1f)), kIdentity, 8.0f, kGrey);
    auto r = run_hand(cloud, {5});
    CHECK(r.paper_at(33, 23) == 0);   // rho^2 = 4.41
    CHECK(r.paper_at(32, 23) == 5);   // 1.1 px, across the tile border
    CHECK(r.paper_at(29, 23) == 5);   // 1.9 px
    CHECK(r.paper_at(28, 23) == 0);   // 2.9 px
    CHECK(r.paper_at(31, 21) == 0);   // rho^2 = 0.1^2 + 2^2 = 4.01
    CHECK(r.occlusion_at(33, 23) == 5);  // well inside the opaque footprint
}

TEST_CASE("all-unlabelled Gaussians give an all-zero label image") {
    auto& ctx = test::gpu();
    auto scene = ref::random_scene(21, 1500, 1);
    render::GpuScene gpu_scene(ctx, scene.cloud);
    render::Renderer renderer(ctx);
    seg::LabelRasterizer raster(ctx);
    auto zeros = vk::upload_vector(ctx, std::vector<uint32_t>(scene.cloud.size(), 0u), "labels");
    for (const auto& cam : scene.cameras) {
        renderer.render(gpu_scene, cam, {});
        for (seg::LabelMode mode : {seg::LabelMode::Paper, seg::LabelMode::Occlusion}) {
            auto img = raster.rasterize_and_read(renderer, zeros, mode);
            REQUIRE(img.size() == size_t(cam.width) * cam.height);
            CHECK(std::all_of(img.begin(), img.end(), [](uint32_t l) { return l == 0; }));
        }
    }
}

TEST_CASE("occlusion mode keeps 8 labels per pixel and drops the weight of an evicted one") {
    // A stack on pixel (31, 23), front to back, alpha ~ opacity at the centre:
    //   label 9 (0.02) -> w 0.02;  label 1 (0.3) -> 0.294;  labels 2..7 (0.05) -> 0.034 .. 0.027;
    //   label 8 (0.05) -> 0.025 meets 8 full slots and evicts the weakest, label 9;
    //   label 9 (0.6) -> 0.287, re-entering from zero.
    // Label 1 wins with 0.294 > 0.287; with unbounded slots label 9 would have 0.307.
    data::GaussianCloud cloud;
    cloud.sh_degree = 0;
    std::vector<uint32_t> labels;
    auto add = [&](uint32_t label, float opacity) {
        const float z = 0.1f * float(labels.size());
        ref::add_gaussian(cloud, at_pixel(31.5f, 23.5f, z), glm::vec3(std::log(0.03f)), kIdentity,
                          std::log(opacity / (1.0f - opacity)), kGrey);
        labels.push_back(label);
    };
    add(9, 0.02f);
    add(1, 0.3f);
    for (uint32_t l = 2; l <= 8; ++l) add(l, 0.05f);
    add(9, 0.6f);
    ref::LabelStats stats;
    ref::label_reference(cloud, hand_camera(), labels, ref::LabelMode::Occlusion, {}, &stats);
    CHECK(stats.overflow_pixels > 0);
    auto r = run_hand(cloud, labels);  // GPU == reference, pixel for pixel
    CHECK(r.occlusion_at(31, 23) == 1);
    CHECK(r.paper_at(31, 23) == 9);  // the first labelled centre
}

TEST_CASE("label passes record into the caller's command list without waiting") {
    auto& ctx = test::gpu();
    auto scene = ref::random_scene(31, 1200, 0);
    render::GpuScene gpu_scene(ctx, scene.cloud);
    render::Renderer renderer(ctx);
    seg::LabelRasterizer raster(ctx);
    const auto& cam = scene.cameras[0];
    renderer.render(gpu_scene, cam, {});
    auto labels = random_labels(scene.cloud.size(), 0.5f, 4, 77);
    auto buffer = vk::upload_vector(ctx, labels, "labels");
    vk::CommandList cmd(ctx);
    vk::Buffer paper, occlusion;  // created by rasterize()
    raster.rasterize(cmd, renderer, buffer, paper, seg::LabelMode::Paper);
    raster.rasterize(cmd, renderer, buffer, occlusion, seg::LabelMode::Occlusion);
    cmd.submit_and_wait();
    const size_t pixels = size_t(cam.width) * cam.height;
    CHECK(vk::download_vector<uint32_t>(ctx, paper, pixels) == raster.rasterize_and_read(renderer, buffer, seg::LabelMode::Paper));
    CHECK(vk::download_vector<uint32_t>(ctx, occlusion, pixels) ==
          raster.rasterize_and_read(renderer, buffer, seg::LabelMode::Occlusion));
    CHECK(seg::parse_label_mode("paper") == seg::LabelMode::Paper);
    CHECK(seg::parse_label_mode("occlusion") == seg::LabelMode::Occlusion);
    CHECK_THROWS_AS(seg::parse_label_mode("nearest"), std::invalid_argument);
    render::Renderer fresh(ctx);
    CHECK_THROWS_AS(raster.rasterize(cmd, fresh, buffer, paper, seg::LabelMode::Paper), std::logic_error);
}
