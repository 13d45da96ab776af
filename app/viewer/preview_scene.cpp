#include "app/viewer/preview_scene.h"

#include <cmath>

#include "dataset/cloud_select.h"

namespace pg::viewer {

PreviewCloud make_preview_cloud(const data::GaussianCloud& cloud, uint32_t count) {
    PreviewCloud p;
    const size_t n = cloud.size();
    p.stride = count == 0 ? 1u : uint32_t(std::max<size_t>(1, (n + count - 1) / count));
    for (size_t i = 0; i < n; i += p.stride) p.ids.push_back(uint32_t(i));
    p.cloud = data::select_gaussians(cloud, p.ids);
    const float widen = 0.25f * std::log(float(p.stride));  // log of m^(1/4)
    for (auto& s : p.cloud.log_scale) s += glm::vec3(widen);
    return p;
}

ViewedScene upload_viewed_scene(vk::Context& ctx, const data::GaussianCloud& cloud, const render::SceneBudget& budget) {
    ViewedScene v;
    v.scene = std::make_unique<render::GpuScene>(ctx, cloud, budget);
    if (!v.scene->streamed()) return v;
    const uint64_t per = render::frame_bytes_per_gaussian(v.scene->sh_words());
    const uint64_t slabs = uint64_t(v.scene->slab_capacity()) * per;
    const uint64_t count = std::min<uint64_t>(cloud.size() / 4, slabs / 5 / per);
    if (count < kMinPreview) return v;
    render::SceneBudget rest = budget;
    rest.max_device_bytes = slabs - count * per;
    v.scene = std::make_unique<render::GpuScene>(ctx, cloud, rest);
    v.preview = std::make_unique<PreviewCloud>(make_preview_cloud(cloud, uint32_t(count)));
    render::SceneBudget own = budget;
    own.max_device_bytes = 0;  // it is sized to fit what the scene gave up
    v.preview_scene = std::make_unique<render::GpuScene>(ctx, v.preview->cloud, own);
    return v;
}

}  // namespace pg::viewer
