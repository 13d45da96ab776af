// A scene past the binding limit or the memory cap is drawn in depth slabs: the frame must be
// the one the resident scene gives (same blending order), styled or not, and a cap that
// cannot hold a slab is one clear error.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "tests/render/render_agreement.h"

using namespace pg;

namespace {

// Binding limit that makes slabs of about `slab` Gaussians for SH degree <= 1 (widest array:
// the 48-byte splats).
render::SceneBudget slabs_of(uint32_t slab) {
    render::SceneBudget b;
    b.max_binding_bytes = uint64_t(slab) * 48;
    return b;
}

// The random scene plus a camera inside it, so Gaussians lie behind it, beside the frustum
// and across the near plane.
ref::TestScene scene_with_inside_camera(uint64_t seed, size_t n, int sh) {
    ref::TestScene s = ref::random_scene(seed, n, sh);
    data::Camera inside = s.cameras[0];
    inside.name = "inside";
    const glm::dvec3 centre = inside.position();
    inside.t = -(inside.R * (0.15 * centre));  // 85 % of the way to the origin
    s.cameras.push_back(inside);
    return s;
}

struct FrameDiff {
    size_t pixels = 0, rgba = 0, depth = 0, tau = 0, contributors = 0;
    float max_rgba = 0;
};

FrameDiff diff(const render::RenderImages& a, const render::RenderImages& b) {
    FrameDiff d;
    d.pixels = a.tau_id.size();
    for (size_t p = 0; p < d.pixels; ++p) {
        float e = 0;
        for (int c = 0; c < 4; ++c) e = std::max(e, std::abs(a.rgba[p * 4 + c] - b.rgba[p * 4 + c]));
        d.max_rgba = std::max(d.max_rgba, e);
        d.rgba += e > 0;
        d.depth += a.depth[p] != b.depth[p] || a.tau_depth[p] != b.tau_depth[p];
        d.tau += a.tau_id[p] != b.tau_id[p];
        d.contributors += a.contributors[p] != b.contributors[p];
    }
    return d;
}

void check_streamed(const ref::TestScene& scene, uint32_t slab, const test::StyleData* style = nullptr) {
    auto& ctx = test::gpu();
    render::GpuScene resident(ctx, scene.cloud), streamed(ctx, scene.cloud, slabs_of(slab));
    REQUIRE_FALSE(resident.streamed());
    REQUIRE(streamed.streamed());
    REQUIRE(streamed.slab_capacity() == slab);
    vk::Buffer labels, palette;
    render::RenderStyle rs;
    if (style) {
        labels = vk::upload_vector(ctx, style->labels, "labels");
        palette = vk::upload_vector(ctx, style->palette, "palette");
        rs = {&labels, &palette, uint32_t(style->palette.size())};
    }
    render::Renderer a(ctx), b(ctx);
    int most_slabs = 0;
    for (const auto& cam : scene.cameras) {
        INFO("camera " << cam.name);
        a.render(resident, cam, {}, style ? &rs : nullptr);
        b.render(streamed, cam, {}, style ? &rs : nullptr);
        CHECK(a.slabs() == 1);
        most_slabs = std::max(most_slabs, b.slabs());
        const auto d = diff(a.read(), b.read());
        // The slabs keep the resident blending order: the same sums in the same sequence.
        CHECK(d.max_rgba <= 1e-6f);
        CHECK(d.depth <= d.pixels / 1000);
        CHECK(d.tau <= d.pixels / 1000);
        CHECK(d.contributors <= d.pixels / 1000);
        CHECK(a.key_count() >= b.key_count());  // the host cull drops only what draws nothing
    }
    CHECK(most_slabs >= 3);
}

}  // namespace

TEST_CASE("a streamed scene renders like the resident one (slabs of 4096, SH degree 1)") {
    check_streamed(scene_with_inside_camera(21, 20000, 1), 4096);
}

TEST_CASE("a streamed scene renders like the resident one with a style (labels gathered per slab)") {
    const auto scene = scene_with_inside_camera(22, 16000, 0);
    test::StyleData style;
    style.palette = {{0.9f, 0.1f, 0.8f, 0.0f}, {1.0f, 0.0f, 0.0f, 0.5f}, {0.0f, 0.0f, 1.0f, -1.0f}};
    for (size_t i = 0; i < scene.cloud.size(); ++i) style.labels.push_back(int32_t(i % 3));
    check_streamed(scene, 5000, &style);
}

TEST_CASE("a streamed tile of 300k Gaussians is walked in windows inside each slab, like the resident one") {
    check_streamed(ref::crowded_tile_scene(300000), 100000);
}

