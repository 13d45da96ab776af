#pragma once
// CPU reference of render/pick_pixel.comp: one pixel's contributors walked front to back as
// the reference rasterizer blends them, split into surfaces where two depth-consecutive ones
// are further apart than kSurfaceGap x the sum of their deviations along the ray; the surface of largest summed
// weight, its weighted median (the Gaussian at which its running weight reaches half its total),
// and the Gaussian at which the opacity reaches tau (or tau x the final opacity where it never
// does).
#include <cstdint>

#include "tests/reference/cpu_rasterizer.h"

namespace pg::ref {

struct RefPick {
    int32_t surface_id = -1, tau_id = -1;
    float surface_depth = 0, surface_weight = 0, tau_depth = 0, tau = 0, opacity = 0;
};

RefPick pick_reference(const pg::data::GaussianCloud& cloud, const pg::data::Camera& camera, int x, int y,
                       const RefOptions& options = {});

}  // namespace pg::ref
