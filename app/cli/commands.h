#pragma once
#include <algorithm>
// Each subcommand registers itself on the CLI11 app; one file per subcommand.
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "dataset/camera.h"
#include "engine/render/gpu_scene.h"

namespace pg::app {

// A run that finished and wrote its outputs, but not for everything asked (e.g. `segment` with
// an object whose clicks could not be lifted): main prints the message and exits with 2.
class PartialFailure : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// Options every GPU subcommand takes.
struct DeviceOptions {
    std::string device;             // --device NAME
    std::string max_device_memory;  // --max-device-memory BYTES (K, M, G suffixes)
    bool half_sh = false;           // --half-sh
};
void add_device_option(CLI::App& cmd, DeviceOptions& opt);
// The positional scene argument and --lod, for every command that reads a scene.
void add_scene_option(CLI::App& cmd, std::string& scene, int& lod, const std::string& what = "Scene");
extern const char* const kSceneFormats;  // "3DGS/2DGS PLY, compressed PLY, .splat, .spz, SOG (...)"
// --max-device-memory and --half-sh, for commands that put a whole scene on the device.
void add_memory_option(CLI::App& cmd, DeviceOptions& opt);
render::SceneBudget scene_budget(const DeviceOptions& opt);
// The scene on the device within --max-device-memory; a cap it cannot fit in names the option.
render::GpuScene upload_scene(vk::Context& ctx, const data::GaussianCloud& cloud, const DeviceOptions& opt);

void register_info(CLI::App& app, std::function<void()>& run);
void register_render(CLI::App& app, std::function<void()>& run);
void register_convert(CLI::App& app, std::function<void()>& run);
void register_bench(CLI::App& app, std::function<void()>& run);
void register_cameras(CLI::App& app, std::function<void()>& run);
void register_eval(CLI::App& app, std::function<void()>& run);
void register_train(CLI::App& app, std::function<void()>& run);
void register_curves(CLI::App& app, std::function<void()>& run);
void register_synth(CLI::App& app, std::function<void()>& run);
void register_segment(CLI::App& app, std::function<void()>& run);
void register_prompts(CLI::App& app, std::function<void()>& run);
void register_bench_segment(CLI::App& bench, std::function<void()>& run);
void register_bench_ptv3(CLI::App& bench, std::function<void()>& run);
void register_bench_train(CLI::App& bench, std::function<void()>& run);
void register_bench_load(CLI::App& bench, std::function<void()>& run);
void register_bench_gemm(CLI::App& bench, std::function<void()>& run);
void register_infer(CLI::App& app, std::function<void()>& run);
void register_clicks(CLI::App& app, std::function<void()>& run);
void register_batch(CLI::App& app, std::function<void()>& run);

// The median (mean of the middle two for an even count); 0 for none. Benchmarks report medians.
inline double median(std::vector<double> v) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// "L,W" (both > 0) -> the ROI length and width; InputError naming --roi otherwise.
void parse_roi(const std::string& spec, double& length, double& width);
// --graph-scales as given, each factor > 0 and finite; InputError naming the flag otherwise.
const std::vector<double>& checked_graph_scales(const std::vector<double>& scales);

// The engine's InputErrors name its parameters ("sigma", "roi", "decoder"); the CLI's name the
// flags that set them. flag_for maps an error's where(), with_flags an object's error text
// ("where: reason").
std::string flag_for(const std::string& where);
std::string with_flags(const std::string& error);

// `segment --semantic`: every Gaussian gets a class from the semantic model, no clicks.
struct SemanticSegmentArgs {
    std::string scene, cameras, out, model, views = "all", mode = "occlusion", up = "cameras";
    double tile = 0;  // 0: the model's
    int lod = 0;
    std::string export_format = "ply";
    uint64_t seed = 1;
    DeviceOptions device;
};
void run_segment_semantic(const SemanticSegmentArgs& args);

// "all" or a comma list of indices or camera names -> indices into `cameras`.
std::vector<size_t> select_views(const std::string& spec, const std::vector<data::Camera>& cameras);

}  // namespace pg::app
