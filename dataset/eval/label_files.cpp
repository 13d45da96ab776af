#include "dataset/eval/label_files.h"

#include <algorithm>
#include <cmath>
#include <set>

#include <nlohmann/json.hpp>

#include "dataset/atomic_file.h"
#include "dataset/error.h"
#include "dataset/formats/scene_io.h"

namespace pg::data::eval {

namespace fs = std::filesystem;
using nlohmann::json;

std::vector<int32_t> read_gaussian_labels(const fs::path& ply, const std::string& property) {
    if (!fs::exists(ply)) throw InputError(ply.string(), "no such file");
    const GaussianCloud cloud = load_scene(ply);
    auto labels = cloud.int_property(property);
    if (!labels) {
        const bool present = cloud.find_extra(property) != nullptr;
        throw InputError(ply.string(), present ? "vertex property '" + property + "' holds non-integer values"
                                               : "no vertex property '" + property + "'");
    }
    return std::move(*labels);
}

Image16 read_mask(const fs::path& png) {
    if (!fs::exists(png)) throw InputError(png.string(), "no such file");
    return read_png16(png);
}

std::vector<std::string> list_mask_views(const fs::path& masks_dir) {
    if (!fs::is_directory(masks_dir)) throw InputError(masks_dir.string(), "no such folder");
    std::vector<std::string> views;
    for (const auto& e : fs::directory_iterator(masks_dir))
        if (e.is_regular_file() && e.path().extension() == ".png") views.push_back(e.path().stem().string());
    std::sort(views.begin(), views.end());
    return views;
}

std::vector<ObjectClicks> read_clicks_json(const fs::path& path) {
    std::vector<ObjectClicks> out;
    try {
        const json j = json::parse(read_text_file(path));
        if (!j.is_object() || !j.contains("objects") || !j.at("objects").is_array())
            throw InputError(path.string(), "expected {\"objects\": [...]}");
        std::set<int32_t> seen;
        for (const json& o : j.at("objects")) {
            ObjectClicks c{o.at("id").get<int32_t>(), o.at("iou_per_click").get<std::vector<double>>()};
            if (!seen.insert(c.id).second)
                throw InputError(path.string(), "object " + std::to_string(c.id) + " listed twice");
            for (double v : c.iou_per_click)
                if (!std::isfinite(v) || v < 0.0 || v > 1.0)
                    throw InputError(path.string(), "object " + std::to_string(c.id) + ": IoU " + std::to_string(v) +
                                                        " outside [0, 1]");
            out.push_back(std::move(c));
        }
    } catch (const json::exception& e) {
        throw InputError(path.string(), e.what());
    }
    return out;
}

}  // namespace pg::data::eval
