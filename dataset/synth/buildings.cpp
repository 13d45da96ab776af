#include "dataset/synth/buildings.h"

#include <cmath>

namespace pg::data::synth {
namespace {

Material surface(Albedo a, float gloss = 0.03f) {
    Material m;
    m.albedo = std::move(a);
    m.gloss = gloss;
    m.colour_noise = 0.05f;
    return m;
}

// A wall block from z = -sink to `height`, facade textured.
Part block(const glm::dvec3& centre_xy, double lx, double ly, double height, double sink, FacadeStyle style) {
    const double c = 0.5 * (height - sink);
    style.ground = -c;
    return {make_box({0.5 * lx, 0.5 * ly, 0.5 * (height + sink)}), Frame::at({centre_xy.x, centre_xy.y, centre_xy.z + c}),
            surface(facade(style))};
}

}  // namespace

double house_height(const HouseSpec& s) {
    const double rise = s.roof == RoofKind::Flat ? 0.3 : s.pitch * (0.5 * s.depth + 0.4);
    return s.storeys * s.storey + rise;
}

double house_span(const HouseSpec& s) { return s.width + (s.garage != 0 ? 3.4 : 0.0); }

std::vector<Part> make_house(const HouseSpec& s) {
    std::vector<Part> parts;
    const double H = s.storeys * s.storey, o = 0.4;
    FacadeStyle st;
    st.wall = s.wall;
    st.roof = s.roof_colour;
    st.storey = s.storey;
    st.window_width = 1.1;
    st.window_height = 1.3;
    st.bay = s.width / std::max(2.0, std::round(s.width / 2.8));
    st.bricks = s.bricks;
    st.seed = s.seed;
    parts.push_back(block({0, 0, 0}, s.width, s.depth, H, s.sink, st));

    const glm::vec3 wall = s.wall, soffit(0.9f), tiles_colour = s.roof_colour;
    const Albedo tiles = roof_tiles(tiles_colour, 0.3, s.seed + 1);
    auto roof_albedo = [=](const glm::dvec3& p, const glm::dvec3& n) {
        if (std::abs(n.x) > 0.9 && std::abs(n.z) < 0.1) return wall;  // gable triangles
        if (n.z < -0.9) return soffit;
        return tiles(p, n);
    };
    const double rise = s.pitch * (0.5 * s.depth + o);
    if (s.roof == RoofKind::Gable)
        parts.push_back({make_gable_roof(s.width + 2 * o, s.depth + 2 * o, rise), Frame::at({0, 0, H}), surface(roof_albedo)});
    else if (s.roof == RoofKind::Hip)
        parts.push_back({make_hip_roof(s.width + 2 * o, s.depth + 2 * o, rise, std::max(0.5, s.width - s.depth)),
                         Frame::at({0, 0, H}), surface(roof_albedo)});
    else
        parts.push_back({make_box({0.5 * s.width + 0.2, 0.5 * s.depth + 0.2, 0.15}), Frame::at({0, 0, H + 0.15}),
                         surface(plain(s.roof_colour, 0.1f, 2.0))});
    if (s.chimney && s.roof != RoofKind::Flat) {
        const double ch = rise + 1.0;
        parts.push_back({make_box({0.35, 0.35, 0.5 * ch}), Frame::at({0.25 * s.width, 0.15 * s.depth, H + 0.5 * ch}),
                         surface(plain(glm::vec3(0.45f, 0.25f, 0.18f), 0.1f, 0.5))});
    }
    if (s.garage != 0) {
        const double gd = 0.7 * s.depth, gh = 2.7, gx = s.garage * (0.5 * s.width + 1.7), gy = -0.5 * s.depth + 0.5 * gd;
        const double c = 0.5 * (gh - s.sink);
        auto garage = [=](const glm::dvec3& p, const glm::dvec3& n) {
            const double v = p.z + c;  // height above the ground
            if (n.z > 0.9) return glm::vec3(0.35f);
            if (n.y < -0.9 && std::abs(p.x) < 1.25 && v > 0.0 && v < 2.2)
                return std::fmod(v, 0.5) < 0.04 ? wall * 0.5f : glm::vec3(0.82f, 0.82f, 0.8f);
            return wall;
        };
        parts.push_back({make_box({1.7, 0.5 * gd, 0.5 * (gh + s.sink)}), Frame::at({gx, gy, c}), surface(garage)});
    }
    return parts;
}

std::vector<Part> make_campus_building(Rng& rng, const CampusBuildingSpec& s) {
    std::vector<Part> parts;
    const double L = s.length, D = s.depth, H = s.height;
    FacadeStyle roof_units = s.facade;
    roof_units.storey = 100.0;  // no windows on plant rooms
    auto units = [&](double cx, double cy, double lx, double ly, double top) {
        const int n = rng.between(1, 4);
        for (int k = 0; k < n; ++k) {
            const double ux = rng.uniform(2.0, 6.0), uy = rng.uniform(2.0, 5.0), uh = rng.uniform(1.5, 3.5);
            const double x = cx + rng.uniform(-0.35, 0.35) * (lx - ux), y = cy + rng.uniform(-0.35, 0.35) * (ly - uy);
            parts.push_back(block({x, y, top}, ux, uy, uh, 0.2, roof_units));
        }
    };
    switch (s.kind) {
        case BlockKind::Slab:
            parts.push_back(block({0, 0, 0}, L, D, H, s.sink, s.facade));
            units(0, 0, L, D, H);
            break;
        case BlockKind::LShape: {
            const double t = 0.45 * D, h2 = H * rng.uniform(0.6, 1.0);
            parts.push_back(block({0, -0.5 * D + 0.5 * t, 0}, L, t, H, s.sink, s.facade));
            parts.push_back(block({0.5 * L - 0.5 * t, 0.5 * t, 0}, t, D - t, h2, s.sink, s.facade));
            units(0, -0.5 * D + 0.5 * t, L, t, H);
            break;
        }
        case BlockKind::Courtyard: {
            const double t = 0.28 * std::min(L, D);
            parts.push_back(block({0, -0.5 * D + 0.5 * t, 0}, L, t, H, s.sink, s.facade));
            parts.push_back(block({0, 0.5 * D - 0.5 * t, 0}, L, t, H, s.sink, s.facade));
            parts.push_back(block({-0.5 * L + 0.5 * t, 0, 0}, t, D - 2 * t, H, s.sink, s.facade));
            parts.push_back(block({0.5 * L - 0.5 * t, 0, 0}, t, D - 2 * t, H, s.sink, s.facade));
            units(0, 0.5 * D - 0.5 * t, L, t, H);
            break;
        }
        case BlockKind::Tower: {
            const double podium = std::min(9.0, 0.3 * H);
            parts.push_back(block({0, 0, 0}, L, D, podium, s.sink, s.facade));
            FacadeStyle glass = s.facade;
            glass.ribbon = true;
            parts.push_back(block({0, 0.1 * D, 0}, 0.5 * L, 0.55 * D, H, s.sink, glass));
            units(0, 0.1 * D, 0.5 * L, 0.55 * D, H);
            break;
        }
        case BlockKind::Hall: {
            const double wall_h = 0.55 * H;
            parts.push_back(block({0, 0, 0}, L, D, wall_h, s.sink, s.facade));
            Material roof;
            roof.albedo = plain(s.facade.roof, 0.08f, 3.0);
            roof.gloss = 0.1f;
            if (s.dome) {
                const double r = 0.42 * std::min(L, D);
                parts.push_back({make_ellipsoid({r, r, 0.45 * H}, 0.0), Frame::at({0, 0, wall_h}), roof});
            } else {
                parts.push_back({make_gable_roof(L + 1.0, D + 1.0, 0.45 * H), Frame::at({0, 0, wall_h}), roof});
            }
            break;
        }
    }
    return parts;
}

}  // namespace pg::data::synth
