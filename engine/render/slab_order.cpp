#include "engine/render/slab_order.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>

#include "shaders/render/render_shared.h"

namespace pg::render {

void radix_sort_by_key(std::vector<std::pair<uint32_t, uint32_t>>& items) {
    std::vector<std::pair<uint32_t, uint32_t>> tmp(items.size());
    for (int shift = 0; shift < 32; shift += 8) {
        std::array<size_t, 257> start{};
        for (auto& it : items) ++start[((it.first >> shift) & 0xFFu) + 1];
        if (start[1 + ((items.empty() ? 0 : items[0].first >> shift) & 0xFFu)] == items.size()) continue;  // one bucket
        for (int b = 0; b < 256; ++b) start[b + 1] += start[b];
        for (auto& it : items) tmp[start[(it.first >> shift) & 0xFFu]++] = it;
        items.swap(tmp);
    }
}

std::vector<std::pair<uint32_t, uint32_t>> slab_order(const data::GaussianCloud& cloud, const data::Camera& camera,
                                                      const RenderSettings& settings) {
    // What preprocess can keep: in front of the near plane, opacity over kAlphaMin, and a
    // footprint that may reach the image. The footprint bound is preprocess's own math with
    // every factor at its largest: the EWA covariance's largest eigenvalue is at most
    // |J|_F^2 sigma_max^2, plus the low-pass term, times the largest squared extent 2 ln 255.
    // The key is preprocess's too: the bits of the float view depth.
    const glm::mat4 view(camera.world_to_camera());
    const float near = settings.near;
    const float fx = float(camera.fx), fy = float(camera.fy), cx = float(camera.cx), cy = float(camera.cy);
    const float w = float(camera.width), h = float(camera.height);
    const glm::ivec4& win = settings.window;
    const bool windowed = win.z > win.x && win.w > win.y;
    const float x0 = windowed ? float(win.x) : 0.0f, x1 = windowed ? float(win.z) : w;
    const float y0 = windowed ? float(win.y) : 0.0f, y1 = windowed ? float(win.w) : h;
    const float limx = gpu::kFovClamp * 0.5f * w / fx, limy = gpu::kFovClamp * 0.5f * h / fy;
    const float extent2 = 2.0f * std::log(255.0f) * 1.001f + 1e-3f;
    const float min_logit = std::log(gpu::kAlphaMin / (1.0f - gpu::kAlphaMin));
    std::vector<std::pair<uint32_t, uint32_t>> order;
    order.reserve(cloud.size() / 2);
    for (size_t i = 0; i < cloud.size(); ++i) {
        if (cloud.opacity_logit[i] < min_logit) continue;
        const glm::vec3 p = glm::vec3(view * glm::vec4(cloud.mean[i], 1.0f));
        if (!(p.z > near)) continue;
        const glm::vec3 ls = cloud.log_scale[i];
        const float s2 = std::exp(2.0f * std::max({ls.x, ls.y, ls.z}));
        const float ux = std::clamp(p.x / p.z, -limx, limx), uy = std::clamp(p.y / p.z, -limy, limy);
        const float j2 = (fx * fx * (1 + ux * ux) + fy * fy * (1 + uy * uy)) / (p.z * p.z);
        const float r = std::sqrt(extent2 * (j2 * s2 + gpu::kLowPass)) + 2.0f;
        const float u = fx * p.x / p.z + cx, v = fy * p.y / p.z + cy;
        if (u + r < x0 || u - r > x1 || v + r < y0 || v - r > y1) continue;  // NaN: kept, as preprocess would
        order.emplace_back(std::bit_cast<uint32_t>(p.z), uint32_t(i));
    }
    radix_sort_by_key(order);
    return order;
}

}  // namespace pg::render