TEST_CASE("a slab whose tile keys would pass the binding limit is drawn in smaller slabs") {
    // Large Gaussians touch most tiles: 4096 of them need far more keys than a binding of
    // 4096 x 48 bytes holds (24,576), so the renderer halves the slab until they fit.
    auto scene = ref::random_scene(25, 6000, 0);
    for (auto& s : scene.cloud.log_scale) s += glm::vec3(std::log(6.0f));
    auto& ctx = test::gpu();
    render::GpuScene resident(ctx, scene.cloud), streamed(ctx, scene.cloud, slabs_of(4096));
    render::Renderer a(ctx), b(ctx);
    const auto& cam = scene.cameras[0];
    a.render(resident, cam, {});
    b.render(streamed, cam, {});
    REQUIRE(a.key_count() > 4 * 24576);
    CHECK(b.slabs() > int(a.key_count() / 24576));
    const auto d = diff(a.read(), b.read());
    CHECK(d.max_rgba <= 1e-6f);
    CHECK(d.tau <= d.pixels / 1000);
}

TEST_CASE("a streamed frame of nothing (the camera turned away) is the background") {
    const auto scene = ref::random_scene(26, 9000, 0);
    data::Camera away = scene.cameras[0];
    away.R = glm::dmat3(-1, 0, 0, 0, 1, 0, 0, 0, -1) * away.R;  // half a turn about the camera's y axis
    away.t = glm::dmat3(-1, 0, 0, 0, 1, 0, 0, 0, -1) * away.t;
    auto& ctx = test::gpu();
    render::GpuScene resident(ctx, scene.cloud), streamed(ctx, scene.cloud, slabs_of(4096));
    render::Renderer a(ctx), b(ctx);
    render::RenderSettings s;
    s.background = {0.25f, 0.5f, 0.75f};
    a.render(resident, away, s);
    b.render(streamed, away, s);
    const auto ra = a.read(), rb = b.read();
    CHECK(ra.rgba == rb.rgba);
    CHECK(rb.rgba[0] == 0.25f);
    CHECK(std::count(rb.tau_id.begin(), rb.tau_id.end(), -1) == long(rb.tau_id.size()));
}

TEST_CASE("a streamed frame's tau ids are scene ids") {
    const auto scene = ref::random_scene(23, 12000, 0);
    auto& ctx = test::gpu();
    render::GpuScene resident(ctx, scene.cloud), streamed(ctx, scene.cloud, slabs_of(4096));
    render::Renderer a(ctx), b(ctx);
    a.render(resident, scene.cameras[0], {});
    b.render(streamed, scene.cameras[0], {});
    REQUIRE(b.slabs() >= 2);
    const auto ra = a.read(), rb = b.read();
    size_t hit = 0, same = 0;
    for (size_t p = 0; p < ra.tau_id.size(); ++p) {
        hit += ra.tau_id[p] >= 0;
        same += ra.tau_id[p] >= 0 && ra.tau_id[p] == rb.tau_id[p];
    }
    REQUIRE(hit > 1000);
    CHECK(same >= hit - hit / 1000);
}

TEST_CASE("a memory cap that cannot hold one slab is one clear error") {
    const auto scene = ref::random_scene(24, 9000, 3);
    auto& ctx = test::gpu();
    render::SceneBudget b;
    b.max_device_bytes = 1 << 20;  // 1 MiB: a slab of 4096 SH-3 Gaussians needs more
    try {
        render::GpuScene s(ctx, scene.cloud, b);
        FAIL("no error");
    } catch (const std::runtime_error& e) {
        const std::string what = e.what();
        CHECK(what.find("needs at least") != std::string::npos);
        CHECK(what.find("1 MiB allowed") != std::string::npos);
    }
    // A cap that holds about half of the scene streams it.
    b.max_device_bytes = render::frame_bytes_per_gaussian(48) * 5000;
    render::GpuScene s(ctx, scene.cloud, b);
    CHECK(s.streamed());
    CHECK(s.slab_capacity() == 5000);
}

TEST_CASE("fp16 SH render within 5e-3 of float SH, and stream exactly like their resident frame") {
    const auto scene = ref::random_scene(27, 9000, 3);
    auto& ctx = test::gpu();
    render::SceneBudget half;
    half.half_sh = true;
    render::SceneBudget half_streamed;
    half_streamed.max_binding_bytes = 4096 * 96;  // the fp16 SH are the widest array: 24 words
    half_streamed.half_sh = true;
    render::GpuScene full(ctx, scene.cloud), compact(ctx, scene.cloud, half), streamed(ctx, scene.cloud, half_streamed);
    CHECK(compact.sh_words() == 24);
    CHECK(compact.sh.size() == full.sh.size() / 2);
    REQUIRE(streamed.streamed());
    render::Renderer r(ctx);
    for (const auto& cam : scene.cameras) {
        r.render(full, cam, {});
        const auto a = r.read();
        r.render(compact, cam, {});
        const auto b = r.read();
        r.render(streamed, cam, {});
        const auto c = r.read();
        double sum = 0;
        float worst = 0;
        for (size_t i = 0; i < a.rgba.size(); ++i) {
            const float e = std::abs(a.rgba[i] - b.rgba[i]);
            worst = std::max(worst, e);
            sum += e;
        }
        CHECK(worst <= 5e-3f);
        CHECK(sum / double(a.rgba.size()) <= 5e-4);
        CHECK(a.tau_id == b.tau_id);  // geometry is untouched
        CHECK(diff(b, c).max_rgba <= 1e-6f);
    }
}
