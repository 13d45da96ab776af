// The viewer's picture passes against CPU references: the overlay byte for byte against the
// CPU overlay of exported pictures (hidden objects and borders included), the object under
// each pixel against the render's tau ids.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <tuple>
#include <vector>

#include "engine/segment/mask_views.h"
#include "engine/segment/picture_passes.h"
#include "engine/vk/buffer.h"
#include "engine/vk/commands.h"
#include "tests/gpu_fixture.h"
#include "tests/reference/test_scenes.h"

using namespace pg;

namespace {

struct Case {
    int w = 0, h = 0;
    std::vector<float> render;      // rgba per pixel
    std::vector<uint32_t> labels;   // per pixel
    std::vector<glm::vec4> palette; // rgb, a < 0: hidden
};

// The reference: what the viewer drew before the overlay moved to the GPU (hidden objects
// and labels past the palette unlabelled, then ViewMask::overlay), as RGBA8.
std::vector<uint32_t> reference(const Case& c, bool with_labels) {
    seg::ViewMask m;
    m.width = c.w;
    m.height = c.h;
    m.rgba = c.render;
    m.labels.assign(c.labels.size(), 0);
    if (with_labels)
        for (size_t p = 0; p < c.labels.size(); ++p) {
            const uint32_t l = c.labels[p];
            m.labels[p] = l < c.palette.size() && c.palette[l].a >= 0 ? l : 0;
        }
    const auto rgb = m.overlay([&](uint32_t l) { return glm::vec3(c.palette[l]); });
    std::vector<uint32_t> out(c.labels.size());
    for (size_t p = 0; p < out.size(); ++p)
        out[p] = rgb[3 * p] | uint32_t(rgb[3 * p + 1]) << 8 | uint32_t(rgb[3 * p + 2]) << 16 | 255u << 24;
    return out;
}

std::vector<uint32_t> gpu_overlay(const Case& c, bool with_labels) {
    auto& ctx = test::gpu();
    auto render = vk::upload_vector(ctx, c.render, "render");
    auto labels = vk::upload_vector(ctx, c.labels, "labels");
    auto palette = vk::upload_vector(ctx, c.palette, "palette");
    vk::Buffer picture(ctx, 4, vk::MemoryUse::Device, "picture");
    seg::PicturePasses passes(ctx);
    vk::CommandList cmd(ctx);
    passes.overlay(cmd, render, with_labels ? &labels : nullptr, with_labels ? &palette : nullptr,
                uint32_t(c.palette.size()), c.w, c.h, picture);
    cmd.submit_and_wait();
    return vk::download_vector<uint32_t>(ctx, picture, c.labels.size());
}

// Blobs of labels 1..6 on background (interiors and borders), colours over and under [0, 1]
// and on the rounding boundaries (k + 0.5) / 255.
Case random_case(int w, int h, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> colour(-0.2f, 1.2f);
    Case c{w, h, {}, std::vector<uint32_t>(size_t(w) * h, 0), {}};
    for (int i = 0; i < w * h; ++i) {
        for (int k = 0; k < 3; ++k) {
            float v = colour(rng);
            if (rng() % 4 == 0) {
                const float edge = (float(rng() % 255) + 0.5f) / 255.0f;
                v = std::nextafter(edge, rng() % 2 ? 2.0f : -1.0f);
                if (rng() % 3 == 0) v = edge;
            }
            c.render.push_back(v);
        }
        c.render.push_back(1.0f);
    }
    for (int blob = 0; blob < 12; ++blob) {
        const int cx = int(rng() % uint32_t(w)), cy = int(rng() % uint32_t(h)), r = 2 + int(rng() % 6);
        const uint32_t l = 1 + uint32_t(blob % 6);
        for (int y = std::max(0, cy - r); y < std::min(h, cy + r); ++y)
            for (int x = std::max(0, cx - r); x < std::min(w, cx + r); ++x) c.labels[size_t(y) * w + x] = l;
    }
    // Label 6 lies past the palette; label 3 is hidden.
    c.palette = {{0, 0, 0, 0}, {1, 0, 0, 0}, {0.2f, 0.7f, 0.1f, 0.5f}, {0, 0, 1, -1}, {0.33f, 0.66f, 0.99f, 0}, {1, 1, 0, 0}};
    return c;
}

}  // namespace

TEST_CASE("picture passes: the GPU overlay equals the CPU overlay byte for byte", "[segment]") {
    for (auto [w, h, seed] : {std::tuple{37, 23, 1u}, {64, 48, 2u}, {131, 70, 3u}}) {
        INFO(w << "x" << h);
        const Case c = random_case(w, h, seed);
        const auto want = reference(c, true);
        const auto got = gpu_overlay(c, true);
        size_t differ = 0;
        for (size_t p = 0; p < want.size(); ++p) differ += want[p] != got[p];
        CHECK(differ == 0);
        // The case reaches every branch: borders, interiors, hidden and unknown labels.
        CHECK(std::count(c.labels.begin(), c.labels.end(), 3u) > 0);
        CHECK(std::count(c.labels.begin(), c.labels.end(), 6u) > 0);
    }
}

TEST_CASE("picture passes: without labels the picture is the render, clamped and rounded", "[segment]") {
    const Case c = random_case(50, 30, 7);
    CHECK(gpu_overlay(c, false) == reference(c, false));
}

TEST_CASE("picture passes: each pixel names the object whose Gaussian made it opaque", "[segment]") {
    auto scene = ref::random_scene(3, 3000, 0);
    auto& ctx = test::gpu();
    render::GpuScene gpu(ctx, scene.cloud);
    render::Renderer renderer(ctx);
    renderer.render(gpu, scene.cameras[0], {});
    const auto tau_id = renderer.read().tau_id;
    std::vector<int32_t> labels(scene.cloud.size());
    for (size_t i = 0; i < labels.size(); ++i) labels[i] = int32_t(i % 5);  // 0: unlabelled
    auto labels_gpu = vk::upload_vector(ctx, labels, "labels");
    vk::Buffer objects(ctx, 4, vk::MemoryUse::Device, "objects");
    seg::PicturePasses passes(ctx);
    vk::CommandList cmd(ctx);
    passes.objects(cmd, renderer, labels_gpu, objects);
    cmd.submit_and_wait();
    const auto got = vk::download_vector<int32_t>(ctx, objects, tau_id.size());
    std::vector<int32_t> want(tau_id.size());
    size_t hit = 0;
    for (size_t p = 0; p < want.size(); ++p) {
        want[p] = tau_id[p] >= 0 ? labels[size_t(tau_id[p])] : 0;
        hit += tau_id[p] >= 0;
    }
    CHECK(hit > want.size() / 10);
    CHECK(got == want);
}
