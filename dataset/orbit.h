#pragma once
// Cameras made rather than read: a look-at camera, and an orbit around a scene for scenes
// that come without cameras (SuperSplat exports, .splat files).
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "dataset/camera.h"
#include "dataset/gaussian_cloud.h"

namespace pg::data {

// A pinhole camera at `eye` looking at `target`; `up` is the world direction that appears
// upwards in the image. Horizontal field of view in degrees, centred principal point.
Camera look_at(const std::string& name, glm::dvec3 eye, glm::dvec3 target, glm::dvec3 up, int width, int height,
               double fov_x_degrees);

struct OrbitOptions {
    int count = 24;
    double elevation_degrees = 20;  // above the plane perpendicular to up
    int width = 1280, height = 720;
    double fov_x_degrees = 60;
    double distance = 0;            // 0: fit the scene's central 90% in view
};

// Cameras evenly spaced on a circle around the middle of the scene's central 90% box,
// named orbit_000, orbit_001, ...
std::vector<Camera> orbit_cameras(const GaussianCloud& cloud, glm::dvec3 up, const OrbitOptions& options);

}  // namespace pg::data
