#pragma once
// The interactive network's coordinate frame, shared by training and inference so the model
// sees the same geometry in both: origin at the ROI centre (the first positive click's
// anchor), x along the ROI length axis, y along its width axis, z up, in units of the scale
// (a typical object size), so objects are about one unit and the ground is below z = 0.
//
// The axes come from data::horizontal_axes: width = up x length, hence length x width = up
// and the frame is right-handed with the same handedness as the world.
#include <glm/glm.hpp>

#include "dataset/up_axis.h"

namespace pg::data {

struct RoiFrame {
    glm::dvec3 centre{0.0};
    glm::dvec3 length_axis{1, 0, 0}, width_axis{0, 1, 0}, up{0, 0, 1};  // unit, orthogonal
    double scale = 1.0;                                                   // world units per frame unit

    // The frame around `centre` for a scene whose up axis is `up` (need not be unit).
    static RoiFrame around(glm::dvec3 centre, glm::dvec3 up, double scale) {
        RoiFrame f;
        f.centre = centre;
        f.up = glm::normalize(up);
        horizontal_axes(f.up, f.length_axis, f.width_axis);
        f.scale = scale;
        return f;
    }

    // World point -> network coordinates ((p-c).L, (p-c).W, (p-c).U) / scale.
    glm::vec3 map(glm::dvec3 p) const {
        const glm::dvec3 d = (p - centre) / scale;
        return glm::vec3(float(glm::dot(d, length_axis)), float(glm::dot(d, width_axis)), float(glm::dot(d, up)));
    }
    // Network coordinates -> world point (the inverse of map, up to float rounding).
    glm::dvec3 unmap(glm::vec3 q) const {
        return centre + scale * (double(q.x) * length_axis + double(q.y) * width_axis + double(q.z) * up);
    }
};

}  // namespace pg::data
