#include "dataset/synth/poly_roots.h"

#include <cmath>

#include "dataset/synth/primitives.h"

namespace pg::data::synth {
namespace {

double eval(const double* c, int degree, double t) {
    double v = c[degree];
    for (int k = degree - 1; k >= 0; --k) v = v * t + c[k];
    return v;
}

// The root of a monotonic piece [a, b] with f(a), f(b) of opposite signs.
double bisect(const double* c, int degree, double a, double b, double fa) {
    for (int it = 0; it < 200; ++it) {
        const double m = 0.5 * (a + b);
        if (m <= a || m >= b) break;  // no representable midpoint left
        const double fm = eval(c, degree, m);
        if (fm == 0.0) return m;
        if ((fm < 0.0) == (fa < 0.0)) {
            a = m;
            fa = fm;
        } else {
            b = m;
        }
    }
    return 0.5 * (a + b);
}

}  // namespace

int poly_roots(const double* c, int degree, double lo, double hi, double* roots) {
    while (degree > 0 && c[degree] == 0.0) --degree;
    if (degree == 0) return 0;
    if (degree == 1) {
        const double t = -c[0] / c[1];
        if (t < lo || t > hi) return 0;
        roots[0] = t;
        return 1;
    }
    if (degree == 2) {
        double t0, t1;
        const int n = solve_quadratic(c[2], c[1], c[0], t0, t1);
        int k = 0;
        if (n >= 1 && t0 >= lo && t0 <= hi) roots[k++] = t0;
        if (n == 2 && t1 >= lo && t1 <= hi && t1 != t0) roots[k++] = t1;
        return k;
    }
    double d[8], crit[8];
    for (int k = 1; k <= degree; ++k) d[k - 1] = k * c[k];
    const int nc = poly_roots(d, degree - 1, lo, hi, crit);
    double edges[10];
    int ne = 0;
    edges[ne++] = lo;
    for (int k = 0; k < nc; ++k) edges[ne++] = crit[k];
    edges[ne++] = hi;
    int count = 0;
    for (int k = 0; k + 1 < ne && count < degree; ++k) {
        const double a = edges[k], b = edges[k + 1];
        const double fa = eval(c, degree, a), fb = eval(c, degree, b);
        if (fa == 0.0) {
            if (count == 0 || roots[count - 1] != a) roots[count++] = a;
        } else if ((fa < 0.0) != (fb < 0.0) && fb != 0.0) {
            roots[count++] = bisect(c, degree, a, b, fa);
        }
        if (k + 2 == ne && fb == 0.0 && count < degree) roots[count++] = b;
    }
    return count;
}

}  // namespace pg::data::synth
