// nerfstudio / instant-ngp / NeRF-synthetic transforms.json. Intrinsics fl_x, fl_y, cx, cy,
// w, h (and k1 k2 p1 p2, k3 k4) come from the top level, each overridable per frame; when
// fl_x is absent, camera_angle_x (and camera_angle_y) give the focal length from the width
// (height). cx, cy default to the image centre, fl_y to fl_x.
// frames[].transform_matrix is camera-to-world in the OpenGL/Blender convention (x right,
// y up, z back): C2W_cv = C2W_gl * diag(1, -1, -1, 1), R = C2W_cv[:3,:3]^T, t = -R * C2W_cv[:3,3].
// Poses are taken in the file's own world frame: nerfstudio's "applied_transform" (how it
// rotated the COLMAP world) is not undone, and instant-ngp's scale/offset are not applied.
#include <cmath>
#include <numbers>

#include <nlohmann/json.hpp>

#include "dataset/atomic_file.h"
#include "dataset/error.h"
#include "dataset/formats/camera_import.h"
#include "dataset/formats/camera_io.h"
#include "dataset/json_file.h"

namespace pg::data {

namespace fs = std::filesystem;

namespace {

using nlohmann::json;

// One frame's view of the file: a key is looked up in the frame first, then at the top level.
class FrameReader {
public:
    FrameReader(const json& top, const json& frame, size_t index, const fs::path& file)
        : top_(top), frame_(frame), file_(file) {
        what_ = "frame " + std::to_string(index);
        if (!frame.is_object()) fail("is not a JSON object");
        if (frame.contains("file_path") && frame["file_path"].is_string())
            what_ += " ('" + frame["file_path"].get<std::string>() + "')";
    }

    [[noreturn]] void fail(const std::string& reason) const { throw InputError(file_.string(), what_ + ": " + reason); }

    const json* find(const char* key) const {
        if (auto it = frame_.find(key); it != frame_.end()) return &*it;
        if (auto it = top_.find(key); it != top_.end()) return &*it;
        return nullptr;
    }

    bool has(const char* key) const { return find(key) != nullptr; }

    double number(const json& v, const std::string& key) const {
        if (!v.is_number()) fail("'" + key + "' is not a number");
        const double d = v.get<double>();
        if (!std::isfinite(d)) fail("'" + key + "' is not finite");
        return d;
    }

    double number(const char* key) const {
        const json* v = find(key);
        if (!v) fail(std::string("missing key '") + key + "'");
        return number(*v, key);
    }

    double number_or(const char* key, double fallback) const { return has(key) ? number(key) : fallback; }

    int size(const char* key, const char* why) const {
        if (!has(key)) fail(std::string("missing key '") + key + "'" + why);
        const double d = number(key);
        if (d != std::floor(d) || d <= 0 || d > 1e9) fail(std::string("'") + key + "' must be a positive integer");
        return int(d);
    }

