// pointgauss bench train: training steps per second, GPU ms per op family (forward and
// backward) and peak device memory of PTv3 training steps on synthetic click crops, as medians.
// The comparison figure is tools/bench_train_torch.py: the same config, step and input size in
// PyTorch on the CPU.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>

#include <nlohmann/json.hpp>

#include "app/cli/commands.h"
#include "app/cli/pass_families.h"
#include "app/common/progress.h"
#include "app/cli/synthetic_crop.h"
#include "app/common/ptv3_decoder.h"
#include "dataset/error.h"
#include "engine/vk/context.h"
#include "nn/safetensors.h"
#include "nn/train/batch.h"
#include "nn/train/initial_weights.h"
#include "nn/train/trainer.h"

namespace pg::app {

namespace {

struct BenchTrainArgs {
    std::string config = "small";
    int points = 8192, clouds = 1, repeats = 5, warmup = 1;
    double lovasz = 0;
    uint64_t seed = 1;
    bool json = false;
    DeviceOptions device;
};

void run_bench_train(const BenchTrainArgs& a) {
    if (a.points < 16) throw data::InputError("--points", "must be at least 16");
    if (a.clouds < 1) throw data::InputError("--clouds", "must be at least 1");
    if (a.repeats < 1) throw data::InputError("--repeats", "must be at least 1");
    if (!(a.lovasz >= 0)) throw data::InputError("--lovasz", "must be 0 or more");
    nn::Ptv3Config config;
    config = ptv3_config_arg(a.config, "--config");
    vk::ContextOptions co;
    co.device = a.device.device;
    co.quiet = a.json;
    vk::Context ctx(co);
    auto pool = nn::Pool::create(ctx);
    nn::train::TrainOptions to;
    to.lovasz_weight = a.lovasz;
    nn::train::Trainer trainer(*pool, nn::Ptv3Weights::from_host(*pool, config, nn::train::initial_weights(config, a.seed),
                                                                 "initial"), to);
    // One batch of `clouds` crops; label 1 where the positive click weight is high (the first shape).
    nn::train::Batch batch;
    for (int b = 0; b < a.clouds; ++b) {
        const nn::Ptv3Input crop = synthetic_crop(a.points, config.in_channels, config.grid_size, a.seed + uint64_t(b));
        std::vector<int32_t> labels(crop.size());
        for (size_t i = 0; i < crop.size(); ++i) labels[i] = crop.feat[i * size_t(config.in_channels)] > 0.5f;
        batch.add(crop.coord, crop.feat, labels);
    }
    uint64_t weights_bytes = 0;  // weights, running statistics and AdamW moments: live between steps

    PassFamilies families;
    std::vector<double> wall;
    uint64_t peak = 0;
    Progress progress("bench train", size_t(a.warmup + a.repeats));
    for (int r = 0; r < a.warmup + a.repeats; ++r) {
        if (r > 0) weights_bytes = pool->live_bytes();  // the previous step's tensors are gone
        pool->reset_peak();
        auto t0 = std::chrono::steady_clock::now();
        const nn::train::StepResult out = trainer.step(batch.input, batch.labels, 1e-4, 0.9);
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        progress.step();
        peak = std::max(peak, pool->peak_bytes());
        if (r < a.warmup) continue;
        families.add(out.passes);
        wall.push_back(ms);
    }
    progress.finish();
    std::sort(families.names.begin(), families.names.end());
    const double wall_med = median(wall), gpu_med = families.median_total();
    const long long params = trainer.weights().parameter_count();
    const double mib = 1.0 / 1048576.0;
    if (a.json) {
        nlohmann::json j;
        j["device"] = ctx.info().name;
        j["config"] = a.config;
        j["parameters"] = params;
        j["points_per_cloud"] = a.points;
        j["clouds"] = a.clouds;
        j["lovasz"] = a.lovasz;
        j["repeats"] = a.repeats;
        for (const auto& f : families.names) j["family_ms"][f] = families.median_ms(f);
        j["gpu_ms"] = gpu_med;
        j["step_ms"] = wall_med;
        j["steps_per_s"] = 1000.0 / wall_med;
        j["weights_mib"] = double(weights_bytes) * mib;
        j["peak_mib"] = double(peak) * mib;
        std::printf("%s\n", j.dump(2).c_str());
        return;
    }
    std::printf("device: %s\nconfig: %s (%lld parameters), %d cloud(s) x %d points, %s, median of %d steps\n\n",
                ctx.info().name.c_str(), a.config.c_str(), params, a.clouds, a.points,
                a.lovasz > 0 ? "cross-entropy + Lovasz loss" : "cross-entropy loss", a.repeats);
    std::printf("%-16s %10s %7s\n", "ops", "GPU ms", "share");
    for (const auto& f : families.names) {
        const double m = families.median_ms(f);
        std::printf("%-16s %10.2f %6.1f%%\n", f.c_str(), m, 100 * m / std::max(gpu_med, 1e-9));
    }
    std::printf("%-16s %10.2f\n%-16s %10.2f\n\n", "GPU total", gpu_med, "step wall", wall_med);
    std::printf("%.2f steps/s, %.0f points/s\n", 1000.0 / wall_med, 1000.0 * a.points * a.clouds / wall_med);
    std::printf("memory: weights + optimizer state %.1f MiB, peak during a step %.1f MiB\n",
                double(weights_bytes) * mib, double(peak) * mib);
}

}  // namespace

void register_bench_train(CLI::App& bench, std::function<void()>& run) {
    auto a = std::make_shared<BenchTrainArgs>();
    auto* cmd = bench.add_subcommand("train", "Steps/s, GPU ms per op family and peak memory of PTv3 training steps");
    cmd->add_option("--config", a->config, "tiny, small, paper, or a model file whose config to use")->capture_default_str();
    cmd->add_option("--points", a->points, "Points per synthetic crop")->capture_default_str();
    cmd->add_option("--clouds", a->clouds, "Crops per batch")->capture_default_str();
    cmd->add_option("--repeats", a->repeats, "Timed steps (medians are reported)")->capture_default_str();
    cmd->add_option("--warmup", a->warmup, "Untimed steps first")->capture_default_str();
    cmd->add_option("--seed", a->seed, "Seed of the weights and the synthetic input")->capture_default_str();
    cmd->add_option("--lovasz", a->lovasz, "Weight of the Lovasz loss added to the cross-entropy (0: off)")
        ->capture_default_str();
    cmd->add_flag("--json", a->json, "Print JSON instead of a table");
    add_device_option(*cmd, a->device);
    cmd->callback([a, &run] { run = [a] { run_bench_train(*a); }; });
}

}  // namespace pg::app
