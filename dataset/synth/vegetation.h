#pragma once
// Trees and hedges: background that overlaps and occludes the labelled objects.
#include <vector>

#include "dataset/synth/layout.h"

namespace pg::data::synth {

// A tree standing at the origin on z = 0, about `height` tall: a broadleaf (clustered
// ellipsoid crowns) or a conifer (stacked cones). Crowns are fuzzy, like trained foliage.
std::vector<Part> make_tree(Rng& rng, double height, bool conifer);

// A clipped hedge or bush: a rounded box of foliage with its base on z = 0.
std::vector<Part> make_hedge(Rng& rng, const glm::dvec3& size);

}  // namespace pg::data::synth
