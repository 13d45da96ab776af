// The moving camera's preview of a streamed scene: every m-th Gaussian widened by m^(1/4),
// within the scene's memory budget, and covering the picture about as the full scene does.
#include <catch2/catch.hpp>

#include <cmath>

#include "app/viewer/preview_scene.h"
#include "dataset/formats/camera_io.h"
#include "dataset/formats/scene_io.h"
#include "engine/render/renderer.h"
#include "tests/gpu_fixture.h"

using namespace pg;

TEST_CASE("the preview keeps every m-th Gaussian, widened by m^(1/4), the rest unchanged", "[viewer]") {
    data::GaussianCloud c;
    c.resize(10);
    for (size_t i = 0; i < c.size(); ++i) {
        c.mean[i] = glm::vec3(float(i), 0.0f, 1.0f);
        c.log_scale[i] = glm::vec3(-float(i));
        c.opacity_logit[i] = float(i) * 0.1f;
    }
    const auto p = viewer::make_preview_cloud(c, 3);
    CHECK(p.stride == 4);
    REQUIRE(p.ids == std::vector<uint32_t>{0, 4, 8});
    for (size_t j = 0; j < p.ids.size(); ++j) {
        CHECK(p.cloud.mean[j] == c.mean[p.ids[j]]);
        CHECK(p.cloud.opacity_logit[j] == c.opacity_logit[p.ids[j]]);
        CHECK(p.cloud.log_scale[j].x == Approx(c.log_scale[p.ids[j]].x + 0.5f * std::log(2.0f)));
    }
}

TEST_CASE("a streamed scene shares its budget with a resident preview, a resident one has none", "[viewer]") {
    auto& ctx = test::gpu();
    data::GaussianCloud c;
    c.resize(200000);
    for (size_t i = 0; i < c.size(); ++i) c.mean[i] = glm::vec3(float(i % 500), float(i / 500), 3.0f);
    const uint64_t per = render::frame_bytes_per_gaussian(3);
    render::SceneBudget budget;
    budget.max_device_bytes = 120000 * per;
    const auto v = viewer::upload_viewed_scene(ctx, c, budget);
    REQUIRE(v.scene->streamed());
    REQUIRE(v.preview);
    REQUIRE(v.preview_scene);
    CHECK_FALSE(v.preview_scene->streamed());
    CHECK(v.preview->ids.size() >= viewer::kMinPreview);
    CHECK(uint64_t(v.scene->slab_capacity() + v.preview_scene->size()) * per <= budget.max_device_bytes);

    const auto resident = viewer::upload_viewed_scene(ctx, c, {});
    CHECK_FALSE(resident.scene->streamed());
    CHECK_FALSE(resident.preview);
}

TEST_CASE("the preview covers the picture about as the full scene does", "[viewer]") {
    auto& ctx = test::gpu();
    const auto cloud = data::load_scene(std::string(PG_SOURCE_DIR) + "/assets/sample/desk_000/scene.ply");
    const auto cams = data::load_cameras(std::string(PG_SOURCE_DIR) + "/assets/sample/desk_000/cameras.json");
    const auto p = viewer::make_preview_cloud(cloud, uint32_t(cloud.size() / 8));
    render::GpuScene full(ctx, cloud), preview(ctx, p.cloud);
    render::Renderer r(ctx);
    auto coverage = [&](const render::GpuScene& s, const data::Camera& cam) {
        r.render(s, cam, {});
        const auto img = vk::download_vector<glm::vec4>(ctx, r.image_buffer(), size_t(cam.width) * cam.height);
        size_t opaque = 0;
        for (auto& px : img) opaque += px.a > 0.5f;
        return double(opaque) / double(img.size());
    };
    for (size_t v : {size_t(0), size_t(7), size_t(15)}) {
        const double a = coverage(full, cams[v]), b = coverage(preview, cams[v]);
        INFO("view " << v << ": full " << a << ", preview " << b);
        CHECK(b >= 0.9 * a);
        CHECK(b <= 1.25 * a);
    }
}
