// pointgauss orbit: cameras around a scene that came without any.
#include <cstdio>
#include <filesystem>

#include "app/cli/commands.h"
#include "app/common/up_arg.h"
#include "dataset/error.h"
#include "dataset/formats/camera_io.h"
#include "dataset/formats/scene_io.h"
#include "dataset/orbit.h"

namespace pg::app {

namespace fs = std::filesystem;

namespace {

struct OrbitArgs {
    std::string scene, out, up = "-y";
    int lod = 0;
    data::OrbitOptions o;
};



void run_orbit(const OrbitArgs& a) {
    auto cloud = data::load_scene(a.scene, {}, a.lod);
    auto cams = data::orbit_cameras(cloud, parse_up(a.up), a.o);
    if (fs::exists(a.out) && fs::equivalent(a.out, a.scene)) throw data::InputError(a.out, "would overwrite the scene");
    data::write_inria_cameras_json(cams, a.out);
    std::printf("wrote %zu cameras to %s\n", cams.size(), a.out.c_str());
}


}  // namespace

void register_cameras(CLI::App& app, std::function<void()>& run) {
    auto a = std::make_shared<OrbitArgs>();
    auto* cmd = app.add_subcommand("orbit", "Write an orbit of cameras (INRIA cameras.json) around a scene");
    add_scene_option(*cmd, a->scene, a->lod);
    cmd->add_option("--out", a->out, "cameras.json to write")->required();
    cmd->add_option("--up", a->up, "World up: x,y,z or x/-x/y/-y/z/-z (COLMAP scenes are y-down: -y)")
        ->capture_default_str();
    cmd->add_option("--count", a->o.count, "Number of cameras")->capture_default_str();
    cmd->add_option("--elevation", a->o.elevation_degrees, "Degrees above the horizontal plane")->capture_default_str();
    cmd->add_option("--width", a->o.width, "Image width")->capture_default_str();
    cmd->add_option("--height", a->o.height, "Image height")->capture_default_str();
    cmd->add_option("--fov", a->o.fov_x_degrees, "Horizontal field of view, degrees")->capture_default_str();
    cmd->add_option("--distance", a->o.distance, "Distance from the centre (default: fit the scene)");
    cmd->callback([a, &run] { run = [a] { run_orbit(*a); }; });

}

}  // namespace pg::app
