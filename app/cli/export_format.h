#pragma once
// --export-format for segment (clicks and --semantic): how the 3D outputs are written.
//   ply  scene.ply with the labels as a vertex property, FOLDER/NAME.ply per object (default)
//   sog  scene.sog and FOLDER/NAME.sog: PlayCanvas SOG (bundled v2), whose codebooks and SH
//        palette are clustered on the GPU. SOG holds no extra properties: the labels are in the
//        per-object files (and in the masks), not in scene.sog.
#include <filesystem>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "dataset/gaussian_cloud.h"
#include "engine/segment/export.h"
#include "engine/vk/context.h"

namespace pg::app {

void add_export_format_option(CLI::App& cmd, std::string& format);
// The scene file's name for a format ("scene.ply" / "scene.sog"); InputError naming
// --export-format for any other format.
std::string scene_file_for(const std::string& format);

// Writes the scene and one file per object into `stage` (objects under `objects_folder`).
void write_3d_outputs(vk::Context& ctx, const std::string& format, const data::GaussianCloud& cloud,
                      const std::vector<int32_t>& labels, const std::string& property,
                      const std::vector<seg::ExportObject>& objects, const std::filesystem::path& stage,
                      const std::string& objects_folder);

}  // namespace pg::app
