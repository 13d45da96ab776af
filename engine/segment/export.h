#pragma once
// The files a segmentation produces, shared by `pointgauss segment` and the viewer's exports:
// the scene with an `instance` property, one standard 3DGS PLY per object, and per-view
// index masks (16-bit PNG) with colour overlays.
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "dataset/camera.h"
#include "dataset/gaussian_cloud.h"
#include "dataset/report/legend.h"
#include "engine/segment/mask_views.h"

namespace pg::seg {

struct ExportObject {
    int id = 0;
    std::string name;
};

// `name` made safe as a file name (anything but letters, digits, - _ . becomes _).
std::string safe_file_name(std::string name);

// InputError when `file` is one of `inputs` (outputs never overwrite what was read).
void refuse_overwriting(const std::filesystem::path& file, const std::vector<std::filesystem::path>& inputs);

// The scene with the labels as an integer vertex property ("instance", or "class" for the
// semantic mode).
void write_labelled_scene(const data::GaussianCloud& cloud, const std::vector<int32_t>& labels,
                          const std::filesystem::path& file, const std::string& property = "instance");

// Writes a cloud to a file of one format (write_ply by default; write_sog through the GPU
// clustering for SOG, see engine/compress/sog_quantizer.h).
using CloudWriter = std::function<void(const data::GaussianCloud&, const std::filesystem::path&)>;

// folder/<name><extension> per object (name_<id> where two objects share a name), written by
// `write` (a PLY when empty); returns the paths.
std::vector<std::filesystem::path> write_object_files(const data::GaussianCloud& cloud,
                                                      const std::vector<int32_t>& labels,
                                                      const std::vector<ExportObject>& objects,
                                                      const std::filesystem::path& folder, const CloudWriter& write = {},
                                                      const std::string& extension = ".ply");

struct ViewExportOptions {
    MaskViewsOptions masks;
    std::function<glm::vec3(uint32_t)> colour = ViewMask::default_colour;
    std::vector<data::report::LegendEntry> legend;  // drawn into each overlay's corner when given
    // Called after each view with the count done so far; returning false stops the export.
    std::function<bool(size_t done, const std::string& view)> progress;
};

// out/masks/<view>.png and out/overlays/<view>.png for each of `views`; returns GPU ms per stage.
// Returns early (false in `completed`) when progress asks to stop.
std::map<std::string, double> write_view_masks(vk::Context& ctx, const render::GpuScene& scene,
                                               const std::vector<int32_t>& labels,
                                               const std::vector<data::Camera>& cameras,
                                               const std::vector<size_t>& views, const std::filesystem::path& out,
                                               const ViewExportOptions& options, bool* completed = nullptr);

}  // namespace pg::seg
