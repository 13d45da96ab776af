#pragma once
// A Gaussian cloud on the device in the layout the shaders read: uploaded once when it fits,
// else streamed in slabs (a few hundred thousand Gaussians at a time) from the host copy.
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "dataset/gaussian_cloud.h"
#include "engine/vk/buffer.h"

namespace pg::render {

// How much of the device a scene may take. Past either limit it is streamed: every frame is
// rendered slab by slab, front to back, each slab small enough that none of its per-Gaussian
// arrays crosses the binding limit and the frame's buffers fit the memory cap.
struct SceneBudget {
    uint64_t max_device_bytes = 0;   // 0: the device's memory
    uint64_t max_binding_bytes = 0;  // 0: the device's maxStorageBufferRange (tests lower it)
    bool half_sh = false;            // SH coefficients as fp16 pairs: half their memory, colour within ~1e-3
};

// Device bytes per Gaussian of one frame: the scene's arrays, the renderer's and its tile keys.
uint64_t frame_bytes_per_gaussian(uint32_t sh_words);

// Gaussian i in the layout of GpuScene's `means` (xyz, opacity logit) and `shapes` (log-scale,
// quaternion): the one place that layout is written on the host.
inline glm::vec4 device_mean(const data::GaussianCloud& cloud, size_t i) { return glm::vec4(cloud.mean[i], cloud.opacity_logit[i]); }
inline void device_shape(const data::GaussianCloud& cloud, size_t i, glm::vec4* two) {
    two[0] = glm::vec4(cloud.log_scale[i], 0.0f);
    two[1] = cloud.rotation[i];
}

class GpuScene {
public:
    // `cloud` must outlive the scene when it is streamed (slabs are gathered from it).
    GpuScene(vk::Context& ctx, const data::GaussianCloud& cloud, const SceneBudget& budget = {});

    uint32_t size() const { return count_; }
    int sh_degree() const { return sh_degree_; }
    uint32_t sh_floats() const { return sh_floats_; }  // SH values per Gaussian: 3 * (degree + 1)^2
    bool half_sh() const { return half_sh_; }
    uint32_t sh_words() const { return sh_words_; }    // 32-bit words per Gaussian in `sh`

    // Streamed: the buffers below are empty; passes gather SceneSlabs of at most
    // slab_capacity() Gaussians from the host copy.
    bool streamed() const { return streamed_; }
    uint32_t slab_capacity() const { return capacity_; }
    uint64_t binding_limit() const { return binding_; }  // bytes one binding may hold (the budget's, if lower)
    // Gaussians a pass over a streamed scene reads at a time: the slab capacity rounded down to a
    // multiple of 256, so windows into per-Gaussian outputs stay at aligned offsets.
    uint32_t chunk() const { return std::max(256u, capacity_ & ~255u); }
    const data::GaussianCloud& cloud() const { return *cloud_; }

    vk::Buffer means;   // vec4: xyz, opacity logit
    vk::Buffer shapes;  // 2 x vec4 per Gaussian: log-scale xyz, quaternion wxyz
    vk::Buffer sh;      // sh_words() per Gaussian: sh_floats() values, coefficient-major then channel,
                        // as floats or (half_sh) fp16 pairs, value j in half j % 2 of word j / 2

private:
    const data::GaussianCloud* cloud_;
    uint32_t count_ = 0, sh_floats_ = 3, sh_words_ = 3, capacity_ = 0;
    bool half_sh_ = false;
    uint64_t binding_ = 0;
    int sh_degree_ = 0;
    bool streamed_ = false;
};

// Some of a streamed scene's Gaussians in GpuScene's layout, owned by the pass that reads them
// (each has its own, so a renderer and a segmenter on two threads never share one).
class SceneSlab {
public:
    SceneSlab(vk::Context& ctx, std::string name);
    // Gathers the listed Gaussians (scene indices, at most scene.slab_capacity()) in that order.
    // The device must be done with the previous slab.
    void load(const GpuScene& scene, const std::vector<uint32_t>& ids);
    uint32_t size() const { return size_; }

    vk::Buffer means, shapes, sh;

private:
    vk::Context& ctx_;
    uint32_t size_ = 0;
};

}  // namespace pg::render
