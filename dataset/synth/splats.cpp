#include "dataset/synth/splats.h"

#include <atomic>
#include <cmath>
#include <thread>

#include <glm/gtc/quaternion.hpp>

#include "dataset/gaussian_cloud.h"

namespace pg::data::synth {

void SplatList::append(const SplatList& o) {
    mean.insert(mean.end(), o.mean.begin(), o.mean.end());
    log_scale.insert(log_scale.end(), o.log_scale.begin(), o.log_scale.end());
    rotation.insert(rotation.end(), o.rotation.begin(), o.rotation.end());
    opacity_logit.insert(opacity_logit.end(), o.opacity_logit.begin(), o.opacity_logit.end());
    sh.insert(sh.end(), o.sh.begin(), o.sh.end());
    instance.insert(instance.end(), o.instance.begin(), o.instance.end());
    cls.insert(cls.end(), o.cls.begin(), o.cls.end());
}

namespace {
// Fraction of hard-surface splats in the translucent opacity tail.
constexpr double kOpacityTail = 0.24;
// The renderer's low-pass filter: variance added to every projected Gaussian, px^2.
constexpr double kLowPassVariance = 0.3;
// Where a saturated layer of splats ends in a fitted scene: the layer's coverage falls to one
// half about this many (blurred) standard deviations beyond its last centres, so an optimiser
// matching the images' silhouettes leaves the centres that far inside the surface.
constexpr double kSilhouetteInset = 1.2;
}  // namespace

float sample_opacity(Rng& rng, float fuzz) {
    // Converged surface splats saturate; a quarter keep a log-uniform tail (pruning stops at
    // 0.005), which is what an optimiser leaves behind in overlaps and at silhouettes.
    const double tail = kOpacityTail + 0.4 * fuzz;
    if (rng.uniform() < tail) return float(std::exp(rng.uniform(std::log(0.006), std::log(0.85))));
    const double u = rng.uniform();
    return float(1.0 - 0.16 * u * u * (1.0 + fuzz));
}

void sh_basis(const glm::dvec3& d, double* b) {
    // The real SH basis with the constants of the 3DGS evaluation (x, y, z a unit direction).
    const double x = d.x, y = d.y, z = d.z, xx = x * x, yy = y * y, zz = z * z;
    b[0] = 0.28209479177387814;
    b[1] = -0.4886025119029199 * y;
    b[2] = 0.4886025119029199 * z;
    b[3] = -0.4886025119029199 * x;
    b[4] = 1.0925484305920792 * x * y;
    b[5] = -1.0925484305920792 * y * z;
    b[6] = 0.31539156525252005 * (2.0 * zz - xx - yy);
    b[7] = -1.0925484305920792 * x * z;
    b[8] = 0.5462742152960396 * (xx - yy);
    b[9] = -0.5900435899266435 * y * (3.0 * xx - yy);
    b[10] = 2.890611442640554 * x * y * z;
    b[11] = -0.4570457994644658 * y * (4.0 * zz - xx - yy);
    b[12] = 0.3731763325901154 * z * (2.0 * zz - 3.0 * xx - 3.0 * yy);
    b[13] = -0.4570457994644658 * x * (4.0 * zz - xx - yy);
    b[14] = 1.445305721320277 * z * (xx - yy);
    b[15] = -0.5900435899266435 * x * (xx - 3.0 * yy);
}

void push_surfel(SplatList& out, const Surfel& s, int sh_degree, Rng& rng, int instance, int cls) {
    const glm::dvec3 n = glm::normalize(s.n);
    glm::dvec3 t = s.tangent - n * glm::dot(n, s.tangent);
    t = glm::length(t) < 1e-9 ? perpendicular(n) : glm::normalize(t);
    const glm::dvec3 b = glm::cross(n, t);
    const glm::quat q = glm::quat_cast(glm::mat3(glm::vec3(t), glm::vec3(b), glm::vec3(n)));
    const float qscale = float(rng.uniform(0.6, 1.6));  // optimised quaternions are not unit length
    out.rotation.push_back(glm::vec4(q.w, q.x, q.y, q.z) * qscale);
    out.log_scale.push_back(glm::vec3(std::log(s.su), std::log(s.sv), std::log(s.sn)));
    out.mean.push_back(glm::vec3(s.pos));
    out.opacity_logit.push_back(logit_from_opacity(s.opacity));

    const glm::vec3 c = glm::clamp(s.colour, glm::vec3(0.005f), glm::vec3(0.995f));
    const glm::vec3 dc = (c - 0.5f) / kShC0;
    out.sh.push_back(dc.x);
    out.sh.push_back(dc.y);
    out.sh.push_back(dc.z);
    // View dependence: a white specular lobe (coefficients = lobe * w_l * basis(v), so the
    // sum over a band is w_l (2l+1)/(4 pi) P_l(v . d)), plus small per-Gaussian noise.
    const glm::dvec3 v = glm::normalize(s.lobe_dir);
    double basis[16];
    sh_basis(v, basis);
    const double band_weight[4] = {0.0, 1.0, 0.6, 0.3};
    for (int l = 1; l <= sh_degree; ++l) {
        const double sd = s.gloss / double(l);
        for (int m = 0; m < 2 * l + 1; ++m) {
            const double lobe = s.lobe * band_weight[l] * basis[l * l + m];
            const double common = lobe + sd * rng.normal();
            for (int ch = 0; ch < 3; ++ch) out.sh.push_back(float(common + 0.25 * sd * rng.normal()));
        }
    }
    out.instance.push_back(instance);
    out.cls.push_back(cls);
}

namespace {

// Light reaching a surface point with normal n, with a shadow ray towards the sun; `sunlit`
// tells whether the sun reaches it (for the specular lobe).
float lighting(const ShapeSet& set, const Lighting& L, const glm::dvec3& p, const glm::dvec3& n, double eps, bool& sunlit) {
    float light = L.ambient + L.sky * float(0.5 + 0.5 * glm::dot(n, L.up));
    const double facing = glm::dot(n, L.sun);
    sunlit = false;
    if (facing > 0.0) {
        float direct = L.direct * float(facing);
        Hit hit;
        sunlit = !set.shadow_hit(Ray{p + n * eps, L.sun}, 0.0, kInf, hit);
        if (!sunlit) direct *= L.shadow;
        light += direct;
    }
    return light;
}

double nearest_distance(const std::vector<glm::dvec3>& viewpoints, const glm::dvec3& p) {
    double d2 = viewpoints.empty() ? 0.0 : kInf;
    for (const glm::dvec3& v : viewpoints) d2 = std::min(d2, glm::dot(v - p, v - p));
    return std::sqrt(d2);
}

// The unit direction (local) along a painted edge at a surface point: across the gradient of
// the distance to it, by central differences; zero where that has no clear gradient.
glm::dvec3 along_edge(const PatternEdge& edge, const SurfacePoint& sp, double step) {
    glm::dvec3 t = sp.tangent - sp.n * glm::dot(sp.n, sp.tangent);
    t = glm::length(t) < 1e-9 ? perpendicular(sp.n) : glm::normalize(t);
    const glm::dvec3 b = glm::cross(sp.n, t);
    const double gt = edge(sp.p + step * t) - edge(sp.p - step * t), gb = edge(sp.p + step * b) - edge(sp.p - step * b);
    const double len = std::hypot(gt, gb);
    return len < 0.2 * step ? glm::dvec3(0.0) : (gt * b - gb * t) / len;
}

bool faces_a_viewpoint(const std::vector<glm::dvec3>& viewpoints, const glm::dvec3& p, const glm::dvec3& n) {
    if (viewpoints.empty()) return true;
    for (const glm::dvec3& v : viewpoints)
        if (glm::dot(n, v - p) > 0.0) return true;
    return false;
}

}  // namespace

SplatList splat_shape(const ShapeSet& set, int index, const SplatStyle& style, uint64_t seed) {
    SplatList out;
    const Shape& shape = set.shapes()[size_t(index)];
    Rng rng(derive_seed(seed, uint64_t(index)));
    const Material& m = shape.material;
    const double sigma = shape.sigma / std::sqrt(style.density), finest = sigma * style.finest;
    // Centre spacing^2 / sigma^2: the opaque splats alone overlap at ~1.3 sigma, so an opaque
    // surface has no pin-holes (tau-depth clicks fall through those); the tail comes on top.
    const double spacing2 = 1.6 * (1.0 - kOpacityTail);
    const double candidates = std::min(2.0e7, shape.prim->area() / (spacing2 * finest * finest));
    const long count = long(candidates) + (rng.uniform() < candidates - std::floor(candidates) ? 1 : 0);
    const double eps = 0.05 * finest;
    for (long k = 0; k < count; ++k) {
        const SurfacePoint sp = shape.prim->sample(rng);
        const glm::dvec3 p = shape.frame.to_world(sp.p);
        // Size by the local detail and the distance from the focus (a coarser capture far away,
        // still bounded by the feature size); candidates come at the finest size, kept with
        // probability finest^2 / area so the density is 1/area. Near a painted edge the width
        // across it is at most a quarter of the distance to it: long, thin splats along the
        // edge, as an optimiser fits a border.
        const double growth = std::clamp(glm::length(p - style.focus) / style.detail_radius, 1.0, style.max_growth);
        const double size = std::clamp(0.5 * sp.feature, finest * growth, sigma * growth);
        const double draw = rng.uniform();
        if (draw >= finest / size) continue;  // whatever the width (>= finest): most go before the edge query
        const double edge = m.edge ? m.edge(sp.p) : kInf;
        const double across = std::clamp(0.25 * edge, finest, size);
        if (draw >= (finest / size) * (finest / across)) continue;
        const glm::dvec3 n = glm::normalize(shape.frame.dir_to_world(sp.n));
        if (!faces_a_viewpoint(style.viewpoints, p, n)) continue;
        if (set.inside(p + n * eps, index)) continue;  // touching another solid: never seen
        // Fitted silhouettes: the splats sit on the solid eroded by the inset (centres moved in
        // along the normal, none within the inset of an edge), so the rendered coverage, blurred
        // by the splat's own size and the renderer's low-pass filter in the nearest view, reaches
        // one half at the true outline, as an optimiser fitting the views would place them.
        const double pixel = style.pixel_angle * nearest_distance(style.viewpoints, p);
        const double inset = kSilhouetteInset * std::sqrt(size * size + kLowPassVariance * pixel * pixel);
        double sink = m.sink ? inset : 0.0, cover = 1.0;
        if (sp.feature < inset) {
            // Thinner than the blur: none, or (keep_thin) a share of them at its core, as faint
            // as the part covers of its blurred footprint.
            cover = sp.feature / inset;
            if (!m.keep_thin || rng.uniform() >= cover) continue;
            sink = m.sink ? sp.feature : 0.0;
        }
        // Painted regions are fitted like outlines too: no centre within the inset of their edge.
        if (edge < kSilhouetteInset * std::sqrt(across * across + kLowPassVariance * pixel * pixel)) continue;

        Surfel s;
        s.n = n;
        s.tangent = shape.frame.dir_to_world(sp.tangent);
        // In-plane angle: along the grain for aligned materials, anything otherwise.
        const double angle = m.aligned > 0.0f ? rng.normal() * (0.08 + 0.5 * (1.0 - m.aligned)) : rng.uniform(0.0, kPi);
        const glm::dvec3 b = glm::cross(n, glm::normalize(s.tangent - n * glm::dot(n, s.tangent)));
        s.tangent = std::cos(angle) * s.tangent + std::sin(angle) * b;
        const double sz = size * rng.uniform(0.8, 1.25), aniso = 1.0 + std::min(1.5, std::abs(0.35 * rng.normal()));
        s.su = sz * std::sqrt(aniso);
        s.sv = sz / std::sqrt(aniso);
        if (across < size) {
            const glm::dvec3 along = along_edge(m.edge, sp, 0.5 * across);
            if (along != glm::dvec3(0.0)) {
                s.tangent = shape.frame.dir_to_world(along);
                s.sv *= across / size;
            }
        }
        s.sn = std::min(s.su, s.sv) * rng.uniform(0.05, 0.2);
        s.pos = p + n * (0.3 * s.sn * rng.normal() - sink);
        if (m.fuzz > 0.0f) {  // foliage: tilted, thicker, spread through a shell
            s.n = glm::normalize(n + double(m.fuzz) * 0.9 * glm::dvec3(rng.normal(), rng.normal(), rng.normal()));
            s.sn = std::min(s.su, s.sv) * rng.uniform(0.2, 0.5);
            s.pos = p + n * (double(m.fuzz) * sigma * rng.normal() - sink);
        }
        glm::vec3 albedo = m.albedo ? m.albedo(sp.p, sp.n) : glm::vec3(0.5f);
        const float bright = 1.0f + m.colour_noise * float(rng.normal());
        for (int c = 0; c < 3; ++c) albedo[c] *= bright * (1.0f + 0.3f * m.colour_noise * float(rng.normal()));
        bool sunlit = false;
        s.colour = albedo * lighting(set, style.light, p, n, 4.0 * eps + 1e-9, sunlit);
        s.opacity = sample_opacity(rng, m.fuzz) * float(cover);
        // Specular: the sun mirrored in the surface (the camera-to-Gaussian direction that
        // sees it is minus the reflected ray); the sky's softer sheen when in shadow.
        const glm::dvec3 reflected = 2.0 * glm::dot(n, style.light.sun) * n - style.light.sun;
        s.lobe_dir = -reflected;
        s.lobe = m.gloss * (sunlit ? 1.5f : 0.4f);
        s.gloss = 0.1f * m.gloss;
        push_surfel(out, s, style.sh_degree, rng, shape.instance, shape.class_of(sp.p));
    }
    return out;
}

SplatList splat_shapes(const ShapeSet& set, const SplatStyle& style, uint64_t seed, int threads) {
    const int n = int(set.size());
    std::vector<SplatList> parts(static_cast<size_t>(n));
    std::atomic<int> next{0};
    auto work = [&] {
        for (int i = next++; i < n; i = next++) parts[size_t(i)] = splat_shape(set, i, style, seed);
    };
    std::vector<std::thread> pool;
    for (int t = 1; t < std::max(1, threads); ++t) pool.emplace_back(work);
    work();
    for (auto& t : pool) t.join();
    SplatList all;
    for (const auto& p : parts) all.append(p);
    return all;
}

}  // namespace pg::data::synth
