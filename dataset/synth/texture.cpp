#include "dataset/synth/texture.h"

#include <cmath>

namespace pg::data::synth {
namespace {

float lattice(int64_t x, int64_t y, int64_t z, uint64_t seed) {
    uint64_t h = mix64(seed ^ 0xA0761D6478BD642Full);
    h = mix64(h ^ uint64_t(x) * 0x9E3779B97F4A7C15ull);
    h = mix64(h ^ uint64_t(y) * 0xC2B2AE3D27D4EB4Full);
    h = mix64(h ^ uint64_t(z) * 0x165667B19E3779F9ull);
    return float(h >> 40) * (1.0f / 16777216.0f);
}

float smooth(float t) { return t * t * (3.0f - 2.0f * t); }

float fract(double x) { return float(x - std::floor(x)); }

glm::vec3 shade(glm::vec3 c, float k) { return glm::clamp(c * k, glm::vec3(0.0f), glm::vec3(1.0f)); }

}  // namespace

float value_noise(const glm::dvec3& p, uint64_t seed) {
    const glm::dvec3 f = glm::floor(p);
    const int64_t x = int64_t(f.x), y = int64_t(f.y), z = int64_t(f.z);
    const float u = smooth(float(p.x - f.x)), v = smooth(float(p.y - f.y)), w = smooth(float(p.z - f.z));
    float c[2][2][2];
    for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j)
            for (int k = 0; k < 2; ++k) c[i][j][k] = lattice(x + i, y + j, z + k, seed);
    auto lerp = [](float a, float b, float t) { return a + (b - a) * t; };
    const float x00 = lerp(c[0][0][0], c[1][0][0], u), x10 = lerp(c[0][1][0], c[1][1][0], u);
    const float x01 = lerp(c[0][0][1], c[1][0][1], u), x11 = lerp(c[0][1][1], c[1][1][1], u);
    return lerp(lerp(x00, x10, v), lerp(x01, x11, v), w);
}

float fbm(const glm::dvec3& p, int octaves, uint64_t seed) {
    float sum = 0.0f, amp = 0.5f, norm = 0.0f;
    glm::dvec3 q = p;
    for (int o = 0; o < octaves; ++o) {
        sum += amp * value_noise(q, seed + uint64_t(o) * 7919);
        norm += amp;
        amp *= 0.5f;
        q = q * 2.03 + glm::dvec3(17.1, 3.7, 9.3);
    }
    return sum / norm;
}

Albedo plain(glm::vec3 colour, float mottle, double feature, uint64_t seed) {
    return [=](const glm::dvec3& p, const glm::dvec3&) {
        const float n = fbm(p / feature, 3, seed) - 0.5f;
        return shade(colour, 1.0f + 2.0f * mottle * n);
    };
}

Albedo wood(glm::vec3 light, glm::vec3 dark, double period, uint64_t seed) {
    return [=](const glm::dvec3& p, const glm::dvec3&) {
        const double warp = 0.8 * period * (fbm(glm::dvec3(p.x * 0.8, p.y * 6.0, p.z * 6.0) / (20.0 * period), 3, seed) - 0.5) * 8.0;
        const float ring = 0.5f + 0.5f * float(std::sin((p.y + 0.15 * p.z + warp) / period * 2.0 * kPi));
        const float g = std::pow(ring, 3.0f);
        const float streak = fbm(glm::dvec3(p.x / (40.0 * period), p.y / period, p.z / period), 2, seed + 3);
        return glm::mix(light, dark, g) * (0.9f + 0.2f * streak);
    };
}

Albedo stripes(glm::vec3 a, glm::vec3 b, double period, const glm::dvec3& axis, float duty) {
    const glm::dvec3 k = glm::normalize(axis);
    return [=](const glm::dvec3& p, const glm::dvec3&) { return fract(glm::dot(p, k) / period) < duty ? a : b; };
}

Albedo checker(glm::vec3 a, glm::vec3 b, double cell) {
    return [=](const glm::dvec3& p, const glm::dvec3&) {
        const int64_t s = int64_t(std::floor(p.x / cell)) + int64_t(std::floor(p.y / cell)) + int64_t(std::floor(p.z / cell));
        return (s & 1) ? a : b;
    };
}

Albedo paper(glm::vec3 colour, glm::dvec2 text_half, double pitch, uint64_t seed) {
    return [=](const glm::dvec3& p, const glm::dvec3& n) {
        if (std::abs(n.z) < 0.5) return colour * 0.92f;
        const double row = std::floor(p.y / pitch);
        // Words: noise along the line; ragged line ends.
        const bool in_line = fract(p.y / pitch) < 0.45f;
        const bool word = value_noise(glm::dvec3(p.x / (2.5 * pitch), row * 3.1, 0.0), seed) > 0.42f;
        const double end = text_half.x * (1.0 - 0.5 * value_noise(glm::dvec3(row * 1.7, 0.0, 5.0), seed + 1));
        const bool text = in_line && word && std::abs(p.y) < text_half.y && p.x > -text_half.x && p.x < end;
        return text ? colour * 0.35f : colour;
    };
}

