#include "dataset/camera.h"

#include <stdexcept>

namespace pg::data {

glm::dmat4 Camera::world_to_camera() const {
    glm::dmat4 m(R);  // glm is column-major: m[column][row]
    m[3] = glm::dvec4(t, 1.0);
    return m;
}

bool Camera::has_distortion() const {
    for (double k : distortion)
        if (k != 0.0) return true;
    return false;
}

std::optional<glm::dvec2> Camera::project(const glm::dvec3& world) const {
    const glm::dvec3 p = R * world + t;
    if (p.z <= 1e-6) return std::nullopt;
    return glm::dvec2(fx * p.x / p.z + cx, fy * p.y / p.z + cy);
}

Camera Camera::resized(int new_width, int new_height) const {
    if (width <= 0 || height <= 0 || new_width <= 0 || new_height <= 0)
        throw std::invalid_argument("Camera::resized: sizes must be positive (camera '" + name + "' is " +
                                    std::to_string(width) + "x" + std::to_string(height) + ", asked for " +
                                    std::to_string(new_width) + "x" + std::to_string(new_height) + ")");
    Camera out = *this;
    const double sx = double(new_width) / width, sy = double(new_height) / height;
    out.width = new_width;
    out.height = new_height;
    // Pixel coordinates with the image's top-left corner at 0: the principal point scales
    // with the image like the focal length (COLMAP and 3DGS use this convention).
    out.fx = fx * sx;
    out.cx = cx * sx;
    out.fy = fy * sy;
    out.cy = cy * sy;
    return out;  // distortion acts on normalized coordinates and is unchanged
}

}  // namespace pg::data
