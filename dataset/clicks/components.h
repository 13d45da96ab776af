#pragma once
// Connected components of an error set, on pixels and on points. Each component is
// reported with its size and its lowest element index, which names it deterministically
// (the tie-break everywhere in click simulation is "lowest index wins").
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <glm/glm.hpp>

namespace pg::data::clicks {

struct Components {
    std::vector<int32_t> label;     // per element: component number, -1 outside the set
    std::vector<uint32_t> size;     // per component
    std::vector<uint32_t> first;    // per component: its lowest element index
    // The component with the most elements; ties -> the lowest `first`. -1 if none.
    int32_t largest() const;
};

// 8-connected components of the set pixels of a w x h mask (row-major): pixels touching
// by an edge or a corner belong together, as the Euclidean distance transform sees them.
// Components are numbered in order of their first pixel.
Components pixel_components(int w, int h, std::span<const uint8_t> mask);

// Components of the set points under the relation "closer than link_radius", closed
// transitively (single linkage), found with a hash grid of cell link_radius. Components
// are numbered in order of their lowest index.
Components point_components(std::span<const glm::vec3> positions, std::span<const uint8_t> mask,
                            float link_radius);

// The region the next click goes to: the larger of the largest false negative region
// (`missed`, positive click) and the largest false positive one (`wrong`, negative);
// ties -> the region with the lower first index. nullopt when there is no error.
struct ErrorRegion {
    bool positive = true;
    int32_t id = -1;  // component number in missed (positive) or wrong
};
std::optional<ErrorRegion> largest_error_region(const Components& missed, const Components& wrong);

}  // namespace pg::data::clicks