Albedo facade(const FacadeStyle& st) {
    return [=](const glm::dvec3& p, const glm::dvec3& n) {
        const float noise = fbm(p * 0.7, 3, st.seed) - 0.5f;
        if (std::abs(n.z) > 0.3) return shade(st.roof, 1.0f + 0.25f * noise);
        const double u = glm::dot(p, glm::dvec3(-n.y, n.x, 0.0)), v = p.z - st.ground;
        glm::vec3 wall = st.wall;
        if (st.bricks) {
            const double course = 0.075, brick = 0.22;
            const double row = std::floor(v / course);
            const double bu = u / brick + 0.5 * std::fmod(row, 2.0);
            const bool mortar = fract(v / course) < 0.15f || fract(bu) < 0.06f;
            wall = mortar ? st.trim * 0.8f : st.wall * (0.85f + 0.3f * lattice(int64_t(std::floor(bu)), int64_t(row), 0, st.seed));
        }
        wall = shade(wall, 1.0f + 0.3f * noise);
        if (v < 0.0) return wall * 0.7f;
        const double storey = std::floor(v / st.storey), sv = v - storey * st.storey;
        const double bay_u = u / st.bay - std::floor(u / st.bay) - 0.5;  // -0.5..0.5 within a bay
        const double wz0 = 0.5 * (st.storey - st.window_height) + 0.2, wz1 = wz0 + st.window_height;
        const bool door_face = st.door && n.y < -0.7;
        if (door_face && storey == 0 && std::abs(u) < 0.55 && sv < 2.1)
            return std::abs(u) > 0.5 || sv > 2.05 ? st.trim : st.wall * 0.35f + glm::vec3(0.12f, 0.06f, 0.02f);
        const double half_w = st.ribbon ? 0.47 : 0.5 * st.window_width / st.bay;
        if (sv > wz0 && sv < wz1 && std::abs(bay_u) < half_w) {
            const double frame = 0.07;
            if (sv < wz0 + frame || sv > wz1 - frame || std::abs(bay_u) * st.bay > half_w * st.bay - frame) return st.trim;
            // Glass: sky reflections brighten towards the top of each window, lit rooms vary.
            const float lit = lattice(int64_t(std::floor(u / st.bay)), int64_t(storey), 7, st.seed);
            return st.glass * (0.8f + 0.5f * float((sv - wz0) / st.window_height)) + glm::vec3(0.12f * lit * lit);
        }
        if (std::abs(sv - wz0 + 0.05) < 0.05 && std::abs(bay_u) < half_w + 0.03) return st.trim;  // sill
        return wall;
    };
}

Albedo roof_tiles(glm::vec3 colour, double row, uint64_t seed) {
    return [=](const glm::dvec3& p, const glm::dvec3& n) {
        // Rows run along the ridge (x); count them along the slope.
        const double along_slope = std::abs(n.z) < 0.999 ? p.z / std::max(1e-3, std::sqrt(1.0 - n.z * n.z)) : p.y;
        const double r = std::floor(along_slope / row);
        const double tile = std::floor(p.x / (0.8 * row) + 0.5 * std::fmod(r, 2.0));
        const float k = 0.8f + 0.35f * lattice(int64_t(tile), int64_t(r), 3, seed);
        const float edge = fract(along_slope / row) < 0.12f ? 0.7f : 1.0f;
        return shade(colour, k * edge * (0.9f + 0.2f * fbm(p * 0.3, 2, seed)));
    };
}

Albedo asphalt(glm::vec3 colour, uint64_t seed) {
    return [=](const glm::dvec3& p, const glm::dvec3&) {
        const float grain = value_noise(p * 40.0, seed), patch = fbm(p * 0.15, 3, seed + 1);
        return shade(colour, 0.8f + 0.2f * grain + 0.3f * (patch - 0.5f));
    };
}

Albedo grass(glm::vec3 colour, uint64_t seed, double feature) {
    return [=](const glm::dvec3& p, const glm::dvec3&) {
        const float a = fbm(p / feature, 4, seed), b = value_noise(p * (8.0 / feature), seed + 2);
        const glm::vec3 dry = colour * glm::vec3(1.35f, 1.15f, 0.7f);
        return shade(glm::mix(colour, dry, std::clamp(2.0f * (a - 0.45f), 0.0f, 1.0f)), 0.85f + 0.3f * b);
    };
}

}  // namespace pg::data::synth
