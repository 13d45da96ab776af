#include "dataset/semantic/gaussian_features.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>

namespace pg::data::semantic {

namespace {

int group_channels(const std::string& g) {
    if (g == "rgb" || g == "log_scale") return 3;
    if (g == "opacity" || g == "verticality") return 1;
    throw std::invalid_argument("unknown feature group '" + g + "' (rgb, opacity, log_scale, verticality)");
}

// The rotation's column for axis `a` (the quaternion need not be unit).
glm::vec3 axis_of(glm::vec4 q, int a) {
    const float n = glm::length(q);
    if (!(n > 0)) return glm::vec3(a == 0, a == 1, a == 2);
    q /= n;
    const float w = q.x, x = q.y, y = q.z, z = q.w;
    switch (a) {
        case 0: return {1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y)};
        case 1: return {2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x)};
        default: return {2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)};
    }
}

}  // namespace

std::vector<std::string> all_feature_groups() { return {"rgb", "opacity", "log_scale", "verticality"}; }

int feature_channels(const std::vector<std::string>& groups) {
    int c = 0;
    for (const auto& g : groups) c += group_channels(g);
    return c;
}

std::vector<float> raw_gaussian_features(const GaussianCloud& cloud, std::span<const uint32_t> indices,
                                         const std::vector<std::string>& groups, glm::dvec3 up) {
    const int channels = feature_channels(groups);
    const size_t n = indices.empty() ? cloud.size() : indices.size();
    const glm::vec3 u = glm::vec3(glm::normalize(up));
    const int coeffs = cloud.coeffs();
    std::vector<float> out(n * size_t(channels));
    for (size_t k = 0; k < n; ++k) {
        const size_t i = indices.empty() ? k : size_t(indices[k]);
        if (i >= cloud.size()) throw std::out_of_range("raw_gaussian_features: index past the cloud");
        float* f = &out[k * size_t(channels)];
        for (const auto& g : groups) {
            if (g == "rgb") {
                for (int c = 0; c < 3; ++c) {
                    const float dc = cloud.sh.empty() ? 0.0f : cloud.sh[(i * size_t(coeffs)) * 3 + size_t(c)];
                    *f++ = std::clamp(0.5f + kShC0 * dc, 0.0f, 1.0f);
                }
            } else if (g == "opacity") {
                *f++ = opacity_from_logit(cloud.opacity_logit[i]);
            } else if (g == "log_scale") {
                glm::vec3 s = cloud.log_scale[i];
                // 2DGS surfels' missing axis is kFlatLogScale: far below any real size; keep it finite.
                std::array<float, 3> v{std::max(s.x, -20.0f), std::max(s.y, -20.0f), std::max(s.z, -20.0f)};
                std::sort(v.begin(), v.end(), std::greater<>());
                for (float x : v) *f++ = x;
            } else {
                const glm::vec3 s = cloud.log_scale[i];
                const int flat = s.x <= s.y && s.x <= s.z ? 0 : (s.y <= s.z ? 1 : 2);
                *f++ = std::min(1.0f, std::abs(glm::dot(axis_of(cloud.rotation[i], flat), u)));
            }
        }
    }
    return out;
}

void finish_gaussian_features(std::span<float> rows, const std::vector<std::string>& groups, double unit) {
    const size_t channels = size_t(feature_channels(groups));
    size_t offset = 0;
    const float log_unit = float(std::log(unit));
    for (const auto& g : groups) {
        if (g == "log_scale")
            for (size_t r = 0; r + channels <= rows.size(); r += channels)
                for (size_t a = 0; a < 3; ++a) {
                    float& x = rows[r + offset + a];
                    x = std::clamp(x - log_unit, -12.0f, 12.0f);
                }
        offset += size_t(group_channels(g));
    }
}

float scale_spacing(std::span<const float> rows, const std::vector<std::string>& groups, std::span<const glm::vec3> coords,
                    double unit, size_t samples) {
    const int offset = group_offset(groups, "log_scale");
    const size_t n = coords.size(), channels = size_t(feature_channels(groups));
    if (offset < 0 || n < 2 || rows.size() < n * channels || samples == 0) return std::nanf("");
    const size_t step = std::max<size_t>(1, n / samples);
    const float log_unit = float(std::log(unit));
    std::vector<float> v;
    for (size_t r = 0; r < n; r += step) {
        float nearest = std::numeric_limits<float>::infinity();
        for (size_t q = 0; q < n; ++q) {
            const glm::vec3 d = coords[q] - coords[r];
            const float dd = glm::dot(d, d);
            if (q != r && dd > 0 && dd < nearest) nearest = dd;
        }
        if (!std::isfinite(nearest)) continue;  // every other point on this one
        const float* f = &rows[r * channels + size_t(offset)];
        v.push_back(0.5f * (f[0] + f[1]) - (0.5f * std::log(nearest) - log_unit));
    }
    if (v.empty()) return std::nanf("");
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
    return v[v.size() / 2];
}

void shift_log_scales(std::span<float> rows, const std::vector<std::string>& groups, float shift) {
    const int offset = group_offset(groups, "log_scale");
    const size_t channels = size_t(feature_channels(groups));
    if (offset < 0 || channels == 0) return;
    for (size_t r = 0; r + channels <= rows.size(); r += channels)
        for (size_t a = 0; a < 3; ++a) {
            float& x = rows[r + size_t(offset) + a];
            x = std::clamp(x + shift, -12.0f, 12.0f);
        }
}

float raise_scale_spacing(std::span<float> rows, const std::vector<std::string>& groups, std::span<const glm::vec3> coords,
                          double unit, double reference) {
    if (reference == 0) return 0.0f;
    const float k = scale_spacing(rows, groups, coords, unit);
    if (!(k < float(reference))) return 0.0f;  // NaN: nothing to measure
    shift_log_scales(rows, groups, float(reference) - k);
    return float(reference) - k;
}

int group_offset(const std::vector<std::string>& groups, const std::string& group) {
    int offset = 0;
    for (const auto& g : groups) {
        if (g == group) return offset;
        offset += group_channels(g);
    }
    return -1;
}

std::vector<float> gaussian_features(const GaussianCloud& cloud, const std::vector<std::string>& groups, glm::dvec3 up,
                                     double unit) {
    std::vector<float> out = raw_gaussian_features(cloud, {}, groups, up);
    finish_gaussian_features(out, groups, unit);
    return out;
}

}  // namespace pg::data::semantic
