#include "engine/render/gpu_scene.h"

#include <limits>
#include <stdexcept>
#include <vector>

#include <glm/glm.hpp>

namespace pg::render {

GpuScene::GpuScene(vk::Context& ctx, const data::GaussianCloud& cloud) {
    if (cloud.size() > std::numeric_limits<uint32_t>::max() / 8)
        throw std::runtime_error("scene has " + std::to_string(cloud.size()) + " Gaussians, more than the renderer indexes");
    count_ = uint32_t(cloud.size());
    sh_degree_ = cloud.sh_degree;
    sh_floats_ = uint32_t(3 * cloud.coeffs());

    std::vector<glm::vec4> m(count_), s(2 * size_t(count_));
    for (uint32_t i = 0; i < count_; ++i) {
        m[i] = glm::vec4(cloud.mean[i], cloud.opacity_logit[i]);
        s[2 * i] = glm::vec4(cloud.log_scale[i], 0.0f);
        s[2 * i + 1] = cloud.rotation[i];
    }
    means = vk::upload_vector(ctx, m, "means");
    shapes = vk::upload_vector(ctx, s, "shapes");
    sh = vk::upload_vector(ctx, cloud.sh, "sh");
}

}  // namespace pg::render
