// load_cameras: finds out which format a path holds and hands it to its reader; also the
// checks every importer shares (camera_import.h).
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <iostream>
#include <map>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "dataset/atomic_file.h"
#include "dataset/error.h"
#include "dataset/formats/camera_import.h"
#include "dataset/formats/camera_io.h"
#include "dataset/json_file.h"

namespace pg::data {

namespace fs = std::filesystem;

namespace detail {

std::string image_stem(std::string_view file_name) {
    const size_t slash = file_name.find_last_of("/\\");
    if (slash != std::string_view::npos) file_name.remove_prefix(slash + 1);
    const size_t dot = file_name.rfind('.');
    if (dot == std::string_view::npos || dot == 0) return std::string(file_name);
    std::string ext(file_name.substr(dot + 1));
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    static const std::set<std::string> image_exts = {"png", "jpg", "jpeg", "exr", "tif", "tiff", "bmp", "webp"};
    if (!image_exts.count(ext)) return std::string(file_name);
    return std::string(file_name.substr(0, dot));
}

namespace {

std::string num(double v) {
    std::ostringstream s;
    s.precision(10);
    s << v;
    return s.str();
}

}  // namespace

void check_camera(const Camera& cam, const fs::path& file) {
    auto fail = [&](const std::string& reason) {
        throw InputError(file.string(), "camera '" + cam.name + "': " + reason);
    };
    if (cam.name.empty()) throw InputError(file.string(), "camera with an empty image name");
    if (cam.width <= 0 || cam.height <= 0)
        fail("image size must be positive (got " + std::to_string(cam.width) + "x" + std::to_string(cam.height) + ")");
    const std::array<std::pair<const char*, double>, 4> intrinsics = {
        {{"fx", cam.fx}, {"fy", cam.fy}, {"cx", cam.cx}, {"cy", cam.cy}}};
    for (const auto& [key, v] : intrinsics)
        if (!std::isfinite(v)) fail(std::string(key) + " is not finite");
    if (cam.fx <= 0 || cam.fy <= 0) fail("focal length must be positive (fx " + num(cam.fx) + ", fy " + num(cam.fy) + ")");
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r)
            if (!std::isfinite(cam.R[c][r])) fail("rotation is not finite");
    for (int i = 0; i < 3; ++i)
        if (!std::isfinite(cam.t[i])) fail("translation is not finite");
    for (double k : cam.distortion)
        if (!std::isfinite(k)) fail("distortion coefficient is not finite");
    const glm::dmat3 rtr = glm::transpose(cam.R) * cam.R;
    double err = 0;
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) err = std::max(err, std::abs(rtr[c][r] - (c == r ? 1.0 : 0.0)));
    if (err > 1e-3) fail("rotation is not orthonormal (|R^T R - I| = " + num(err) + ")");
    if (glm::determinant(cam.R) < 0) fail("rotation is a reflection (determinant -1)");
}

void finish_import(std::vector<Camera>& cams, const fs::path& file) {
    if (cams.empty()) throw InputError(file.string(), "holds no cameras");
    std::sort(cams.begin(), cams.end(), [](const Camera& a, const Camera& b) { return a.name < b.name; });
    for (size_t i = 1; i < cams.size(); ++i)
        if (cams[i].name == cams[i - 1].name)
            throw InputError(file.string(), "two images are named '" + cams[i].name +
                                                "' (names without folder and extension must be unique)");
    std::map<std::string, int> distorted;  // model -> count
    size_t n = 0;
    for (const Camera& c : cams)
        if (c.has_distortion()) {
            ++distorted[c.model];
            ++n;
        }
    if (n == 0) return;
    std::string models;
    for (const auto& [model, count] : distorted) models += (models.empty() ? "" : ", ") + model;
    std::cerr << "warning: " << file.string() << ": " << n << " of " << cams.size() << " cameras have non-zero "
              << models << " distortion; lens distortion ignored by the pinhole renderer\n";
}

}  // namespace detail

namespace {

bool is_colmap_file_name(const fs::path& name) {
    return name == "cameras.bin" || name == "images.bin" || name == "cameras.txt" || name == "images.txt";
}

bool holds_colmap_model(const fs::path& dir) {
    for (const char* f : {"cameras.bin", "images.bin", "cameras.txt", "images.txt"})
        if (fs::is_regular_file(dir / f)) return true;
    return false;
}

enum class JsonKind { inria, nerfstudio, unknown };

JsonKind json_kind(const fs::path& path) {
    const nlohmann::json j = read_json_file(path);
    if (j.is_object() && j.contains("frames")) return JsonKind::nerfstudio;
    if (j.is_array()) {
        if (j.empty()) return JsonKind::inria;  // its reader reports the empty camera set
        const auto& first = j.front();
        if (first.is_object() && (first.contains("rotation") || first.contains("position") || first.contains("fx")))
            return JsonKind::inria;
    }
    return JsonKind::unknown;
}

std::vector<Camera> load_json(const fs::path& path) {
    switch (json_kind(path)) {
        case JsonKind::inria: return read_inria_cameras_json(path);
        case JsonKind::nerfstudio: return read_transforms_json(path);
        case JsonKind::unknown: break;
    }
    throw InputError(path.string(),
                     "not a camera file: expected an INRIA cameras.json (array of objects with rotation, position, "
                     "fx) or a nerfstudio transforms.json (object with frames)");
}

}  // namespace

// A folder: a COLMAP model in it, else in sparse/0 or sparse, else its cameras.json, else its
// transforms.json (in that order). A file: cameras/images .bin/.txt -> its folder's COLMAP
// model; *.json -> INRIA or nerfstudio by content.
std::vector<Camera> load_cameras(const fs::path& path) {
    std::error_code ec;
    const auto status = fs::status(path, ec);
    if (!fs::exists(status)) throw InputError(path.string(), "no such file or folder");
    if (fs::is_directory(status)) {
        if (holds_colmap_model(path)) return read_colmap(path);
        for (const fs::path sub : {"sparse/0", "sparse"})
            if (holds_colmap_model(path / sub)) return read_colmap(path / sub);
        for (const char* f : {"cameras.json", "transforms.json"})
            if (fs::is_regular_file(path / f)) return load_json(path / f);
        throw InputError(path.string(), "no cameras found: expected a COLMAP model (cameras/images .bin or .txt, "
                                        "here or in sparse/0), cameras.json or transforms.json");
    }
    if (is_colmap_file_name(path.filename())) return read_colmap(path.parent_path().empty() ? "." : path.parent_path());
    std::string ext = path.extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (ext == ".json") return load_json(path);
    throw InputError(path.string(), "unrecognized camera file: expected a folder with a COLMAP model, "
                                    "cameras.bin/images.bin/cameras.txt/images.txt, or a .json camera file");
}

}  // namespace pg::data
