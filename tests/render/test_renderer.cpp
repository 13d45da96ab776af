// The GPU splat renderer against the CPU reference (tests/reference/cpu_rasterizer.h).
#include <catch2/catch.hpp>

#include <algorithm>

#include "dataset/formats/scene_io.h"
#include "shaders/render/render_shared.h"
#include "tests/render/render_agreement.h"
#include "tests/test_paths.h"

using namespace pg;
using test::check_scene;
using test::compare;

TEST_CASE("GPU render matches the CPU reference on a random scene (SH degree 1)") { check_scene(ref::random_scene(1, 3000, 1)); }
TEST_CASE("GPU render matches the CPU reference with SH degree 3") { check_scene(ref::sh3_scene()); }
TEST_CASE("GPU render matches the CPU reference with SH degree 0") { check_scene(ref::sh0_scene()); }
TEST_CASE("Gaussians behind the camera are culled like the reference") { check_scene(ref::behind_camera_scene()); }
TEST_CASE("Gaussians across the near plane render like the reference") { check_scene(ref::near_plane_scene()); }
TEST_CASE("a Gaussian covering the whole screen renders like the reference") { check_scene(ref::fullscreen_scene()); }
TEST_CASE("degenerate scales render like the reference") { check_scene(ref::degenerate_scales_scene()); }
TEST_CASE("zero-opacity Gaussians contribute nothing, as in the reference") { check_scene(ref::zero_opacity_scene()); }
TEST_CASE("2DGS surfels render as flat Gaussians like the reference") { check_scene(ref::flat_2dgs_scene()); }
TEST_CASE("early termination at transmittance 1e-4 matches the reference") { check_scene(ref::dense_scene()); }

TEST_CASE("a tile of 300k Gaussians that never saturates renders like the reference, window by window") {
    // Lavapipe silently ends an invocation's loops after ~65 k iterations: one blend pass over
    // this tile's list drew garbage. Windows of kTileWindow keys pass the pixels on.
    const auto scene = ref::crowded_tile_scene(300000);
    const auto& cam = scene.cameras[0];
    const auto cpu = ref::render_reference(scene.cloud, cam, {});
    const auto deepest = *std::max_element(cpu.contributors.begin(), cpu.contributors.end());
    REQUIRE(deepest > 1000);  // deep and unsaturated: the whole list is walked
    auto& ctx = test::gpu();
    render::GpuScene gpu_scene(ctx, scene.cloud);
    render::Renderer renderer(ctx);
    for (int frame = 0; frame < 2; ++frame) {  // the second frame plans its windows from the first
        renderer.render(gpu_scene, cam, {});
        REQUIRE(renderer.key_count() > 4 * render::gpu::kTileWindow);  // all in one tile
        CHECK(renderer.tile_windows() == vk::ceil_div(renderer.key_count(), render::gpu::kTileWindow));
        const auto a = compare(renderer.read(), cpu);
        CHECK(a.rgb_psnr >= 45.0);
        CHECK(a.alpha_psnr >= 45.0);
        CHECK(a.contributors_match >= 0.99);
    }
}

TEST_CASE("the one-pixel and the column-of-four blends draw the same frames, bit for bit, as the reference does") {
    // Auto picks the column of four on CPU devices (these tests' lavapipe) and one pixel on GPUs;
    // each invocation's arithmetic is the same, so every output must be too. Frames not a
    // multiple of the tile, early termination, and a tile walked in windows (carried state).
    auto odd = ref::random_scene(21, 3000, 1);
    for (auto& c : odd.cameras) c = c.resized(c.width / 2 + 5, c.height / 2 + 3);
    const std::vector<ref::TestScene> scenes = {odd, ref::dense_scene(), ref::crowded_tile_scene(40000)};
    auto& ctx = test::gpu();
    render::Renderer renderer(ctx);
    for (const auto& scene : scenes) {
        render::GpuScene gpu_scene(ctx, scene.cloud);
        for (const auto& cam : scene.cameras) {
            render::RenderImages frames[2];
            const render::BlendKernel kernels[2] = {render::BlendKernel::Pixel, render::BlendKernel::Column};
            for (int k = 0; k < 2; ++k) {
                render::RenderSettings s;
                s.blend_kernel = kernels[k];
                renderer.render(gpu_scene, cam, s);
                frames[k] = renderer.read();
            }
            INFO("camera " << cam.name << " " << cam.width << "x" << cam.height << ", " << renderer.tile_windows()
                           << " windows");
            const auto a = compare(frames[1], ref::render_reference(scene.cloud, cam, {}));
            CHECK(a.rgb_psnr >= 45.0);
            CHECK(a.contributors_match >= 0.99);
            CHECK(frames[0].rgba == frames[1].rgba);
            CHECK(frames[0].depth == frames[1].depth);
            CHECK(frames[0].tau_depth == frames[1].tau_depth);
            CHECK(frames[0].tau_id == frames[1].tau_id);
            CHECK(frames[0].contributors == frames[1].contributors);
        }
    }
}

TEST_CASE("background colour, tau, antialiasing and an SH cap follow the settings") {
    render::RenderSettings s;
    s.background = {0.2f, 0.5f, 0.9f};
    s.tau = 0.5f;
    s.antialiased = true;
    s.max_sh_degree = 1;
    check_scene(ref::random_scene(7, 1500, 3), s);
}

TEST_CASE("a resized render scales the intrinsics like the reference") {
    auto scene = ref::random_scene(3, 1000, 0);
    for (auto& c : scene.cameras) c = c.resized(c.width / 2 + 3, c.height / 2 + 5);
    check_scene(scene);
}

