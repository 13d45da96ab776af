#include "dataset/synth/rig.h"

#include <cmath>
#include <cstdio>

#include "dataset/orbit.h"

namespace pg::data::synth {

std::vector<Camera> orbit_rig(const OrbitSpec& spec, const Frame& world, int count, int width, int height,
                              double fov_x, const ShapeSet& shapes, uint64_t seed) {
    Rng rng(seed);
    const int rings = std::max(1, int(spec.elevations.size()));
    const glm::dvec3 up = world.dir_to_world(glm::dvec3(0, 0, 1));
    const double phase = rng.uniform(0.0, 2.0 * kPi);
    std::vector<Camera> cams;
    for (int ring = 0; ring < rings; ++ring) {
        const int n = count / rings + (ring < count % rings ? 1 : 0);
        const double el = spec.elevations[size_t(ring)] * kPi / 180.0;
        for (int i = 0; i < n; ++i) {
            const double az = phase + 2.0 * kPi * (i + 0.5 * ring / rings) / n + 0.2 * rng.normal() / n;
            const double radius = spec.radius * (1.0 + spec.radius_jitter * rng.normal());
            const double e = el + 0.02 * rng.normal();
            const glm::dvec3 target = spec.target + spec.target_jitter * glm::dvec3(rng.normal(), rng.normal(), 0.3 * rng.normal());
            const glm::dvec3 dir(std::cos(e) * std::cos(az), std::cos(e) * std::sin(az), std::sin(e));
            glm::dvec3 eye = target + radius * dir;
            // A camera inside a tree or a pole moves towards the target until it is free.
            for (int step = 0; step < 12 && shapes.inside(world.to_world(eye)); ++step) eye = target + (eye - target) * 0.95;
            char name[32];
            std::snprintf(name, sizeof name, "view_%03d", int(cams.size()));
            cams.push_back(look_at(name, world.to_world(eye), world.to_world(target), up, width, height, fov_x));
        }
    }
    return cams;
}

}  // namespace pg::data::synth
