#pragma once
// SplatSeg-Synth: procedurally generated 3DGS scenes with exact ground truth, in four
// suites after the paper's SplatSeg-360 (desk, vehicles, residence: instances; campus:
// seven semantic classes, suites.h). A scene is analytic shapes; its Gaussians are sampled
// on them like a trained capture, and its per-view masks are ray cast against the shapes.
//
// Folder layout (the benchmark contract, read by `pointgauss eval` and the click simulator):
//   SUITE/suite.json, SUITE/<scene>/{scene.ply, cameras.json, sparse/0/, masks/<view>.png,
//   meta.json, contact_sheet.png (written by the CLI, which renders RGB)}.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "dataset/camera.h"
#include "dataset/gaussian_cloud.h"
#include "dataset/synth/layout.h"
#include "dataset/synth/shape.h"

namespace pg::data::synth {

enum class SuiteKind { Desk, Vehicles, Residence, Campus };
constexpr SuiteKind kAllSuites[] = {SuiteKind::Desk, SuiteKind::Vehicles, SuiteKind::Residence, SuiteKind::Campus};

const char* suite_name(SuiteKind suite);                // "desk", "vehicles", "residence", "campus"
SuiteKind parse_suite(const std::string& name);         // throws InputError("--suite", ...)
bool suite_is_semantic(SuiteKind suite);                // campus: masks and labels by class
const char* suite_task(SuiteKind suite);                // "instance" or "semantic"
std::vector<ClassInfo> suite_classes(SuiteKind suite);  // the same for every scene of a suite
std::string scene_name(SuiteKind suite, int index);     // "desk_000"

struct SynthOptions {
    double density = 1.0;  // multiplies the Gaussian count (sizes shrink by 1/sqrt)
    int cameras = 0;       // 0: the suite's default
    int width = 320, height = 240;
    double fov_x = 0.0;    // degrees; 0: the suite's default
    int sh_degree = -1;    // 0..3; -1: the suite's default (desk 3, vehicles 3, others 1)
    bool masks = true;     // cast the ground-truth masks
    int threads = 0;       // 0: all hardware threads
};

struct SynthScene {
    std::string name;
    SuiteKind suite = SuiteKind::Desk;
    int index = 0;                            // scene index in the suite
    uint64_t seed = 0;                        // the suite seed it was made with
    uint64_t scene_seed = 0;                  // derived from (suite, index, seed)
    glm::dvec3 up{0.0, -1.0, 0.0};            // world up
    glm::dvec3 centre{0.0};                   // orbit target (world)
    double scale = 1.0;                       // typical object size, scene units
    GaussianCloud cloud;                      // int properties "instance" and "class"
    std::vector<Camera> cameras;              // view_000 ...
    std::vector<std::vector<uint16_t>> masks; // per camera, row-major width*height; empty if not cast
    std::vector<ClassInfo> classes;
    std::vector<InstanceInfo> instances;      // ids 1..n with their Gaussian counts
    ShapeSet shapes;                          // world coordinates, for exact ray casts
};

// Scene `scene_index` of a suite; the same (suite, index, seed, options) give the same bytes.
SynthScene make_suite_scene(SuiteKind suite, int scene_index, uint64_t seed, const SynthOptions& options = {});

// Ground-truth mask of one camera: per pixel centre (u + 0.5, v + 0.5), the instance id of
// the first shape hit (semantic: its class at the hit point), 0 for background or nothing.
std::vector<uint16_t> cast_mask(const ShapeSet& shapes, const Camera& camera, bool semantic);
// All cameras, rows shared among `threads` workers (0: all hardware threads).
std::vector<std::vector<uint16_t>> cast_masks(const ShapeSet& shapes, const std::vector<Camera>& cameras, bool semantic,
                                              int threads);
// The ray through pixel coordinates (u, v) (pixel centres at +0.5), unit direction.
Ray camera_ray(const Camera& camera, double u, double v);

// Writes scene.ply, cameras.json, sparse/0/{cameras,images,points3D}.bin, masks/<view>.png
// (if cast) and meta.json into dir (created if needed). Every file is written atomically.
void write_scene(const SynthScene& scene, const std::filesystem::path& dir);

struct SuiteSplit {
    std::vector<std::string> train, test;
};
// About 80/20 (at least one test scene when there are two or more), chosen by the seed.
SuiteSplit split_suite(const std::vector<std::string>& scenes, uint64_t seed);
// Writes suite_dir/suite.json for the given scene names.
void write_suite_index(SuiteKind suite, uint64_t seed, const std::vector<std::string>& scenes,
                       const std::filesystem::path& suite_dir);

}  // namespace pg::data::synth
