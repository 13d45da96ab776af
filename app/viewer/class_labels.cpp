#include "app/viewer/class_labels.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <unordered_map>

#include "dataset/clicks/point_grid.h"

namespace pg::viewer {

namespace {

struct CellHash {
    size_t operator()(const glm::ivec3& c) const {
        return size_t(uint32_t(c.x)) * 73856093u ^ size_t(uint32_t(c.y)) * 19349663u ^
               size_t(uint32_t(c.z)) * 83492791u;
    }
};

bool finite(const glm::vec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

}  // namespace

std::string ClassLabels::name(int c) const {
    return c >= 0 && c < int(names.size()) ? names[size_t(c)] : "class_" + std::to_string(c);
}

int ClassLabels::find(const std::string& wanted) const {
    const int k = int(std::max(names.size(), counts.size()));
    for (int c = 0; c < k; ++c)
        if (name(c) == wanted) return c;
    char* end = nullptr;
    const long c = std::strtol(wanted.c_str(), &end, 10);
    return !wanted.empty() && *end == '\0' && c >= 0 && c < k ? int(c) : -1;
}

std::shared_ptr<const Region> class_region(const std::vector<glm::vec3>& means, const ClassLabels& labels, int cls,
                                           int64_t seed) {
    const size_t n = std::min(means.size(), labels.classes.size());
    std::vector<uint32_t> members;
    for (uint32_t g = 0; g < n; ++g)
        if (labels.classes[g] == cls) members.push_back(g);
    auto region = std::make_shared<Region>();
    region->source = "class " + labels.name(cls);
    if (seed >= 0) {
        if (size_t(seed) >= n || labels.classes[size_t(seed)] != cls)
            throw std::invalid_argument("class_region: the seed Gaussian is not of class " + labels.name(cls));
        std::vector<glm::vec3> points;
        for (uint32_t g : members)
            if (finite(means[g])) points.push_back(means[g]);
        const float cell = kRegionCell * data::clicks::median_spacing(points);
        if (cell > 0 && std::isfinite(cell) && finite(means[size_t(seed)])) {
            // Flood fill over occupied cells from the seed's.
            auto cell_of = [&](const glm::vec3& p) {
                const glm::vec3 c = glm::clamp(glm::floor(p / cell), glm::vec3(-1e9f), glm::vec3(1e9f));
                return glm::ivec3(c);
            };
            std::unordered_map<glm::ivec3, std::vector<uint32_t>, CellHash> cells;
            for (uint32_t g : members)
                if (finite(means[g])) cells[cell_of(means[g])].push_back(g);
            std::unordered_map<glm::ivec3, bool, CellHash> seen;
            std::vector<glm::ivec3> stack{cell_of(means[size_t(seed)])};
            seen[stack.back()] = true;
            std::vector<uint32_t> kept;
            while (!stack.empty()) {
                const glm::ivec3 c = stack.back();
                stack.pop_back();
                const auto& in = cells.at(c);
                kept.insert(kept.end(), in.begin(), in.end());
                for (int dz = -1; dz <= 1; ++dz)
                    for (int dy = -1; dy <= 1; ++dy)
                        for (int dx = -1; dx <= 1; ++dx) {
                            const glm::ivec3 nb = c + glm::ivec3(dx, dy, dz);
                            if (seen.count(nb) || !cells.count(nb)) continue;
                            seen[nb] = true;
                            stack.push_back(nb);
                        }
            }
            std::sort(kept.begin(), kept.end());
            members = std::move(kept);
            region->source += " (connected region)";
        }
    }
    region->gaussians = std::move(members);
    region->probability.reserve(region->gaussians.size());
    for (uint32_t g : region->gaussians)
        region->probability.push_back(std::max(g < labels.confidence.size() ? labels.confidence[g] : 1.0f, 1e-3f));
    return region;
}

}  // namespace pg::viewer
