#pragma once
// PlayCanvas SOG: Gaussians packed in WebP images beside a meta.json. Three layouts
// (bundled .sog zip, unbundled meta.json + images, streamed lod-meta.json over unbundled
// chunks) and two versions (v1: per-attribute min/max; v2: 256-entry codebooks).
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "dataset/gaussian_cloud.h"

namespace pg::data {

enum class SogLayout { Bundled, Unbundled, Streamed };
const char* sog_layout_name(SogLayout layout);  // "bundled", "unbundled", "streamed"

// What `info` prints, read from the JSON alone (no image is decoded).
struct SogSummary {
    SogLayout layout = SogLayout::Bundled;
    int version = 2;                  // of the Gaussian data (a streamed scene's first chunk)
    uint64_t count = 0;               // Gaussians at the finest LOD (streamed: plus the environment)
    int sh_degree = 0;
    int lod_levels = 1;
    std::vector<uint64_t> lod_counts; // streamed: Gaussians per level, finest (0) first
    uint64_t environment = 0;         // streamed: Gaussians drawn at every level
};

// The file a SOG folder is read through (lod-meta.json, else meta.json, else scene.sog), or
// nullopt for a folder that is not SOG.
std::optional<std::filesystem::path> sog_folder_entry(const std::filesystem::path& folder);

// read_sog (scene_io.h) decodes any layout and version.
SogSummary describe_sog(const std::filesystem::path& path);

}  // namespace pg::data
