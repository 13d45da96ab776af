#include "dataset/clicks/components.h"

#include <numeric>

#include "dataset/clicks/point_grid.h"

namespace pg::data::clicks {

int32_t Components::largest() const {
    int32_t best = -1;
    for (size_t c = 0; c < size.size(); ++c)
        if (best < 0 || size[c] > size[best] || (size[c] == size[best] && first[c] < first[best]))
            best = int32_t(c);
    return best;
}

std::optional<ErrorRegion> largest_error_region(const Components& missed, const Components& wrong) {
    const int32_t a = missed.largest(), b = wrong.largest();
    if (a < 0 && b < 0) return std::nullopt;
    const bool positive = b < 0 || (a >= 0 && (missed.size[a] > wrong.size[b] ||
                                               (missed.size[a] == wrong.size[b] && missed.first[a] < wrong.first[b])));
    return ErrorRegion{positive, positive ? a : b};
}

Components pixel_components(int w, int h, std::span<const uint8_t> mask) {
    Components out;
    out.label.assign(size_t(w) * h, -1);
    std::vector<uint32_t> stack;
    for (size_t seed = 0; seed < out.label.size(); ++seed) {
        if (!mask[seed] || out.label[seed] >= 0) continue;
        const int32_t id = int32_t(out.size.size());
        uint32_t n = 0;
        out.label[seed] = id;
        stack.push_back(uint32_t(seed));
        while (!stack.empty()) {
            const uint32_t p = stack.back();
            stack.pop_back();
            ++n;
            const int x = int(p % w), y = int(p / w);
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int nx = x + dx, ny = y + dy;
                    if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
                    const size_t q = size_t(ny) * w + nx;
                    if (mask[q] && out.label[q] < 0) {
                        out.label[q] = id;
                        stack.push_back(uint32_t(q));
                    }
                }
        }
        out.size.push_back(n);
        out.first.push_back(uint32_t(seed));  // row-major scan: the seed is the lowest index
    }
    return out;
}

namespace {

// Union-find whose root is always the lowest index of its set, so the result does not
// depend on the order in which links are found.
struct LowestRootSets {
    std::vector<uint32_t> parent;
    explicit LowestRootSets(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
    uint32_t find(uint32_t i) {
        while (parent[i] != i) {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        return i;
    }
    void unite(uint32_t a, uint32_t b) {
        a = find(a);
        b = find(b);
        if (a < b) parent[b] = a;
        else if (b < a) parent[a] = b;
    }
};

}  // namespace

Components point_components(std::span<const glm::vec3> positions, std::span<const uint8_t> mask,
                            float link_radius) {
    Components out;
    out.label.assign(positions.size(), -1);
    std::vector<uint32_t> members;
    for (size_t i = 0; i < positions.size(); ++i)
        if (mask[i]) members.push_back(uint32_t(i));
    if (members.empty()) return out;

    const PointGrid grid(positions, members, link_radius);
    LowestRootSets sets(positions.size());
    const double r2 = double(link_radius) * link_radius;
    // Each unordered pair of neighbouring cells once: the cell itself and 13 of its 26
    // neighbours (those after it in z, then y, then x order).
    for (const glm::ivec3& c : grid.cells()) {
        const std::span<const uint32_t> here = grid.points_in(c);
        for (int dz = 0; dz <= 1; ++dz)
            for (int dy = dz ? -1 : 0; dy <= 1; ++dy)
                for (int dx = (dz || dy) ? -1 : 0; dx <= 1; ++dx) {
                    const bool self = dx == 0 && dy == 0 && dz == 0;
                    const std::span<const uint32_t> there = grid.points_in(c + glm::ivec3(dx, dy, dz));
                    for (size_t a = 0; a < here.size(); ++a) {
                        const glm::dvec3 pa(positions[here[a]]);
                        for (size_t b = self ? a + 1 : 0; b < there.size(); ++b) {
                            const glm::dvec3 d = glm::dvec3(positions[there[b]]) - pa;
                            if (glm::dot(d, d) < r2 && sets.find(here[a]) != sets.find(there[b]))
                                sets.unite(here[a], there[b]);
                        }
                    }
                }
    }
    for (uint32_t i : members) {  // ascending, so roots (lowest members) come first
        const uint32_t root = sets.find(i);
        if (root == i) {
            out.label[i] = int32_t(out.size.size());
            out.size.push_back(0);
            out.first.push_back(i);
        } else {
            out.label[i] = out.label[root];
        }
        ++out.size[out.label[i]];
    }
    return out;
}

}  // namespace pg::data::clicks
