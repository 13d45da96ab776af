#pragma once
// Camera importers. Accepts a COLMAP model folder (sparse/0 with cameras/images .bin or
// .txt), a COLMAP cameras/images file, an INRIA cameras.json or a nerfstudio
// transforms.json; all produce world-to-camera OpenCV cameras sorted by name.
#include <filesystem>
#include <string>
#include <vector>

#include "dataset/camera.h"

namespace pg::data {

std::vector<Camera> load_cameras(const std::filesystem::path& path);

std::vector<Camera> read_colmap(const std::filesystem::path& model_dir);  // picks .bin, else .txt
std::vector<Camera> read_inria_cameras_json(const std::filesystem::path& path);
std::vector<Camera> read_transforms_json(const std::filesystem::path& path);

// Writers used by the synthetic scenes and tests; outputs are written atomically.
void write_colmap_text(const std::vector<Camera>& cams, const std::filesystem::path& model_dir);
void write_colmap_binary(const std::vector<Camera>& cams, const std::filesystem::path& model_dir);
void write_inria_cameras_json(const std::vector<Camera>& cams, const std::filesystem::path& path);

}  // namespace pg::data
