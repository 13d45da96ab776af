#pragma once
// Summary numbers of a loaded scene, for `pointgauss info` and sanity checks.
#include <array>
#include <cstddef>

#include <glm/glm.hpp>

#include "dataset/gaussian_cloud.h"

namespace pg::data {

// Percentiles p1, p5, p25, p50, p75, p95, p99 (linear interpolation between ranks, as
// numpy's default), over the finite values only; all zero for an empty set.
struct Percentiles {
    static constexpr std::array<float, 7> kLevels = {1, 5, 25, 50, 75, 95, 99};
    std::array<float, 7> value{};  // value[k] is percentile kLevels[k]
    float p(float level) const;    // one of kLevels
};

struct SceneStats {
    size_t count = 0;
    int sh_degree = 0;
    bool flat = false;
    SceneFormat format = SceneFormat::Synthetic;
    glm::vec3 bounds_min{0.0f}, bounds_max{0.0f};  // of the finite means; zero if none
    Percentiles opacity;    // sigmoid of the opacity logit
    Percentiles max_scale;  // exp of the largest log-scale of each Gaussian
    size_t non_finite = 0;  // NaN/Inf values among means, scales, rotations, opacities, SH
};

SceneStats compute_stats(const GaussianCloud& cloud);

}  // namespace pg::data
