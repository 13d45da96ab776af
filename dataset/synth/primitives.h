#pragma once
// The analytic solids the scenes are made of, each in its own local coordinates (z is the
// solid's axis or up). Place them with a Frame (see shape.h).
#include <memory>
#include <vector>

#include "dataset/synth/geometry.h"

namespace pg::data::synth {

using PrimitivePtr = std::shared_ptr<const Primitive>;

// Convex polyhedra, as intersections of half-spaces dot(n, x) <= d.
struct HalfSpace {
    glm::dvec3 n;
    double d;
};
PrimitivePtr make_convex(const std::vector<HalfSpace>& planes);
PrimitivePtr make_box(const glm::dvec3& half);  // centred on the origin
// A convex polygon (counter-clockwise in x-y) extruded from z0 to z1.
PrimitivePtr make_prism(const std::vector<glm::dvec2>& polygon, double z0, double z1);
// A box from z = 0 to height whose top rectangle may be smaller and shifted (car cabins,
// tapering towers): bottom half extents, top half extents, top centre offset in x-y.
PrimitivePtr make_tapered_box(glm::dvec2 bottom_half, glm::dvec2 top_half, double height,
                              glm::dvec2 top_shift = glm::dvec2(0.0));
// Roofs on the rectangle |x| <= length/2, |y| <= width/2 at z = 0, ridge along x at z = height.
PrimitivePtr make_gable_roof(double length, double width, double height);
PrimitivePtr make_hip_roof(double length, double width, double height, double ridge_length);

// A box with every edge rounded to `radius` (phones, cardboard, car bodies); centred.
PrimitivePtr make_rounded_box(const glm::dvec3& half, double radius);
// An ellipsoid centred on the origin, optionally cut flat below z = z_cut (domes, bowls).
PrimitivePtr make_ellipsoid(const glm::dvec3& radii, double z_cut = -kInf);
// A cylinder from z = 0 to height. inner_radius > 0 makes a tube with walls of thickness
// radius - inner_radius; `floor` > 0 closes its bottom with that thickness (a cup).
PrimitivePtr make_cylinder(double radius, double height, double inner_radius = 0.0, double floor = 0.0);
// A solid frustum from radius r0 at z = 0 to r1 at z = height (r1 = 0: a cone).
PrimitivePtr make_cone(double r0, double r1, double height);
// A segment from z = 0 to z = length swept by a sphere (poles, pens, cables, antennas).
PrimitivePtr make_capsule(double radius, double length);
// A torus around the z axis (tube radius `minor` at distance `major`), optionally only the
// part with azimuth in [phi0, phi1] (a handle), closed by flat discs at both ends.
PrimitivePtr make_torus(double major, double minor, double phi0 = 0.0, double phi1 = 2.0 * kPi);
// Terrain: heights on an nx x ny grid of vertices over |x| <= size_x/2, |y| <= size_y/2
// (row-major, x fastest), triangulated; the solid reaches down to z = base.
PrimitivePtr make_heightfield(int nx, int ny, double size_x, double size_y, std::vector<double> heights, double base);

// Roots of a*t^2 + b*t + c = 0 in ascending order (cancellation-free form); returns the count.
int solve_quadratic(double a, double b, double c, double& t0, double& t1);

}  // namespace pg::data::synth
