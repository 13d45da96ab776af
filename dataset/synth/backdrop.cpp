#include "dataset/synth/backdrop.h"

#include <cmath>

#include "dataset/synth/sampling.h"
#include "dataset/synth/texture.h"

namespace pg::data::synth {

SplatList sky_dome(const SkySpec& sky, const glm::dvec3& centre, const glm::dvec3& up_in, int sh_degree, uint64_t seed) {
    SplatList out;
    if (!sky.enabled || sky.count <= 0) return out;
    Rng rng(seed);
    const glm::dvec3 up = glm::normalize(up_in), a = perpendicular(up), b = glm::cross(up, a);
    const double lowest = std::sin(-15.0 * kPi / 180.0);
    const double kept = 0.5 * (1.0 - lowest);  // fraction of the sphere above `lowest`
    const int total = int(sky.count / kept);
    const double sigma = 0.8 * sky.radius * std::sqrt(4.0 * kPi / total);
    const double golden = kPi * (3.0 - std::sqrt(5.0));
    for (int i = 0; i < total; ++i) {
        const double z = 1.0 - 2.0 * (i + 0.5) / total;  // sin(elevation)
        if (z < lowest) break;
        const double r = std::sqrt(1.0 - z * z), az = golden * i;
        const glm::dvec3 dir = z * up + r * (std::cos(az) * a + std::sin(az) * b);
        glm::vec3 colour;
        if (z >= 0.0) {
            const float t = float(std::pow(z, 0.6));
            colour = glm::mix(sky.horizon, sky.zenith, t);
            const float cloud = fbm(glm::dvec3(dir.x, dir.y, dir.z) * 3.0 / std::max(0.2, z + 0.2), 4, seed);
            colour = glm::mix(colour, glm::vec3(0.95f, 0.95f, 0.97f), std::clamp((cloud - 0.55f) * 4.0f, 0.0f, 0.85f));
        } else {  // distant land, hazier towards the horizon
            const float haze = float(std::exp(z * 12.0));
            const float n = fbm(dir * 6.0, 3, seed + 5);
            colour = glm::mix(sky.ground * (0.7f + 0.6f * n), sky.horizon * 0.9f, haze);
        }
        Surfel s;
        s.pos = centre + sky.radius * (1.0 + 0.02 * rng.normal()) * dir;
        s.n = -dir;
        s.tangent = glm::cross(up, dir);
        const double size = sigma * rng.uniform(0.8, 1.3);
        s.su = size * 1.3;  // wider along the horizon
        s.sv = size;
        s.sn = size * rng.uniform(0.05, 0.15);
        s.colour = colour * float(1.0 + 0.03 * rng.normal());
        s.opacity = float(rng.uniform(0.9, 0.995));
        s.gloss = 0.0f;
        push_surfel(out, s, sh_degree, rng, 0, 0);
    }
    return out;
}

SplatList floaters(const ShapeSet& shapes, const Aabb& region, const Frame& world, size_t count, double sigma,
                   int sh_degree, uint64_t seed) {
    SplatList out;
    if (region.empty() || count == 0) return out;
    Rng rng(seed);
    for (size_t tries = 0; out.size() < count && tries < 20 * count; ++tries) {
        const glm::dvec3 c(rng.uniform(region.lo.x, region.hi.x), rng.uniform(region.lo.y, region.hi.y),
                           rng.uniform(region.lo.z, region.hi.z));
        const glm::dvec3 p = world.to_world(c);
        if (shapes.inside(p)) continue;
        Surfel s;
        s.pos = p;
        s.n = uniform_on_sphere(rng);
        s.tangent = perpendicular(s.n);
        const double size = sigma * rng.uniform(0.5, 3.0);
        s.su = size;
        s.sv = size * rng.uniform(0.3, 1.0);
        s.sn = size * rng.uniform(0.1, 0.5);
        const float grey = float(rng.uniform(0.2, 0.8));
        s.colour = glm::vec3(grey) * glm::vec3(float(rng.uniform(0.9, 1.1)), 1.0f, float(rng.uniform(0.85, 1.1)));
        s.opacity = float(std::exp(rng.uniform(std::log(0.005), std::log(0.3))));
        s.gloss = 0.05f;
        push_surfel(out, s, sh_degree, rng, 0, 0);
    }
    return out;
}

}  // namespace pg::data::synth
