#pragma once
// Checks shared by the camera importers and writers (private to dataset/, implemented in
// camera_loader.cpp). Every failure is an InputError naming the file and the camera.
#include <array>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "dataset/camera.h"

namespace pg::data::detail {

// "images/frame_001.png" -> "frame_001": the directory and a known image extension
// (png, jpg, jpeg, exr, tif, tiff, bmp, webp; any case) are dropped, other dots are kept.
std::string image_stem(std::string_view file_name);

// Throws InputError(file, "camera 'name': reason") unless the camera is usable: positive
// size and focal lengths, finite intrinsics, pose and distortion, and a proper rotation
// (orthonormal to 1e-3, determinant +1).
void check_camera(const Camera& cam, const std::filesystem::path& file);

// Last step of every importer: rejects an empty set and duplicate names, sorts by name,
// and prints one warning line to stderr when any camera has lens distortion.
void finish_import(std::vector<Camera>& cams, const std::filesystem::path& file);

// COLMAP camera models by id (colmap/sensor/models.h). Only the first five are pinhole with
// an optional radial/tangential distortion and are read; the rest are rejected by name.
struct ColmapModel {
    int id;
    const char* name;
    int num_params;
};
inline constexpr std::array<ColmapModel, 12> colmap_models = {{
    {0, "SIMPLE_PINHOLE", 3},         // f cx cy
    {1, "PINHOLE", 4},                // fx fy cx cy
    {2, "SIMPLE_RADIAL", 4},          // f cx cy k
    {3, "RADIAL", 5},                 // f cx cy k1 k2
    {4, "OPENCV", 8},                 // fx fy cx cy k1 k2 p1 p2
    {5, "OPENCV_FISHEYE", 8},
    {6, "FULL_OPENCV", 12},
    {7, "FOV", 5},
    {8, "SIMPLE_RADIAL_FISHEYE", 4},
    {9, "RADIAL_FISHEYE", 5},
    {10, "THIN_PRISM_FISHEYE", 12},
    {11, "RAD_TAN_THIN_PRISM_FISHEYE", 16},
}};
inline constexpr int colmap_supported_models = 5;  // ids 0..4

// COLMAP's unit quaternion (w, x, y, z) of a world-to-camera rotation and back; the writer
// returns w >= 0. rotation_from_qvec normalizes and needs a non-zero, finite quaternion.
glm::dmat3 rotation_from_qvec(const glm::dvec4& wxyz);
glm::dvec4 qvec_from_rotation(const glm::dmat3& R);

}  // namespace pg::data::detail
