#include "tests/reference/cpu_rasterizer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace pg::ref {
namespace {

constexpr float kShC0 = 0.28209479177387814f;
constexpr float kShC1 = 0.4886025119029199f;
constexpr float kShC2[5] = {1.0925484305920792f, -1.0925484305920792f, 0.31539156525252005f,
                            -1.0925484305920792f, 0.5462742152960396f};
constexpr float kShC3[7] = {-0.5900435899266435f, 2.890611442640554f, -0.4570457994644658f,
                            0.3731763325901154f,  -0.4570457994644658f, 1.445305721320277f,
                            -0.5900435899266435f};

constexpr float kLowPass = 0.3f;           // px^2 added to the screen covariance diagonal
constexpr float kMinAlpha = 1.0f / 255.0f;  // below this a Gaussian does not touch a pixel
constexpr float kMaxAlpha = 0.99f;
constexpr float kMinTransmittance = 1e-4f;
constexpr int kBin = 16;                    // pixel bins used only to skip far Gaussians

float sigmoid(float x) { return 1.0f / (1.0f + std::exp(-x)); }


// Same basis order as diff-gaussian-rasterization's computeColorFromSH.
glm::vec3 sh_colour(const float* coeffs, int degree, glm::vec3 dir) {
    auto sh = [&](int k) { return glm::vec3(coeffs[k * 3 + 0], coeffs[k * 3 + 1], coeffs[k * 3 + 2]); };
    glm::vec3 result = kShC0 * sh(0);
    if (degree > 0) {
        const float x = dir.x, y = dir.y, z = dir.z;
        result = result - kShC1 * y * sh(1) + kShC1 * z * sh(2) - kShC1 * x * sh(3);
        if (degree > 1) {
            const float xx = x * x, yy = y * y, zz = z * z;
            const float xy = x * y, yz = y * z, xz = x * z;
            result = result + kShC2[0] * xy * sh(4) + kShC2[1] * yz * sh(5) +
                     kShC2[2] * (2.0f * zz - xx - yy) * sh(6) + kShC2[3] * xz * sh(7) +
                     kShC2[4] * (xx - yy) * sh(8);
            if (degree > 2) {
                result = result + kShC3[0] * y * (3.0f * xx - yy) * sh(9) + kShC3[1] * xy * z * sh(10) +
                         kShC3[2] * y * (4.0f * zz - xx - yy) * sh(11) +
                         kShC3[3] * z * (2.0f * zz - 3.0f * xx - 3.0f * yy) * sh(12) +
                         kShC3[4] * x * (4.0f * zz - xx - yy) * sh(13) + kShC3[5] * z * (xx - yy) * sh(14) +
                         kShC3[6] * x * (xx - 3.0f * yy) * sh(15);
            }
        }
    }
    result += 0.5f;
    return glm::max(result, glm::vec3(0.0f));
}

// Pixel rectangle [x0, x1] x [y0, y1] (inclusive, clamped to the image) that holds every
// pixel centre the Gaussian can reach with alpha >= 1/255, plus one pixel of margin.
struct PixelRect {
    int x0, y0, x1, y1;
    bool empty() const { return x0 > x1 || y0 > y1; }
};

PixelRect support_rect(const ProjectedGaussian& g, int width, int height) {
    // o * exp(-q/2) >= 1/255  <=>  q <= 2 ln(255 o); the ellipse q <= k spans
    // sqrt(k * cov_xx) along x and sqrt(k * cov_yy) along y.
    const double k = std::max(0.0, 2.0 * std::log(255.0 * double(g.opacity)));
    const double hx = std::sqrt(k * double(g.cov2d.x)) + 1.0;
    const double hy = std::sqrt(k * double(g.cov2d.z)) + 1.0;
    // Pixel i has its centre at i + 0.5: i in [mx - hx - 0.5, mx + hx - 0.5].
    auto clampi = [](double v, int lo, int hi) {
        if (!(v >= lo)) return lo;  // also catches NaN
        if (v > hi) return hi;
        return int(v);
    };
    PixelRect r;
    r.x0 = clampi(std::floor(double(g.mean2d.x) - hx - 0.5), 0, width);
    r.x1 = clampi(std::ceil(double(g.mean2d.x) + hx - 0.5), -1, width - 1);
    r.y0 = clampi(std::floor(double(g.mean2d.y) - hy - 0.5), 0, height);
    r.y1 = clampi(std::ceil(double(g.mean2d.y) + hy - 0.5), -1, height - 1);
    return r;
}

// The palette entry of Gaussian i, or nullptr without a style.
const glm::vec4* style_entry(const RefOptions& options, size_t i, size_t count) {
    if (!options.palette) return nullptr;
    if (options.palette->empty() || !options.labels || options.labels->size() != count)
        throw std::invalid_argument("RefOptions style needs a non-empty palette and one label per Gaussian");
    const int32_t label = (*options.labels)[i];
    const bool known = label >= 0 && size_t(label) < options.palette->size();
    return &(*options.palette)[known ? size_t(label) : 0];
}

}  // namespace

