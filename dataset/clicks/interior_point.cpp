#include "dataset/clicks/interior_point.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "dataset/clicks/distance_transform.h"
#include "dataset/clicks/kd_tree.h"

namespace pg::data::clicks {
namespace {

// The region's cells, and which of them hold a non-member.
struct CellGrid {
    glm::dvec3 origin;
    double cell = 1;
    glm::ivec3 n{1};

    size_t count() const { return size_t(n.x) * n.y * n.z; }
    size_t index_of(glm::dvec3 p) const {
        const glm::ivec3 c = glm::clamp(glm::ivec3(glm::floor((p - origin) / cell)), glm::ivec3(0), n - 1);
        return (size_t(c.z) * n.y + c.y) * n.x + c.x;
    }
};

struct Bound {
    double lo2, hi2;  // squared bounds on the capped distance
    uint32_t index;
};

}  // namespace

uint32_t most_interior_point(std::span<const glm::vec3> positions, std::span<const uint8_t> in_set,
                             std::span<const uint32_t> members, float min_cap, float min_cell) {
    if (members.size() == 1) return members[0];
    glm::dvec3 lo(positions[members[0]]), hi = lo;
    for (uint32_t i : members) {
        lo = glm::min(lo, glm::dvec3(positions[i]));
        hi = glm::max(hi, glm::dvec3(positions[i]));
    }
    const glm::dvec3 side = hi - lo;
    const double cap = std::max(0.5 * std::max({side.x, side.y, side.z}), double(min_cap));
    const double cap2 = cap * cap;
    // Non-members outside S's box grown by the cap are farther than the cap from every
    // member: only those inside matter.
    const glm::dvec3 region_lo = lo - cap, region_hi = hi + cap, ext = region_hi - region_lo;
    CellGrid g;
    g.origin = region_lo;
    g.cell = std::max({std::cbrt(ext.x * ext.y * ext.z / kMaxCells), double(min_cell), 1e-12});
    g.n = glm::max(glm::ivec3(glm::ceil(ext / g.cell)), glm::ivec3(1));
    std::vector<double> edt(g.count(), kFar);
    std::vector<uint32_t> near;
    for (size_t i = 0; i < positions.size(); ++i) {
        const glm::dvec3 p(positions[i]);
        if (in_set[i] || glm::any(glm::lessThan(p, region_lo)) || glm::any(glm::greaterThan(p, region_hi))) continue;
        near.push_back(uint32_t(i));
        edt[g.index_of(p)] = 0;
    }
    squared_edt_3d(edt, g.n.x, g.n.y, g.n.z);

    // A member and its nearest non-member each lie within half a cell diagonal of their
    // cell centres, so the true distance is the centre distance +- one diagonal.
    const double slack = std::sqrt(3.0) * g.cell;
    std::vector<Bound> bounds(members.size());
    double best_lo2 = 0;
    for (size_t m = 0; m < members.size(); ++m) {
        const double e2 = edt[g.index_of(glm::dvec3(positions[members[m]]))];
        Bound& b = bounds[m];
        b.index = members[m];
        if (e2 == kFar) {
            b.lo2 = b.hi2 = cap2;
        } else {
            const double e = std::sqrt(e2) * g.cell, elo = std::max(e - slack, 0.0), ehi = e + slack;
            b.lo2 = std::min(elo * elo, cap2);
            b.hi2 = std::min(ehi * ehi, cap2);
        }
        best_lo2 = std::max(best_lo2, b.lo2);
    }
    std::erase_if(bounds, [&](const Bound& b) { return b.hi2 < best_lo2; });
    std::sort(bounds.begin(), bounds.end(),
              [](const Bound& a, const Bound& b) { return a.hi2 != b.hi2 ? a.hi2 > b.hi2 : a.index < b.index; });

    // Exact queries only ever look within a candidate's upper bound: index just the
    // non-members that close to the candidates' box (usually a small part of the region).
    glm::dvec3 cand_lo(positions[bounds[0].index]), cand_hi = cand_lo;
    for (const Bound& b : bounds) {
        cand_lo = glm::min(cand_lo, glm::dvec3(positions[b.index]));
        cand_hi = glm::max(cand_hi, glm::dvec3(positions[b.index]));
    }
    const double reach = std::sqrt(bounds[0].hi2);
    std::erase_if(near, [&](uint32_t i) {
        const glm::dvec3 p(positions[i]);
        return glm::any(glm::lessThan(p, cand_lo - reach)) || glm::any(glm::greaterThan(p, cand_hi + reach));
    });
    const KdTree tree(positions, near);

    // Branch and bound: exact distances in order of decreasing upper bound, until no
    // remaining bound can beat (or tie) the best. Members at the cap are all collected.
    double best2 = -1;
    uint32_t best = members[0];
    std::vector<uint32_t> at_cap;
    for (const Bound& b : bounds) {
        if (b.hi2 < best2) break;
        const double d2 = b.lo2 < cap2 ? tree.nearest2(glm::dvec3(positions[b.index]), cap2) : cap2;
        if (d2 > best2 || (d2 == best2 && b.index < best)) {
            best2 = d2;
            best = b.index;
        }
        if (d2 >= cap2) at_cap.push_back(b.index);
    }
    if (best2 < cap2 || at_cap.size() < 2) return best;

    glm::dvec3 centre(0);
    for (uint32_t i : at_cap) centre += glm::dvec3(positions[i]);
    centre /= double(at_cap.size());
    double nearest2 = kFar;
    for (uint32_t i : at_cap) {
        const glm::dvec3 d = glm::dvec3(positions[i]) - centre;
        const double d2 = glm::dot(d, d);
        if (d2 < nearest2) {  // ascending index order: the lowest wins a tie
            nearest2 = d2;
            best = i;
        }
    }
    return best;
}

}  // namespace pg::data::clicks
