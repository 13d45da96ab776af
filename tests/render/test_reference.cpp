// Tests of the CPU reference rasterizer itself, against hand-computed values.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "tests/reference/cpu_rasterizer.h"
#include "tests/reference/test_scenes.h"

using pg::data::Camera;
using pg::data::GaussianCloud;
using pg::ref::add_gaussian;
using pg::ref::dc_from_rgb;
using pg::ref::ProjectedGaussian;
using pg::ref::RefImage;
using pg::ref::RefOptions;
using pg::ref::render_reference;

namespace {

// Camera at the origin looking down +z (R = I, t = 0): view space is world space.
Camera identity_camera(int width = 64, int height = 48, double f = 100.0) {
    Camera cam;
    cam.name = "identity";
    cam.width = width;
    cam.height = height;
    cam.fx = cam.fy = f;
    cam.cx = width / 2.0;
    cam.cy = height / 2.0;
    return cam;
}

size_t pix(const RefImage& img, int x, int y) { return size_t(y) * img.width + x; }

glm::vec3 rgb_at(const RefImage& img, int x, int y) {
    const size_t p = pix(img, x, y) * 3;
    return glm::vec3(img.rgb[p], img.rgb[p + 1], img.rgb[p + 2]);
}

// An isotropic Gaussian of world standard deviation s at depth z has screen variance
// (f s / z)^2 + 0.3 on the image axis; its alpha at pixel (x, y) follows directly.
float expected_alpha(float opacity, glm::vec2 mean2d, float variance, int x, int y) {
    const float dx = mean2d.x - (x + 0.5f), dy = mean2d.y - (y + 0.5f);
    const float a = opacity * std::exp(-0.5f * (dx * dx + dy * dy) / variance);
    return a < 1.0f / 255.0f ? 0.0f : std::min(0.99f, a);
}

float logit(float o) { return std::log(o / (1.0f - o)); }

}  // namespace

TEST_CASE("single isotropic Gaussian matches the closed form", "[reference]") {
    GaussianCloud cloud;
    const glm::vec3 colour(0.2f, 0.6f, 0.9f);
    // f s / z = 100 * 0.04 / 2 = 2 px, so the screen variance is 4 + 0.3.
    add_gaussian(cloud, glm::vec3(0, 0, 2), glm::vec3(std::log(0.04f)), glm::vec4(2, 0, 0, 0), 0.0f, dc_from_rgb(colour));
    const Camera cam = identity_camera();
    RefOptions opt;
    opt.background = glm::vec3(0.1f, 0.2f, 0.3f);
    const RefImage img = render_reference(cloud, cam, opt);
    REQUIRE(img.width == 64);
    REQUIRE(img.rgb.size() == 64 * 48 * 3);

    const glm::vec2 centre(32.0f, 24.0f);
    const float variance = 4.3f;
    for (auto [x, y] : {std::pair{32, 24}, {31, 23}, {34, 24}, {32, 27}, {29, 26}, {36, 20}, {38, 24}}) {
        const float a = expected_alpha(0.5f, centre, variance, x, y);
        CAPTURE(x, y, a);
        CHECK(img.alpha[pix(img, x, y)] == Approx(a).margin(1e-6));
        const glm::vec3 rgb = rgb_at(img, x, y);
        const glm::vec3 want = colour * a + (1.0f - a) * opt.background;
        CHECK(rgb.x == Approx(want.x).margin(1e-5));
        CHECK(rgb.y == Approx(want.y).margin(1e-5));
        CHECK(rgb.z == Approx(want.z).margin(1e-5));
        CHECK(img.contributors[pix(img, x, y)] == (a > 0.0f ? 1u : 0u));
        CHECK(img.depth[pix(img, x, y)] == Approx(a > 0.0f ? 2.0f : 0.0f));
        CHECK(img.tau_id[pix(img, x, y)] == -1);  // alpha <= 0.5 never reaches tau = 0.9
    }
    // Support: o exp(-d^2 / (2 var)) >= 1/255 up to d = sqrt(2 var ln 127.5) = 6.46 px.
    CHECK(img.alpha[pix(img, 37, 24)] > 0.0f);   // d^2 = 5.5^2 + 0.5^2 = 30.5 < 41.7
    CHECK(img.alpha[pix(img, 38, 24)] == 0.0f);  // d^2 = 42.5 > 41.7
    CHECK(img.alpha[pix(img, 0, 0)] == 0.0f);
    CHECK(rgb_at(img, 0, 0) == opt.background);

    // A lower tau is reached at the centre: tau-depth is the Gaussian's z.
    opt.tau = 0.3f;
    const RefImage img2 = render_reference(cloud, cam, opt);
    CHECK(img2.tau_id[pix(img2, 32, 24)] == 0);
    CHECK(img2.tau_depth[pix(img2, 32, 24)] == Approx(2.0f));
    CHECK(img2.tau_id[pix(img2, 36, 24)] == -1);  // alpha there is below 0.3
    CHECK(img2.tau_depth[pix(img2, 36, 24)] == 0.0f);
}

