#include "dataset/synth/vegetation.h"

#include <cmath>

#include "dataset/synth/texture.h"

namespace pg::data::synth {
namespace {

Material foliage(Rng& rng, double feature) {
    const glm::vec3 green = hsv(float(rng.uniform(0.2, 0.33)), float(rng.uniform(0.45, 0.7)), float(rng.uniform(0.3, 0.5)));
    Material m;
    m.albedo = plain(green, 0.25f, feature, rng.next());
    m.gloss = 0.02f;
    m.colour_noise = 0.12f;
    m.fuzz = 0.6f;
    return m;
}

}  // namespace

std::vector<Part> make_tree(Rng& rng, double height, bool conifer) {
    std::vector<Part> parts;
    Material bark;
    bark.albedo = plain(glm::vec3(0.3f, 0.22f, 0.15f), 0.1f, 0.1 * height, rng.next());
    bark.aligned = 1.0f;
    const double trunk_r = 0.025 * height;
    if (conifer) {
        parts.push_back({make_cylinder(trunk_r, 0.3 * height), Frame{}, bark, 0.5});
        const Material m = foliage(rng, 0.15 * height);
        const int tiers = 3;
        for (int k = 0; k < tiers; ++k) {
            const double z = (0.2 + 0.22 * k) * height, r = (0.3 - 0.07 * k) * height;
            parts.push_back({make_cone(r, 0.0, (0.45 - 0.05 * k) * height), Frame::at({0, 0, z}), m});
        }
        return parts;
    }
    const double crown_z = rng.uniform(0.55, 0.7) * height, crown_r = rng.uniform(0.25, 0.35) * height;
    parts.push_back({make_cylinder(trunk_r, crown_z), Frame{}, bark, 0.5});
    const Material m = foliage(rng, 0.2 * height);
    const int blobs = rng.between(2, 4);
    for (int k = 0; k < blobs; ++k) {
        const double a = rng.uniform(0.0, 2.0 * kPi), off = k == 0 ? 0.0 : rng.uniform(0.3, 0.6) * crown_r;
        const glm::dvec3 radii = crown_r * glm::dvec3(rng.uniform(0.7, 1.0), rng.uniform(0.7, 1.0), rng.uniform(0.6, 0.9));
        const glm::dvec3 c(off * std::cos(a), off * std::sin(a), crown_z + rng.uniform(0.0, 0.3) * crown_r);
        parts.push_back({make_ellipsoid(radii), Frame::at(c) * Frame::rotation({0, 0, 1}, a), m});
    }
    return parts;
}

std::vector<Part> make_hedge(Rng& rng, const glm::dvec3& size) {
    Material m = foliage(rng, 0.3);
    m.fuzz = 0.4f;
    const double r = 0.3 * std::min({size.x, size.y, size.z});
    return {{make_rounded_box(0.5 * size, r), Frame::at({0, 0, 0.5 * size.z}), m}};
}

}  // namespace pg::data::synth