glm::mat3 rotation_matrix(glm::vec4 q) {
    const float len = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
    if (!(len > 0.0f)) return glm::mat3(1.0f);  // zero quaternion: identity
    q /= len;
    const float w = q.x, x = q.y, y = q.z, z = q.w;
    glm::mat3 r;
    // glm is column-major: r[col][row].
    r[0][0] = 1.0f - 2.0f * (y * y + z * z);
    r[1][0] = 2.0f * (x * y - w * z);
    r[2][0] = 2.0f * (x * z + w * y);
    r[0][1] = 2.0f * (x * y + w * z);
    r[1][1] = 1.0f - 2.0f * (x * x + z * z);
    r[2][1] = 2.0f * (y * z - w * x);
    r[0][2] = 2.0f * (x * z - w * y);
    r[1][2] = 2.0f * (y * z + w * x);
    r[2][2] = 1.0f - 2.0f * (x * x + y * y);
    return r;
}

bool project_gaussian(const pg::data::GaussianCloud& cloud, size_t i, const pg::data::Camera& camera,
                      const RefOptions& options, ProjectedGaussian& out) {
    const glm::mat3 W(camera.R);  // world -> camera rotation
    const glm::vec3 t(camera.t);
    const float fx = float(camera.fx), fy = float(camera.fy);
    const float cx = float(camera.cx), cy = float(camera.cy);

    // 0. Style: a hidden Gaussian is culled before anything else.
    const glm::vec4* style = style_entry(options, i, cloud.size());
    if (style && style->a < 0.0f) return false;

    // 1. View-space position and near-plane cull.
    const glm::vec3 p = W * cloud.mean[i] + t;
    if (!(p.z > options.near)) return false;

    // 2. World covariance Sigma = Rq S S^T Rq^T.
    const glm::mat3 Rq = rotation_matrix(cloud.rotation[i]);
    const glm::vec3 s = glm::exp(cloud.log_scale[i]);
    const glm::mat3 S(s.x, 0, 0, 0, s.y, 0, 0, 0, s.z);
    const glm::mat3 M = Rq * S;
    const glm::mat3 Sigma = M * glm::transpose(M);

    // 3. EWA: Jacobian of the perspective projection at the (frustum-clamped) mean.
    const float tan_fovx = 0.5f * float(camera.width) / fx;
    const float tan_fovy = 0.5f * float(camera.height) / fy;
    const float limx = 1.3f * tan_fovx, limy = 1.3f * tan_fovy;
    const float tx = std::clamp(p.x / p.z, -limx, limx) * p.z;
    const float ty = std::clamp(p.y / p.z, -limy, limy) * p.z;
    const float z2 = p.z * p.z;
    // J = [[fx/z, 0, -fx tx/z^2], [0, fy/z, -fy ty/z^2], [0, 0, 0]] (columns below).
    const glm::mat3 J(fx / p.z, 0.0f, 0.0f,  //
                      0.0f, fy / p.z, 0.0f,  //
                      -fx * tx / z2, -fy * ty / z2, 0.0f);
    const glm::mat3 T = J * W;
    const glm::mat3 cov = T * Sigma * glm::transpose(T);
    float a = cov[0][0], b = cov[0][1], c = cov[1][1];
    const float det0 = a * c - b * b;
    a += kLowPass;
    c += kLowPass;
    const float det1 = a * c - b * b;
    if (!(det1 > 0.0f)) return false;

    // 4. Opacity, with the antialiasing compensation when asked.
    float opacity = sigmoid(cloud.opacity_logit[i]);
    if (options.antialiased) opacity *= std::sqrt(std::max(0.000025f, det0 / det1));
    if (!(opacity >= kMinAlpha)) return false;

    // 5. Conic and pixel-space mean.
    const float inv = 1.0f / det1;
    out.index = uint32_t(i);
    out.depth = p.z;
    out.cov2d = glm::vec3(a, b, c);
    out.conic = glm::vec3(c * inv, -b * inv, a * inv);
    out.mean2d = glm::vec2(fx * p.x / p.z + cx, fy * p.y / p.z + cy);
    out.opacity = opacity;
    if (!std::isfinite(out.mean2d.x) || !std::isfinite(out.mean2d.y) || !std::isfinite(out.conic.x) ||
        !std::isfinite(out.conic.y) || !std::isfinite(out.conic.z))
        return false;

    // 6. View-dependent colour.
    const int degree = std::min(cloud.sh_degree, std::max(0, options.max_sh_degree));
    const glm::vec3 campos(camera.position());
    const glm::vec3 dir = glm::normalize(cloud.mean[i] - campos);
    out.colour = sh_colour(&cloud.sh[size_t(i) * size_t(cloud.coeffs()) * 3], degree, dir);
    if (style) out.colour = glm::mix(out.colour, glm::vec3(*style), style->a);
    return true;
}