TEST_CASE("image axes follow the OpenCV convention", "[reference]") {
    GaussianCloud cloud;
    // +x world lands right of centre, +y world lands below it: u = fx x/z + cx, v = fy y/z + cy.
    add_gaussian(cloud, glm::vec3(0.2f, 0.1f, 2.0f), glm::vec3(std::log(0.01f)), glm::vec4(1, 0, 0, 0), 5.0f,
                 dc_from_rgb(glm::vec3(1.0f)));
    Camera cam = identity_camera();
    cam.cx = 30.25;
    cam.cy = 20.75;
    ProjectedGaussian g;
    REQUIRE(pg::ref::project_gaussian(cloud, 0, cam, RefOptions{}, g));
    CHECK(g.mean2d.x == Approx(100.0f * 0.1f + 30.25f));
    CHECK(g.mean2d.y == Approx(100.0f * 0.05f + 20.75f));
    const RefImage img = render_reference(cloud, cam);
    // The brightest pixel is the one containing (40.25, 25.75).
    size_t best = 0;
    for (size_t p = 1; p < img.alpha.size(); ++p)
        if (img.alpha[p] > img.alpha[best]) best = p;
    CHECK(best == pix(img, 40, 25));
}

TEST_CASE("two overlapping Gaussians: the nearer one wins", "[reference]") {
    GaussianCloud cloud;
    const glm::vec3 red(0.9f, 0.1f, 0.1f), green(0.1f, 0.9f, 0.1f);
    // Index 0 is the farther one, so order comes from depth, not from the array.
    add_gaussian(cloud, glm::vec3(0, 0, 3), glm::vec3(std::log(0.3f)), glm::vec4(1, 0, 0, 0), logit(0.96f), dc_from_rgb(green));
    add_gaussian(cloud, glm::vec3(0, 0, 2), glm::vec3(std::log(0.2f)), glm::vec4(1, 0, 0, 0), logit(0.96f), dc_from_rgb(red));
    const Camera cam = identity_camera();
    RefOptions opt;
    opt.background = glm::vec3(0.0f, 0.0f, 1.0f);
    const RefImage img = render_reference(cloud, cam, opt);

    // Screen variances: (100 * 0.2 / 2)^2 + 0.3 = 100.3 and (100 * 0.3 / 3)^2 + 0.3 = 100.3.
    const int x = 33, y = 22;
    const float a_near = expected_alpha(0.96f, {32, 24}, 100.3f, x, y);
    const float a_far = expected_alpha(0.96f, {32, 24}, 100.3f, x, y);
    const float T1 = 1.0f - a_near, T2 = T1 * (1.0f - a_far);
    const glm::vec3 want = red * a_near + green * a_far * T1 + opt.background * T2;
    const glm::vec3 got = rgb_at(img, x, y);
    CHECK(got.x == Approx(want.x).margin(1e-5));
    CHECK(got.y == Approx(want.y).margin(1e-5));
    CHECK(got.z == Approx(want.z).margin(1e-5));
    CHECK(got.x > 0.8f);
    CHECK(img.alpha[pix(img, x, y)] == Approx(1.0f - T2).margin(1e-6));
    CHECK(img.contributors[pix(img, x, y)] == 2);
    CHECK(img.tau_id[pix(img, x, y)] == 1);
    CHECK(img.tau_depth[pix(img, x, y)] == Approx(2.0f));
    const float w_near = a_near, w_far = a_far * T1;
    CHECK(img.depth[pix(img, x, y)] == Approx((2.0f * w_near + 3.0f * w_far) / (w_near + w_far)).epsilon(1e-5));
}