    const json& frame() const { return frame_; }

private:
    const json& top_;
    const json& frame_;
    const fs::path& file_;
    std::string what_;
};

Camera read_frame(const FrameReader& in) {
    Camera cam;
    const json* path = in.frame().contains("file_path") ? &in.frame()["file_path"] : nullptr;
    if (!path) in.fail("missing key 'file_path'");
    if (!path->is_string()) in.fail("'file_path' is not a string");
    cam.name = detail::image_stem(path->get<std::string>());

    const char* size_why = " (the image size must be given, at the top level or per frame)";
    cam.width = in.size("w", size_why);
    cam.height = in.size("h", size_why);
    if (in.has("fl_x")) {
        cam.fx = in.number("fl_x");
        cam.fy = in.number_or("fl_y", cam.fx);
    } else if (in.has("camera_angle_x")) {
        const double ax = in.number("camera_angle_x");
        if (!(ax > 0 && ax < std::numbers::pi)) in.fail("'camera_angle_x' must be in (0, pi)");
        cam.fx = 0.5 * cam.width / std::tan(0.5 * ax);
        cam.fy = cam.fx;
        if (in.has("camera_angle_y")) {
            const double ay = in.number("camera_angle_y");
            if (!(ay > 0 && ay < std::numbers::pi)) in.fail("'camera_angle_y' must be in (0, pi)");
            cam.fy = 0.5 * cam.height / std::tan(0.5 * ay);
        }
    } else {
        in.fail("no focal length: neither 'fl_x' nor 'camera_angle_x' is given");
    }
    cam.cx = in.number_or("cx", cam.width / 2.0);
    cam.cy = in.number_or("cy", cam.height / 2.0);

    if (in.has("camera_model")) {
        const json& m = *in.find("camera_model");
        if (!m.is_string()) in.fail("'camera_model' is not a string");
        const std::string model = m.get<std::string>();
        if (model != "OPENCV" && model != "PINHOLE" && model != "SIMPLE_PINHOLE")
            in.fail("camera_model " + model + " is not supported (only OPENCV and PINHOLE)");
    }
    const double k1 = in.number_or("k1", 0), k2 = in.number_or("k2", 0), p1 = in.number_or("p1", 0),
                 p2 = in.number_or("p2", 0), k3 = in.number_or("k3", 0), k4 = in.number_or("k4", 0);
    if (k1 != 0 || k2 != 0 || p1 != 0 || p2 != 0 || k3 != 0 || k4 != 0) {
        cam.model = "OPENCV";
        cam.distortion = {k1, k2, p1, p2};
        if (k3 != 0 || k4 != 0) {
            cam.model = "NERFSTUDIO_OPENCV";  // k1 k2 p1 p2 k3 k4
            cam.distortion.push_back(k3);
            cam.distortion.push_back(k4);
        }
    }

    const json* tm = in.frame().contains("transform_matrix") ? &in.frame()["transform_matrix"] : nullptr;
    if (!tm) in.fail("missing key 'transform_matrix'");
    auto bad = [&] { in.fail("'transform_matrix' must be a 4x4 (or 3x4) array of numbers"); };
    if (!tm->is_array() || (tm->size() != 4 && tm->size() != 3)) bad();
    glm::dmat3 rot;  // C2W_gl rotation, glm column-major
    glm::dvec3 centre;
    for (size_t r = 0; r < 3; ++r) {
        const json& row = (*tm)[r];
        if (!row.is_array() || row.size() != 4) bad();
        for (size_t c = 0; c < 3; ++c) rot[c][r] = in.number(row[c], "transform_matrix");
        centre[int(r)] = in.number(row[3], "transform_matrix");
    }
    if (tm->size() == 4) {
        const json& row = (*tm)[3];
        if (!row.is_array() || row.size() != 4) bad();
        for (size_t c = 0; c < 4; ++c)
            if (std::abs(in.number(row[c], "transform_matrix") - (c == 3 ? 1.0 : 0.0)) > 1e-6)
                in.fail("'transform_matrix' last row must be 0 0 0 1");
    }
    // OpenGL -> OpenCV camera axes: negate the camera's y and z columns.
    rot[1] = -rot[1];
    rot[2] = -rot[2];
    cam.R = glm::transpose(rot);
    cam.t = -(cam.R * centre);
    return cam;
}

}  // namespace

std::vector<Camera> read_transforms_json(const fs::path& path) {
    const json doc = read_json_file(path);
    if (!doc.is_object() || !doc.contains("frames"))
        throw InputError(path.string(), "expected a JSON object with 'frames' (nerfstudio transforms.json)");
    const json& frames = doc["frames"];
    if (!frames.is_array()) throw InputError(path.string(), "'frames' is not an array");

    std::vector<Camera> cams;
    try {
        for (size_t i = 0; i < frames.size(); ++i) {
            Camera cam = read_frame(FrameReader(doc, frames[i], i, path));
            detail::check_camera(cam, path);
            cams.push_back(std::move(cam));
        }
    } catch (const json::exception& e) {
        throw InputError(path.string(), e.what());
    }
    detail::finish_import(cams, path);
    return cams;
}

}  // namespace pg::data
