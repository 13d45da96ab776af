// pointgauss render SCENE --cameras FILE --out DIR: PNGs of any outputs for many views.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include <nlohmann/json.hpp>

#include "app/cli/commands.h"
#include "app/common/progress.h"
#include "app/common/staged_output.h"
#include "dataset/atomic_file.h"
#include "dataset/error.h"
#include "dataset/formats/camera_io.h"
#include "dataset/formats/image_io.h"
#include "dataset/formats/scene_io.h"
#include "engine/render/renderer.h"
#include "engine/vk/context.h"

namespace pg::app {

namespace fs = std::filesystem;

namespace {

struct RenderArgs {
    std::string scene, cameras, out, views = "all", outputs = "rgb", background = "0,0,0";
    int lod = 0;
    int width = 0, height = 0;
    bool antialiased = false;
    float tau = 0.9f;
    DeviceOptions device;
};

glm::vec3 parse_colour(const std::string& s) {
    glm::vec3 c;
    char extra;
    if (std::sscanf(s.c_str(), "%f,%f,%f%c", &c.x, &c.y, &c.z, &extra) != 3 || !std::isfinite(c.x + c.y + c.z))
        throw data::InputError("--background", "expected r,g,b in [0,1], got '" + s + "'");
    return c;
}

std::vector<std::string> parse_outputs(const std::string& s) {
    static const std::vector<std::string> known = {"rgb", "alpha", "depth", "tau-depth", "contributors"};
    std::vector<std::string> out;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, ','))
        if (!item.empty()) {
            if (std::find(known.begin(), known.end(), item) == known.end())
                throw data::InputError("--outputs", "unknown output '" + item +
                                                        "' (known: rgb, alpha, depth, tau-depth, contributors)");
            out.push_back(item);
        }
    if (out.empty()) throw data::InputError("--outputs", "no output selected");
    return out;
}

// Depth-like images as 16-bit PNG scaled so `max_value` maps to 65535; the scale goes in render.json.
void write_scaled16(const fs::path& path, int w, int h, const std::vector<float>& v, float max_value) {
    std::vector<uint16_t> px(v.size());
    float scale = max_value > 0 ? 65535.0f / max_value : 0.0f;
    for (size_t i = 0; i < v.size(); ++i) px[i] = uint16_t(std::clamp(std::lround(v[i] * scale), 0l, 65535l));
    data::write_png16(path, w, h, px);
}