TEST_CASE("equal depths are ordered by index", "[reference]") {
    GaussianCloud cloud;
    const glm::vec3 red(0.9f, 0.1f, 0.1f), green(0.1f, 0.9f, 0.1f);
    add_gaussian(cloud, glm::vec3(0, 0, 2), glm::vec3(std::log(0.2f)), glm::vec4(1, 0, 0, 0), logit(0.95f), dc_from_rgb(red));
    add_gaussian(cloud, glm::vec3(0, 0, 2), glm::vec3(std::log(0.2f)), glm::vec4(1, 0, 0, 0), logit(0.95f), dc_from_rgb(green));
    const RefImage img = render_reference(cloud, identity_camera());
    CHECK(rgb_at(img, 32, 24).x > 0.8f);
    CHECK(img.tau_id[pix(img, 32, 24)] == 0);
}

TEST_CASE("empty pixels show the background", "[reference]") {
    GaussianCloud cloud;
    const Camera cam = identity_camera(40, 30);
    RefOptions opt;
    opt.background = glm::vec3(0.25f, 0.5f, 0.75f);
    const RefImage empty = render_reference(cloud, cam, opt);
    for (size_t p = 0; p < empty.alpha.size(); ++p) {
        CHECK(empty.rgb[p * 3 + 0] == 0.25f);
        CHECK(empty.rgb[p * 3 + 2] == 0.75f);
        CHECK(empty.alpha[p] == 0.0f);
        CHECK(empty.depth[p] == 0.0f);
        CHECK(empty.tau_depth[p] == 0.0f);
        CHECK(empty.tau_id[p] == -1);
        CHECK(empty.contributors[p] == 0);
    }
}

TEST_CASE("degree-1 SH colour depends on the view direction as the formula says", "[reference]") {
    GaussianCloud cloud;
    cloud.sh_degree = 1;
    const glm::vec3 mean(0.3f, -0.2f, 2.0f);
    add_gaussian(cloud, mean, glm::vec3(std::log(0.05f)), glm::vec4(1, 0, 0, 0), 3.0f, glm::vec3(0.1f, -0.2f, 0.3f));
    // sh[k] for k = 1, 2, 3 (basis -C1 y, C1 z, -C1 x).
    const glm::vec3 sh1(0.4f, -0.3f, 0.2f), sh2(-0.25f, 0.5f, 0.1f), sh3(0.3f, 0.2f, -0.6f);
    for (int c = 0; c < 3; ++c) {
        cloud.sh[1 * 3 + c] = sh1[c];
        cloud.sh[2 * 3 + c] = sh2[c];
        cloud.sh[3 * 3 + c] = sh3[c];
    }
    const float C0 = 0.28209479177387814f, C1 = 0.4886025119029199f;
    glm::vec3 previous(-1.0f);
    for (glm::dvec3 eye : {glm::dvec3(0, 0, -1), glm::dvec3(1.5, 0.5, -1), glm::dvec3(-1, -1, 0.5)}) {
        const Camera cam = pg::ref::look_at_camera("sh", eye, glm::dvec3(mean), glm::dvec3(0, -1, 0), 64, 48, 100, 100, 32, 24);
        ProjectedGaussian g;
        REQUIRE(pg::ref::project_gaussian(cloud, 0, cam, RefOptions{}, g));
        const glm::vec3 d = glm::normalize(mean - glm::vec3(eye));
        const glm::vec3 dc(0.1f, -0.2f, 0.3f);
        const glm::vec3 want = glm::max(glm::vec3(0.0f), 0.5f + C0 * dc - C1 * d.y * sh1 + C1 * d.z * sh2 - C1 * d.x * sh3);
        CHECK(g.colour.x == Approx(want.x).margin(1e-5));
        CHECK(g.colour.y == Approx(want.y).margin(1e-5));
        CHECK(g.colour.z == Approx(want.z).margin(1e-5));
        CHECK(glm::length(g.colour - previous) > 0.05f);
        previous = g.colour;

        // max_sh_degree = 0 keeps the DC term only.
        RefOptions dc_only;
        dc_only.max_sh_degree = 0;
        REQUIRE(pg::ref::project_gaussian(cloud, 0, cam, dc_only, g));
        CHECK(g.colour.x == Approx(0.5f + C0 * 0.1f));
        CHECK(g.colour.y == Approx(0.5f - C0 * 0.2f));

        // The pixel under the mean shows that colour (alpha < 1 there, black background).
        const RefImage img = render_reference(cloud, cam);
        const int px = int(std::floor(g.mean2d.x)), py = int(std::floor(g.mean2d.y));
        const float a = img.alpha[pix(img, px, py)];
        REQUIRE(a > 0.5f);
        CHECK(rgb_at(img, px, py).x == Approx(want.x * a).margin(1e-5));
    }
}

