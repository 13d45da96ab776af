#include "dataset/sample_scene.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>

#include <glm/gtc/quaternion.hpp>

namespace pg::data {
namespace {

constexpr float kPi = 3.14159265358979323846f;

// splitmix64 with our own float mapping: identical streams on every platform.
class Random {
public:
    explicit Random(uint64_t seed) : state_(seed * 0xD1B54A32D192ED03ull + 0x5851F42D4C957F2Dull) {}
    uint64_t next() {
        uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    float uniform() { return float(next() >> 40) * (1.0f / 16777216.0f); }
    float uniform(float lo, float hi) { return lo + (hi - lo) * uniform(); }
    float normal() {
        const float u1 = 1.0f - uniform();
        return std::sqrt(-2.0f * std::log(u1)) * std::cos(2.0f * kPi * uniform());
    }

private:
    uint64_t state_;
};

// Light baked into the colours, as a real capture has it: from above (-y), a little from the side.
const glm::vec3 kLight = glm::normalize(glm::vec3(0.35f, -1.0f, 0.25f));

float shade(glm::vec3 n) { return 0.62f + 0.38f * std::max(0.0f, glm::dot(n, kLight)); }

// One flat Gaussian: in-plane standard deviations su (along tangent) and sv, thin along normal.
struct Surfel {
    glm::vec3 pos;
    glm::vec3 normal;
    glm::vec3 tangent;       // hint for the long axis; projected onto the surface plane
    float su, sv;            // metres
    glm::vec3 colour;        // albedo before lighting and noise
    float gloss = 0.0f;      // strength of the view-dependent SH terms
    float angle_jitter = kPi;  // sd of the random in-plane rotation (radians)
    float colour_noise = 0.04f;
};

class SceneBuilder {
public:
    explicit SceneBuilder(uint32_t seed) : rng_(seed) {
        cloud_.sh_degree = 1;
        cloud_.format = SceneFormat::Synthetic;
    }
    Random& rng() { return rng_; }

    void add(const Surfel& s, int instance) {
        const glm::vec3 n = glm::normalize(s.normal);
        glm::vec3 t = s.tangent - n * glm::dot(n, s.tangent);
        if (glm::length(t) < 1e-4f) t = std::abs(n.x) < 0.9f ? glm::cross(n, glm::vec3(1, 0, 0)) : glm::cross(n, glm::vec3(0, 1, 0));
        t = glm::normalize(t);
        const float angle = s.angle_jitter * rng_.normal();
        t = std::cos(angle) * t + std::sin(angle) * glm::cross(n, t);
        const glm::vec3 b = glm::cross(n, t);
        // Columns (t, b, n): local x, y, z in world; the thin axis z is the surface normal.
        const glm::quat q = glm::quat_cast(glm::mat3(t, b, n));
        const float qscale = rng_.uniform(0.8f, 1.25f);  // files rarely hold unit quaternions
        cloud_.rotation.push_back(glm::vec4(q.w, q.x, q.y, q.z) * qscale);

        const float su = s.su * rng_.uniform(0.8f, 1.2f), sv = s.sv * rng_.uniform(0.8f, 1.2f);
        const float sn = rng_.uniform(0.0003f, 0.001f);
        cloud_.log_scale.push_back(glm::log(glm::vec3(su, sv, sn)));
        cloud_.mean.push_back(s.pos + n * (0.0002f * rng_.normal()));

        // Opacity: mostly nearly opaque, with a low tail like an optimised capture.
        const float o = rng_.uniform() < 0.88f ? rng_.uniform(0.92f, 0.995f) : rng_.uniform(0.05f, 0.9f);
        cloud_.opacity_logit.push_back(std::log(o / (1.0f - o)));

        const float brightness = 1.0f + s.colour_noise * rng_.normal();
        glm::vec3 c = s.colour * shade(n) * brightness;
        for (int k = 0; k < 3; ++k) c[k] *= 1.0f + 0.5f * s.colour_noise * rng_.normal();
        c = glm::clamp(c, glm::vec3(0.01f), glm::vec3(0.99f));
        const glm::vec3 dc = (c - 0.5f) / kShC0;
        const float rest_sd = 0.015f + s.gloss;
        cloud_.sh.push_back(dc.x);
        cloud_.sh.push_back(dc.y);
        cloud_.sh.push_back(dc.z);
        for (int k = 1; k < 4; ++k) {
            const float common = rest_sd * rng_.normal();  // mostly grey view-dependence
            for (int ch = 0; ch < 3; ++ch) cloud_.sh.push_back(common + 0.3f * rest_sd * rng_.normal());
        }
        instance_.push_back(instance);
    }