float splat_alpha(const ProjectedGaussian& g, glm::vec2 centre) {
    const glm::vec2 d = g.mean2d - centre;
    const float power = -0.5f * (g.conic.x * d.x * d.x + g.conic.z * d.y * d.y) - g.conic.y * d.x * d.y;
    if (power > 0.0f) return 0.0f;
    const float alpha = std::min(kMaxAlpha, g.opacity * std::exp(power));
    return alpha < kMinAlpha ? 0.0f : alpha;
}

RefImage render_reference(const pg::data::GaussianCloud& cloud, const pg::data::Camera& camera,
                          const RefOptions& options) {
    const int width = camera.width, height = camera.height;
    if (width <= 0 || height <= 0) throw std::invalid_argument("render_reference: camera has no pixels");

    // Per-Gaussian stage.
    std::vector<ProjectedGaussian> splats;
    splats.reserve(cloud.size());
    for (size_t i = 0; i < cloud.size(); ++i) {
        ProjectedGaussian g;
        if (project_gaussian(cloud, i, camera, options, g)) splats.push_back(g);
    }
    // Front to back; ties by cloud index so the order is total.
    std::sort(splats.begin(), splats.end(), [](const ProjectedGaussian& l, const ProjectedGaussian& r) {
        return l.depth < r.depth || (l.depth == r.depth && l.index < r.index);
    });

    // Bin each splat into the 16x16 pixel blocks its support touches. Binning only skips
    // Gaussians that cannot reach a pixel; every pixel still sees its Gaussians in depth order.
    const int bins_x = (width + kBin - 1) / kBin, bins_y = (height + kBin - 1) / kBin;
    std::vector<PixelRect> rects(splats.size());
    std::vector<std::vector<uint32_t>> bins(size_t(bins_x) * bins_y);
    for (size_t s = 0; s < splats.size(); ++s) {
        rects[s] = support_rect(splats[s], width, height);
        if (rects[s].empty()) continue;
        for (int by = rects[s].y0 / kBin; by <= rects[s].y1 / kBin; ++by)
            for (int bx = rects[s].x0 / kBin; bx <= rects[s].x1 / kBin; ++bx)
                bins[size_t(by) * bins_x + bx].push_back(uint32_t(s));
    }

    RefImage img;
    img.width = width;
    img.height = height;
    const size_t n = size_t(width) * height;
    img.rgb.assign(n * 3, 0.0f);
    img.alpha.assign(n, 0.0f);
    img.depth.assign(n, 0.0f);
    img.tau_depth.assign(n, 0.0f);
    img.tau_id.assign(n, -1);
    img.contributors.assign(n, 0);

    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const auto& bin = bins[size_t(y / kBin) * bins_x + x / kBin];
            const glm::vec2 centre(float(x) + 0.5f, float(y) + 0.5f);
            float T = 1.0f;
            glm::vec3 C(0.0f);
            float D = 0.0f, Wsum = 0.0f;
            float tau_depth = 0.0f;
            int32_t tau_id = -1;
            uint32_t count = 0;
            for (uint32_t s : bin) {
                const PixelRect& r = rects[s];
                if (x < r.x0 || x > r.x1 || y < r.y0 || y > r.y1) continue;
                const ProjectedGaussian& g = splats[s];
                const float alpha = splat_alpha(g, centre);
                if (alpha == 0.0f) continue;
                const float test_T = T * (1.0f - alpha);
                if (test_T < kMinTransmittance) break;
                const float w = alpha * T;
                C += g.colour * w;
                D += g.depth * w;
                Wsum += w;
                ++count;
                T = test_T;
                if (tau_id < 0 && 1.0f - T >= options.tau) {
                    tau_depth = g.depth;
                    tau_id = int32_t(g.index);
                }
            }
            const size_t p = size_t(y) * width + x;
            const glm::vec3 rgb = C + T * options.background;
            img.rgb[p * 3 + 0] = rgb.x;
            img.rgb[p * 3 + 1] = rgb.y;
            img.rgb[p * 3 + 2] = rgb.z;
            img.alpha[p] = 1.0f - T;
            img.depth[p] = Wsum > 0.0f ? D / Wsum : 0.0f;
            img.tau_depth[p] = tau_depth;
            img.tau_id[p] = tau_id;
            img.contributors[p] = count;
        }
    }
    return img;
}

double psnr(const std::vector<float>& a, const std::vector<float>& b, double peak) {
    if (a.size() != b.size()) throw std::invalid_argument("psnr: images differ in size");
    if (a.empty()) return std::numeric_limits<double>::infinity();
    double sum = 0.0;
    for (size_t i = 0; i < a.size(); ++i) {
        const double d = double(a[i]) - double(b[i]);
        sum += d * d;
    }
    const double mse = sum / double(a.size());
    if (mse == 0.0) return std::numeric_limits<double>::infinity();
    return 10.0 * std::log10(peak * peak / mse);
}

}  // namespace pg::ref
