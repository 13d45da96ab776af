#include "engine/segment/prompt_encoder.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "dataset/error.h"
#include "engine/segment/pixel_candidates.h"
#include "engine/vk/context.h"
#include "shaders/segment/prompt_shared.h"

namespace pg::seg {

LiftRule parse_lift_rule(const std::string& name, const std::string& option) {
    if (name == "surface") return LiftRule::Surface;
    if (name == "tau") return LiftRule::Tau;
    throw data::InputError(option, "expected surface or tau, got '" + name + "'");
}

const char* lift_rule_name(LiftRule rule) { return rule == LiftRule::Surface ? "surface" : "tau"; }

Anchor lift_click(render::Renderer& renderer, const render::GpuScene& scene, const data::Camera& camera, double u,
                  double v, bool positive, const render::RenderSettings& settings, LiftRule rule,
                  const std::string& what, PixelBins* bins) {
    const int px = int(std::floor(u)), py = int(std::floor(v));
    if (!std::isfinite(u) || !std::isfinite(v) || px < 0 || py < 0 || px >= camera.width || py >= camera.height)
        throw data::InputError(what, "pixel (" + std::to_string(u) + ", " + std::to_string(v) + ") is off the " +
                                         std::to_string(camera.width) + "x" + std::to_string(camera.height) +
                                         " image of view " + camera.name);
    render::RenderSettings s = settings;
    s.width = s.height = 0;
    // Only what may reach the pixel is drawn, as a scene of its own: the frame's passes over a
    // few hundred Gaussians, not the scene's (on lavapipe the projection of 150 k was 9 of a
    // lift's 15 ms), whatever the scene's size. Colour plays no part in the pick: SH degree 0.
    const data::GaussianCloud& cloud = scene.cloud();
    const std::vector<uint32_t> near = bins ? bins->candidates(cloud, camera, px, py) : pixel_candidates(cloud, camera, px, py);
    auto empty = [&](float opacity) {
        return data::InputError(what, "pixel (" + std::to_string(px) + ", " + std::to_string(py) + ") of view " +
                                          camera.name + " is nearly empty (opacity " + std::to_string(opacity) + " < " +
                                          std::to_string(kMinLiftCoverage) + "): click on the object's surface");
    };
    if (near.empty()) throw empty(0.0f);
    data::GaussianCloud few;
    few.flat = cloud.flat;
    for (uint32_t i : near) {
        few.mean.push_back(cloud.mean[i]);
        few.log_scale.push_back(cloud.log_scale[i]);
        few.rotation.push_back(cloud.rotation[i]);
        few.opacity_logit.push_back(cloud.opacity_logit[i]);
        for (int c = 0; c < 3; ++c) few.sh.push_back(cloud.sh[size_t(i) * cloud.coeffs() * 3 + c]);
    }
    const render::GpuScene few_scene(renderer.context(), few);
    struct Forget {  // the renderer's last frame is few_scene's, gone when this returns
        render::Renderer& r;
        ~Forget() { r.forget_scene(); }
    } forget{renderer};
    s.window = glm::ivec4(px, py, px + 1, py + 1);
    s.lists_only = true;  // the pick walks the pixel's tile list itself
    renderer.render(few_scene, camera, s);
    render::PixelPick pick = renderer.pick(px, py);
    if (!(pick.opacity >= kMinLiftCoverage)) throw empty(pick.opacity);
    if (pick.tau_id >= 0) pick.tau_id = int32_t(near[pick.tau_id]);
    if (pick.surface_id >= 0) pick.surface_id = int32_t(near[pick.surface_id]);
    if (pick.tau_id < 0 || pick.surface_id < 0)  // cannot happen: the ray's own opacity passes tau x opacity
        throw std::runtime_error("lift_click: the fallback tau " + std::to_string(pick.tau) + " was not reached");
    const double z = rule == LiftRule::Surface ? pick.surface_depth : pick.tau_depth;
    const glm::dvec3 cam((px + 0.5 - camera.cx) / camera.fx * z, (py + 0.5 - camera.cy) / camera.fy * z, z);
    Anchor a;
    a.positive = positive;
    a.position = glm::transpose(camera.R) * (cam - camera.t);
    a.gaussian = rule == LiftRule::Surface ? pick.surface_id : pick.tau_id;
    if (pick.opacity < settings.tau) {
        a.fallback = true;
        a.coverage = pick.opacity;
    }
    return a;
}

Anchor anchor_at_point(const data::GaussianCloud& cloud, const glm::dvec3& point, bool positive) {
    Anchor a;
    a.position = point;
    a.positive = positive;
    double best = std::numeric_limits<double>::max();
    for (size_t i = 0; i < cloud.size(); ++i) {
        const double d = glm::length(glm::dvec3(cloud.mean[i]) - point);
        if (d < best) best = d, a.gaussian = int32_t(i);
    }
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
      roi_weights_(ctx, 0, vk::MemoryUse::Device, "roi weights"),
      means_window_(ctx, 0, vk::MemoryUse::Device, "centres (chunk)") {}

EncodedPrompt PromptEncoder::encode(const render::GpuScene& scene, const std::vector<Anchor>& anchors, double sigma,
                                    const RoiBox& roi, const std::vector<uint32_t>* candidates) {
    if (!(sigma > 0)) throw data::InputError("sigma", "must be positive");
    if (!(roi.length > 0 && roi.width > 0)) throw data::InputError("roi", "length and width must be positive");
    // The Gaussians looked at: the candidates (a superset of the ROI column, ascending), or all.
    const uint32_t n = candidates ? uint32_t(candidates->size()) : scene.size();
    if (n == 0) return {};
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
    if (!candidates && !scene.streamed()) {
        cmd_.dispatch("segment/click_weights", {scene.means, anchors_, weights_, flags_}, push,
                      vk::ceil_div(n, gpu::kPromptGroup));
    } else {
        // The candidates' or a streamed scene's centres from the host, a chunk at a time (a
        // resident scene's candidates at once); each chunk waits for the last to be read.
        const uint32_t chunk = scene.streamed() ? scene.chunk() : n;
        means_window_.ensure(uint64_t(std::min(chunk, n)) * 16);
        std::vector<glm::vec4> m;
        const auto& cloud = scene.cloud();
        for (uint32_t off = 0; off < n; off += chunk) {
            const uint32_t c = std::min(chunk, n - off);
            m.resize(c);
            for (uint32_t i = 0; i < c; ++i) m[i] = render::device_mean(cloud, candidates ? (*candidates)[off + i] : off + i);
            vk::upload(ctx_, means_window_, m.data(), uint64_t(c) * 16);
            gpu::ClickWeightsPush part = push;
            part.count = c;
            cmd_.dispatch("segment/click_weights",
                          {means_window_, anchors_, vk::BufferRange(weights_, off * 8ull, c * 8ull),
                           vk::BufferRange(flags_, off * 4ull, c * 4ull)},
                          part, vk::ceil_div(c, gpu::kPromptGroup));
            if (off + c < n) cmd_.submit_and_wait();
        }
    }
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
    if (candidates)
        for (auto& i : out.indices) i = (*candidates)[i];
    return out;
}

bool in_column(const RoiBox& r, const glm::dvec3& p, double factor) {
    const glm::dvec3 rel = p - r.centre;
    return std::abs(glm::dot(rel, r.length_axis)) <= factor * r.length / 2 &&
           std::abs(glm::dot(rel, r.width_axis)) <= factor * r.width / 2;
}

}  // namespace pg::seg
