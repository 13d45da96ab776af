#include "engine/segment/warm_up.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "dataset/orbit.h"
#include "engine/render/gpu_scene.h"
#include "shaders/segment/graph_shared.h"

namespace pg::seg {

namespace {

// A 4 x 4 m floor of 60 x 60 Gaussians and `objects` cubes of 7^3 standing on it in rows of
// four, each its own colour: enough nodes for the walk's multigrid levels, the coarse graph and
// scans of more than one block.
struct MadeUpScene {
    data::GaussianCloud cloud;
    glm::dvec3 across{0.0}, along{0.0};  // the floor's axes
    std::vector<glm::dvec3> tops;         // a point on each cube's top face, to click
};

MadeUpScene made_up_scene(glm::dvec3 up, size_t objects) {
    MadeUpScene s;
    const glm::dvec3 a = s.across = glm::normalize(glm::cross(up, std::abs(up.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
    const glm::dvec3 b = s.along = glm::cross(up, a);
    auto add = [&](glm::dvec3 p, glm::vec3 rgb) {
        const size_t i = s.cloud.size();
        s.cloud.resize(i + 1);
        s.cloud.mean[i] = glm::vec3(p);
        s.cloud.log_scale[i] = glm::vec3(std::log(0.04f));
        s.cloud.rotation[i] = {1, 0, 0, 0};
        s.cloud.opacity_logit[i] = 4.0f;
        for (int c = 0; c < 3; ++c) s.cloud.sh[i * 3 + c] = (rgb[c] - 0.5f) / data::kShC0;
    };
    for (int i = 0; i < 60; ++i)
        for (int j = 0; j < 60; ++j)
            add(a * (-2.0 + 0.067 * i) + b * (-2.0 + 0.067 * j), glm::vec3(0.45f + 0.1f * float((i + j) % 2), 0.45f, 0.4f));
    for (size_t o = 0; o < objects; ++o) {
        const glm::dvec3 base = a * (-1.2 + 0.8 * double(o % 4)) + b * (-1.2 + 0.8 * double(o / 4));
        const float hue = float(o) / float(objects);
        const glm::vec3 rgb(0.5f + 0.45f * std::cos(6.283f * hue), 0.5f + 0.45f * std::cos(6.283f * (hue + 0.33f)),
                            0.5f + 0.45f * std::cos(6.283f * (hue + 0.67f)));
        for (int i = 0; i < 7; ++i)
            for (int j = 0; j < 7; ++j)
                for (int k = 0; k < 7; ++k) add(base + a * (0.06 * i - 0.18) + b * (0.06 * j - 0.18) + up * (0.08 + 0.06 * k), rgb);
        s.tops.push_back(base + up * 0.44);
    }
    return s;
}

}  // namespace

double warm_up(vk::Context& ctx, const SegmentOptions& options, size_t objects) {
    const auto t0 = std::chrono::steady_clock::now();
    const glm::dvec3 up = glm::normalize(options.up);
    // One run per kernel width (labels = objects + 1, four label columns per vec4), with the
    // fewest objects that need it; 16 or more labels run in batches of every width.
    const uint32_t widths = (std::min<uint32_t>(uint32_t(std::min<size_t>(objects, 64)) + 1, gpu::kWalkMaxLabels) + 3) / 4;
    const MadeUpScene s = made_up_scene(up, 12);
    const render::GpuScene scene(ctx, s.cloud);
    const std::vector<data::Camera> cameras{data::look_at("warm_up", up * 3.0 - s.along * 3.5, glm::dvec3(0.0), up, 160, 120, 70.0)};
    const data::Camera& cam = cameras.front();

    SegmentOptions o = options;
    o.graph = GraphUse::Alone;
    o.scale = 0.5;
    o.sigma = o.roi_length = o.roi_width = 0;
    o.strict = false;
    o.cancel = nullptr;
    o.on_coarse = [](const SegmentResult&) {};  // the viewer's path: a coarse answer before the cold solve
    for (uint32_t w = 1; w <= widths; ++w) {
        data::Prompts prompts;
        for (size_t i = 0; i < (w == 1 ? 1 : 4 * (w - 1)); ++i) {
            const glm::dvec2 at = cam.project(s.tops[i]).value();  // the camera looks down on every cube
            data::PromptClick click;
            click.view = cam.name;
            click.u = at.x;
            click.v = at.y;
            prompts.objects.push_back({"cube " + std::to_string(i + 1), int(i + 1), {click}});
        }
        Segmenter segmenter(ctx, s.cloud, scene, cameras);  // new each time: a cold solve, as on a new scene
        segmenter.segment(prompts, o);
    }
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace pg::seg
