#pragma once
// Gaussians the way a trained 3DGS scene holds them, sampled on the exact shapes: flat and
// surface-aligned, smaller near edges and on small parts, a long low-opacity tail, baked
// lighting with cast shadows, and small view-dependent SH terms.
#include <cstdint>
#include <vector>

#include "dataset/synth/shape.h"

namespace pg::data::synth {

// Structure of arrays in the GaussianCloud units (log-scale, opacity logit, SH with DC first).
struct SplatList {
    std::vector<glm::vec3> mean, log_scale;
    std::vector<glm::vec4> rotation;  // (w, x, y, z), not normalised
    std::vector<float> opacity_logit;
    std::vector<float> sh;            // sh_coeffs(degree) * 3 per Gaussian
    std::vector<int32_t> instance, cls;

    size_t size() const { return mean.size(); }
    void append(const SplatList& other);
};

struct Lighting {
    glm::dvec3 up{0, 0, 1};
    glm::dvec3 sun{0.3, 0.2, 0.93};  // unit, towards the light
    float ambient = 0.5f;            // light everywhere
    float direct = 0.5f;             // extra light on surfaces facing the sun
    float shadow = 0.3f;             // fraction of the direct light left in cast shadows
    float sky = 0.12f;               // extra light on surfaces facing up
};

struct SplatStyle {
    int sh_degree = 3;
    Lighting light;
    double density = 1.0;            // Gaussians per area; sizes shrink by 1/sqrt(density)
    double finest = 1.0 / 3.0;       // smallest Gaussian near edges, relative to a shape's sigma
    // Camera centres: surfaces facing none of them were never observed and get no Gaussians
    // (outer sides of walls, undersides of tables). Empty: keep everything.
    std::vector<glm::dvec3> viewpoints;
    // Detail falls off away from where the cameras look, as in a capture: beyond
    // detail_radius from `focus` Gaussians grow linearly with distance, up to max_growth.
    glm::dvec3 focus{0.0};
    double detail_radius = kInf;
    double max_growth = 4.0;
    // Radians per pixel of the views the splats were fitted to (0: no image-space blur).
    double pixel_angle = 0.0;
};

// One Gaussian on a surface point (world): long axis along `tangent` in the plane normal to n.
struct Surfel {
    glm::dvec3 pos, n, tangent;
    double su = 0, sv = 0, sn = 0;   // standard deviations along tangent, bitangent, normal
    glm::vec3 colour{0.5f};          // final linear colour in [0, 1]
    float opacity = 1.0f;
    float gloss = 0.02f;             // per-Gaussian noise in the view-dependent terms
    // A white specular lobe in SH bands 1..degree, brightest for cameras whose viewing
    // direction (camera to Gaussian, as the renderer evaluates SH) is lobe_dir.
    glm::dvec3 lobe_dir{0.0, 0.0, 1.0};
    float lobe = 0.0f;
};
// The SH basis functions 0..15 at a unit direction, as the 3DGS renderer evaluates them.
void sh_basis(const glm::dvec3& d, double* basis16);
void push_surfel(SplatList& out, const Surfel& s, int sh_degree, Rng& rng, int instance, int cls);

// Opacity as optimised captures have it: mostly near 1, a long tail down to ~0.005;
// fuzzy materials (foliage) are more translucent.
float sample_opacity(Rng& rng, float fuzz = 0.0f);

// Samples shape `index` of the set. Deterministic for a seed.
SplatList splat_shape(const ShapeSet& set, int index, const SplatStyle& style, uint64_t seed);

// Every shape, split over `threads` workers; the result is in shape order, so it
// does not depend on the thread count.
SplatList splat_shapes(const ShapeSet& set, const SplatStyle& style, uint64_t seed, int threads);

}  // namespace pg::data::synth
