// INRIA 3DGS cameras.json (gaussian-splatting utils/camera_utils.py, camera_to_JSON): an
// array of {id, img_name, width, height, position, rotation, fy, fx}. `rotation` holds the
// rows of the camera-to-world rotation and `position` the camera centre, so
// R_w2c = rotation^T and t = -R_w2c * position. The principal point is the image centre;
// our writer adds "cx"/"cy" only for an off-centre one, and the reader honours them.
#include <cmath>
#include <ostream>

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

class EntryReader {
public:
    EntryReader(const json& entry, size_t index, const fs::path& file) : entry_(entry), file_(file) {
        what_ = "camera " + std::to_string(index);
        if (!entry.is_object()) fail("is not a JSON object");
        if (entry.contains("img_name") && entry["img_name"].is_string())
            what_ += " ('" + entry["img_name"].get<std::string>() + "')";
    }

    [[noreturn]] void fail(const std::string& reason) const { throw InputError(file_.string(), what_ + ": " + reason); }

    const json& get(const char* key) const {
        auto it = entry_.find(key);
        if (it == entry_.end()) fail(std::string("missing key '") + key + "'");
        return *it;
    }

    double number(const json& v, const std::string& key) const {
        if (!v.is_number()) fail("'" + key + "' is not a number");
        const double d = v.get<double>();
        if (!std::isfinite(d)) fail("'" + key + "' is not finite");
        return d;
    }

    double number(const char* key) const { return number(get(key), key); }

    int size(const char* key) const {
        const double d = number(key);
        if (d != std::floor(d) || d <= 0 || d > 1e9) fail(std::string("'") + key + "' must be a positive integer");
        return int(d);
    }

    glm::dvec3 vec3(const char* key) const {
        const json& v = get(key);
        if (!v.is_array() || v.size() != 3) fail(std::string("'") + key + "' must be an array of 3 numbers");
        glm::dvec3 out;
        for (int i = 0; i < 3; ++i) out[i] = number(v[size_t(i)], key);
        return out;
    }

    // rows[i][j] -> glm's m[j][i]
    glm::dmat3 mat3_rows(const char* key) const {
        const json& v = get(key);
        auto bad = [&] { fail(std::string("'") + key + "' must be a 3x3 array of numbers"); };
        if (!v.is_array() || v.size() != 3) bad();
        glm::dmat3 m;
        for (size_t i = 0; i < 3; ++i) {
            if (!v[i].is_array() || v[i].size() != 3) bad();
            for (size_t j = 0; j < 3; ++j) m[j][i] = number(v[i][j], key);
        }
        return m;
    }

private:
    const json& entry_;
    const fs::path& file_;
    std::string what_;
};

}  // namespace

std::vector<Camera> read_inria_cameras_json(const fs::path& path) {
    const json doc = read_json_file(path);
    if (!doc.is_array()) throw InputError(path.string(), "expected a JSON array of cameras (INRIA cameras.json)");

    std::vector<Camera> cams;
    try {
        for (size_t i = 0; i < doc.size(); ++i) {
            const EntryReader in(doc[i], i, path);
            const json& name = in.get("img_name");
            if (!name.is_string()) in.fail("'img_name' is not a string");
            Camera cam;
            cam.name = detail::image_stem(name.get<std::string>());
            cam.width = in.size("width");
            cam.height = in.size("height");
            cam.fx = in.number("fx");
            cam.fy = in.number("fy");
            cam.cx = doc[i].contains("cx") ? in.number("cx") : cam.width / 2.0;
            cam.cy = doc[i].contains("cy") ? in.number("cy") : cam.height / 2.0;
            const glm::dmat3 c2w = in.mat3_rows("rotation");
            const glm::dvec3 centre = in.vec3("position");
            cam.R = glm::transpose(c2w);
            cam.t = -(cam.R * centre);
            detail::check_camera(cam, path);
            cams.push_back(std::move(cam));
        }
    } catch (const json::exception& e) {
        throw InputError(path.string(), e.what());
    }
    detail::finish_import(cams, path);
    return cams;
}

void write_inria_cameras_json(const std::vector<Camera>& cams, const fs::path& path) {
    nlohmann::ordered_json doc = nlohmann::ordered_json::array();
    for (size_t i = 0; i < cams.size(); ++i) {
        const Camera& c = cams[i];
        detail::check_camera(c, path);
        const glm::dmat3 c2w = glm::transpose(c.R);
        const glm::dvec3 centre = c.position();
        nlohmann::ordered_json e;
        e["id"] = i;
        e["img_name"] = c.name;
        e["width"] = c.width;
        e["height"] = c.height;
        e["position"] = {centre.x, centre.y, centre.z};
        e["rotation"] = nlohmann::ordered_json::array();
        for (int r = 0; r < 3; ++r) e["rotation"].push_back({c2w[0][r], c2w[1][r], c2w[2][r]});
        e["fy"] = c.fy;
        e["fx"] = c.fx;
        if (c.cx != c.width / 2.0 || c.cy != c.height / 2.0) {
            e["cx"] = c.cx;
            e["cy"] = c.cy;
        }
        doc.push_back(std::move(e));
    }
    if (path.has_parent_path()) {
        std::error_code ec;
        fs::create_directories(path.parent_path(), ec);
        if (ec) throw InputError(path.parent_path().string(), "cannot create folder: " + ec.message());
    }
    write_atomically(path, [&](std::ostream& out) { out << doc.dump(); });
}

}  // namespace pg::data
