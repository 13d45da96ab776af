#pragma once
// Real roots of a polynomial inside an interval, robust for the ray-torus quartic: the
// derivative's roots split the interval into monotonic pieces, each bisected to the end.

namespace pg::data::synth {

// c[0] + c[1] t + ... + c[degree] t^degree; writes the roots in [lo, hi] in ascending order
// into roots (room for `degree`) and returns their count. Degree at most 8.
int poly_roots(const double* c, int degree, double lo, double hi, double* roots);

}  // namespace pg::data::synth
