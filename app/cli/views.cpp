#include <charconv>
#include <sstream>

#include "app/cli/commands.h"
#include "app/common/memory_arg.h"
#include "dataset/error.h"

namespace pg::app {

void add_device_option(CLI::App& cmd, DeviceOptions& opt) {
    cmd.add_option("--device", opt.device, "Vulkan device name (substring); default: PG_DEVICE, else the best GPU");
}

const char* const kSceneFormats =
    "3DGS/2DGS PLY, compressed PLY, .splat, .spz, or PlayCanvas SOG: .sog, meta.json or its folder, lod-meta.json";

void add_scene_option(CLI::App& cmd, std::string& scene, int& lod, const std::string& what) {
    cmd.add_option("scene", scene, what + ": " + kSceneFormats)->required();
    cmd.add_option("--lod", lod, "Level of a streamed SOG (lod-meta.json) to load: 0, the finest (default), or coarser")
        ->check(CLI::NonNegativeNumber);
}

void add_memory_option(CLI::App& cmd, DeviceOptions& opt) {
    cmd.add_option("--max-device-memory", opt.max_device_memory,
                   "Device memory the scene may use (e.g. 512M, 2G); a scene past it, or past the device's "
                   "largest binding, is streamed in slabs. Default: the device's memory");
    cmd.add_flag("--half-sh", opt.half_sh,
                 "Keep SH coefficients on the device as fp16: half their memory (and twice the Gaussians per "
                 "slab), colours within about 1e-3");
}

render::SceneBudget scene_budget(const DeviceOptions& opt) { return scene_budget(opt.max_device_memory, opt.half_sh); }

render::GpuScene upload_scene(vk::Context& ctx, const data::GaussianCloud& cloud, const DeviceOptions& opt) {
    const render::SceneBudget budget = scene_budget(opt);
    try {
        return render::GpuScene(ctx, cloud, budget);
    } catch (const std::runtime_error& e) {
        if (!budget.max_device_bytes) throw;
        throw data::InputError("--max-device-memory " + opt.max_device_memory, e.what());
    }
}

std::vector<size_t> select_views(const std::string& spec, const std::vector<data::Camera>& cameras) {
    std::vector<size_t> out;
    if (spec.empty() || spec == "all") {
        for (size_t i = 0; i < cameras.size(); ++i) out.push_back(i);
        return out;
    }
    std::stringstream ss(spec);
    std::string item;
    while (std::getline(ss, item, ',')) {
        if (item.empty()) continue;
        size_t index = 0;
        auto [ptr, ec] = std::from_chars(item.data(), item.data() + item.size(), index);
        if (ec == std::errc() && ptr == item.data() + item.size()) {
            if (index >= cameras.size())
                throw data::InputError("--views", "view " + item + " is out of range (there are " +
                                                      std::to_string(cameras.size()) + " cameras)");
            out.push_back(index);
            continue;
        }
        bool found = false;
        for (size_t i = 0; i < cameras.size(); ++i)
            if (cameras[i].name == item) {
                out.push_back(i);
                found = true;
                break;
            }
        if (!found) throw data::InputError("--views", "no camera named '" + item + "'");
    }
    if (out.empty()) throw data::InputError("--views", "selects no camera");
    return out;
}

}  // namespace pg::app