TEST_CASE("key overflow grows the buffers and renders the frame again") {
    // Few Gaussians, each covering every tile: far more keys than the initial guess.
    ref::TestScene scene = ref::fullscreen_scene();
    ref::Rng rng(5);
    auto base = scene.cloud.mean[0];
    for (int k = 0; k < 400; ++k)
        ref::add_gaussian(scene.cloud, base + glm::vec3(rng.uniform(-0.1f, 0.1f), rng.uniform(-0.1f, 0.1f), rng.uniform(0.0f, 2.0f)),
                          glm::vec3(3.0f), rng.rotation(), -4.0f, glm::vec3(rng.uniform(), rng.uniform(), rng.uniform()));
    auto& ctx = test::gpu();
    render::GpuScene gpu_scene(ctx, scene.cloud);
    render::Renderer renderer(ctx);
    const auto& cam = scene.cameras[0];
    renderer.render(gpu_scene, cam, {});
    CHECK(renderer.retries() >= 1);
    auto a = compare(renderer.read(), ref::render_reference(scene.cloud, cam, {}));
    CHECK(a.rgb_psnr >= 45.0);
}

TEST_CASE("the real guitar scene renders like the reference (needs ../shared)") {
    auto path = test::shared_dir() / "data/real/guitar.ply";
    if (!std::filesystem::exists(path)) {
        WARN("skipped: " << path << " is absent (it is not part of a user's clone)");
        return;
    }
    auto cloud = data::load_scene(path);
    // A camera 2.5 units from the guitar's centre, looking along +z, y down (the scene is y-down).
    data::Camera cam;
    cam.name = "guitar_front";
    cam.width = 200;
    cam.height = 240;
    cam.fx = cam.fy = 260;
    cam.cx = 100;
    cam.cy = 120;
    glm::dvec3 centre(0.08, -2.1, 0.2);
    cam.R = glm::dmat3(1.0);
    cam.t = -(centre - glm::dvec3(0, 0, 3.2));
    auto& ctx = test::gpu();
    render::GpuScene gpu_scene(ctx, cloud);
    render::Renderer renderer(ctx);
    renderer.render(gpu_scene, cam, {});
    auto gpu = renderer.read();
    auto cpu = ref::render_reference(cloud, cam, {});
    auto a = compare(gpu, cpu);
    INFO("rgb " << a.rgb_psnr << " dB, alpha " << a.alpha_psnr << " dB");
    CHECK(a.rgb_psnr >= 45.0);
    CHECK(a.alpha_psnr >= 45.0);
    // The guitar fills a good part of the frame.
    size_t covered = 0;
    for (size_t p = 0; p < gpu.tau_id.size(); ++p) covered += gpu.rgba[p * 4 + 3] > 0.5f;
    CHECK(covered > gpu.tau_id.size() / 10);
}

TEST_CASE("a windowed frame draws its pixels exactly as the whole frame does, from fewer tile keys") {
    // A window inside one tile takes the depth-keyed path (no sort of all Gaussians); the others
    // the two sorts of a whole frame.
    // What a click's lift renders: only the Gaussians that reach the window, so its pixels and
    // its pick must be the whole frame's, bit for bit.
    auto scene = ref::random_scene(11, 3000, 2);
    const auto& cam = scene.cameras[0];
    auto& ctx = test::gpu();
    render::GpuScene gpu_scene(ctx, scene.cloud);
    render::Renderer renderer(ctx);
    renderer.render(gpu_scene, cam, {});
    const auto full = renderer.read();
    const uint32_t full_keys = renderer.key_count();
    const int w = cam.width, h = cam.height;
    const std::vector<glm::ivec4> windows = {{w / 2, h / 2, w / 2 + 1, h / 2 + 1}, {0, 0, 1, 1}, {w - 1, h - 1, w, h},
                                             {w / 3, h / 4, w / 3 + 21, h / 4 + 13}, {-5, -5, 3, 2}};
    for (const auto& win : windows) {
        INFO("window " << win.x << "," << win.y << " - " << win.z << "," << win.w);
        render::RenderSettings s;
        s.window = win;
        renderer.render(gpu_scene, cam, s);
        CHECK(renderer.key_count() < full_keys / 4);
        const auto part = renderer.read();
        size_t differing = 0, pixels = 0;
        for (int y = std::max(0, win.y); y < std::min(h, win.w); ++y)
            for (int x = std::max(0, win.x); x < std::min(w, win.z); ++x) {
                const size_t p = size_t(y) * w + x;
                ++pixels;
                bool same = full.depth[p] == part.depth[p] && full.tau_depth[p] == part.tau_depth[p] &&
                            full.tau_id[p] == part.tau_id[p] && full.contributors[p] == part.contributors[p];
                for (int c = 0; c < 4; ++c) same = same && full.rgba[p * 4 + c] == part.rgba[p * 4 + c];
                differing += same ? 0 : 1;
            }
        CHECK(pixels > 0);
        CHECK(differing == 0);
        const int px = std::max(0, win.x), py = std::max(0, win.y);
        const auto windowed = renderer.pick(px, py);
        s.lists_only = true;  // as a lift renders: the tile lists alone, no blend
        renderer.render(gpu_scene, cam, s);
        const auto listed = renderer.pick(px, py);
        renderer.render(gpu_scene, cam, {});
        const auto whole = renderer.pick(px, py);
        for (const auto& got : {windowed, listed}) {
            CHECK(got.surface_id == whole.surface_id);
            CHECK(got.tau_id == whole.tau_id);
            CHECK(got.surface_depth == whole.surface_depth);
            CHECK(got.tau_depth == whole.tau_depth);
            CHECK(got.opacity == whole.opacity);
        }
    }
}
