// pointgauss bench ptv3: GPU ms per op family and in total, wall ms and peak device memory of
// one PTv3 forward (medians over repeated runs), and the effective GFLOP/s. `--model paper`
// or `small` builds seeded weights of that config (nn/ptv3/seeded_weights.h); the input is a
// synthetic click crop: surface samples of boxes and spheres, one point per voxel, with
// positive/negative click weights as features.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <set>

#include <nlohmann/json.hpp>

#include "app/cli/commands.h"
#include "app/cli/pass_families.h"
#include "app/cli/point_file.h"
#include "app/common/progress.h"
#include "app/cli/synthetic_crop.h"
#include "dataset/error.h"
#include "dataset/random.h"
#include "engine/vk/context.h"
#include "nn/ptv3/model.h"
#include "nn/ptv3/seeded_weights.h"
#include "nn/safetensors.h"

namespace pg::app {

namespace {

struct BenchPtv3Args {
    std::string model = "paper", input;
    int points = 8192, repeats = 5, warmup = 1;
    uint64_t seed = 1;
    bool json = false;
    DeviceOptions device;
};

void run_bench_ptv3(const BenchPtv3Args& a) {
    if (a.points < 1) throw data::InputError("--points", "must be at least 1");
    if (a.repeats < 1) throw data::InputError("--repeats", "must be at least 1");
    vk::ContextOptions co;
    co.device = a.device.device;
    co.quiet = a.json;
    vk::Context ctx(co);
    auto pool = nn::Pool::create(ctx);
    nn::Ptv3Weights weights;
    if (a.model == "paper" || a.model == "small") {
        auto config = a.model == "paper" ? nn::Ptv3Config::paper() : nn::Ptv3Config::small();
        weights = nn::Ptv3Weights::from_host(*pool, config, nn::seeded_weights(config), "seeded " + a.model);
    } else {
        try {
            weights = nn::Ptv3Weights::load(*pool, a.model);
        } catch (const nn::FormatError& e) {
            throw data::InputError("--model", e.what());
        }
    }
    const nn::Ptv3Config config = weights.config();
    const long long params = weights.parameter_count();
    nn::Ptv3 model(*pool, std::move(weights));
    nn::Ptv3Input in;
    if (a.input.empty()) {
        in = synthetic_crop(a.points, config.in_channels, config.grid_size, a.seed);
    } else {
        in = read_point_file(a.input, config.in_channels);
    }
    in.count_conv_pairs = true;

    PassFamilies families;
    std::vector<double> wall;
    std::map<std::string, double> flops;
    std::vector<int64_t> level_points;
    uint64_t peak = 0;
    Progress progress("bench ptv3", size_t(a.warmup + a.repeats));
    for (int r = 0; r < a.warmup + a.repeats; ++r) {
        pool->reset_peak();
        auto t0 = std::chrono::steady_clock::now();
        nn::Ptv3Output out = model.forward(in);
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        progress.step();
        in.count_conv_pairs = false;
        if (r == 0) {
            flops = out.flops;
            level_points = out.level_points;
        }
        peak = std::max(peak, pool->peak_bytes());
        if (r < a.warmup) continue;
        families.add(out.passes);
        wall.push_back(ms);
    }
    progress.finish();
    double total_flops = 0;
    for (const auto& [k, v] : flops) total_flops += v;
    const double wall_med = median(wall), gpu_med = families.median_total();
    const double weights_mb = double(params) * 4 / 1048576.0;

    if (a.json) {
        nlohmann::json j;
        j["device"] = ctx.info().name;
        j["model"] = a.model;
        j["parameters"] = params;
        j["points"] = in.size();
        j["level_points"] = level_points;
        j["repeats"] = a.repeats;
        for (const auto& f : families.names) j["family_ms"][f] = families.median_ms(f);
        j["gpu_ms"] = gpu_med;
        j["wall_ms"] = wall_med;
        j["gflop"] = total_flops * 1e-9;
        for (const auto& [k, v] : flops) j["gflop_by_family"][k] = v * 1e-9;
        j["gflops_per_s"] = total_flops * 1e-6 / wall_med;
        j["peak_activation_mib"] = double(peak) / 1048576.0;
        j["weights_mib"] = weights_mb;
        std::printf("%s\n", j.dump(2).c_str());
        return;
    }
    std::printf("device: %s\nmodel: %s (%lld parameters), %zu points -> levels", ctx.info().name.c_str(), a.model.c_str(),
                params, in.size());
    for (auto n : level_points) std::printf(" %lld", (long long)n);
    std::printf("\nmedian of %d runs\n\n%-12s %10s %7s\n", a.repeats, "ops", "GPU ms", "share");
    for (const auto& f : families.names) {
        const double m = families.median_ms(f);
        std::printf("%-12s %10.2f %6.1f%%\n", f.c_str(), m, 100 * m / std::max(gpu_med, 1e-9));
    }
    std::printf("%-12s %10.2f\n%-12s %10.2f\n\n", "GPU total", gpu_med, "wall", wall_med);
    std::printf("work: %.2f GFLOP (", total_flops * 1e-9);
    bool first = true;
    for (const auto& [k, v] : flops) {
        std::printf("%s%s %.2f", first ? "" : ", ", k.c_str(), v * 1e-9);
        first = false;
    }
    std::printf(") -> %.1f GFLOP/s over wall time\n", total_flops * 1e-6 / wall_med);
    std::printf("memory: weights %.1f MiB, peak activations %.1f MiB\n", weights_mb, double(peak) / 1048576.0);
}

}  // namespace

void register_bench_ptv3(CLI::App& bench, std::function<void()>& run) {
    auto a = std::make_shared<BenchPtv3Args>();
    auto* cmd = bench.add_subcommand("ptv3", "GPU ms per op family, wall ms, GFLOP/s and peak memory of a PTv3 forward");
    cmd->add_option("--model", a->model, "A model file, or 'paper' / 'small' for seeded weights of that config")
        ->capture_default_str();
    cmd->add_option("--points", a->points, "Points in the synthetic input crop")->capture_default_str();
    cmd->add_option("--input", a->input, "Use this input instead (coord f32 [N,3] then feat f32 [N,C], as for infer)");
    cmd->add_option("--repeats", a->repeats, "Timed runs (medians are reported)")->capture_default_str();
    cmd->add_option("--warmup", a->warmup, "Untimed runs first")->capture_default_str();
    cmd->add_option("--seed", a->seed, "Seed of the synthetic input")->capture_default_str();
    cmd->add_flag("--json", a->json, "Print JSON instead of a table");
    add_device_option(*cmd, a->device);
    cmd->callback([a, &run] { run = [a] { run_bench_ptv3(*a); }; });
}

}  // namespace pg::app
