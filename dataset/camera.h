#pragma once
// One camera type for every importer: world-to-camera in the OpenCV convention
// (x right, y down, z forward), pinhole intrinsics in pixels.
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace pg::data {

struct Camera {
    std::string name;          // image name without directory, used to name outputs
    int width = 0, height = 0;
    double fx = 0, fy = 0, cx = 0, cy = 0;
    glm::dmat3 R{1.0};         // x_cam = R * x_world + t
    glm::dvec3 t{0.0};
    // Lens model as read ("PINHOLE", "OPENCV", ...) and its distortion coefficients;
    // rendering is pinhole, so importers warn once when these are non-zero.
    std::string model = "PINHOLE";
    std::vector<double> distortion;

    glm::dvec3 position() const { return -glm::transpose(R) * t; }
    glm::dvec3 forward() const { return glm::transpose(R)[2]; }  // camera +z in world
    glm::dvec3 up() const { return -glm::transpose(R)[1]; }      // camera -y in world
    glm::dmat4 world_to_camera() const;
    // Pixel coordinates (top-left corner at 0) of a world point; none behind or at the camera.
    std::optional<glm::dvec2> project(const glm::dvec3& world) const;
    bool has_distortion() const;
    // Same camera at another resolution: intrinsics scale with the image.
    Camera resized(int new_width, int new_height) const;
};

}  // namespace pg::data
