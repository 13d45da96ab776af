// label_hull SCENE --cameras CAMS --polygons POLYGONS.json --out OUT.ply [--dilate PX] [--suite DIR]:
// labels a capture's Gaussians by visual hulls of polygons drawn around each object in a few
// views. A Gaussian belongs to a label's hull when its centre projects inside (or within
// --dilate pixels of) that label's polygon in every view that sees it: a view where the centre
// falls outside the image or behind the camera does not carve, so polygons may stop at the
// frame. Labels are tried in the file's order, so a thin object listed first keeps the
// Gaussians where another's generous hull overlaps it; a Gaussian in no hull gets 0.
// With --suite it also writes a one-scene benchmark suite (suite.json, NAME/scene.ply,
// cameras.json, meta.json) that `pointgauss eval` scores once NAME/masks/ is added.
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "dataset/formats/camera_io.h"
#include "dataset/formats/scene_io.h"
#include "dataset/json_file.h"

using namespace pg;
namespace fs = std::filesystem;

namespace {

struct HullLabel {
    int id = 0;
    std::string name;
    std::map<std::string, std::vector<glm::dvec2>> polygons;  // by camera name
};

std::vector<HullLabel> read_polygons(const std::string& path) {
    const nlohmann::json j = data::read_json_file(path);
    std::vector<HullLabel> labels;
    if (!j.contains("labels") || !j["labels"].is_array()) throw std::runtime_error(path + ": no \"labels\" array");
    for (const auto& l : j["labels"]) {
        HullLabel h;
        h.id = l.at("id").get<int>();
        h.name = l.at("name").get<std::string>();
        if (h.id <= 0 || h.id > 65535) throw std::runtime_error(path + ": label '" + h.name + "' needs an id in 1..65535");
        for (const auto& [view, pts] : l.at("views").items()) {
            auto& poly = h.polygons[view];
            for (const auto& p : pts) poly.push_back({p.at(0).get<double>(), p.at(1).get<double>()});
            if (poly.size() < 3) throw std::runtime_error(path + ": label '" + h.name + "' view " + view + " has fewer than 3 points");
        }
        if (h.polygons.empty()) throw std::runtime_error(path + ": label '" + h.name + "' has no polygon");
        labels.push_back(std::move(h));
    }
    return labels;
}

double segment_distance(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b) {
    const glm::dvec2 ab = b - a;
    const double t = glm::clamp(glm::dot(p - a, ab) / std::max(glm::dot(ab, ab), 1e-12), 0.0, 1.0);
    return glm::length(p - (a + t * ab));
}

// Inside by the even-odd rule, or within `dilate` pixels of an edge.
bool inside(const std::vector<glm::dvec2>& poly, glm::dvec2 p, double dilate) {
    bool in = false;
    for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
        const glm::dvec2 a = poly[i], b = poly[j];
        if ((a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x) in = !in;
        if (!in && dilate > 0 && segment_distance(p, a, b) <= dilate) return true;
    }
    return in;
}

void write_text(const fs::path& path, const std::string& text) {
    std::ofstream out(path);
    out << text;
    if (!out) throw std::runtime_error(path.string() + ": cannot write");
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Label a scene's Gaussians by visual hulls of polygons drawn in a few views"};
    std::string scene, cameras_path, polygons_path, out, suite, name = "scene";
    double dilate = 0;
    app.add_option("scene", scene, "Input scene")->required();
    app.add_option("--cameras", cameras_path, "The cameras the polygons were drawn in")->required();
    app.add_option("--polygons", polygons_path, "JSON: {\"labels\": [{\"id\", \"name\", \"views\": {CAMERA: [[x, y], ...]}}]}")
        ->required();
    app.add_option("--out", out, "Output PLY: the scene with an integer 'instance' property");
    app.add_option("--dilate", dilate, "Pixels a centre may lie outside a polygon and still count as inside")
        ->check(CLI::Range(0.0, 1000.0));
    app.add_option("--suite", suite, "Also write a one-scene benchmark suite into this folder");
    app.add_option("--name", name, "The scene's name in the suite");
    CLI11_PARSE(app, argc, argv);
    try {
        if (out.empty() && suite.empty()) throw std::runtime_error("give --out, --suite or both");
        if (!out.empty() && fs::weakly_canonical(scene) == fs::weakly_canonical(out))
            throw std::runtime_error(out + ": would overwrite the input");
        data::GaussianCloud cloud = data::load_scene(scene);
        const auto cameras = data::load_cameras(cameras_path);
        const auto labels = read_polygons(polygons_path);
        std::map<std::string, const data::Camera*> by_name;
        for (const auto& c : cameras) by_name[c.name] = &c;
        for (const auto& l : labels)
            for (const auto& [view, poly] : l.polygons)
                if (!by_name.count(view)) throw std::runtime_error(polygons_path + ": view " + view + " is not in " + cameras_path);

        std::vector<int32_t> id(cloud.size(), 0);
        std::vector<size_t> count(labels.size(), 0), also(labels.size(), 0);
        for (size_t i = 0; i < cloud.size(); ++i) {
            const glm::dvec3 mu(cloud.mean[i]);
            for (size_t l = 0; l < labels.size(); ++l) {
                bool hull = true;
                for (const auto& [view, poly] : labels[l].polygons) {
                    const data::Camera& c = *by_name[view];
                    const auto px = c.project(mu);
                    if (!px) continue;
                    const glm::dvec2 p = *px;
                    if (p.x < 0 || p.y < 0 || p.x >= c.width || p.y >= c.height) continue;
                    if (!inside(poly, p, dilate)) {
                        hull = false;
                        break;
                    }
                }
                if (!hull) continue;
                if (id[i] == 0) id[i] = labels[l].id, ++count[l];
                else ++also[l];
            }
        }
        size_t none = cloud.size();
        for (size_t l = 0; l < labels.size(); ++l) {
            none -= count[l];
            std::printf("%-12s id %d: %zu Gaussians (%zu more also in its hull, taken by an earlier label)\n",
                        labels[l].name.c_str(), labels[l].id, count[l], also[l]);
        }
        std::printf("%-12s id 0: %zu Gaussians\n", "no hull", none);
        cloud.set_int_property("instance", id);
        if (!out.empty()) data::write_ply(cloud, out);
        if (!suite.empty()) {
            const fs::path dir = fs::path(suite) / name;
            fs::create_directories(dir);
            data::write_ply(cloud, dir / "scene.ply");
            fs::copy_file(cameras_path, dir / "cameras.json", fs::copy_options::overwrite_existing);
            nlohmann::json meta{{"name", name}, {"suite", "real"}, {"task", "instance"}, {"instances", nlohmann::json::array()}};
            nlohmann::json info{{"suite", "real"}, {"seed", 0}, {"task", "instance"}, {"scenes", {name}},
                                {"split", {{"train", nlohmann::json::array()}, {"test", {name}}}},
                                {"classes", {{{"id", 0}, {"name", "background"}}}}};
            for (size_t l = 0; l < labels.size(); ++l) {
                meta["instances"].push_back({{"id", labels[l].id}, {"class", labels[l].id}, {"name", labels[l].name},
                                             {"gaussians", count[l]}});
                info["classes"].push_back({{"id", labels[l].id}, {"name", labels[l].name}});
            }
            write_text(dir / "meta.json", meta.dump(2) + "\n");
            write_text(fs::path(suite) / "suite.json", info.dump(2) + "\n");
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "label_hull: %s\n", e.what());
        return 1;
    }
    return 0;
}
