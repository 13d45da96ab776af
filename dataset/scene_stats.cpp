#include "dataset/scene_stats.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace pg::data {

namespace {

Percentiles percentiles(std::vector<float>& v) {
    Percentiles out;
    if (v.empty()) return out;
    std::sort(v.begin(), v.end());
    for (size_t k = 0; k < Percentiles::kLevels.size(); ++k) {
        const double rank = Percentiles::kLevels[k] / 100.0 * static_cast<double>(v.size() - 1);
        const size_t lo = static_cast<size_t>(std::floor(rank));
        const size_t hi = std::min(lo + 1, v.size() - 1);
        const double t = rank - static_cast<double>(lo);
        out.value[k] = static_cast<float>(v[lo] * (1.0 - t) + v[hi] * t);
    }
    return out;
}

}  // namespace

float Percentiles::p(float level) const {
    for (size_t k = 0; k < kLevels.size(); ++k)
        if (kLevels[k] == level) return value[k];
    return std::numeric_limits<float>::quiet_NaN();
}

SceneStats compute_stats(const GaussianCloud& cloud) {
    SceneStats s;
    s.count = cloud.size();
    s.sh_degree = cloud.sh_degree;
    s.flat = cloud.flat;
    s.format = cloud.format;

    const float inf = std::numeric_limits<float>::infinity();
    glm::vec3 lo(inf), hi(-inf);
    bool any_mean = false;
    std::vector<float> opacity, max_scale;
    opacity.reserve(s.count);
    max_scale.reserve(s.count);
    auto count_bad = [&](float v) { s.non_finite += !std::isfinite(v); };

    for (size_t i = 0; i < s.count; ++i) {
        const glm::vec3& m = cloud.mean[i];
        if (std::isfinite(m.x) && std::isfinite(m.y) && std::isfinite(m.z)) {
            lo = glm::min(lo, m);
            hi = glm::max(hi, m);
            any_mean = true;
        }
        for (int k = 0; k < 3; ++k) count_bad(m[k]);
        if (i < cloud.log_scale.size()) {
            const glm::vec3& ls = cloud.log_scale[i];
            for (int k = 0; k < 3; ++k) count_bad(ls[k]);
            // The flat third axis of a 2DGS surfel is not a size.
            float big = cloud.flat ? std::max(ls.x, ls.y) : std::max({ls.x, ls.y, ls.z});
            if (std::isfinite(big)) max_scale.push_back(std::exp(big));
        }
        if (i < cloud.rotation.size())
            for (int k = 0; k < 4; ++k) count_bad(cloud.rotation[i][k]);
        if (i < cloud.opacity_logit.size()) {
            const float o = cloud.opacity_logit[i];
            count_bad(o);
            if (!std::isnan(o)) opacity.push_back(opacity_from_logit(o));
        }
    }
    for (float v : cloud.sh) count_bad(v);

    if (any_mean) {
        s.bounds_min = lo;
        s.bounds_max = hi;
    }
    s.opacity = percentiles(opacity);
    s.max_scale = percentiles(max_scale);
    return s;
}

}  // namespace pg::data
