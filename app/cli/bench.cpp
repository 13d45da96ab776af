// pointgauss bench render: per-pass GPU milliseconds and wall time per frame, as medians
// over repeated frames; a table, or JSON with --json.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>

#include <nlohmann/json.hpp>

#include "app/cli/commands.h"
#include "app/common/host_memory.h"
#include "app/common/progress.h"
#include "dataset/error.h"
#include "dataset/formats/camera_io.h"
#include "dataset/formats/scene_io.h"
#include "engine/render/renderer.h"
#include "engine/vk/context.h"

namespace pg::app {

namespace {

struct BenchRenderArgs {
    std::string scene, cameras, views = "0";
    int lod = 0;
    int width = 0, height = 0, frames = 20, warmup = 3;
    bool json = false;
    DeviceOptions device;
};

void run_bench_render(const BenchRenderArgs& a) {
    scene_budget(a.device);  // a bad --max-device-memory fails before anything loads
    if (a.frames < 1) throw data::InputError("--frames", "must be at least 1");
    if (a.warmup < 0) throw data::InputError("--warmup", "must not be negative");
    auto t_load = std::chrono::steady_clock::now();
    auto cloud = load_scene_shown(a.scene, a.lod);
    auto cameras = data::load_cameras(a.cameras);
    auto views = select_views(a.views, cameras);
    vk::ContextOptions co;
    co.device = a.device.device;
    co.quiet = a.json;
    vk::Context ctx(co);
    render::GpuScene scene = upload_scene(ctx, cloud, a.device);
    const double load_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_load).count();
    render::Renderer renderer(ctx);
    render::RenderSettings settings;
    settings.width = a.width;
    settings.height = a.height;

    std::vector<std::string> order;
    std::map<std::string, std::vector<double>> pass_ms;
    std::vector<double> wall_ms, gpu_ms;
    uint32_t keys = 0;
    int slabs = 1;
    Progress progress("bench", size_t(a.warmup + a.frames));
    for (int f = 0; f < a.warmup + a.frames; ++f) {
        const auto& cam = cameras[views[size_t(f) % views.size()]];
        auto t0 = std::chrono::steady_clock::now();
        renderer.render(scene, cam, settings);
        double wall = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        progress.step();
        if (f < a.warmup) continue;
        wall_ms.push_back(wall);
        double total = 0;
        for (auto& t : renderer.timings()) {
            if (!pass_ms.count(t.name)) order.push_back(t.name);
            pass_ms[t.name].push_back(t.ms);
            total += t.ms;
        }
        gpu_ms.push_back(total);
        keys = renderer.key_count();
        slabs = renderer.slabs();
    }
    progress.finish();
    auto mem = vk::memory_stats();

    if (a.json) {
        nlohmann::json j;
        j["device"] = ctx.info().name;
        j["scene"] = a.scene;
        j["gaussians"] = cloud.size();
        j["width"] = renderer.width();
        j["height"] = renderer.height();
        j["frames"] = a.frames;
        j["tile_keys"] = keys;
        for (auto& name : order) j["gpu_ms"][name] = median(pass_ms[name]);
        j["gpu_ms"]["total"] = median(gpu_ms);
        j["wall_ms"] = median(wall_ms);
        j["peak_device_bytes"] = mem.peak;
        j["peak_host_bytes"] = peak_host_bytes();
        j["load_ms"] = load_ms;
        j["slabs"] = slabs;
        if (scene.streamed()) j["slab_capacity"] = scene.slab_capacity();
        std::printf("%s\n", j.dump(2).c_str());
        return;
    }
    std::printf("device     %s\n", ctx.info().name.c_str());
    std::printf("scene      %s (%zu Gaussians), %dx%d, %d frames after %d warm-up\n", a.scene.c_str(), cloud.size(),
                renderer.width(), renderer.height(), a.frames, a.warmup);
    std::printf("tile keys  %u\n", keys);
    std::printf("load       %.0f ms (read, upload)\n", load_ms);
    if (scene.streamed())
        std::printf("streamed   %d slabs of at most %u Gaussians per frame\n", slabs, scene.slab_capacity());
    std::printf("\n");
    std::printf("| pass | median ms |\n|---|---:|\n");
    for (auto& name : order) std::printf("| %s | %.3f |\n", name.c_str(), median(pass_ms[name]));
    std::printf("| **GPU total** | %.3f |\n| **wall per frame** | %.3f |\n", median(gpu_ms), median(wall_ms));
    std::printf("\npeak device memory %.1f MiB, peak host memory %.1f MiB\n", double(mem.peak) / (1 << 20),
                double(peak_host_bytes()) / (1 << 20));
}

}  // namespace

void register_bench(CLI::App& app, std::function<void()>& run) {
    auto* bench = app.add_subcommand("bench", "Measure speed and memory");
    bench->require_subcommand(1);
    auto a = std::make_shared<BenchRenderArgs>();
    auto* cmd = bench->add_subcommand("render", "Per-pass GPU ms and wall ms per frame (medians)");
    add_scene_option(*cmd, a->scene, a->lod);
    cmd->add_option("--cameras", a->cameras, "Camera file or COLMAP folder")->required();
    cmd->add_option("--views", a->views, "Views to cycle through (all, or indices/names)")->capture_default_str();
    cmd->add_option("--width", a->width, "Image width");
    cmd->add_option("--height", a->height, "Image height");
    cmd->add_option("--frames", a->frames, "Measured frames")->capture_default_str();
    cmd->add_option("--warmup", a->warmup, "Frames before measuring")->capture_default_str();
    cmd->add_flag("--json", a->json, "Print JSON instead of a table");
    add_device_option(*cmd, a->device);
    add_memory_option(*cmd, a->device);
    cmd->callback([a, &run] { run = [a] { run_bench_render(*a); }; });
    register_bench_segment(*bench, run);
    register_bench_ptv3(*bench, run);
    register_bench_train(*bench, run);
    register_bench_load(*bench, run);
    register_bench_gemm(*bench, run);
}

}  // namespace pg::app
