#pragma once
// How closely a GPU frame matches the CPU reference, and the per-scene check built on it:
// shared by the renderer tests with and without a style.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "engine/render/renderer.h"
#include "engine/vk/buffer.h"
#include "tests/gpu_fixture.h"
#include "tests/reference/cpu_rasterizer.h"
#include "tests/reference/test_scenes.h"

namespace pg::test {

struct Agreement {
    double rgb_psnr, alpha_psnr, depth_psnr;
    double tau_id_match, contributors_match;
};

inline Agreement compare(const render::RenderImages& gpu, const ref::RefImage& cpu) {
    const size_t pixels = size_t(gpu.width) * size_t(gpu.height);
    std::vector<float> rgb(pixels * 3), alpha(pixels);
    for (size_t p = 0; p < pixels; ++p) {
        for (int c = 0; c < 3; ++c) rgb[p * 3 + c] = gpu.rgba[p * 4 + c];
        alpha[p] = gpu.rgba[p * 4 + 3];
    }
    float max_depth = 1e-6f;
    for (float d : cpu.depth) max_depth = std::max(max_depth, d);
    size_t id_same = 0, contrib_same = 0;
    for (size_t p = 0; p < pixels; ++p) {
        id_same += gpu.tau_id[p] == cpu.tau_id[p];
        contrib_same += gpu.contributors[p] == cpu.contributors[p];
    }
    return {ref::psnr(rgb, cpu.rgb), ref::psnr(alpha, cpu.alpha), ref::psnr(gpu.depth, cpu.depth, max_depth),
            double(id_same) / double(pixels), double(contrib_same) / double(pixels)};
}

// Host side of a render::RenderStyle, as the reference takes it.
struct StyleData {
    std::vector<int32_t> labels;     // one per Gaussian
    std::vector<glm::vec4> palette;  // rgb, a
};

// Renders every camera of the scene on the GPU and with the reference, optionally styled,
// and checks that they agree.
inline void check_scene(const ref::TestScene& scene, const render::RenderSettings& s = {},
                        const StyleData* style = nullptr) {
    auto& ctx = gpu();
    render::GpuScene gpu_scene(ctx, scene.cloud);
    render::Renderer renderer(ctx);
    ref::RefOptions o;
    o.background = s.background;
    o.tau = s.tau;
    o.antialiased = s.antialiased;
    o.max_sh_degree = s.max_sh_degree;
    o.near = s.near;
    vk::Buffer labels, palette;
    render::RenderStyle gpu_style;
    if (style) {
        labels = vk::upload_vector(ctx, style->labels, "test labels");
        palette = vk::upload_vector(ctx, style->palette, "test palette");
        gpu_style = {&labels, &palette, uint32_t(style->palette.size())};
        o.labels = &style->labels;
        o.palette = &style->palette;
    }
    for (const auto& cam : scene.cameras) {
        renderer.render(gpu_scene, cam, s, style ? &gpu_style : nullptr);
        auto gpu = renderer.read();
        auto cpu = ref::render_reference(scene.cloud, cam, o);
        REQUIRE(gpu.width == cpu.width);
        REQUIRE(gpu.height == cpu.height);
        auto a = compare(gpu, cpu);
        INFO("camera " << cam.name << " " << cam.width << "x" << cam.height << ": rgb " << a.rgb_psnr << " dB, alpha "
                       << a.alpha_psnr << " dB, depth " << a.depth_psnr << " dB, tau id " << a.tau_id_match
                       << ", contributors " << a.contributors_match);
        CHECK(a.rgb_psnr >= 45.0);
        CHECK(a.alpha_psnr >= 45.0);
        CHECK(a.depth_psnr >= 45.0);
        CHECK(a.tau_id_match >= 0.99);
        CHECK(a.contributors_match >= 0.99);
    }
}

}  // namespace pg::test
