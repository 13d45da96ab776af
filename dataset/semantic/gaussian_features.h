#pragma once
// Per-Gaussian appearance and shape features, for models that see more than click maps (the
// semantic model, and interactive models whose config lists feature groups). A model's config
// lists the groups it was trained on, by these names; training and inference both compute them
// here, so they cannot drift apart.
//   rgb          3  colour of the SH DC term, clamped to [0, 1]
//   opacity      1  sigmoid of the logit
//   log_scale    3  the three axis scales' natural logs, largest first, less log(unit): the unit
//                   is the model's voxel in world units, so 0 means "as large as a voxel"
//   verticality  1  |n . up| for n the flattest axis (1: a horizontal surface, 0: a wall); the
//                   sign of a surfel's normal is arbitrary, and only the angle to up survives the
//                   rotations about up that training applies
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "dataset/gaussian_cloud.h"

namespace pg::data::semantic {

// The groups above, in the order a semantic model lists them.
std::vector<std::string> all_feature_groups();

// Channels of these groups together; std::invalid_argument naming an unknown group.
int feature_channels(const std::vector<std::string>& groups);

// [n, feature_channels(groups)] row-major, in the order of `groups`. `up` need not be unit.
std::vector<float> gaussian_features(const GaussianCloud& cloud, const std::vector<std::string>& groups, glm::dvec3 up,
                                     double unit);

// The same in two steps, so a caller can keep rows and apply the unit later (an interactive
// model's unit is its voxel in the frame of each click): rows of `indices` (every Gaussian when
// empty) with log scales as they are, then the unit and the clamps in place. gaussian_features is
// exactly the two together. std::out_of_range for an index past the cloud.
std::vector<float> raw_gaussian_features(const GaussianCloud& cloud, std::span<const uint32_t> indices,
                                         const std::vector<std::string>& groups, glm::dvec3 up);
void finish_gaussian_features(std::span<float> rows, const std::vector<std::string>& groups, double unit);

// How large a batch's Gaussians are against how densely the batch samples the surface: the
// median, over up to `samples` of its rows (evenly spaced), of the mean of the two largest log
// scales (as finished: in the unit) less the log of the distance to the row's nearest other point
// in that unit. A denser capture, or an ROI split into more batches, has smaller Gaussians
// than its batch's spacing: the model's log-scale inputs shift (seed 5501 at the generator's
// default density: about 0.5 below the density-0.15 data the shipped model saw). NaN without a
// log_scale group or with fewer than two points.
float scale_spacing(std::span<const float> rows, const std::vector<std::string>& groups, std::span<const glm::vec3> coords,
                    double unit, size_t samples = 256);

// Adds `shift` to every row's three log scales (then the same clamps as finishing).
void shift_log_scales(std::span<float> rows, const std::vector<std::string>& groups, float shift);

// A model's scale_spacing applied to one batch, as inference and training both do: where the
// batch's scale_spacing is below `reference`, its log scales are raised by the difference.
// Returns the shift (0: none; also for reference 0, which means no raise).
float raise_scale_spacing(std::span<float> rows, const std::vector<std::string>& groups, std::span<const glm::vec3> coords,
                          double unit, double reference);

// The first channel of `group` within rows of `groups`; -1 when absent.
int group_offset(const std::vector<std::string>& groups, const std::string& group);

}  // namespace pg::data::semantic
