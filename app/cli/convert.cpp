// pointgauss convert SCENE OUT.ply|OUT.sog: any scene format the readers take, written as a
// 3DGS PLY or a PlayCanvas SOG (bundled v2; codebooks and SH palette clustered on the GPU).
#include <chrono>
#include <cstdio>

#include "app/cli/commands.h"
#include "app/common/progress.h"
#include "dataset/error.h"
#include "dataset/formats/scene_io.h"
#include "engine/compress/sog_quantizer.h"
#include "engine/segment/export.h"
#include "engine/vk/context.h"

namespace pg::app {

namespace {

struct ConvertArgs {
    std::string scene, out;
    int lod = 0, iterations = 10;
    uint64_t seed = 1;
    DeviceOptions device;
};

void run_convert(const ConvertArgs& a) {
    const std::filesystem::path out(a.out);
    const std::string ext = out.extension().string();
    if (ext != ".ply" && ext != ".sog")
        throw data::InputError(a.out, "writes .ply or .sog (a bundled PlayCanvas SOG), not '" + ext + "'");
    seg::refuse_overwriting(out, {a.scene});
    const auto cloud = load_scene_shown(a.scene, a.lod);
    const auto t0 = std::chrono::steady_clock::now();
    if (ext == ".ply") {
        data::write_ply(cloud, out);
    } else {
        vk::ContextOptions co;
        co.device = a.device.device;
        vk::Context ctx(co);
        compress::gpu_sog_writer(ctx, a.iterations, a.seed)(cloud, out);
    }
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("wrote %s: %zu Gaussians, SH %d, %.1f s\n", a.out.c_str(), cloud.size(), cloud.sh_degree, s);
}

}  // namespace

void register_convert(CLI::App& app, std::function<void()>& run) {
    auto a = std::make_shared<ConvertArgs>();
    auto* cmd = app.add_subcommand("convert", "Write a scene as a 3DGS PLY or a PlayCanvas SOG (.sog)");
    add_scene_option(*cmd, a->scene, a->lod);
    cmd->add_option("out", a->out, "Output file: .ply, or .sog (bundled SOG v2, lossless WebP)")->required();
    cmd->add_option("--iterations", a->iterations, "SOG: k-means iterations for the SH palette and codebooks")
        ->capture_default_str()
        ->check(CLI::Range(1, 100));
    cmd->add_option("--seed", a->seed, "SOG: seed of the palette's first centroids (same seed, same file)")
        ->capture_default_str();
    add_device_option(*cmd, a->device);
    cmd->callback([a, &run] { run = [a] { run_convert(*a); }; });
}

}  // namespace pg::app
