#pragma once
// The scene's up axis, never assumed: from the cameras (they are mostly held upright), from
// the user, or from the dominant plane of the Gaussians (the ground or a table top).
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "dataset/camera.h"
#include "dataset/gaussian_cloud.h"

namespace pg::data {

// Normalised mean of the cameras' up directions (camera -y in world); throws InputError
// when there are no cameras or they disagree so much that the mean is near zero.
glm::dvec3 up_from_cameras(const std::vector<Camera>& cameras);

// RANSAC fit of the plane holding the most Gaussian centres (seeded, deterministic); up is
// its normal, pointing to the side where most of the other Gaussians are.
glm::dvec3 up_from_ground_plane(const GaussianCloud& cloud, uint64_t seed = 1);

// Two unit vectors spanning the plane perpendicular to `up`, fixed for a given up, so the
// ROI's length and width directions are reproducible.
void horizontal_axes(glm::dvec3 up, glm::dvec3& length_axis, glm::dvec3& width_axis);

}  // namespace pg::data
