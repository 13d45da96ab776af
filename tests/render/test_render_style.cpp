// The renderer's optional style (labels -> palette tint or hide) against the CPU reference,
// and hiding as an exact deletion of the hidden Gaussians.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "tests/render/render_agreement.h"

using namespace pg;
using test::StyleData;

namespace {

// Every kind of palette entry, cycled over the Gaussians in index order: untouched (a = 0,
// rgb set so a wrong mix shows), half tint, flat colour, hidden, faint tint, and labels
// below 0 or past the palette that fall back to entry 0.
StyleData mixed_style(size_t n) {
    StyleData s;
    s.palette = {{0.9f, 0.1f, 0.8f, 0.0f}, {1.0f, 0.0f, 0.0f, 0.5f}, {0.0f, 1.0f, 0.0f, 1.0f},
                 {0.0f, 0.0f, 1.0f, -1.0f}, {0.2f, 0.4f, 1.0f, 0.25f}};
    const int32_t cycle[] = {0, 1, 2, 3, 4, -5, 9};
    for (size_t i = 0; i < n; ++i) s.labels.push_back(cycle[i % 7]);
    return s;
}

void check_styled(const ref::TestScene& scene, const render::RenderSettings& s = {}) {
    StyleData style = mixed_style(scene.cloud.size());
    test::check_scene(scene, s, &style);
}

// The Gaussians of `cloud` whose label is not `drop`, with their labels; keep[j] is the
// original index of Gaussian j.
struct Kept {
    data::GaussianCloud cloud;
    std::vector<int32_t> labels;
    std::vector<int32_t> keep;
};

Kept without_label(const data::GaussianCloud& cloud, const std::vector<int32_t>& labels, int32_t drop) {
    Kept k;
    k.cloud.sh_degree = cloud.sh_degree;
    for (size_t i = 0; i < cloud.size(); ++i) {
        if (labels[i] == drop) continue;
        k.cloud.mean.push_back(cloud.mean[i]);
        k.cloud.log_scale.push_back(cloud.log_scale[i]);
        k.cloud.rotation.push_back(cloud.rotation[i]);
        k.cloud.opacity_logit.push_back(cloud.opacity_logit[i]);
        const size_t floats = size_t(cloud.coeffs()) * 3;
        k.cloud.sh.insert(k.cloud.sh.end(), cloud.sh.begin() + i * floats, cloud.sh.begin() + (i + 1) * floats);
        k.labels.push_back(labels[i]);
        k.keep.push_back(int32_t(i));
    }
    return k;
}

}  // namespace

TEST_CASE("a styled render matches the reference on a random scene (SH degree 1)") { check_styled(ref::random_scene(1, 3000, 1)); }
TEST_CASE("a styled render matches the reference with SH degree 3") { check_styled(ref::sh3_scene()); }
TEST_CASE("a styled render matches the reference behind the camera and across the near plane") {
    check_styled(ref::behind_camera_scene());
    check_styled(ref::near_plane_scene());
}
TEST_CASE("a styled render matches the reference with a fullscreen Gaussian and degenerate scales") {
    check_styled(ref::fullscreen_scene());
    check_styled(ref::degenerate_scales_scene());
}
TEST_CASE("a styled render matches the reference with zero opacities, surfels and early termination") {
    check_styled(ref::zero_opacity_scene());
    check_styled(ref::flat_2dgs_scene());
    check_styled(ref::dense_scene());
}
TEST_CASE("a styled render follows the settings like the reference") {
    render::RenderSettings s;
    s.background = {0.2f, 0.5f, 0.9f};
    s.tau = 0.5f;
    s.antialiased = true;
    s.max_sh_degree = 1;
    check_styled(ref::random_scene(7, 1500, 3), s);
}

TEST_CASE("hiding a label renders exactly as if its Gaussians were deleted") {
    // Two ball-shaped objects in the random scene: label 1 is hidden, label 2 tinted.
    const ref::TestScene scene = ref::random_scene(11, 3000, 1);
    StyleData style;
    style.palette = {{0.0f, 0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f, -1.0f}, {1.0f, 0.5f, 0.0f, 0.5f}};
    size_t hidden = 0;
    for (const auto& m : scene.cloud.mean) {
        const int32_t label = glm::length(m - glm::vec3(0.3f, 0.0f, 0.0f)) < 0.6f ? 1
                              : glm::length(m - glm::vec3(-0.6f, 0.2f, 0.0f)) < 0.4f ? 2 : 0;
        style.labels.push_back(label);
        hidden += label == 1;
    }
    REQUIRE(hidden > 100);
    const Kept kept = without_label(scene.cloud, style.labels, 1);

    auto& ctx = test::gpu();
    render::Renderer renderer(ctx);
    render::GpuScene full(ctx, scene.cloud), reduced(ctx, kept.cloud);
    vk::Buffer labels = vk::upload_vector(ctx, style.labels, "labels");
    vk::Buffer kept_labels = vk::upload_vector(ctx, kept.labels, "kept labels");
    vk::Buffer palette = vk::upload_vector(ctx, style.palette, "palette");
    const render::RenderStyle full_style{&labels, &palette, uint32_t(style.palette.size())};
    const render::RenderStyle kept_style{&kept_labels, &palette, uint32_t(style.palette.size())};
    for (const auto& cam : scene.cameras) {
        INFO("camera " << cam.name);
        renderer.render(full, cam, {});
        const auto plain = renderer.read();
        renderer.render(full, cam, {}, &full_style);
        const auto styled = renderer.read();
        renderer.render(reduced, cam, {}, &kept_style);
        const auto deleted = renderer.read();

        size_t hidden_before = 0, hidden_after = 0, ids_differ = 0;
        for (size_t p = 0; p < plain.tau_id.size(); ++p) {
            hidden_before += plain.tau_id[p] >= 0 && style.labels[size_t(plain.tau_id[p])] == 1;
            hidden_after += styled.tau_id[p] >= 0 && style.labels[size_t(styled.tau_id[p])] == 1;
            const int32_t id = deleted.tau_id[p] < 0 ? -1 : kept.keep[size_t(deleted.tau_id[p])];
            ids_differ += styled.tau_id[p] != id;
        }
        CHECK(hidden_before > 0);  // the object was in view
        CHECK(hidden_after == 0);
        CHECK(ids_differ == 0);
        CHECK(styled.rgba == deleted.rgba);
        CHECK(styled.depth == deleted.depth);
        CHECK(styled.tau_depth == deleted.tau_depth);
        CHECK(styled.contributors == deleted.contributors);
    }
}