TEST_CASE("negative SH colour is clamped at zero, not above one", "[reference]") {
    GaussianCloud cloud;
    add_gaussian(cloud, glm::vec3(0, 0, 2), glm::vec3(std::log(0.05f)), glm::vec4(1, 0, 0, 0), 3.0f,
                 glm::vec3(-5.0f, 5.0f, 0.0f));
    ProjectedGaussian g;
    REQUIRE(pg::ref::project_gaussian(cloud, 0, identity_camera(), RefOptions{}, g));
    CHECK(g.colour.x == 0.0f);
    CHECK(g.colour.y == Approx(0.5f + 5.0f * 0.28209479177387814f));
    CHECK(g.colour.z == Approx(0.5f));
}

TEST_CASE("antialiasing scales the opacity of a sub-pixel Gaussian", "[reference]") {
    GaussianCloud cloud;
    // f s / z = 100 * 0.002 / 2 = 0.1 px: screen variance 0.01 before the low-pass.
    add_gaussian(cloud, glm::vec3(0, 0, 2), glm::vec3(std::log(0.002f)), glm::vec4(1, 0, 0, 0), logit(0.9f),
                 dc_from_rgb(glm::vec3(1.0f)));
    const Camera cam = identity_camera();
    ProjectedGaussian plain, aa;
    RefOptions opt;
    REQUIRE(pg::ref::project_gaussian(cloud, 0, cam, opt, plain));
    opt.antialiased = true;
    REQUIRE(pg::ref::project_gaussian(cloud, 0, cam, opt, aa));
    CHECK(plain.opacity == Approx(0.9f));
    const float factor = std::sqrt((0.01f * 0.01f) / (0.31f * 0.31f));
    CHECK(aa.opacity == Approx(0.9f * factor).epsilon(1e-4));
    CHECK(aa.cov2d.x == Approx(0.31f));
    const RefImage a = render_reference(cloud, cam), b = render_reference(cloud, cam, opt);
    CHECK(b.alpha[pix(b, 32, 24)] == Approx(a.alpha[pix(a, 32, 24)] * factor).epsilon(1e-4));

    // A Gaussian much larger than a pixel is barely affected: variance 25 -> factor 25 / 25.3.
    cloud.log_scale[0] = glm::vec3(std::log(0.1f));
    REQUIRE(pg::ref::project_gaussian(cloud, 0, cam, opt, aa));
    CHECK(aa.opacity == Approx(0.9f * 25.0f / 25.3f).epsilon(1e-4));
}

TEST_CASE("Gaussians behind the camera or inside the near plane are culled", "[reference]") {
    GaussianCloud cloud;
    add_gaussian(cloud, glm::vec3(0, 0, -1), glm::vec3(std::log(2.0f)), glm::vec4(1, 0, 0, 0), 5.0f, dc_from_rgb({1, 0, 0}));
    add_gaussian(cloud, glm::vec3(0, 0, 0), glm::vec3(std::log(2.0f)), glm::vec4(1, 0, 0, 0), 5.0f, dc_from_rgb({1, 0, 0}));
    add_gaussian(cloud, glm::vec3(0, 0, 0.15f), glm::vec3(std::log(0.1f)), glm::vec4(1, 0, 0, 0), 5.0f, dc_from_rgb({1, 0, 0}));
    add_gaussian(cloud, glm::vec3(0, 0, 0.25f), glm::vec3(std::log(0.1f)), glm::vec4(1, 0, 0, 0), 5.0f, dc_from_rgb({0, 1, 0}));
    const Camera cam = identity_camera();
    ProjectedGaussian g;
    CHECK_FALSE(pg::ref::project_gaussian(cloud, 0, cam, RefOptions{}, g));
    CHECK_FALSE(pg::ref::project_gaussian(cloud, 1, cam, RefOptions{}, g));
    CHECK_FALSE(pg::ref::project_gaussian(cloud, 2, cam, RefOptions{}, g));
    CHECK(pg::ref::project_gaussian(cloud, 3, cam, RefOptions{}, g));
    const RefImage img = render_reference(cloud, cam);
    // Only the green one at z = 0.25 shows.
    CHECK(img.tau_id[pix(img, 32, 24)] == 3);
    CHECK(rgb_at(img, 32, 24).x < 0.01f);
    // A nearer plane than the default culls it too.
    RefOptions far_near;
    far_near.near = 0.3f;
    const RefImage none = render_reference(cloud, cam, far_near);
    CHECK(none.alpha[pix(none, 32, 24)] == 0.0f);
}