void run_render(const RenderArgs& a) {
    scene_budget(a.device);  // a bad --max-device-memory fails before anything loads
    if ((a.width > 0) != (a.height > 0)) throw data::InputError("--width/--height", "give both or neither");
    if (a.width < 0 || a.height < 0 || a.width > 16384 || a.height > 16384)
        throw data::InputError("--width/--height", "must be between 1 and 16384");
    if (!(a.tau > 0.0f && a.tau < 1.0f)) throw data::InputError("--tau", "must be in (0, 1)");
    auto outputs = parse_outputs(a.outputs);
    glm::vec3 background = parse_colour(a.background);
    auto cloud = load_scene_shown(a.scene, a.lod);
    auto cameras = data::load_cameras(a.cameras);
    auto views = select_views(a.views, cameras);

    StagedOutput staged(a.out);  // every picture appears at the end, or none
    const fs::path& out = staged.dir();

    vk::ContextOptions co;
    co.device = a.device.device;
    vk::Context ctx(co);
    render::GpuScene scene = upload_scene(ctx, cloud, a.device);
    render::Renderer renderer(ctx);
    render::RenderSettings settings;
    settings.width = a.width;
    settings.height = a.height;
    settings.background = background;
    settings.antialiased = a.antialiased;
    settings.tau = a.tau;

    nlohmann::json report;
    report["scene"] = a.scene;
    report["device"] = ctx.info().name;
    report["gaussians"] = cloud.size();
    if (scene.streamed()) report["slab_capacity"] = scene.slab_capacity();
    Progress progress("render", views.size());
    auto start = std::chrono::steady_clock::now();
    for (size_t v : views) {
        const auto& cam = cameras[v];
        renderer.render(scene, cam, settings);
        auto img = renderer.read();
        const int w = img.width, h = img.height;
        const size_t pixels = size_t(w) * size_t(h);
        nlohmann::json entry{{"camera", cam.name}, {"width", w}, {"height", h}};
        for (auto& o : outputs) {
            if (o == "rgb") {
                std::vector<float> rgb(pixels * 3);
                for (size_t p = 0; p < pixels; ++p)
                    for (int c = 0; c < 3; ++c) rgb[p * 3 + c] = img.rgba[p * 4 + c];
                data::write_png8(out / (cam.name + ".png"), w, h, 3, data::to_8bit(rgb));
            } else if (o == "alpha") {
                std::vector<float> alpha(pixels);
                for (size_t p = 0; p < pixels; ++p) alpha[p] = img.rgba[p * 4 + 3];
                data::write_png8(out / (cam.name + ".alpha.png"), w, h, 1, data::to_8bit(alpha));
            } else if (o == "depth" || o == "tau-depth") {
                const auto& d = o == "depth" ? img.depth : img.tau_depth;
                float max_d = 0;
                for (float x : d) max_d = std::max(max_d, x);
                write_scaled16(out / (cam.name + "." + o + ".png"), w, h, d, max_d);
                entry[o + "_max"] = max_d;  // pixel value 65535 is this depth, 0 is empty
            } else if (o == "contributors") {
                std::vector<float> c(pixels);
                uint32_t max_c = 1;
                for (auto x : img.contributors) max_c = std::max(max_c, x);
                for (size_t p = 0; p < pixels; ++p) c[p] = float(img.contributors[p]);
                write_scaled16(out / (cam.name + ".contributors.png"), w, h, c, float(max_c));
                entry["contributors_max"] = max_c;
            }
        }
        double gpu_ms = 0;
        for (auto& t : renderer.timings()) gpu_ms += t.ms;
        entry["gpu_ms"] = gpu_ms;
        if (scene.streamed()) entry["slabs"] = renderer.slabs();
        report["views"].push_back(entry);
        progress.step(cam.name);
    }
    progress.finish();
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    report["seconds"] = seconds;
    data::write_atomically(out / "render.json", [&](std::ostream& os) { os << report.dump(2) << "\n"; });
    staged.commit();
    std::printf("rendered %zu view(s) of %zu Gaussians to %s in %.2f s\n", views.size(), cloud.size(), a.out.c_str(),
                seconds);
}

}  // namespace

void register_render(CLI::App& app, std::function<void()>& run) {
    auto a = std::make_shared<RenderArgs>();
    auto* cmd = app.add_subcommand("render", "Render a scene from its cameras to PNG files named after the cameras");
    add_scene_option(*cmd, a->scene, a->lod);
    cmd->add_option("--cameras", a->cameras, "COLMAP model folder, cameras.json or transforms.json")->required();
    cmd->add_option("--out", a->out, "Output folder")->required();
    cmd->add_option("--views", a->views, "all, or a comma list of camera indices or names")->capture_default_str();
    cmd->add_option("--width", a->width, "Image width (intrinsics scale with it)");
    cmd->add_option("--height", a->height, "Image height");
    cmd->add_option("--outputs", a->outputs, "Comma list of rgb, alpha, depth, tau-depth, contributors")
        ->capture_default_str();
    cmd->add_option("--background", a->background, "Background colour r,g,b in [0,1]")->capture_default_str();
    cmd->add_option("--tau", a->tau, "Opacity at which the tau-depth is taken")->capture_default_str();
    cmd->add_flag("--antialiased", a->antialiased, "Mip-Splatting opacity compensation (for scenes trained with it)");
    add_device_option(*cmd, a->device);
    add_memory_option(*cmd, a->device);
    cmd->callback([a, &run] { run = [a] { run_render(*a); }; });
}

}  // namespace pg::app
