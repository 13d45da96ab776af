#pragma once
// Where a click lands in 3D: the anchor the prompt encoder, the ROI and the graph seeds start
// from. Plain data, so a caller that lifted a click already (the viewer, for its marker) can
// hand the anchor to the segmenter instead of having it lifted again.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace pg::seg {

// Where a click in a view lands (`--lift`). `surface`: on the pixel's dominant surface — its
// contributors split into surfaces where they lie apart in depth, and the surface of largest
// summed blending weight wins (render/pick_pixel.comp); that is what the occlusion masks show
// at the pixel. `tau`: where the accumulated opacity first reaches tau (the paper's rule);
// it can land on a translucent blob in front of the clicked object, or on the ground behind
// the object's edge when the object alone does not reach tau.
enum class LiftRule { Surface, Tau };
LiftRule parse_lift_rule(const std::string& name, const std::string& option = "lift");
const char* lift_rule_name(LiftRule rule);

struct Anchor {
    glm::dvec3 position{0.0};
    bool positive = true;
    int32_t gaussian = -1;  // the Gaussian the click landed on (the nearest one for 3D clicks)
    // The pixel's opacity never reached tau, so the tau rule used tau x its final opacity
    // (see lift_click); `coverage` is that final opacity (1 for 3D clicks).
    bool fallback = false;
    float coverage = 1.0f;
    bool operator==(const Anchor&) const = default;
};

// Clicks a caller lifted already, per object of a prompts file and per click, with the options
// the segmenter would use (the viewer lifts each click once, for its marker).
using LiftedClicks = std::vector<std::vector<Anchor>>;

// A pixel whose final opacity is below this is empty: a click there lifts to nothing.
constexpr float kMinLiftCoverage = 0.5f;

}  // namespace pg::seg
