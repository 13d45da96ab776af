#pragma once
// The --up argument shared by the CLI and the viewer.
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "dataset/camera.h"
#include "dataset/gaussian_cloud.h"

namespace pg::app {

// "-y", "z", or "x,y,z" -> a unit vector; InputError naming --up otherwise.
glm::dvec3 parse_up(const std::string& s);

// "cameras" (mean camera up), "ground" (plane fit) or an explicit axis.
glm::dvec3 resolve_up(const std::string& spec, const std::vector<data::Camera>& cameras,
                      const data::GaussianCloud& cloud);

}  // namespace pg::app
