// The per-view bins a click's lift reads: the same Gaussians, in the same order, as a scan of
// the whole cloud, for every pixel, view after view.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/segment/pixel_candidates.h"
#include "tests/reference/test_scenes.h"

using namespace pg;

TEST_CASE("pixel bins: a click's candidates are the scan's, pixel by pixel, as views come and go") {
    // Random footprints, Gaussians behind and straddling the near plane, one over every pixel,
    // degenerate and flat ones, broken ones (NaN scale, infinite opacity) that the scan keeps, and
    // faint ones at the opacity floor.
    auto scenes = std::vector<ref::TestScene>{ref::random_scene(4242, 1500, 0), ref::behind_camera_scene(),
                                              ref::near_plane_scene(), ref::fullscreen_scene(),
                                              ref::degenerate_scales_scene(), ref::flat_2dgs_scene()};
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    ref::add_gaussian(scenes[0].cloud, glm::vec3(0.1f, 0.0f, 0.0f), glm::vec3(nan, -3.0f, -3.0f), glm::vec4(1, 0, 0, 0),
                      1.0f, glm::vec3(0.0f));
    ref::add_gaussian(scenes[0].cloud, glm::vec3(-0.1f, 0.05f, 0.0f), glm::vec3(-3.0f), glm::vec4(1, 0, 0, 0), inf,
                      glm::vec3(0.0f));
    // At the renderer's opacity floor, either side of it.
    for (double f : {1.0 - 1e-7, 1.0, 1.0 + 1e-7}) {
        const double o = f / 255.0;
        ref::add_gaussian(scenes[0].cloud, glm::vec3(0.0f, -0.05f, 0.0f), glm::vec3(-2.5f), glm::vec4(1, 0, 0, 0),
                          float(std::log(o / (1.0 - o))), glm::vec3(0.0f));
    }
    size_t pixels = 0, nonempty = 0, partial = 0;  // partial: some Gaussian cannot reach the pixel
    for (const auto& scene : scenes) {
        // Three views against a bin store of two: each revisit finds its view evicted or kept.
        std::vector<data::Camera> views{scene.cameras.front()};
        for (int k = 1; k < 3; ++k) {
            data::Camera c = scene.cameras[size_t(k) % scene.cameras.size()];
            c.t += glm::dvec3(0.03 * k, -0.02 * k, 0.0);
            views.push_back(c);
        }
        seg::PixelBins bins(2);
        for (int round = 0; round < 2; ++round)
            for (size_t v : {0, 1, 2, 1, 0}) {
                const data::Camera& cam = views[v];
                for (int py = round; py < cam.height; py += 3)
                    for (int px = (int(v) + round) % 4; px < cam.width; px += 4) {
                        const auto want = seg::pixel_candidates(scene.cloud, cam, px, py);
                        const auto got = bins.candidates(scene.cloud, cam, px, py);
                        if (got != want) {
                            INFO("view " << v << " pixel " << px << ", " << py << ": " << got.size() << " vs " << want.size());
                            CHECK(got == want);
                        }
                        ++pixels;
                        nonempty += !want.empty();
                        partial += want.size() < scene.cloud.size();
                    }
            }
    }
    INFO(pixels << " pixels, " << nonempty << " with candidates, " << partial << " without some");
    CHECK(nonempty >= pixels / 4);
    CHECK(partial >= pixels / 2);
}

TEST_CASE("pixel bins: a cloud the scan splits across threads gives the bins' candidates, in order") {
    // Past 65,536 Gaussians the scan and the binning run in contiguous ranges on the cores; joined
    // in order they give the same ascending lists (a misjoined or lost range fails).
    auto scene = ref::random_scene(77, 90000, 0);
    // Footprints over more bins than a bin list takes, in every range: the unbinned list the
    // ranges join must ascend too.
    for (uint32_t i : {5u, 30000u, 44999u, 45000u, 89999u}) scene.cloud.log_scale[i] = glm::vec3(1.5f);
    const data::Camera& cam = scene.cameras.front();
    seg::PixelBins bins(1);
    size_t nonempty = 0, wide = 0;  // wide: pixels both ranges' wide footprints reach
    for (int py = 1; py < cam.height; py += 7)
        for (int px = 2; px < cam.width; px += 9) {
            const auto want = seg::pixel_candidates(scene.cloud, cam, px, py);
            const auto got = bins.candidates(scene.cloud, cam, px, py);
            CHECK(std::is_sorted(want.begin(), want.end()));
            CHECK(got == want);
            nonempty += want.size() > 1000;
            wide += std::count_if(want.begin(), want.end(), [](uint32_t i) { return i == 44999 || i == 45000; }) == 2;
        }
    CHECK(nonempty > 10);
    CHECK(wide > 10);
}
