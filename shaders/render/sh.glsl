// View-dependent colour from spherical harmonics, degree 0-3, in the basis order of the
// reference 3DGS rasterizer; +0.5 and a clamp at 0 per channel.
#ifndef PG_SH_GLSL
#define PG_SH_GLSL
const float SH_C0 = 0.28209479177387814;
const float SH_C1 = 0.4886025119029199;
const float SH_C2[5] = float[](1.0925484305920792, -1.0925484305920792, 0.31539156525252005,
                              -1.0925484305920792, 0.5462742152960396);
const float SH_C3[7] = float[](-0.5900435899266435, 2.890611442640554, -0.4570457994644658, 0.3731763325901154,
                              -0.4570457994644658, 1.445305721320277, -0.5900435899266435);

// `SH_COEFF(k)` must expand to the vec3 of coefficient k of the current Gaussian.
#define PG_EVAL_SH(result, degree, dir)                                                        \
    {                                                                                          \
        vec3 r_ = SH_C0 * SH_COEFF(0);                                                         \
        if ((degree) > 0) {                                                                    \
            float x = (dir).x, y = (dir).y, z = (dir).z;                                       \
            r_ += -SH_C1 * y * SH_COEFF(1) + SH_C1 * z * SH_COEFF(2) - SH_C1 * x * SH_COEFF(3); \
            if ((degree) > 1) {                                                                \
                float xx = x * x, yy = y * y, zz = z * z, xy = x * y, yz = y * z, xz = x * z;  \
                r_ += SH_C2[0] * xy * SH_COEFF(4) + SH_C2[1] * yz * SH_COEFF(5) +              \
                      SH_C2[2] * (2.0 * zz - xx - yy) * SH_COEFF(6) + SH_C2[3] * xz * SH_COEFF(7) + \
                      SH_C2[4] * (xx - yy) * SH_COEFF(8);                                      \
                if ((degree) > 2) {                                                            \
                    r_ += SH_C3[0] * y * (3.0 * xx - yy) * SH_COEFF(9) +                       \
                          SH_C3[1] * xy * z * SH_COEFF(10) +                                   \
                          SH_C3[2] * y * (4.0 * zz - xx - yy) * SH_COEFF(11) +                 \
                          SH_C3[3] * z * (2.0 * zz - 3.0 * xx - 3.0 * yy) * SH_COEFF(12) +     \
                          SH_C3[4] * x * (4.0 * zz - xx - yy) * SH_COEFF(13) +                 \
                          SH_C3[5] * z * (xx - yy) * SH_COEFF(14) +                            \
                          SH_C3[6] * x * (xx - 3.0 * yy) * SH_COEFF(15);                       \
                }                                                                              \
            }                                                                                  \
        }                                                                                      \
        result = max(r_ + 0.5, vec3(0.0));                                                     \
    }
#endif
