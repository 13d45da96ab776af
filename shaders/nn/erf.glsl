// erf, erfc and exact GELU in f32 (GLSL has no erf). Two pieces, fitted for this project by
// weighted least squares on 300 Chebyshev nodes in 40-digit arithmetic (mpmath):
//   |x| < 0.875:  erf(x)  = x * P(x^2)               (relative error of the fit 9e-9)
//   |x| >= 0.875: erfc(x) = exp(-x^2) * Q(1/x - 0.6) (absolute error of the fit 7e-11)
// Evaluated in f32 without fused multiply-adds, |erf - erf_exact| <= 1.1e-7 over [-10, 10]
// (tests/nn_ops check 2e-7). GELU goes through erfc for x < 0, which keeps its relative
// accuracy where 1 + erf(x) would cancel.
#ifndef PG_ERF_GLSL
#define PG_ERF_GLSL

float pg_erf_small(float x) {  // |x| < 0.875
    const float u = x * x;
    float p = -0.00062185033382;
    p = p * u + 0.0050351221633;
    p = p * u - 0.0267934525865;
    p = p * u + 0.112825104529;
    p = p * u - 0.376125558391;
    p = p * u + 1.12837915834;
    return x * p;
}

float pg_erfc_large(float x) {  // x >= 0.875
    const float t = 1.0 / x - 0.6;
    float q = 0.00699878175888;
    q = q * t - 0.0258564366167;
    q = q * t + 0.0470344389873;
    q = q * t - 0.0536746735828;
    q = q * t + 0.0296259445415;
    q = q * t + 0.041123997773;
    q = q * t - 0.175581979987;
    q = q * t + 0.39098402106;
    q = q * t + 0.296287476372;
    const float xc = min(x, 10.0);  // exp underflows to 0 beyond; keeps x*x finite
    return exp(-xc * xc) * q;
}

float pg_erf(float x) {
    const float a = abs(x);
    const float r = a < 0.875 ? pg_erf_small(a) : 1.0 - pg_erfc_large(max(a, 0.875));
    return x < 0.0 ? -r : r;
}

float pg_erfc(float x) {
    const float a = abs(x);
    const float c = a < 0.875 ? 1.0 - pg_erf_small(a) : pg_erfc_large(max(a, 0.875));
    return x < 0.0 ? 2.0 - c : c;
}

// 0.5 * x * (1 + erf(x / sqrt(2))) = 0.5 * x * erfc(-x / sqrt(2)).
float pg_gelu(float x) { return 0.5 * x * pg_erfc(-0.70710678118654752 * x); }

#endif
