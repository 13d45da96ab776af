#pragma once
// The viewer tests' stand-in decoder: a positive click at (u, v) claims Gaussians u .. u + 9 with
// probability v; a negative click at u takes u .. u + 9 back. No GPU, so sessions and documents
// are tested alone.
#include <cstdint>
#include <map>

#include "app/viewer/document.h"
#include "engine/segment/segmenter.h"

namespace pg::test {

inline viewer::Click stand_in_click(double u, double p, bool positive = true) {
    viewer::Click c;
    c.prompt.view = "view_000";
    c.prompt.u = u;
    c.prompt.v = p;
    c.prompt.positive = positive;
    c.anchor.positive = positive;
    return c;
}

inline seg::ObjectResult stand_in_claims(const data::ObjectPrompt& object) {
    std::map<uint32_t, float> claims;
    for (auto& c : object.clicks)
        for (uint32_t g = uint32_t(c.u); g < uint32_t(c.u) + 10; ++g)
            if (c.positive) claims[g] = float(c.v);
            else claims.erase(g);
    seg::ObjectResult r;
    r.id = object.id;
    r.name = object.name;
    r.claims.assign(claims.begin(), claims.end());
    return r;
}

}  // namespace pg::test
