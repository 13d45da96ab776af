#pragma once
// A Gaussian cloud uploaded once to device buffers in the layout the shaders read.
#include <cstdint>

#include "dataset/gaussian_cloud.h"
#include "engine/vk/buffer.h"

namespace pg::render {

class GpuScene {
public:
    GpuScene(vk::Context& ctx, const data::GaussianCloud& cloud);

    uint32_t size() const { return count_; }
    int sh_degree() const { return sh_degree_; }
    uint32_t sh_floats() const { return sh_floats_; }  // SH floats per Gaussian: 3 * (degree + 1)^2

    vk::Buffer means;   // vec4: xyz, opacity logit
    vk::Buffer shapes;  // 2 x vec4 per Gaussian: log-scale xyz, quaternion wxyz
    vk::Buffer sh;      // sh_floats() per Gaussian, coefficient-major then channel

private:
    uint32_t count_ = 0, sh_floats_ = 3;
    int sh_degree_ = 0;
};

}  // namespace pg::render
