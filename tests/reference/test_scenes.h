#pragma once
// Small deterministic clouds and cameras for renderer tests: a random scene and one scene
// per edge case of the splat pipeline. Every scene has a few small cameras, some with an
// off-centre principal point and sizes that are not multiples of a tile.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "dataset/camera.h"
#include "dataset/gaussian_cloud.h"

namespace pg::ref {

struct TestScene {
    pg::data::GaussianCloud cloud;
    std::vector<pg::data::Camera> cameras;
};

// Deterministic PRNG (splitmix64) with its own float mapping, so every platform and
// standard library produces the same scenes.
class Rng {
public:
    explicit Rng(uint64_t seed) : state_(seed) {}
    uint64_t next_u64();
    float uniform();                      // [0, 1), 24 random bits
    float uniform(float lo, float hi);    // [lo, hi)
    float normal();                       // Box-Muller, mean 0, sd 1
    uint32_t below(uint32_t n);           // [0, n)
    glm::vec4 rotation();                 // random unnormalised quaternion (w, x, y, z)

private:
    uint64_t state_;
};

// World-to-camera (OpenCV) pinhole camera at eye looking at target; `up` is the world
// direction that appears upwards in the image.
pg::data::Camera look_at_camera(const char* name, glm::dvec3 eye, glm::dvec3 target, glm::dvec3 up,
                                int width, int height, double fx, double fy, double cx, double cy);

// Appends one Gaussian; sh_dc is the DC coefficient per channel, the rest start at zero.
size_t add_gaussian(pg::data::GaussianCloud& cloud, glm::vec3 mean, glm::vec3 log_scale, glm::vec4 rotation,
                    float opacity_logit, glm::vec3 sh_dc);
// SH DC coefficient that gives `rgb` (view-independent part 0.5 + C0 * dc).
glm::vec3 dc_from_rgb(glm::vec3 rgb);

// Gaussians in a box of side ~2 around the origin, seen by an orbit of cameras at ~4 units.
TestScene random_scene(uint64_t seed, size_t n, int sh_degree);

// Edge cases. World up is -y (COLMAP style); cameras look at the origin.
TestScene behind_camera_scene();     // Gaussians behind / at the camera, some large, plus visible ones
TestScene near_plane_scene();        // Gaussians straddling z = 0.2, large ones just in front of it
TestScene fullscreen_scene();        // a huge Gaussian covering every pixel, plus normal ones
TestScene degenerate_scales_scene(); // log_scale -20 on 1, 2 or 3 axes; very elongated ones
TestScene zero_opacity_scene();      // opacity logits -30 mixed with visible Gaussians
TestScene sh3_scene();               // degree 3 with strong view-dependent terms
TestScene sh0_scene();               // degree 0 only
TestScene flat_2dgs_scene();         // flat surfels, log_scale.z = kFlatLogScale, some edge-on
TestScene dense_scene();             // many opaque overlapping Gaussians: T reaches 1e-4 early
TestScene crowded_tile_scene(size_t n);  // n faint point-like Gaussians in one tile, none saturating

// Near plane the edge-case scenes are built around (the renderer default).
constexpr float kTestNear = 0.2f;

}  // namespace pg::ref
