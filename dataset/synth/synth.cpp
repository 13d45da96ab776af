// From a suite's Layout to a scene: a seeded up axis and placement in the world, Gaussians
// sampled on the shapes plus floaters and sky, cameras, ground-truth masks.
#include "dataset/synth/synth.h"

#include <algorithm>
#include <cstdio>
#include <thread>

#include "dataset/error.h"
#include "dataset/synth/backdrop.h"
#include "dataset/synth/rig.h"
#include "dataset/synth/suites.h"

namespace pg::data::synth {

const char* suite_name(SuiteKind s) {
    switch (s) {
        case SuiteKind::Desk: return "desk";
        case SuiteKind::Vehicles: return "vehicles";
        case SuiteKind::Residence: return "residence";
        case SuiteKind::Campus: return "campus";
    }
    return "?";
}

SuiteKind parse_suite(const std::string& name) {
    for (SuiteKind s : kAllSuites)
        if (name == suite_name(s)) return s;
    throw InputError("--suite", "unknown suite '" + name + "' (desk, vehicles, residence, campus)");
}

bool suite_is_semantic(SuiteKind s) { return s == SuiteKind::Campus; }
const char* suite_task(SuiteKind s) { return suite_is_semantic(s) ? "semantic" : "instance"; }

std::vector<ClassInfo> suite_classes(SuiteKind s) {
    switch (s) {
        case SuiteKind::Desk: return desk_classes();
        case SuiteKind::Vehicles: return vehicles_classes();
        case SuiteKind::Residence: return residence_classes();
        case SuiteKind::Campus: return campus_classes();
    }
    return {};
}

std::string scene_name(SuiteKind s, int index) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%s_%03d", suite_name(s), index);
    return buf;
}

namespace {

void check_options(const SynthOptions& o, int scene_index) {
    if (scene_index < 0) throw InputError("scene index", "must be >= 0");
    if (!(o.density > 0.0 && o.density <= 100.0)) throw InputError("--density", "must be in (0, 100]");
    if (o.cameras < 0 || o.cameras > 1000) throw InputError("--cameras", "must be between 1 and 1000 (0: default)");
    if (o.width < 8 || o.height < 8 || o.width > 16384 || o.height > 16384)
        throw InputError("--width/--height", "must be between 8 and 16384");
    if (o.sh_degree < -1 || o.sh_degree > kMaxShDegree) throw InputError("--sh-degree", "must be 0..3");
    if (o.fov_x != 0.0 && !(o.fov_x > 1.0 && o.fov_x < 179.0)) throw InputError("--fov", "must be in (1, 179) degrees");
}

Layout build_layout(SuiteKind s, uint64_t seed) {
    switch (s) {
        case SuiteKind::Desk: return build_desk(seed);
        case SuiteKind::Vehicles: return build_vehicles(seed);
        case SuiteKind::Residence: return build_residence(seed);
        case SuiteKind::Campus: return build_campus(seed);
    }
    return {};
}

// Canonical (z up) to world. Desk: y down like COLMAP. Others: up is -y or +z by the seed,
// with a seeded turn about up and a shift, so no consumer can assume either.
Frame world_frame(const Layout& layout, double scale, Rng& rng) {
    const glm::dmat3 z_to_minus_y(glm::dvec3(1, 0, 0), glm::dvec3(0, 0, 1), glm::dvec3(0, -1, 0));  // columns
    if (layout.fixed_up) return Frame{z_to_minus_y, glm::dvec3(0.0)};
    const bool y_down = rng.chance(0.5);
    const Frame yaw = Frame::rotation(glm::dvec3(0, 0, 1), rng.uniform(0.0, 2.0 * kPi));
    const glm::dvec3 shift = scale * glm::dvec3(rng.uniform(-3, 3), rng.uniform(-3, 3), rng.uniform(-3, 3));
    return Frame{y_down ? z_to_minus_y : glm::dmat3(1.0), shift} * yaw;
}

// Median over instances of the largest extent of their shapes' bounds.
double typical_size(const Layout& layout) {
    std::vector<Aabb> boxes(layout.instances.size());
    for (const Shape& s : layout.shapes)
        if (s.instance > 0 && size_t(s.instance) <= boxes.size())
            boxes[size_t(s.instance) - 1].grow(transform_box(s.frame, s.prim->bounds()));
    std::vector<double> sizes;
    for (const Aabb& b : boxes)
        if (!b.empty()) sizes.push_back(std::max({b.size().x, b.size().y, b.size().z}));
    if (sizes.empty()) return 1.0;
    std::nth_element(sizes.begin(), sizes.begin() + long(sizes.size() / 2), sizes.end());
    return sizes[sizes.size() / 2];
}

GaussianCloud to_cloud(SplatList& all, int sh_degree, uint64_t seed) {
    // Optimisers leave Gaussians in densification order, not grouped by object: shuffle.
    const size_t n = all.size(), nc = size_t(sh_coeffs(sh_degree)) * 3;
    std::vector<size_t> order(n);
    for (size_t i = 0; i < n; ++i) order[i] = i;
    Rng rng(seed);
    for (size_t i = n; i > 1; --i) std::swap(order[i - 1], order[size_t(rng.next() % i)]);
    GaussianCloud c;
    c.sh_degree = sh_degree;
    c.format = SceneFormat::Synthetic;
    c.resize(n);
    std::vector<int32_t> instance(n), cls(n);
    for (size_t k = 0; k < n; ++k) {
        const size_t i = order[k];
        c.mean[k] = all.mean[i];
        c.log_scale[k] = all.log_scale[i];
        c.rotation[k] = all.rotation[i];
        c.opacity_logit[k] = all.opacity_logit[i];
        std::copy_n(all.sh.begin() + long(i * nc), nc, c.sh.begin() + long(k * nc));
        instance[k] = all.instance[i];
        cls[k] = all.cls[i];
    }
    all = SplatList{};
    // INRIA files carry (zero) normals; tools that expect them find them.
    for (const char* name : {"nx", "ny", "nz"}) c.extras.push_back({name, PlyType::Float32, std::vector<double>(n, 0.0)});
    c.set_int_property("instance", instance);
    c.set_int_property("class", cls);
    return c;
}

}  // namespace

