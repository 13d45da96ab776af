#pragma once
// Reading the labels of a GT or prediction scene folder, with errors that name the file:
// per-Gaussian ids from scene.ply, per-view masks/<camera>.png, and clicks.json.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "dataset/eval/click_metrics.h"
#include "dataset/formats/image_io.h"

namespace pg::data::eval {

// The integer vertex property `property` ("instance" or "class") of a 3DGS PLY.
// InputError naming the file if it is missing or not integral.
std::vector<int32_t> read_gaussian_labels(const std::filesystem::path& ply, const std::string& property);

// A 16-bit (or 8-bit) grey index mask.
Image16 read_mask(const std::filesystem::path& png);

// The view names of a masks/ folder: the stems of its .png files, sorted.
std::vector<std::string> list_mask_views(const std::filesystem::path& masks_dir);

// {"objects": [{"id": k, "iou_per_click": [...]}]}; every IoU must lie in [0, 1] and ids
// must be distinct, else InputError naming the file.
std::vector<ObjectClicks> read_clicks_json(const std::filesystem::path& path);

}  // namespace pg::data::eval
