#include "tests/reference/test_scenes.h"

#include <cmath>
#include <string>

namespace pg::ref {

using pg::data::Camera;
using pg::data::GaussianCloud;

// ---- PRNG ----------------------------------------------------------------------------

uint64_t Rng::next_u64() {
    uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

float Rng::uniform() { return float(next_u64() >> 40) * (1.0f / 16777216.0f); }

float Rng::uniform(float lo, float hi) { return lo + (hi - lo) * uniform(); }

float Rng::normal() {
    const float u1 = 1.0f - uniform();  // (0, 1]
    const float u2 = uniform();
    return std::sqrt(-2.0f * std::log(u1)) * std::cos(6.2831853071795864f * u2);
}

uint32_t Rng::below(uint32_t n) { return uint32_t((next_u64() >> 32) * uint64_t(n) >> 32); }

glm::vec4 Rng::rotation() {
    glm::vec4 q(normal(), normal(), normal(), normal());
    const float len = glm::length(q);
    if (len < 1e-3f) return glm::vec4(1, 0, 0, 0);
    return q / len * uniform(0.5f, 2.0f);
}

// ---- building blocks -----------------------------------------------------------------

Camera look_at_camera(const char* name, glm::dvec3 eye, glm::dvec3 target, glm::dvec3 up, int width, int height,
                      double fx, double fy, double cx, double cy) {
    const glm::dvec3 f = glm::normalize(target - eye);   // camera +z
    const glm::dvec3 x = glm::normalize(glm::cross(-up, f));  // camera +x (right)
    const glm::dvec3 y = glm::cross(f, x);                // camera +y (down)
    Camera cam;
    cam.name = name;
    cam.width = width;
    cam.height = height;
    cam.fx = fx;
    cam.fy = fy;
    cam.cx = cx;
    cam.cy = cy;
    cam.R = glm::transpose(glm::dmat3(x, y, f));  // rows are the camera axes in world
    cam.t = -(cam.R * eye);
    return cam;
}

size_t add_gaussian(GaussianCloud& cloud, glm::vec3 mean, glm::vec3 log_scale, glm::vec4 rotation,
                    float opacity_logit, glm::vec3 sh_dc) {
    cloud.mean.push_back(mean);
    cloud.log_scale.push_back(log_scale);
    cloud.rotation.push_back(rotation);
    cloud.opacity_logit.push_back(opacity_logit);
    const size_t first = cloud.sh.size();
    cloud.sh.resize(first + size_t(cloud.coeffs()) * 3, 0.0f);
    cloud.sh[first + 0] = sh_dc.x;
    cloud.sh[first + 1] = sh_dc.y;
    cloud.sh[first + 2] = sh_dc.z;
    return cloud.mean.size() - 1;
}

glm::vec3 dc_from_rgb(glm::vec3 rgb) { return (rgb - 0.5f) / pg::data::kShC0; }

namespace {

const glm::dvec3 kUp(0.0, -1.0, 0.0);  // COLMAP-style world: y points down

// Cameras that look at the origin from `distance`, in varied sizes and principal points.
std::vector<Camera> orbit_cameras(double distance) {
    struct Spec {
        const char* name;
        double azimuth_deg, elevation_deg;
        int w, h;
        double fx, fy, cx, cy;
    };
    const Spec specs[] = {
        {"orbit_0", 0, 10, 160, 120, 150, 150, 80, 60},
        {"orbit_1", 100, 30, 96, 80, 100, 110, 41.5, 36.0},
        {"orbit_2", 200, -15, 127, 93, 120, 120, 70.25, 40.75},
        {"orbit_3", 290, 55, 160, 120, 140, 150, 84, 57},
    };
    std::vector<Camera> cams;
    for (const Spec& s : specs) {
        const double az = glm::radians(s.azimuth_deg), el = glm::radians(s.elevation_deg);
        const glm::dvec3 eye = distance * glm::dvec3(std::cos(el) * std::sin(az), -std::sin(el),
                                                      -std::cos(el) * std::cos(az));
        cams.push_back(look_at_camera(s.name, eye, glm::dvec3(0.0), kUp, s.w, s.h, s.fx, s.fy, s.cx, s.cy));
    }
    return cams;
}

// Cameras at (0, 0, -3) looking down +z with R = identity, so view z = world z + 3; used by
// the scenes whose Gaussians are placed relative to one camera.
std::vector<Camera> frontal_cameras() {
    const glm::dvec3 eye(0.0, 0.0, -3.0);
    return {
        look_at_camera("front_160", eye, glm::dvec3(0.0), kUp, 160, 120, 150, 150, 80, 60),
        look_at_camera("front_96", eye, glm::dvec3(0.0), kUp, 96, 80, 90, 95, 40.3, 44.7),
        look_at_camera("front_127", eye, glm::dvec3(0.0), kUp, 127, 93, 110, 110, 60.5, 47.25),
    };
}

glm::vec3 random_colour(Rng& rng) { return glm::vec3(rng.uniform(0.05f, 0.95f), rng.uniform(0.05f, 0.95f), rng.uniform(0.05f, 0.95f)); }

// A typical visible Gaussian inside a box of half-side `half` around `centre`.
size_t add_random_gaussian(GaussianCloud& cloud, Rng& rng, glm::vec3 centre, float half, float min_log_scale,
                           float max_log_scale, float min_logit, float max_logit, float rest_sd) {
    const glm::vec3 mean = centre + glm::vec3(rng.uniform(-half, half), rng.uniform(-half, half), rng.uniform(-half, half));
    const glm::vec3 ls(rng.uniform(min_log_scale, max_log_scale), rng.uniform(min_log_scale, max_log_scale),
                       rng.uniform(min_log_scale, max_log_scale));
    const size_t i = add_gaussian(cloud, mean, ls, rng.rotation(), rng.uniform(min_logit, max_logit),
                                  dc_from_rgb(random_colour(rng)));
    const size_t k = size_t(cloud.coeffs());
    for (size_t c = 3; c < k * 3; ++c) cloud.sh[i * k * 3 + c] = rest_sd * rng.normal();
    return i;
}

void add_background_gaussians(GaussianCloud& cloud, Rng& rng, size_t n) {
    for (size_t j = 0; j < n; ++j)
        add_random_gaussian(cloud, rng, glm::vec3(0.0f), 1.0f, std::log(0.02f), std::log(0.2f), -2.0f, 5.0f, 0.1f);
}

}  // namespace

// ---- scenes --------------------------------------------------------------------------

TestScene random_scene(uint64_t seed, size_t n, int sh_degree) {
    TestScene s;
    s.cloud.sh_degree = sh_degree;
    Rng rng(seed);
    for (size_t j = 0; j < n; ++j)
        add_random_gaussian(s.cloud, rng, glm::vec3(0.0f), 1.0f, std::log(0.01f), std::log(0.2f), -4.0f, 6.0f, 0.15f);
    s.cameras = orbit_cameras(4.0);
    return s;
}

TestScene behind_camera_scene() {
    TestScene s;
    s.cloud.sh_degree = 1;
    Rng rng(101);
    // World z = view z - 3 for the frontal cameras.
    for (int j = 0; j < 60; ++j) {  // behind the camera, small to very large
        const glm::vec3 mean(rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-6.0f, -3.05f));
        const float ls = rng.uniform(std::log(0.05f), std::log(2.0f));
        add_gaussian(s.cloud, mean, glm::vec3(ls, ls + rng.uniform(-1, 1), ls), rng.rotation(), 4.0f,
                     dc_from_rgb(random_colour(rng)));
    }
    add_gaussian(s.cloud, glm::vec3(0, 0, -3), glm::vec3(std::log(0.5f)), glm::vec4(1, 0, 0, 0), 5.0f,
                 dc_from_rgb({1, 0, 0}));  // at the camera centre (view z = 0)
    add_gaussian(s.cloud, glm::vec3(0.01f, 0, -2.9f), glm::vec3(std::log(0.3f)), glm::vec4(1, 0, 0, 0), 5.0f,
                 dc_from_rgb({0, 1, 0}));  // view z = 0.1, in front but inside the near plane
    add_gaussian(s.cloud, glm::vec3(0, 0.02f, -2.85f), glm::vec3(std::log(1.0f)), glm::vec4(1, 0, 0, 0), 5.0f,
                 dc_from_rgb({0, 0, 1}));  // view z = 0.15, large
    add_background_gaussians(s.cloud, rng, 80);
    s.cameras = frontal_cameras();
    return s;
}

TestScene near_plane_scene() {
    TestScene s;
    s.cloud.sh_degree = 0;
    Rng rng(202);
    // Straddling the near plane (view z in [0.05, 0.4]), avoiding the razor edge |z - 0.2| < 0.005.
    for (int j = 0; j < 40; ++j) {
        float z = rng.uniform(0.05f, 0.4f);
        if (std::abs(z - kTestNear) < 0.005f) z += 0.01f;
        const glm::vec3 mean(rng.uniform(-0.15f, 0.15f), rng.uniform(-0.1f, 0.1f), z - 3.0f);
        const float ls = rng.uniform(std::log(0.005f), std::log(0.1f));
        add_gaussian(s.cloud, mean, glm::vec3(ls, ls + rng.uniform(-0.5f, 0.5f), ls), rng.rotation(),
                     rng.uniform(-1.0f, 4.0f), dc_from_rgb(random_colour(rng)));
    }
    // Large Gaussians whose centre is just in front of the near plane: huge on screen, and
    // off-axis ones exercise the frustum clamp of the Jacobian.
    const glm::vec3 big[] = {{0.0f, 0.0f, 0.21f}, {0.3f, 0.0f, 0.23f}, {-0.5f, 0.2f, 0.25f}, {0.05f, -0.6f, 0.3f}};
    for (const glm::vec3& v : big)
        add_gaussian(s.cloud, glm::vec3(v.x, v.y, v.z - 3.0f), glm::vec3(std::log(0.4f), std::log(0.2f), std::log(0.6f)),
                     rng.rotation(), rng.uniform(-2.0f, 0.0f), dc_from_rgb(random_colour(rng)));
    add_background_gaussians(s.cloud, rng, 100);
    s.cameras = frontal_cameras();
    return s;
}

TestScene fullscreen_scene() {
    TestScene s;
    s.cloud.sh_degree = 1;
    Rng rng(303);
    add_background_gaussians(s.cloud, rng, 150);
    // Behind the content: an enormous, fairly opaque Gaussian that covers every pixel.
    add_gaussian(s.cloud, glm::vec3(0.2f, -0.1f, 4.0f), glm::vec3(std::log(6.0f), std::log(5.0f), std::log(3.0f)),
                 rng.rotation(), 1.5f, dc_from_rgb({0.3f, 0.5f, 0.8f}));
    // In front of the content: a huge, faint veil.
    add_gaussian(s.cloud, glm::vec3(0.0f, 0.0f, -1.5f), glm::vec3(std::log(4.0f)), glm::vec4(1, 0, 0, 0), -2.0f,
                 dc_from_rgb({0.9f, 0.8f, 0.2f}));
    // Absurdly large (scale e^4 ~ 55 units) at the origin.
    add_gaussian(s.cloud, glm::vec3(0.0f), glm::vec3(4.0f), rng.rotation(), -1.0f, dc_from_rgb({0.5f, 0.5f, 0.5f}));
    s.cameras = frontal_cameras();
    return s;
}

TestScene degenerate_scales_scene() {
    TestScene s;
    s.cloud.sh_degree = 0;
    Rng rng(404);
    for (int j = 0; j < 240; ++j) {
        glm::vec3 ls(rng.uniform(std::log(0.02f), std::log(0.15f)), rng.uniform(std::log(0.02f), std::log(0.15f)),
                     rng.uniform(std::log(0.02f), std::log(0.15f)));
        switch (j % 6) {
            case 0: ls.z = -20.0f; break;                    // flat
            case 1: ls.y = -20.0f; ls.z = -20.0f; break;     // a line
            case 2: ls = glm::vec3(-20.0f); break;           // a point
            case 3: ls = glm::vec3(std::log(0.8f), -6.0f, -6.0f); break;  // a long needle
            case 4: ls = glm::vec3(std::log(0.3f), std::log(0.3f), -8.0f); break;  // a wide disc
            default: break;                                  // ordinary
        }
        const glm::vec3 mean(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
        add_gaussian(s.cloud, mean, ls, rng.rotation(), rng.uniform(0.0f, 5.0f), dc_from_rgb(random_colour(rng)));
    }
    // Exactly edge-on discs and axis-aligned needles for the frontal camera.
    add_gaussian(s.cloud, glm::vec3(0.3f, 0.2f, 0.0f), glm::vec3(std::log(0.3f), std::log(0.3f), -20.0f),
                 glm::vec4(std::sqrt(0.5f), std::sqrt(0.5f), 0, 0), 5.0f, dc_from_rgb({1, 1, 0}));
    add_gaussian(s.cloud, glm::vec3(-0.3f, -0.2f, 0.0f), glm::vec3(-20.0f, -20.0f, std::log(0.5f)),
                 glm::vec4(1, 0, 0, 0), 5.0f, dc_from_rgb({0, 1, 1}));  // needle along the view axis
    s.cameras = frontal_cameras();
    for (Camera& c : orbit_cameras(3.5)) s.cameras.push_back(c);
    return s;
}

TestScene zero_opacity_scene() {
    TestScene s;
    s.cloud.sh_degree = 1;
    Rng rng(505);
    for (int j = 0; j < 300; ++j) {
        const size_t i = add_random_gaussian(s.cloud, rng, glm::vec3(0.0f), 1.0f, std::log(0.02f), std::log(0.3f),
                                             -2.0f, 5.0f, 0.1f);
        switch (j % 4) {
            case 0: s.cloud.opacity_logit[i] = -30.0f; break;  // invisible
            case 1: s.cloud.opacity_logit[i] = -7.0f; break;   // o ~ 0.0009 < 1/255: culled
            case 2: s.cloud.opacity_logit[i] = -4.5f; break;   // o ~ 0.011: faint but kept
            default: break;
        }
    }
    s.cameras = orbit_cameras(4.0);
    return s;
}

TestScene sh3_scene() {
    TestScene s;
    s.cloud.sh_degree = 3;
    Rng rng(606);
    for (int j = 0; j < 400; ++j)
        add_random_gaussian(s.cloud, rng, glm::vec3(0.0f), 1.0f, std::log(0.03f), std::log(0.2f), -1.0f, 5.0f, 0.4f);
    s.cameras = orbit_cameras(4.0);
    return s;
}

TestScene sh0_scene() {
    TestScene s;
    s.cloud.sh_degree = 0;
    Rng rng(707);
    for (int j = 0; j < 400; ++j)
        add_random_gaussian(s.cloud, rng, glm::vec3(0.0f), 1.0f, std::log(0.03f), std::log(0.2f), -1.0f, 5.0f, 0.0f);
    s.cameras = orbit_cameras(4.0);
    return s;
}

TestScene flat_2dgs_scene() {
    TestScene s;
    s.cloud.sh_degree = 1;
    s.cloud.flat = true;
    Rng rng(808);
    for (int j = 0; j < 400; ++j) {
        const size_t i = add_random_gaussian(s.cloud, rng, glm::vec3(0.0f), 1.0f, std::log(0.03f), std::log(0.2f),
                                             -1.0f, 5.0f, 0.1f);
        s.cloud.log_scale[i].z = pg::data::kFlatLogScale;
        // Every fourth surfel has its normal along world x: edge-on to the frontal cameras.
        if (j % 4 == 0) s.cloud.rotation[i] = glm::vec4(std::cos(0.25f * 3.14159265f), 0.0f, std::sin(0.25f * 3.14159265f), 0.0f);
    }
    s.cameras = frontal_cameras();
    for (Camera& c : orbit_cameras(4.0)) s.cameras.push_back(c);
    return s;
}

TestScene dense_scene() {
    TestScene s;
    s.cloud.sh_degree = 0;
    Rng rng(909);
    // Opaque Gaussians packed in a small box: most pixels over it saturate after a few.
    for (int j = 0; j < 4000; ++j)
        add_random_gaussian(s.cloud, rng, glm::vec3(0.0f), 0.5f, std::log(0.06f), std::log(0.2f), 3.0f, 8.0f, 0.0f);
    add_background_gaussians(s.cloud, rng, 100);
    s.cameras = frontal_cameras();
    for (Camera& c : orbit_cameras(3.0)) s.cameras.push_back(c);
    return s;
}

TestScene crowded_tile_scene(size_t n) {
    TestScene s;
    s.cloud.sh_degree = 0;
    Rng rng(4711);
    // Identity camera, f 100, 32x32: the box x, y in [-0.07, 0.07] at z 2 projects into the
    // first tile. Opacity 0.0045 is just above 1/255, so each splat reaches at most one pixel
    // centre: the tile holds n keys while each pixel blends only a few hundred of them.
    for (size_t j = 0; j < n; ++j) {
        const glm::vec3 mean(rng.uniform(-0.155f, -0.005f), rng.uniform(-0.155f, -0.005f), rng.uniform(1.9f, 2.1f));
        add_gaussian(s.cloud, mean, glm::vec3(std::log(1e-4f)), rng.rotation(), std::log(0.0045f / 0.9955f),
                     dc_from_rgb(glm::vec3(rng.uniform(), rng.uniform(), rng.uniform())));
    }
    s.cameras.push_back(look_at_camera("crowded", glm::dvec3(0.0), glm::dvec3(0.0, 0.0, 1.0), glm::dvec3(0.0, -1.0, 0.0),
                                       32, 32, 100.0, 100.0, 16.0, 16.0));
    return s;
}

}  // namespace pg::ref
