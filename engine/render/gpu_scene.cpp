#include "engine/render/gpu_scene.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/packing.hpp>

#include "engine/vk/context.h"

namespace pg::render {

namespace {
// The fewest Gaussians a slab may hold: below this a frame would be hundreds of passes.
constexpr uint32_t kMinSlab = 4096;
// Tile keys per Gaussian the renderer starts with (it grows them when a frame needs more).
constexpr uint64_t kKeysPerGaussian = 4;

std::string mib(uint64_t bytes) { return std::to_string((bytes + (1u << 20) - 1) >> 20) + " MiB"; }

// One Gaussian's SH values in the device layout: as they are, or fp16 pairs.
void put_sh(const float* src, uint32_t count, bool half, uint32_t* dst) {
    if (!half) {
        std::memcpy(dst, src, size_t(count) * 4);
        return;
    }
    for (uint32_t j = 0; j < count; j += 2)
        dst[j / 2] = glm::packHalf2x16(glm::vec2(src[j], j + 1 < count ? src[j + 1] : 0.0f));
}
}  // namespace

uint64_t frame_bytes_per_gaussian(uint32_t sh_words) {
    const uint64_t scene = 16 + 32 + 4ull * sh_words;
    // splats 48, tiles touched 4 (and in depth order 4), key offsets 4, tile rect 8, depth key 4,
    // depth order 4, slab ids 4
    const uint64_t renderer = 48 + 4 + 4 + 4 + 8 + 4 + 4 + 4;
    // keys and values, and the sort's scratch copies of both
    const uint64_t keys = kKeysPerGaussian * (4 + 4 + 8);
    return scene + renderer + keys;
}

GpuScene::GpuScene(vk::Context& ctx, const data::GaussianCloud& cloud, const SceneBudget& budget) : cloud_(&cloud) {
    if (cloud.size() > std::numeric_limits<uint32_t>::max() / 8)
        throw std::runtime_error("scene has " + std::to_string(cloud.size()) + " Gaussians, more than the renderer indexes");
    count_ = uint32_t(cloud.size());
    sh_degree_ = cloud.sh_degree;
    sh_floats_ = uint32_t(3 * cloud.coeffs());
    half_sh_ = budget.half_sh;
    sh_words_ = half_sh_ ? (sh_floats_ + 1) / 2 : sh_floats_;

    // The widest per-Gaussian array sets how many Gaussians one binding holds.
    const auto& info = ctx.info();
    uint64_t binding = info.max_storage_buffer_range;
    if (budget.max_binding_bytes) binding = std::min<uint64_t>(binding, budget.max_binding_bytes);
    binding_ = binding;
    const uint64_t widest = std::max<uint64_t>({48, 32, 4ull * sh_words_});
    uint64_t by_binding = binding / widest;
    // Tile keys are 4-byte arrays of kKeysPerGaussian per Gaussian.
    by_binding = std::min(by_binding, binding / (4 * kKeysPerGaussian));
    const uint64_t memory = budget.max_device_bytes ? budget.max_device_bytes : info.device_memory_bytes;
    const uint64_t per = frame_bytes_per_gaussian(sh_words_);
    const uint64_t by_memory = memory / per;
    const uint64_t fit = std::min(by_binding, by_memory);
    if (fit < kMinSlab && fit < count_) {
        if (by_binding < kMinSlab)
            throw std::runtime_error("a binding of " + std::to_string(binding) + " bytes holds only " +
                                     std::to_string(by_binding) + " of this scene's Gaussians (" +
                                     std::to_string(widest) + " bytes each in the widest array); slabs need " +
                                     std::to_string(kMinSlab));
        throw std::runtime_error("scene of " + std::to_string(count_) + " Gaussians (SH degree " +
                                 std::to_string(sh_degree_) + ") needs at least " + mib(uint64_t(kMinSlab) * per) +
                                 " of device memory for slabs of " + std::to_string(kMinSlab) + " Gaussians; " +
                                 mib(memory) + (budget.max_device_bytes ? " allowed" : " available"));
    }
    streamed_ = fit < count_;
    capacity_ = streamed_ ? uint32_t(fit) : count_;
    if (streamed_) return;
    std::vector<glm::vec4> m(count_), s(2 * size_t(count_));
    for (uint32_t i = 0; i < count_; ++i) {
        m[i] = device_mean(cloud, i);
        device_shape(cloud, i, &s[2 * size_t(i)]);
    }
    means = vk::upload_vector(ctx, m, "means");
    shapes = vk::upload_vector(ctx, s, "shapes");
    if (!half_sh_) {
        sh = vk::upload_vector(ctx, cloud.sh, "sh");
        return;
    }
    std::vector<uint32_t> packed(size_t(count_) * sh_words_);
    for (uint32_t i = 0; i < count_; ++i) put_sh(&cloud.sh[size_t(i) * sh_floats_], sh_floats_, true, &packed[size_t(i) * sh_words_]);
    sh = vk::upload_vector(ctx, packed, "sh (fp16)");
}

SceneSlab::SceneSlab(vk::Context& ctx, std::string name)
    : means(ctx, 0, vk::MemoryUse::Device, name + " means"),
      shapes(ctx, 0, vk::MemoryUse::Device, name + " shapes"),
      sh(ctx, 0, vk::MemoryUse::Device, name + " sh"),
      ctx_(ctx) {}

void SceneSlab::load(const GpuScene& scene, const std::vector<uint32_t>& ids) {
    if (!scene.streamed()) throw std::logic_error("SceneSlab::load: the scene is resident");
    if (ids.size() > scene.slab_capacity()) throw std::logic_error("SceneSlab::load: more Gaussians than a slab holds");
    const data::GaussianCloud& cloud = scene.cloud();
    const uint32_t n = uint32_t(ids.size()), shf = scene.sh_floats(), words = scene.sh_words();
    const bool half = scene.half_sh();
    means.ensure(std::max<uint64_t>(uint64_t(scene.slab_capacity()) * 16, 16));
    shapes.ensure(std::max<uint64_t>(uint64_t(scene.slab_capacity()) * 32, 16));
    sh.ensure(std::max<uint64_t>(uint64_t(scene.slab_capacity()) * 4 * words, 16));
    // On unified memory the Gaussians are gathered straight into the mapped buffers.
    const bool direct = means.mapped() && shapes.mapped() && sh.mapped();
    std::vector<glm::vec4> host_m(direct ? 0 : n), host_s(direct ? 0 : 2 * size_t(n));
    std::vector<uint32_t> host_c(direct ? 0 : size_t(n) * words);
    glm::vec4* m = direct ? means.as<glm::vec4>() : host_m.data();
    glm::vec4* s = direct ? shapes.as<glm::vec4>() : host_s.data();
    uint32_t* c = direct ? sh.as<uint32_t>() : host_c.data();
    for (uint32_t k = 0; k < n; ++k) {
        const uint32_t i = ids[k];
        m[k] = device_mean(cloud, i);
        device_shape(cloud, i, &s[2 * size_t(k)]);
        put_sh(&cloud.sh[size_t(i) * shf], shf, half, &c[size_t(k) * words]);
    }
    if (!direct && n) {
        vk::upload(ctx_, means, m, size_t(n) * sizeof(glm::vec4));
        vk::upload(ctx_, shapes, s, 2 * size_t(n) * sizeof(glm::vec4));
        vk::upload(ctx_, sh, c, size_t(n) * words * 4);
    }
    size_ = n;
}

}  // namespace pg::render