SynthScene make_suite_scene(SuiteKind suite, int scene_index, uint64_t seed, const SynthOptions& opt) {
    check_options(opt, scene_index);
    const int threads = opt.threads > 0 ? opt.threads : int(std::max(1u, std::thread::hardware_concurrency()));
    const uint64_t own = derive_seed(derive_seed(seed, uint64_t(suite) + 1), uint64_t(scene_index));
    Layout layout = build_layout(suite, own);

    SynthScene scene;
    scene.name = scene_name(suite, scene_index);
    scene.suite = suite;
    scene.index = scene_index;
    scene.seed = seed;
    scene.scene_seed = own;
    scene.classes = suite_classes(suite);
    scene.instances = layout.instances;
    scene.scale = typical_size(layout);

    Rng placement(derive_seed(own, 1));
    const Frame world = world_frame(layout, scene.scale, placement);
    for (Shape& s : layout.shapes) s.frame = world * s.frame;
    scene.shapes = ShapeSet(std::move(layout.shapes));
    scene.up = world.dir_to_world(glm::dvec3(0, 0, 1));
    scene.centre = world.to_world(layout.orbit.target);

    const int count = opt.cameras > 0 ? opt.cameras : layout.orbit.default_count;
    const double fov = opt.fov_x > 0.0 ? opt.fov_x : layout.orbit.fov_x;
    scene.cameras = orbit_rig(layout.orbit, world, count, opt.width, opt.height, fov, scene.shapes, derive_seed(own, 6));

    SplatStyle style;
    // Viewpoints for culling unobserved surfaces: a fixed rig, so the Gaussians do not depend
    // on the requested camera count or size.
    for (const Camera& c : orbit_rig(layout.orbit, world, 48, 64, 48, 60.0, scene.shapes, derive_seed(own, 7)))
        style.viewpoints.push_back(c.position());
    style.sh_degree = opt.sh_degree >= 0 ? opt.sh_degree : layout.default_sh_degree;
    style.density = opt.density;
    style.light = layout.light;
    style.focus = scene.centre;
    style.detail_radius = layout.detail_radius;
    // The splats are fitted to the views' resolution, as a capture is trained on its images.
    style.pixel_angle = 2.0 * std::tan(0.5 * fov * kPi / 180.0) / double(opt.width);
    style.light.up = scene.up;
    style.light.sun = glm::normalize(world.dir_to_world(layout.light.sun));
    SplatList all = splat_shapes(scene.shapes, style, derive_seed(own, 2), threads);
    const size_t floater_count = size_t(layout.floater_fraction * double(all.size()));
    all.append(floaters(scene.shapes, layout.floater_region, world, floater_count,
                        layout.floater_sigma / std::sqrt(opt.density), style.sh_degree, derive_seed(own, 3)));
    SkySpec sky = layout.sky;
    sky.count = std::max(200, int(sky.count * std::min(1.0, opt.density)));
    all.append(sky_dome(sky, scene.centre, scene.up, style.sh_degree, derive_seed(own, 4)));
    for (InstanceInfo& inst : scene.instances)
        inst.gaussians = size_t(std::count(all.instance.begin(), all.instance.end(), inst.id));
    scene.cloud = to_cloud(all, style.sh_degree, derive_seed(own, 5));

    if (opt.masks) scene.masks = cast_masks(scene.shapes, scene.cameras, suite_is_semantic(suite), threads);
    return scene;
}

}  // namespace pg::data::synth
