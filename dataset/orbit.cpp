#include "dataset/orbit.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "dataset/error.h"

namespace pg::data {

Camera look_at(const std::string& name, glm::dvec3 eye, glm::dvec3 target, glm::dvec3 up, int width, int height,
               double fov_x_degrees) {
    glm::dvec3 f = glm::normalize(target - eye);  // camera +z
    glm::dvec3 side = glm::cross(f, -up);         // camera +x before normalising; zero if f || up
    if (glm::length(side) < 1e-9) side = glm::cross(f, std::abs(f.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0));
    glm::dvec3 x = -glm::normalize(side);
    glm::dvec3 y = glm::cross(f, x);  // camera +y: down in the image
    Camera c;
    c.name = name;
    c.width = width;
    c.height = height;
    c.fx = c.fy = 0.5 * width / std::tan(glm::radians(fov_x_degrees) * 0.5);
    c.cx = 0.5 * width;
    c.cy = 0.5 * height;
    // Rows of R are the camera axes in world coordinates.
    c.R = glm::transpose(glm::dmat3(x, y, f));
    c.t = -(c.R * eye);
    return c;
}

std::vector<Camera> orbit_cameras(const GaussianCloud& cloud, glm::dvec3 up, const OrbitOptions& o) {
    if (cloud.size() == 0) throw InputError("scene", "has no Gaussians to orbit");
    if (o.count < 1 || o.count > 100000) throw InputError("--count", "must be between 1 and 100000");
    if (o.width < 1 || o.height < 1 || o.width > 16384 || o.height > 16384)
        throw InputError("--width/--height", "must be between 1 and 16384");
    if (!(o.fov_x_degrees > 1 && o.fov_x_degrees < 179)) throw InputError("--fov", "must be in (1, 179) degrees");
    if (!(glm::length(up) > 0) || !std::isfinite(glm::length(up))) throw InputError("--up", "must be a non-zero vector");
    up = glm::normalize(up);

    // Robust extent: the per-axis 5..95 percentile box, centred on its middle (the median
    // would sit in the densest part, e.g. a guitar's body, and cut off its neck).
    glm::dvec3 lo(0.0), hi(0.0);
    std::vector<float> v(cloud.size());
    for (int a = 0; a < 3; ++a) {
        for (size_t i = 0; i < v.size(); ++i) v[i] = cloud.mean[i][a];
        auto at = [&](double q) {
            size_t k = std::min(v.size() - 1, size_t(q * double(v.size() - 1)));
            std::nth_element(v.begin(), v.begin() + long(k), v.end());
            return double(v[k]);
        };
        lo[a] = at(0.05);
        hi[a] = at(0.95);
    }
    glm::dvec3 centre = 0.5 * (lo + hi);
    double radius = 0.5 * glm::length(hi - lo);
    double fov_min = std::min(glm::radians(o.fov_x_degrees),
                              2 * std::atan(std::tan(glm::radians(o.fov_x_degrees) / 2) * o.height / o.width));
    double distance = o.distance > 0 ? o.distance : std::max(radius / std::sin(fov_min / 2), 1e-3);

    // An orthonormal frame (a, b) of the plane perpendicular to up.
    glm::dvec3 a = glm::normalize(glm::cross(up, std::abs(up.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
    glm::dvec3 b = glm::cross(up, a);
    double el = glm::radians(o.elevation_degrees);
    std::vector<Camera> cams;
    for (int k = 0; k < o.count; ++k) {
        double az = 2 * M_PI * k / o.count;
        glm::dvec3 dir = std::cos(el) * (std::cos(az) * a + std::sin(az) * b) + std::sin(el) * up;
        char name[32];
        std::snprintf(name, sizeof name, "orbit_%03d", k);
        cams.push_back(look_at(name, centre + distance * dir, centre, up, o.width, o.height, o.fov_x_degrees));
    }
    return cams;
}

}  // namespace pg::data
