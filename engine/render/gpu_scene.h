#pragma once
// A Gaussian cloud on the device in the layout the shaders read: uploaded once when it fits,
// else streamed in slabs (a few hundred thousand Gaussians at a time) from the host copy.
#include <cstdint>
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
};

// Device bytes per Gaussian of one frame: the scene's arrays, the renderer's and its tile keys.
uint64_t frame_bytes_per_gaussian(uint32_t sh_floats);

class GpuScene {
public:
    // `cloud` must outlive the scene when it is streamed (slabs are gathered from it).
    GpuScene(vk::Context& ctx, const data::GaussianCloud& cloud, const SceneBudget& budget = {});

    uint32_t size() const { return count_; }
    int sh_degree() const { return sh_degree_; }
    uint32_t sh_floats() const { return sh_floats_; }  // SH floats per Gaussian: 3 * (degree + 1)^2

    // Streamed: the device buffers hold one slab of at most slab_capacity() Gaussians at a time.
    bool streamed() const { return streamed_; }
    uint32_t slab_capacity() const { return capacity_; }
    const data::GaussianCloud& cloud() const { return *cloud_; }
    // Gathers the listed Gaussians (scene indices) into the device buffers, in that order.
    void load_slab(const std::vector<uint32_t>& ids);
    uint32_t loaded() const { return loaded_; }  // Gaussians in the device buffers now

    vk::Buffer means;   // vec4: xyz, opacity logit
    vk::Buffer shapes;  // 2 x vec4 per Gaussian: log-scale xyz, quaternion wxyz
    vk::Buffer sh;      // sh_floats() per Gaussian, coefficient-major then channel

private:
    void upload(const std::vector<uint32_t>* ids, uint32_t n);

    vk::Context& ctx_;
    const data::GaussianCloud* cloud_;
    uint32_t count_ = 0, sh_floats_ = 3, capacity_ = 0, loaded_ = 0;
    int sh_degree_ = 0;
    bool streamed_ = false;
};

}  // namespace pg::render