    // Calls fn(u, v) once per cell of a jittered nu x nv grid over [0,1)^2.
    void grid(int nu, int nv, const std::function<void(float, float)>& fn) {
        for (int j = 0; j < nv; ++j)
            for (int i = 0; i < nu; ++i) {
                const float u = (float(i) + rng_.uniform(0.1f, 0.9f)) / float(nu);
                const float v = (float(j) + rng_.uniform(0.1f, 0.9f)) / float(nv);
                fn(u, v);
            }
    }

    GaussianCloud finish() {
        cloud_.set_int_property("instance", instance_);
        return std::move(cloud_);
    }

private:
    Random rng_;
    GaussianCloud cloud_;
    std::vector<int32_t> instance_;
};

int cells(float length, float spacing) { return std::max(1, int(std::lround(length / spacing))); }

glm::vec3 rotate_y(glm::vec3 p, float yaw) {
    const float c = std::cos(yaw), s = std::sin(yaw);
    return glm::vec3(c * p.x + s * p.z, p.y, -s * p.x + c * p.z);
}

// An axis-aligned box (before the yaw about the vertical) without its bottom face.
// colour(face, local point) gives the albedo; faces are 0:+x 1:-x 2:top(-y) 3:+z 4:-z, and
// bit f of face_mask keeps face f.
constexpr unsigned kAllFaces = 0x1F, kSideFaces = 0x1B;
void add_box(SceneBuilder& sb, glm::vec3 centre, glm::vec3 half, float yaw, float spacing, float gloss, int instance,
             unsigned face_mask, const std::function<glm::vec3(int, glm::vec3)>& colour) {
    struct Face {
        int axis;
        float sign;
        int u_axis, v_axis;
    };
    const Face faces[] = {{0, 1, 2, 1}, {0, -1, 2, 1}, {1, -1, 0, 2}, {2, 1, 0, 1}, {2, -1, 0, 1}};
    for (int f = 0; f < 5; ++f) {
        if (!(face_mask & (1u << f))) continue;
        const Face& face = faces[f];
        const float lu = 2.0f * half[face.u_axis], lv = 2.0f * half[face.v_axis];
        const int nu = cells(lu, spacing), nv = cells(lv, spacing);
        const float sigma = 0.7f * std::sqrt(lu * lv / float(nu * nv));
        sb.grid(nu, nv, [&](float u, float v) {
            glm::vec3 local(0.0f), n(0.0f), t(0.0f);
            local[face.axis] = face.sign * half[face.axis];
            local[face.u_axis] = (u - 0.5f) * lu;
            local[face.v_axis] = (v - 0.5f) * lv;
            n[face.axis] = face.sign;
            t[face.u_axis] = 1.0f;
            Surfel s;
            s.pos = centre + rotate_y(local, yaw);
            s.normal = rotate_y(n, yaw);
            s.tangent = rotate_y(t, yaw);
            s.su = s.sv = sigma;
            s.colour = colour(f, local);
            s.gloss = gloss;
            sb.add(s, instance);
        });
    }
}

// ---- table and room ------------------------------------------------------------------

constexpr float kTableHalfX = 0.6f, kTableHalfZ = 0.4f, kTableThickness = 0.03f, kFloorY = 0.75f;
constexpr float kRoomHalf = 2.5f, kCeilingY = -1.75f;

struct Footprint {
    float x, z, radius;
};

// Albedo of the wood at a point of the table top: five planks along x with a wavy grain.
glm::vec3 wood(float x, float z) {
    const float plank_width = 2.0f * kTableHalfZ / 5.0f;
    const int plank = std::clamp(int((z + kTableHalfZ) / plank_width), 0, 4);
    const float tints[5] = {1.0f, 0.92f, 1.06f, 0.96f, 1.03f};
    const float local = z - (-kTableHalfZ + (float(plank) + 0.5f) * plank_width);
    const float phase = 2.0f * kPi *
                        (local * 32.0f + 0.35f * std::sin(x * 5.0f + float(plank) * 1.7f) +
                         0.08f * std::sin(x * 21.0f + float(plank) * 3.1f));
    const float g = std::pow(0.5f + 0.5f * std::sin(phase), 3.0f);
    glm::vec3 c = glm::mix(glm::vec3(0.68f, 0.47f, 0.27f), glm::vec3(0.44f, 0.27f, 0.13f), g) * tints[plank];
    const float seam = std::abs(std::remainder(z + kTableHalfZ, plank_width));
    if (seam < 0.0035f) c *= 0.5f;
    return c;
}

void add_table(SceneBuilder& sb, const std::vector<Footprint>& shadows) {
    // Top: a jittered grid of ~9 mm cells, long axes along the grain.
    const float spacing = 0.0092f;
    const int nu = cells(2 * kTableHalfX, spacing), nv = cells(2 * kTableHalfZ, spacing);
    sb.grid(nu, nv, [&](float u, float v) {
        Surfel s;
        s.pos = glm::vec3((u - 0.5f) * 2 * kTableHalfX, 0.0f, (v - 0.5f) * 2 * kTableHalfZ);
        s.normal = glm::vec3(0, -1, 0);
        s.tangent = glm::vec3(1, 0, 0);
        s.su = 0.95f * spacing;
        s.sv = 0.6f * spacing;
        s.angle_jitter = 0.15f;
        s.gloss = 0.02f;
        s.colour_noise = 0.03f;
        // Soft contact shadows around the objects, offset away from the light.
        float light = 1.0f;
        for (const Footprint& f : shadows) {
            const float dx = s.pos.x - (f.x - 0.02f), dz = s.pos.z - (f.z - 0.015f);
            const float d = std::max(0.0f, std::sqrt(dx * dx + dz * dz) - f.radius);
            light *= 1.0f - 0.45f * std::exp(-d * d / (2.0f * 0.018f * 0.018f));
        }
        s.colour = wood(s.pos.x, s.pos.z) * light;
        sb.add(s, 0);
    });
    // Edges of the top.
    add_box(sb, glm::vec3(0.0f, kTableThickness / 2, 0.0f), glm::vec3(kTableHalfX, kTableThickness / 2, kTableHalfZ),
            0.0f, 0.01f, 0.0f, 0, kSideFaces, [](int, glm::vec3) { return glm::vec3(0.50f, 0.32f, 0.17f); });
    // Legs.
    for (float sx : {-1.0f, 1.0f})
        for (float sz : {-1.0f, 1.0f}) {
            const float h = kFloorY - kTableThickness;
            add_box(sb, glm::vec3(sx * (kTableHalfX - 0.07f), kTableThickness + h / 2, sz * (kTableHalfZ - 0.07f)),
                    glm::vec3(0.025f, h / 2, 0.025f), 0.0f, 0.018f, 0.0f, 0, kSideFaces,
                    [](int, glm::vec3) { return glm::vec3(0.40f, 0.25f, 0.13f); });
        }
}

void add_room(SceneBuilder& sb) {
    const float span = 2 * kRoomHalf, height = kFloorY - kCeilingY;
    auto add_plane = [&](int nu, int nv, float su, float sv, const std::function<void(float, float, Surfel&)>& place) {
        sb.grid(nu, nv, [&](float u, float v) {
            Surfel s;
            s.su = su;
            s.sv = sv;
            s.colour_noise = 0.05f;
            place(u, v, s);
            sb.add(s, 0);
        });
    };
    // Floor: tiles, with a rug under the table.
    add_plane(55, 55, 0.065f, 0.065f, [&](float u, float v, Surfel& s) {
        s.pos = glm::vec3((u - 0.5f) * span, kFloorY, (v - 0.5f) * span);
        s.normal = glm::vec3(0, -1, 0);
        s.tangent = glm::vec3(1, 0, 0);
        const int tile = (int(std::floor(s.pos.x / 0.5f)) + int(std::floor(s.pos.z / 0.5f))) & 1;
        s.colour = tile ? glm::vec3(0.52f, 0.50f, 0.47f) : glm::vec3(0.44f, 0.42f, 0.40f);
        if (std::abs(s.pos.x) < 0.95f && std::abs(s.pos.z) < 0.75f) s.colour = glm::vec3(0.46f, 0.17f, 0.14f);
    });
    // Walls, inward normals: a window, a door and a picture.
    for (int w = 0; w < 4; ++w) {
        add_plane(32, 16, 0.11f, 0.11f, [&](float u, float v, Surfel& s) {
            const float a = (u - 0.5f) * span, y = kCeilingY + v * height;
            const glm::vec3 inward[4] = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {-1, 0, 0}};
            s.normal = inward[w];
            s.pos = w < 2 ? glm::vec3(a, y, -s.normal.z * kRoomHalf) : glm::vec3(-s.normal.x * kRoomHalf, y, a);
            s.tangent = glm::vec3(0, 1, 0);
            s.colour = glm::vec3(0.80f, 0.78f, 0.72f) * (0.9f + 0.1f * std::sin(a * 1.3f + float(w)));
            if (y > kFloorY - 0.1f) s.colour = glm::vec3(0.35f, 0.33f, 0.3f);  // skirting
            if (w == 0 && a > -1.0f && a < 0.6f && y > -1.4f && y < -0.3f) s.colour = glm::vec3(0.72f, 0.84f, 0.96f);
            if (w == 2 && a > -0.5f && a < 0.4f && y > -1.3f) s.colour = glm::vec3(0.45f, 0.30f, 0.18f);
            if (w == 3 && a > 0.2f && a < 1.2f && y > -1.2f && y < -0.5f)
                s.colour = glm::mix(glm::vec3(0.15f, 0.35f, 0.6f), glm::vec3(0.3f, 0.6f, 0.3f), (a - 0.2f));
        });
    }
    // Ceiling.
    add_plane(30, 30, 0.12f, 0.12f, [&](float u, float v, Surfel& s) {
        s.pos = glm::vec3((u - 0.5f) * span, kCeilingY, (v - 0.5f) * span);
        s.normal = glm::vec3(0, 1, 0);
        s.tangent = glm::vec3(1, 0, 0);
        s.colour = glm::vec3(0.9f, 0.9f, 0.88f);
    });
}

// ---- objects -------------------------------------------------------------------------

const glm::vec3 kMugCentre(-0.28f, 0.0f, 0.12f);
constexpr float kMugRadius = 0.042f, kMugHeight = 0.095f, kMugWall = 0.004f, kCoffeeDepth = 0.025f;
const glm::vec3 kBallCentre(0.22f, -0.065f, 0.16f);
constexpr float kBallRadius = 0.065f;
const glm::vec3 kBoxCentre(0.27f, -0.055f, -0.15f);
const glm::vec3 kBoxHalf(0.08f, 0.055f, 0.06f);
constexpr float kBoxYaw = 0.44f;
const glm::vec3 kConeBase(0.0f, 0.0f, -0.2f);
constexpr float kConeRadius = 0.055f, kConeHeight = 0.14f;
const glm::vec3 kBookCentre(-0.25f, -0.0175f, -0.15f);
const glm::vec3 kBookHalf(0.12f, 0.0175f, 0.085f);
constexpr float kBookYaw = -0.26f;

void add_mug(SceneBuilder& sb, int instance) {
    const glm::vec3 blue(0.16f, 0.32f, 0.66f);
    const float gloss = 0.05f;
    auto cylinder = [&](float radius, float y0, float y1, float outward, int nu, int nv, glm::vec3 colour) {
        const float sigma = 0.7f * std::sqrt(2 * kPi * radius * (y1 - y0) / float(nu * nv));
        sb.grid(nu, nv, [&](float u, float v) {
            const float a = 2 * kPi * u;
            const glm::vec3 radial(std::cos(a), 0.0f, std::sin(a));
            Surfel s;
            s.pos = kMugCentre + radius * radial + glm::vec3(0.0f, y0 + (y1 - y0) * v, 0.0f);
            s.normal = outward * radial;
            s.tangent = glm::vec3(0, 1, 0);
            s.su = s.sv = std::max(0.003f, sigma);
            s.colour = colour;
            s.gloss = gloss;
            sb.add(s, instance);
        });
    };
    cylinder(kMugRadius, -kMugHeight, 0.0f, 1.0f, 64, 19, blue);
    cylinder(kMugRadius - kMugWall, -kMugHeight, -kMugHeight + kCoffeeDepth, -1.0f, 56, 5, blue * 1.1f);
    // Rim.
    sb.grid(64, 1, [&](float u, float) {
        const float a = 2 * kPi * u;
        Surfel s;
        s.pos = kMugCentre + glm::vec3((kMugRadius - kMugWall / 2) * std::cos(a), -kMugHeight,
                                       (kMugRadius - kMugWall / 2) * std::sin(a));
        s.normal = glm::vec3(0, -1, 0);
        s.tangent = glm::vec3(-std::sin(a), 0.0f, std::cos(a));
        s.su = 0.004f;
        s.sv = 0.003f;
        s.angle_jitter = 0.1f;
        s.colour = glm::vec3(0.85f, 0.87f, 0.9f);
        sb.add(s, instance);
    });
    // Coffee surface.
    const float coffee_r = kMugRadius - kMugWall;
    sb.grid(10, 36, [&](float u, float v) {
        const float r = coffee_r * std::sqrt(u), a = 2 * kPi * v;
        Surfel s;
        s.pos = kMugCentre + glm::vec3(r * std::cos(a), -kMugHeight + kCoffeeDepth, r * std::sin(a));
        s.normal = glm::vec3(0, -1, 0);
        s.tangent = glm::vec3(1, 0, 0);
        s.su = s.sv = 0.7f * std::sqrt(kPi * coffee_r * coffee_r / 360.0f);
        s.colour = glm::vec3(0.24f, 0.13f, 0.06f);
        s.gloss = 0.06f;
        sb.add(s, instance);
    });
    // Handle: half a torus on the +x side, in the x-y plane.
    const glm::vec3 hc = kMugCentre + glm::vec3(kMugRadius, -0.048f, 0.0f);
    const float major = 0.028f, minor = 0.007f;
    sb.grid(24, 12, [&](float u, float v) {
        const float phi = (u - 0.5f) * 2.0f * 1.48f, psi = 2 * kPi * v;
        const glm::vec3 radial(std::cos(phi), std::sin(phi), 0.0f);
        const glm::vec3 normal = std::cos(psi) * radial + std::sin(psi) * glm::vec3(0, 0, 1);
        Surfel s;
        s.pos = hc + major * radial + minor * normal;
        s.normal = normal;
        s.tangent = glm::vec3(-std::sin(phi), std::cos(phi), 0.0f);
        s.su = s.sv = 0.003f;
        s.colour = blue;
        s.gloss = gloss;
        sb.add(s, instance);
    });
}

void add_ball(SceneBuilder& sb, int instance) {
    const int n = 1800;
    const float golden = kPi * (3.0f - std::sqrt(5.0f));
    const float sigma = 0.7f * std::sqrt(4 * kPi * kBallRadius * kBallRadius / float(n));
    for (int i = 0; i < n; ++i) {
        const float y = 1.0f - 2.0f * (float(i) + sb.rng().uniform(0.2f, 0.8f)) / float(n);
        const float r = std::sqrt(std::max(0.0f, 1.0f - y * y));
        const float a = golden * float(i) + 0.05f * sb.rng().normal();
        const glm::vec3 normal(r * std::cos(a), y, r * std::sin(a));
        Surfel s;
        s.pos = kBallCentre + kBallRadius * normal;
        s.normal = normal;
        s.tangent = glm::vec3(0, 1, 0);
        s.su = s.sv = sigma;
        // Beach ball: six coloured segments and white caps.
        const glm::vec3 segment_colours[3] = {{0.82f, 0.12f, 0.10f}, {0.93f, 0.93f, 0.9f}, {0.95f, 0.72f, 0.08f}};
        const float longitude = std::atan2(normal.z, normal.x) + kPi;
        s.colour = segment_colours[int(longitude / (2 * kPi) * 6.0f) % 3];
        if (std::abs(y) > 0.93f) s.colour = segment_colours[1];
        s.gloss = 0.06f;
        sb.add(s, instance);
    }
}

void add_cone(SceneBuilder& sb, int instance) {
    const float slant = std::sqrt(kConeRadius * kConeRadius + kConeHeight * kConeHeight);
    const int nu = 64, nv = 16;
    const float sigma = 0.7f * std::sqrt(kPi * kConeRadius * slant / float(nu * nv));
    sb.grid(nu, nv, [&](float u, float v) {
        const float a = 2 * kPi * u, t = std::sqrt(v);  // t: 0 at the apex, 1 at the base (uniform area)
        const glm::vec3 radial(std::cos(a), 0.0f, std::sin(a));
        Surfel s;
        s.pos = kConeBase + kConeRadius * t * radial + glm::vec3(0.0f, -kConeHeight * (1.0f - t), 0.0f);
        s.normal = (kConeHeight / slant) * radial + glm::vec3(0.0f, -kConeRadius / slant, 0.0f);
        s.tangent = glm::vec3(0, 1, 0);
        s.su = s.sv = std::max(0.003f, sigma);
        s.colour = (t > 0.45f && t < 0.62f) ? glm::vec3(0.95f, 0.95f, 0.92f) : glm::vec3(0.95f, 0.42f, 0.07f);
        s.gloss = 0.03f;
        sb.add(s, instance);
    });
}

}  // namespace

SampleScene make_sample_scene(uint32_t seed) {
    SceneBuilder sb(seed);
    const std::vector<Footprint> shadows = {
        {kMugCentre.x, kMugCentre.z, kMugRadius},
        {kBallCentre.x, kBallCentre.z, 0.03f},
        {kBoxCentre.x, kBoxCentre.z, 0.07f},
        {kConeBase.x, kConeBase.z, kConeRadius},
        {kBookCentre.x, kBookCentre.z, 0.09f},
    };
    add_table(sb, shadows);
    add_room(sb);
    add_mug(sb, 1);
    add_ball(sb, 2);
    add_box(sb, kBoxCentre, kBoxHalf, kBoxYaw, 0.006f, 0.02f, 3, kAllFaces, [](int face, glm::vec3 p) {
        const glm::vec3 cardboard(0.70f, 0.54f, 0.34f);
        if (face == 2 && std::abs(p.z) < 0.013f) return glm::vec3(0.80f, 0.74f, 0.62f);  // tape
        if (face == 3 && std::abs(p.x) < 0.04f && std::abs(p.y) < 0.025f) return glm::vec3(0.15f, 0.15f, 0.18f);  // label
        return cardboard;
    });
    add_cone(sb, 4);
    add_box(sb, kBookCentre, kBookHalf, kBookYaw, 0.006f, 0.02f, 5, kAllFaces, [](int face, glm::vec3 p) {
        const glm::vec3 cover(0.12f, 0.32f, 0.20f);
        if (face == 2) return std::abs(p.z) < 0.012f ? glm::vec3(0.85f, 0.68f, 0.25f) : cover;  // title band
        if (face == 1) return cover;                                                            // spine
        // Pages, with a fine line pattern across their edge.
        return glm::vec3(0.93f, 0.90f, 0.81f) * (0.93f + 0.07f * std::sin(p.y * 900.0f));
    });

    SampleScene scene;
    scene.cloud = sb.finish();

    // 24 views: 12 azimuths at 25 degrees of elevation, 12 (offset by 15 degrees) at 50.
    const glm::dvec3 target(0.0);
    const glm::dvec3 down(0.0, 1.0, 0.0);  // world down = image down
    for (int i = 0; i < 24; ++i) {
        const int ring = i / 12;
        const double az = glm::radians(30.0 * (i % 12) + 15.0 * ring);
        const double el = glm::radians(ring == 0 ? 25.0 : 50.0);
        const glm::dvec3 eye = target + 1.6 * glm::dvec3(std::cos(el) * std::sin(az), -std::sin(el), std::cos(el) * std::cos(az));
        const glm::dvec3 f = glm::normalize(target - eye);
        const glm::dvec3 x = glm::normalize(glm::cross(down, f));
        const glm::dvec3 y = glm::cross(f, x);
        Camera cam;
        char name[16];
        std::snprintf(name, sizeof name, "view_%03d", i);
        cam.name = name;
        cam.width = 640;
        cam.height = 480;
        cam.fx = cam.fy = 560.0;
        cam.cx = 320.0;
        cam.cy = 240.0;
        cam.R = glm::transpose(glm::dmat3(x, y, f));
        cam.t = -(cam.R * eye);
        scene.cameras.push_back(cam);
    }
    return scene;
}

}  // namespace pg::data
