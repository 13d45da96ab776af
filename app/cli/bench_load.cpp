// pointgauss bench load SCENE: how long reading a scene takes (median of runs), to compare
// formats and readers (the README sets SOG beside splat-transform's own decode).
#include <chrono>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "app/cli/commands.h"
#include "app/common/host_memory.h"
#include "dataset/formats/scene_io.h"

namespace pg::app {

namespace {

struct BenchLoadArgs {
    std::string scene;
    int lod = 0, runs = 5;
    bool json = false;
};

void run_bench_load(const BenchLoadArgs& a) {
    std::vector<double> ms;
    data::GaussianCloud cloud;
    for (int r = 0; r < a.runs; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        cloud = data::load_scene(a.scene, {}, a.lod);
        ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    const double peak = double(peak_host_bytes()) / (1 << 20);
    if (a.json) {
        nlohmann::json j{{"scene", a.scene},          {"format", data::scene_format_name(cloud.format)},
                         {"gaussians", cloud.size()}, {"sh_degree", cloud.sh_degree},
                         {"runs", a.runs},            {"median_ms", median(ms)},
                         {"ms", ms},                  {"peak_host_mib", peak}};
        std::printf("%s\n", j.dump(2).c_str());
        return;
    }
    std::printf("scene      %s\nformat     %s\ngaussians  %zu (SH %d)\n", a.scene.c_str(),
                data::scene_format_name(cloud.format), cloud.size(), cloud.sh_degree);
    std::printf("load       %.1f ms median of %d runs (%.1f to %.1f)\n", median(ms), a.runs,
                *std::min_element(ms.begin(), ms.end()), *std::max_element(ms.begin(), ms.end()));
    std::printf("peak host memory %.1f MiB\n", peak);
}

}  // namespace

void register_bench_load(CLI::App& bench, std::function<void()>& run) {
    auto a = std::make_shared<BenchLoadArgs>();
    auto* cmd = bench.add_subcommand("load", "Milliseconds to read and decode a scene (median of runs)");
    add_scene_option(*cmd, a->scene, a->lod);
    cmd->add_option("--runs", a->runs, "Timed loads")->capture_default_str()->check(CLI::Range(1, 1000));
    cmd->add_flag("--json", a->json, "Print JSON instead of text");
    cmd->callback([a, &run] { run = [a] { run_bench_load(*a); }; });
}

}  // namespace pg::app
