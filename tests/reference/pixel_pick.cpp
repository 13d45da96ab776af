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

RefPick walk(const std::vector<Hit>& hits, float tau) {
    RefPick r;
    float T = 1.0f, cur_w = 0, cur_peak = 0, cur_depth = 0, last_depth = 0, last_size = 0;
    int32_t cur_id = -1;
    bool first = true;
    const auto close = [&] {
        if (cur_w > r.surface_weight) r.surface_weight = cur_w, r.surface_id = cur_id, r.surface_depth = cur_depth;
    };
    for (const Hit& h : hits) {
        const float test_T = T * (1.0f - h.alpha);
        if (test_T < render::gpu::kTransmittanceMin) break;
        const float w = h.alpha * T;
        if (!first && h.depth - last_depth > render::gpu::kSurfaceGap * (h.size + last_size)) {
            close();
            cur_w = cur_peak = 0;
        }
        first = false;
        cur_w += w;
        if (w > cur_peak) cur_peak = w, cur_id = int32_t(h.index), cur_depth = h.depth;
        last_depth = h.depth;
        last_size = h.size;
        T = test_T;
        if (r.tau_id < 0 && 1.0f - T >= tau) r.tau_id = int32_t(h.index), r.tau_depth = h.depth;
    }
    close();
    r.opacity = 1.0f - T;
    r.tau = tau;
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
    RefPick r = walk(hits, options.tau);
    if (r.tau_id < 0 && r.opacity > 0) {
        const RefPick again = walk(hits, options.tau * r.opacity);
        r.tau_id = again.tau_id;
        r.tau_depth = again.tau_depth;
        r.tau = again.tau;
    }
    return r;
}

}  // namespace pg::ref
