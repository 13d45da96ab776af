// pointgauss info SCENE [--cameras FILE]: what a scene holds, at a glance.
#include <algorithm>
#include <cstdio>

#include <glm/glm.hpp>

#include "app/cli/commands.h"
#include "dataset/formats/camera_io.h"
#include "dataset/formats/scene_io.h"
#include "dataset/formats/sog.h"
#include "dataset/scene_stats.h"

namespace pg::app {

namespace {

struct InfoArgs {
    std::string scene, cameras;
    int lod = 0;
};

void print_percentiles(const char* name, const data::Percentiles& p) {
    std::printf("%-10s", name);
    for (size_t k = 0; k < p.value.size(); ++k)
        std::printf("  p%-2g %-9.4g", double(data::Percentiles::kLevels[k]), double(p.value[k]));
    std::printf("\n");
}

void run_info(const InfoArgs& a) {
    auto cloud = data::load_scene(a.scene, {}, a.lod);
    auto s = data::compute_stats(cloud);
    std::printf("scene      %s\n", a.scene.c_str());
    std::printf("format     %s%s\n", data::scene_format_name(s.format), s.flat ? " (2DGS surfels)" : "");
    if (s.format == data::SceneFormat::Sog) {
        const auto sog = data::describe_sog(a.scene);
        std::printf("sog        %s, version %d\n", data::sog_layout_name(sog.layout), sog.version);
        if (sog.layout == data::SogLayout::Streamed) {
            std::printf("lod levels %d:", sog.lod_levels);
            for (size_t l = 0; l < sog.lod_counts.size(); ++l)
                std::printf(" %zu: %llu%s", l, (unsigned long long)sog.lod_counts[l], int(l) == a.lod ? " (loaded)" : "");
            std::printf("; environment %llu (drawn at every level)\n", (unsigned long long)sog.environment);
        }
    }
    std::printf("gaussians  %zu\n", s.count);
    std::printf("sh degree  %d\n", s.sh_degree);
    std::printf("bounds     x [%.4g, %.4g]  y [%.4g, %.4g]  z [%.4g, %.4g]\n", s.bounds_min.x, s.bounds_max.x,
                s.bounds_min.y, s.bounds_max.y, s.bounds_min.z, s.bounds_max.z);
    print_percentiles("opacity", s.opacity);
    print_percentiles("max scale", s.max_scale);
    if (!cloud.extras.empty()) {
        std::printf("extra      ");
        for (auto& e : cloud.extras) std::printf("%s:%s ", e.name.c_str(), data::ply_type_name(e.type));
        std::printf("\n");
    }
    if (a.cameras.empty()) return;
    auto cams = data::load_cameras(a.cameras);
    int wmin = 1 << 30, wmax = 0, hmin = 1 << 30, hmax = 0;
    size_t distorted = 0;
    glm::dvec3 up(0.0), centre(0.0);
    for (auto& c : cams) {
        wmin = std::min(wmin, c.width), wmax = std::max(wmax, c.width);
        hmin = std::min(hmin, c.height), hmax = std::max(hmax, c.height);
        distorted += c.has_distortion();
        up += c.up();
        centre += c.position();
    }
    std::printf("cameras    %zu from %s\n", cams.size(), a.cameras.c_str());
    std::printf("image size %dx%d", wmin, hmin);
    if (wmax != wmin || hmax != hmin) std::printf(" .. %dx%d", wmax, hmax);
    std::printf("\n");
    if (!cams.empty()) {
        up = glm::normalize(up);
        centre /= double(cams.size());
        std::printf("mean up    (%.3f, %.3f, %.3f)\n", up.x, up.y, up.z);
        std::printf("mean centre (%.4g, %.4g, %.4g)\n", centre.x, centre.y, centre.z);
        std::printf("first      %s  fx %.2f fy %.2f cx %.2f cy %.2f  %s\n", cams[0].name.c_str(), cams[0].fx, cams[0].fy,
                    cams[0].cx, cams[0].cy, cams[0].model.c_str());
    }
    if (distorted) std::printf("distortion %zu cameras have lens distortion (rendering is pinhole)\n", distorted);
}

}  // namespace

void register_info(CLI::App& app, std::function<void()>& run) {
    auto args = std::make_shared<InfoArgs>();
    auto* cmd = app.add_subcommand("info", "Format, Gaussian count, SH degree, bounds, opacity/scale percentiles, cameras");
    add_scene_option(*cmd, args->scene, args->lod);
    cmd->add_option("--cameras", args->cameras, "COLMAP model folder, cameras.json or transforms.json");
    cmd->callback([args, &run] { run = [args] { run_info(*args); }; });
}

}  // namespace pg::app