TEST_CASE("transparent Gaussians below 1/255 opacity are culled", "[reference]") {
    GaussianCloud cloud;
    add_gaussian(cloud, glm::vec3(0, 0, 2), glm::vec3(std::log(0.1f)), glm::vec4(1, 0, 0, 0), -30.0f, dc_from_rgb({1, 1, 1}));
    add_gaussian(cloud, glm::vec3(0, 0, 2), glm::vec3(std::log(0.1f)), glm::vec4(1, 0, 0, 0), logit(0.003f), dc_from_rgb({1, 1, 1}));
    ProjectedGaussian g;
    CHECK_FALSE(pg::ref::project_gaussian(cloud, 0, identity_camera(), RefOptions{}, g));
    CHECK_FALSE(pg::ref::project_gaussian(cloud, 1, identity_camera(), RefOptions{}, g));
    const RefImage img = render_reference(cloud, identity_camera());
    for (float a : img.alpha) CHECK(a == 0.0f);
}

TEST_CASE("blending stops once transmittance would fall below 1e-4", "[reference]") {
    GaussianCloud cloud;
    // Ten identical-looking Gaussians stacked along the axis: scale grows with z so each is
    // 2 px on screen; at pixel (32, 24) every alpha is a = 0.8 exp(-0.25 / 4.3) = 0.7548.
    for (int k = 0; k < 10; ++k) {
        const float z = 2.0f + 0.1f * k;
        add_gaussian(cloud, glm::vec3(0, 0, z), glm::vec3(std::log(0.02f * z)), glm::vec4(1, 0, 0, 0), logit(0.8f),
                     dc_from_rgb({0.5f, 0.5f, 0.5f}));
    }
    const RefImage img = render_reference(cloud, identity_camera());
    const float a = expected_alpha(0.8f, {32, 24}, 4.3f, 32, 24);
    // (1 - a)^6 = 2.2e-4 is kept, (1 - a)^7 = 5.3e-5 < 1e-4 is not blended.
    CHECK(img.contributors[pix(img, 32, 24)] == 6);
    CHECK(img.alpha[pix(img, 32, 24)] == Approx(1.0f - std::pow(1.0f - a, 6.0f)).margin(1e-6));
    CHECK(img.tau_id[pix(img, 32, 24)] == 1);  // 1 - (1-a)^2 = 0.94 >= 0.9
    CHECK(img.tau_depth[pix(img, 32, 24)] == Approx(2.1f));
    // Off-centre every alpha is small (0.023 at 5.5 px), so all ten are blended.
    CHECK(img.contributors[pix(img, 37, 24)] == 10);
}

TEST_CASE("binning never changes the result", "[reference]") {
    // Brute force over every projected Gaussian, without any bounding box.
    const auto scene = pg::ref::random_scene(7, 1500, 2);
    for (const Camera& cam : scene.cameras) {
        const RefImage img = render_reference(scene.cloud, cam);
        std::vector<ProjectedGaussian> gs;
        for (size_t i = 0; i < scene.cloud.size(); ++i) {
            ProjectedGaussian g;
            if (pg::ref::project_gaussian(scene.cloud, i, cam, RefOptions{}, g)) gs.push_back(g);
        }
        std::stable_sort(gs.begin(), gs.end(), [](const auto& l, const auto& r) { return l.depth < r.depth; });
        size_t mismatches = 0;
        for (int y = 0; y < cam.height; ++y)
            for (int x = 0; x < cam.width; ++x) {
                float T = 1.0f;
                uint32_t n = 0;
                glm::vec3 C(0.0f);
                for (const auto& g : gs) {
                    const glm::vec2 d = g.mean2d - glm::vec2(x + 0.5f, y + 0.5f);
                    const float power = -0.5f * (g.conic.x * d.x * d.x + g.conic.z * d.y * d.y) - g.conic.y * d.x * d.y;
                    if (power > 0.0f) continue;
                    const float alpha = std::min(0.99f, g.opacity * std::exp(power));
                    if (alpha < 1.0f / 255.0f) continue;
                    const float test_T = T * (1.0f - alpha);
                    if (test_T < 1e-4f) break;
                    C += g.colour * (alpha * T);
                    T = test_T;
                    ++n;
                }
                const size_t p = pix(img, x, y);
                if (img.contributors[p] != n || img.alpha[p] != 1.0f - T || img.rgb[p * 3] != C.x) ++mismatches;
            }
        CAPTURE(cam.name);
        CHECK(mismatches == 0);
    }
}

