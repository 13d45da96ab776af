#include "engine/segment/prompt_encoder.h"

#include <bit>
#include <cmath>
#include <stdexcept>

#include "dataset/error.h"
#include "engine/vk/context.h"
#include "shaders/segment/prompt_shared.h"

namespace pg::seg {

Anchor lift_click(render::Renderer& renderer, const render::GpuScene& scene, const data::Camera& camera, double u,
                  double v, bool positive, const render::RenderSettings& settings, const std::string& what,
                  bool rendered) {
    const int px = int(std::floor(u)), py = int(std::floor(v));
    if (!std::isfinite(u) || !std::isfinite(v) || px < 0 || py < 0 || px >= camera.width || py >= camera.height)
        throw data::InputError(what, "pixel (" + std::to_string(u) + ", " + std::to_string(v) + ") is off the " +
                                         std::to_string(camera.width) + "x" + std::to_string(camera.height) +
                                         " image of view " + camera.name);
    render::RenderSettings s = settings;
    s.width = s.height = 0;
    if (!rendered) renderer.render(scene, camera, s);
    const uint64_t pixel = uint64_t(py) * uint64_t(camera.width) + uint64_t(px);
    // One pixel of the aux image: depth, tau-depth, tau id, contributors.
    auto aux = vk::download_vector<glm::uvec4>(renderer.context(), renderer.aux_buffer(), 1, pixel * 16)[0];
    Anchor a;
    a.positive = positive;
    if (aux.z == 0xFFFFFFFFu) {
        const float coverage = vk::download_vector<glm::vec4>(renderer.context(), renderer.image_buffer(), 1, pixel * 16)[0].w;
        if (!(coverage >= kMinLiftCoverage))
            throw data::InputError(what, "pixel (" + std::to_string(px) + ", " + std::to_string(py) + ") of view " +
                                             camera.name + " is nearly empty (opacity " + std::to_string(coverage) +
                                             " < " + std::to_string(kMinLiftCoverage) +
                                             "): click on the object's surface");
        s.tau = settings.tau * coverage;
        renderer.render(scene, camera, s);
        aux = vk::download_vector<glm::uvec4>(renderer.context(), renderer.aux_buffer(), 1, pixel * 16)[0];
        if (aux.z == 0xFFFFFFFFu)  // cannot happen: the ray's own opacity passes tau x coverage < coverage
            throw std::runtime_error("lift_click: the fallback tau " + std::to_string(s.tau) + " was not reached");
        a.fallback = true;
        a.coverage = coverage;
    }
    const double z = double(std::bit_cast<float>(aux.y));
    const glm::dvec3 cam((px + 0.5 - camera.cx) / camera.fx * z, (py + 0.5 - camera.cy) / camera.fy * z, z);
    a.position = glm::transpose(camera.R) * (cam - camera.t);
    a.gaussian = int32_t(aux.z);
    return a;
}

PromptEncoder::PromptEncoder(vk::Context& ctx)
    : ctx_(ctx),
      cmd_(ctx),
      scan_(ctx),
      anchors_(ctx, 0, vk::MemoryUse::Device, "click anchors"),
      weights_(ctx, 0, vk::MemoryUse::Device, "click weights"),
      flags_(ctx, 0, vk::MemoryUse::Device, "roi flags"),
      offsets_(ctx, 0, vk::MemoryUse::Device, "roi offsets"),
      total_(ctx, 16, vk::MemoryUse::Device, "roi count"),
      indices_(ctx, 0, vk::MemoryUse::Device, "roi indices"),
      roi_weights_(ctx, 0, vk::MemoryUse::Device, "roi weights") {}

EncodedPrompt PromptEncoder::encode(const render::GpuScene& scene, const std::vector<Anchor>& anchors, double sigma,
                                    const RoiBox& roi) {
    if (!(sigma > 0)) throw data::InputError("sigma", "must be positive");
    if (!(roi.length > 0 && roi.width > 0)) throw data::InputError("roi", "length and width must be positive");
    const uint32_t n = scene.size();
    std::vector<glm::vec4> a;
    for (auto& anchor : anchors) a.push_back(glm::vec4(glm::vec3(anchor.position), anchor.positive ? 1.0f : -1.0f));
    anchors_.ensure(a.size() * sizeof(glm::vec4));
    if (!a.empty()) vk::upload(ctx_, anchors_, a.data(), a.size() * sizeof(glm::vec4));
    weights_.ensure(uint64_t(n) * 8);
    flags_.ensure(uint64_t(n) * 4);
    offsets_.ensure(uint64_t(n) * 4);
    indices_.ensure(uint64_t(n) * 4);
    roi_weights_.ensure(uint64_t(n) * 8);

    gpu::ClickWeightsPush push{n,
                               uint32_t(a.size()),
                               float(1.0 / (2.0 * sigma * sigma)),
                               float(roi.length / 2),
                               float(roi.width / 2),
                               0, 0, 0,
                               glm::vec4(glm::vec3(roi.centre), 0),
                               glm::vec4(glm::vec3(roi.length_axis), 0),
                               glm::vec4(glm::vec3(roi.width_axis), 0)};
    cmd_.begin_pass("click weights");
    cmd_.dispatch("segment/click_weights", {scene.means, anchors_, weights_, flags_}, push,
                  vk::ceil_div(n, gpu::kPromptGroup));
    cmd_.begin_pass("roi");
    scan_.exclusive(cmd_, flags_, offsets_, n, &total_, 0);
    cmd_.dispatch("segment/roi_compact", {flags_, offsets_, weights_, indices_, roi_weights_}, gpu::RoiCompactPush{n},
                  vk::ceil_div(n, gpu::kPromptGroup));
    cmd_.end_pass();
    cmd_.submit_and_wait();
    timings_ = cmd_.timings();

    EncodedPrompt out;
    uint32_t count = vk::download_vector<uint32_t>(ctx_, total_, 1)[0];
    out.indices = vk::download_vector<uint32_t>(ctx_, indices_, count);
    out.weights = vk::download_vector<glm::vec2>(ctx_, roi_weights_, count);
    return out;
}

}  // namespace pg::seg
