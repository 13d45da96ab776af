#pragma once
// What a suite's scene builder produces: labelled shapes in canonical coordinates (z up,
// scene units), the classes and instances, and how to film it (orbit, sky, floaters).
// synth.cpp turns a Layout into a scene in world coordinates with a seeded up axis.
#include <string>
#include <vector>

#include "dataset/synth/shape.h"
#include "dataset/synth/splats.h"

namespace pg::data::synth {

struct ClassInfo {
    int id = 0;
    std::string name;
};

struct InstanceInfo {
    int id = 0;
    int cls = 0;
    std::string name;
    size_t gaussians = 0;
};

// A part of a multi-part object, in the object's coordinates.
struct Part {
    PrimitivePtr prim;
    Frame frame;
    Material material;
    double sigma_scale = 1.0;  // relative to the object's sigma
};

struct OrbitSpec {
    glm::dvec3 target{0.0};                    // canonical
    double radius = 1.0;                       // horizontal distance from the target
    std::vector<double> elevations = {20, 40}; // degrees above the horizon, one ring each
    double radius_jitter = 0.05;               // relative, per camera
    double target_jitter = 0.0;                // scene units, per camera
    double fov_x = 60.0;
    int default_count = 60;
};

struct SkySpec {
    bool enabled = false;
    double radius = 100.0;                     // distance of the dome from the target
    glm::vec3 zenith{0.30f, 0.50f, 0.85f}, horizon{0.75f, 0.85f, 0.95f}, ground{0.35f, 0.38f, 0.30f};
    int count = 3000;
};

struct Layout {
    std::vector<Shape> shapes;
    std::vector<ClassInfo> classes;            // id 0 is background
    std::vector<InstanceInfo> instances;       // ids 1..n
    OrbitSpec orbit;
    SkySpec sky;
    Lighting light;                            // canonical: up is +z
    Aabb floater_region;                       // canonical; empty: none
    double floater_fraction = 0.004;           // of the surface Gaussians
    double floater_sigma = 0.01;
    double detail_radius = kInf;               // see SplatStyle: detail falls off beyond it
    int default_sh_degree = 3;
    bool fixed_up = false;                     // desk: always -y like COLMAP; others: seeded

    int add_instance(int cls, const std::string& name) {
        const int id = int(instances.size()) + 1;
        instances.push_back({id, cls, name, 0});
        return id;
    }
    Shape& add(PrimitivePtr prim, const Frame& frame, const Material& m, double sigma, int instance = 0, int cls = 0) {
        Shape s;
        s.prim = std::move(prim);
        s.frame = frame;
        s.material = m;
        s.sigma = sigma;
        s.instance = instance;
        s.cls = cls;
        shapes.push_back(std::move(s));
        return shapes.back();
    }
    void add_parts(const std::vector<Part>& parts, const Frame& pose, double sigma, int instance, int cls) {
        for (const Part& p : parts) add(p.prim, pose * p.frame, p.material, sigma * p.sigma_scale, instance, cls);
    }
};

}  // namespace pg::data::synth