TEST_CASE("edge-case scenes render finite images", "[reference]") {
    const std::pair<const char*, pg::ref::TestScene> scenes[] = {
        {"random", pg::ref::random_scene(1, 2000, 3)},
        {"behind_camera", pg::ref::behind_camera_scene()},
        {"near_plane", pg::ref::near_plane_scene()},
        {"fullscreen", pg::ref::fullscreen_scene()},
        {"degenerate_scales", pg::ref::degenerate_scales_scene()},
        {"zero_opacity", pg::ref::zero_opacity_scene()},
        {"sh3", pg::ref::sh3_scene()},
        {"sh0", pg::ref::sh0_scene()},
        {"flat_2dgs", pg::ref::flat_2dgs_scene()},
        {"dense", pg::ref::dense_scene()},
    };
    for (const auto& [name, scene] : scenes) {
        CAPTURE(name);
        REQUIRE(scene.cloud.size() > 0);
        REQUIRE(scene.cloud.sh.size() == scene.cloud.size() * scene.cloud.coeffs() * 3);
        REQUIRE(scene.cameras.size() >= 3);
        for (const Camera& cam : scene.cameras) {
            for (bool aa : {false, true}) {
                RefOptions opt;
                opt.antialiased = aa;
                const RefImage img = render_reference(scene.cloud, cam, opt);
                size_t covered = 0;
                for (size_t p = 0; p < img.alpha.size(); ++p) {
                    REQUIRE(std::isfinite(img.rgb[p * 3]));
                    REQUIRE(std::isfinite(img.depth[p]));
                    REQUIRE(img.alpha[p] >= 0.0f);
                    REQUIRE(img.alpha[p] <= 1.0f);
                    if (img.alpha[p] > 0.0f) ++covered;
                }
                CAPTURE(cam.name, aa);
                CHECK(covered > 0);  // every camera of every scene sees something
            }
        }
    }

    // Scene-specific properties.
    const auto full = pg::ref::fullscreen_scene();
    for (const Camera& cam : full.cameras) {
        const RefImage img = render_reference(full.cloud, cam);
        for (float a : img.alpha) REQUIRE(a > 0.0f);
    }
    const auto dense = pg::ref::dense_scene();
    const RefImage img = render_reference(dense.cloud, dense.cameras[0]);
    size_t saturated = 0;
    for (size_t p = 0; p < img.alpha.size(); ++p)
        if (img.alpha[p] > 0.999f) ++saturated;  // blending stopped near T = 1e-4
    CHECK(saturated > 3000);
    const auto zero = pg::ref::zero_opacity_scene();
    for (const Camera& cam : zero.cameras) {
        const RefImage z = render_reference(zero.cloud, cam, RefOptions{.tau = 0.01f});
        for (int32_t id : z.tau_id)
            if (id >= 0) REQUIRE(zero.cloud.opacity_logit[size_t(id)] > -6.0f);
    }
}

TEST_CASE("scenes are deterministic", "[reference]") {
    const auto a = pg::ref::random_scene(42, 300, 3), b = pg::ref::random_scene(42, 300, 3);
    const auto c = pg::ref::random_scene(43, 300, 3);
    CHECK(a.cloud.mean == b.cloud.mean);
    CHECK(a.cloud.sh == b.cloud.sh);
    CHECK(a.cloud.mean != c.cloud.mean);
    pg::ref::Rng rng(5);
    CHECK(rng.next_u64() == pg::ref::Rng(5).next_u64());
    for (int i = 0; i < 1000; ++i) {
        const float u = rng.uniform();
        REQUIRE(u >= 0.0f);
        REQUIRE(u < 1.0f);
    }
}

TEST_CASE("psnr", "[reference]") {
    const std::vector<float> a(100, 0.5f);
    std::vector<float> b(100, 0.6f);
    CHECK(std::isinf(pg::ref::psnr(a, a)));
    CHECK(pg::ref::psnr(a, b) == Approx(20.0).epsilon(1e-5));          // mse 0.01
    CHECK(pg::ref::psnr(a, b, 255.0) == Approx(20.0 + 20.0 * std::log10(255.0)).epsilon(1e-5));
    b[0] = 1.5f;  // one error of 1 among 100: mse 0.01 * 99/100 + 1/100
    CHECK(pg::ref::psnr(a, b) == Approx(-10.0 * std::log10(0.0099 + 0.01)).epsilon(1e-4));
    CHECK_THROWS(pg::ref::psnr(a, std::vector<float>(99, 0.5f)));
}
