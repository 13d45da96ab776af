#pragma once
// --max-device-memory and --half-sh, shared by the CLI and the viewer.
#include <string>

#include "engine/render/gpu_scene.h"

namespace pg::app {

// "512M", "2G", "800000000" (K, M, G: powers of 1024; empty: no cap) -> the scene's budget;
// InputError naming --max-device-memory otherwise.
render::SceneBudget scene_budget(const std::string& max_device_memory, bool half_sh);

}  // namespace pg::app