TEST_CASE("a palette that tints nothing leaves the render bit-identical") {
    const ref::TestScene scene = ref::random_scene(1, 3000, 1);
    StyleData style = mixed_style(scene.cloud.size());
    for (auto& e : style.palette) e.a = 0.0f;
    auto& ctx = test::gpu();
    render::Renderer renderer(ctx);
    render::GpuScene gpu_scene(ctx, scene.cloud);
    vk::Buffer labels = vk::upload_vector(ctx, style.labels, "labels");
    vk::Buffer palette = vk::upload_vector(ctx, style.palette, "palette");
    const render::RenderStyle gpu_style{&labels, &palette, uint32_t(style.palette.size())};
    for (const auto& cam : scene.cameras) {
        renderer.render(gpu_scene, cam, {});
        const auto plain = renderer.read();
        renderer.render(gpu_scene, cam, {}, &gpu_style);
        const auto styled = renderer.read();
        CHECK(styled.rgba == plain.rgba);
        CHECK(styled.depth == plain.depth);
        CHECK(styled.tau_depth == plain.tau_depth);
        CHECK(styled.tau_id == plain.tau_id);
        CHECK(styled.contributors == plain.contributors);
    }
}

TEST_CASE("a style with missing or short buffers is refused") {
    const ref::TestScene scene = ref::sh0_scene();
    auto& ctx = test::gpu();
    render::Renderer renderer(ctx);
    render::GpuScene gpu_scene(ctx, scene.cloud);
    vk::Buffer labels(ctx, scene.cloud.size() * 4, vk::MemoryUse::Device, "labels");
    vk::Buffer short_labels(ctx, 4, vk::MemoryUse::Device, "short labels");
    vk::Buffer palette(ctx, 2 * 16, vk::MemoryUse::Device, "palette");
    const auto& cam = scene.cameras[0];
    const render::RenderStyle no_palette{&labels, nullptr, 2};
    const render::RenderStyle empty_palette{&labels, &palette, 0};
    const render::RenderStyle too_few_labels{&short_labels, &palette, 2};
    const render::RenderStyle palette_overrun{&labels, &palette, 3};
    CHECK_THROWS_AS(renderer.render(gpu_scene, cam, {}, &no_palette), std::invalid_argument);
    CHECK_THROWS_AS(renderer.render(gpu_scene, cam, {}, &empty_palette), std::invalid_argument);
    CHECK_THROWS_AS(renderer.render(gpu_scene, cam, {}, &too_few_labels), std::invalid_argument);
    CHECK_THROWS_AS(renderer.render(gpu_scene, cam, {}, &palette_overrun), std::invalid_argument);
}

TEST_CASE("the reference tints, hides and falls back to palette entry 0", "[reference]") {
    data::GaussianCloud cloud;
    ref::add_gaussian(cloud, glm::vec3(0, 0, 2), glm::vec3(std::log(0.05f)), glm::vec4(1, 0, 0, 0), 2.0f,
                      ref::dc_from_rgb(glm::vec3(0.2f, 0.4f, 0.6f)));
    data::Camera cam;
    cam.name = "identity";
    cam.width = cam.height = 32;
    cam.fx = cam.fy = 100.0;
    cam.cx = cam.cy = 16.0;
    const std::vector<glm::vec4> palette = {{0.0f, 0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f, 0.5f}, {0.0f, 0.0f, 0.0f, -1.0f}};
    ref::RefOptions o;
    o.palette = &palette;
    auto colour_with = [&](int32_t label, bool& visible) {
        const std::vector<int32_t> labels = {label};
        o.labels = &labels;
        ref::ProjectedGaussian g;
        visible = ref::project_gaussian(cloud, 0, cam, o, g);
        return g.colour;
    };
    bool visible = false;
    const glm::vec3 half = colour_with(1, visible);
    CHECK(visible);
    CHECK(half.x == Approx(0.6f));
    CHECK(half.y == Approx(0.2f));
    CHECK(half.z == Approx(0.3f));
    colour_with(2, visible);
    CHECK_FALSE(visible);
    for (int32_t out_of_range : {-1, 3, 1000}) {
        const glm::vec3 c = colour_with(out_of_range, visible);
        CHECK(visible);
        CHECK(c.x == Approx(0.2f));
        CHECK(c.y == Approx(0.4f));
        CHECK(c.z == Approx(0.6f));
    }
    const std::vector<int32_t> hidden = {2};
    o.labels = &hidden;
    const ref::RefImage img = ref::render_reference(cloud, cam, o);
    CHECK(std::count(img.alpha.begin(), img.alpha.end(), 0.0f) == std::ptrdiff_t(img.alpha.size()));
}
