#include "tests/reference/pixel_pick.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "shaders/render/render_shared.h"

namespace pg::ref {

namespace {

struct Hit {
    float depth, alpha, size;
    uint32_t index;
};

// The Gaussian's standard deviation along the unit world ray, as a depth extent (x cos_z).
float ray_extent(const pg::data::GaussianCloud& cloud, size_t i, glm::vec3 ray, float cos_z) {
    const glm::mat3 r = rotation_matrix(cloud.rotation[i]);
    const glm::vec3 s = glm::exp(cloud.log_scale[i]);
    const glm::vec3 along = s * glm::vec3(glm::dot(r[0], ray), glm::dot(r[1], ray), glm::dot(r[2], ray));
    return glm::length(along) * cos_z;
}

// The surfaces: each contributor's surface ordinal and weight alpha * T, the final transmittance
// and the tau Gaussian.
struct Walked {
    std::vector<uint32_t> surface;
    std::vector<float> w;
    float T = 1.0f;
    int32_t tau_id = -1;
    float tau_depth = 0;
};

Walked walk(const std::vector<Hit>& hits, float tau) {
    Walked r;
    float last_depth = 0, last_size = 0;
    uint32_t surface = 0;
    for (size_t k = 0; k < hits.size(); ++k) {
        const Hit& h = hits[k];
        const float test_T = r.T * (1.0f - h.alpha);
        if (test_T < render::gpu::kTransmittanceMin) break;
        if (k > 0 && h.depth - last_depth > render::gpu::kSurfaceGap * (h.size + last_size)) ++surface;
        r.surface.push_back(surface);
        r.w.push_back(h.alpha * r.T);
        last_depth = h.depth;
        last_size = h.size;
        r.T = test_T;
        if (r.tau_id < 0 && 1.0f - r.T >= tau) r.tau_id = int32_t(h.index), r.tau_depth = h.depth;
    }
    return r;
}

}  // namespace

RefPick pick_reference(const pg::data::GaussianCloud& cloud, const pg::data::Camera& camera, int x, int y,
                       const RefOptions& options) {
    const glm::vec2 centre(float(x) + 0.5f, float(y) + 0.5f);
    const glm::vec3 cam_ray = glm::normalize(glm::vec3((centre.x - float(camera.cx)) / float(camera.fx),
                                                       (centre.y - float(camera.cy)) / float(camera.fy), 1.0f));
    const glm::vec3 ray = glm::transpose(glm::mat3(camera.R)) * cam_ray;
    std::vector<Hit> hits;
    for (size_t i = 0; i < cloud.size(); ++i) {
        ProjectedGaussian g;
        if (!project_gaussian(cloud, i, camera, options, g)) continue;
        if (const float a = splat_alpha(g, centre); a > 0)
            hits.push_back({g.depth, a, ray_extent(cloud, i, ray, cam_ray.z), g.index});
    }
    std::sort(hits.begin(), hits.end(), [](const Hit& l, const Hit& r) {
        return l.depth < r.depth || (l.depth == r.depth && l.index < r.index);
    });
    const Walked first = walk(hits, options.tau);
    RefPick r;
    r.opacity = 1.0f - first.T;
    r.tau = options.tau;
    r.tau_id = first.tau_id;
    r.tau_depth = first.tau_depth;
    if (r.tau_id < 0 && r.opacity > 0) {
        const Walked again = walk(hits, options.tau * r.opacity);
        r.tau_id = again.tau_id;
        r.tau_depth = again.tau_depth;
        r.tau = options.tau * r.opacity;
    }
    // The surface of largest summed weight (the first of equals), then its weighted median.
    std::vector<float> total;
    for (size_t k = 0; k < first.w.size(); ++k) {
        if (first.surface[k] >= total.size()) total.resize(first.surface[k] + 1, 0.0f);
        total[first.surface[k]] += first.w[k];
    }
    uint32_t best = 0;
    for (uint32_t s = 0; s < total.size(); ++s)
        if (total[s] > total[best]) best = s;
    if (total.empty()) return r;
    r.surface_weight = total[best];
    float run = 0;
    for (size_t k = 0; k < first.w.size(); ++k)
        if (first.surface[k] == best && (run += first.w[k]) >= 0.5f * total[best]) {
            r.surface_id = int32_t(hits[k].index);
            r.surface_depth = hits[k].depth;
            break;
        }
    return r;
}

}  // namespace pg::ref
