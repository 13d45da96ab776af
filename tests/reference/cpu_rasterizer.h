#pragma once
// CPU reference of the GPU splat renderer: the standard 3DGS forward model (EWA splatting,
// front-to-back alpha blending) with an opacity-aware screen-space bound. Written for
// clarity, in float like the GPU, with no tiling in the model itself: the result of a
// pixel depends only on the Gaussians, never on how they were binned.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "dataset/camera.h"
#include "dataset/gaussian_cloud.h"

namespace pg::ref {

struct RefOptions {
    glm::vec3 background{0.0f};
    float tau = 0.9f;          // tau-depth: depth where accumulated opacity first reaches tau
    bool antialiased = false;  // Mip-Splatting style opacity compensation of the 0.3 px filter
    int max_sh_degree = 3;
    float near = 0.2f;         // Gaussians with view-space z <= near are culled
    // Optional style (render::RenderStyle): labels[i] picks a palette entry (labels < 0 or past
    // the end pick entry 0); colour = mix(colour, rgb, a), and a < 0 culls the Gaussian.
    const std::vector<int32_t>* labels = nullptr;  // one per Gaussian; needed when palette is set
    const std::vector<glm::vec4>* palette = nullptr;
};

// Every buffer is row-major, top row first; rgb holds 3 floats per pixel.
struct RefImage {
    int width = 0, height = 0;
    std::vector<float> rgb;       // C + T * background
    std::vector<float> alpha;     // 1 - T
    std::vector<float> depth;     // sum(z * w) / sum(w), 0 where nothing contributed
    std::vector<float> tau_depth; // z of the Gaussian that made 1 - T reach tau, else 0
    std::vector<int32_t> tau_id;  // its index in the cloud, else -1
    std::vector<uint32_t> contributors;  // Gaussians blended into the pixel
};

// Screen-space data of one Gaussian after preprocessing (exposed for tests).
struct ProjectedGaussian {
    uint32_t index = 0;     // in the cloud
    float depth = 0;        // view-space z
    glm::vec2 mean2d{0};    // pixel coordinates, pixel (i, j) has its centre at (i+0.5, j+0.5)
    glm::vec3 cov2d{0};     // (a, b, c) after the +0.3 low-pass
    glm::vec3 conic{0};     // inverse of cov2d
    float opacity = 0;      // sigmoid(logit), times the antialiasing factor
    glm::vec3 colour{0};    // SH evaluated for this camera, clamped below at 0, then tinted by the style
};

// Rotation matrix of the quaternion (w, x, y, z), normalised; columns are the local axes in world.
glm::mat3 rotation_matrix(glm::vec4 q);

// Runs the per-Gaussian stage; culled Gaussians return false.
bool project_gaussian(const pg::data::GaussianCloud& cloud, size_t i, const pg::data::Camera& camera,
                      const RefOptions& options, ProjectedGaussian& out);

// The alpha a projected Gaussian adds at a pixel centre: min(0.99, o * exp(power)), or 0
// where the model skips it (power > 0 or alpha < 1/255). Shared by the reference passes.
float splat_alpha(const ProjectedGaussian& g, glm::vec2 centre);

RefImage render_reference(const pg::data::GaussianCloud& cloud, const pg::data::Camera& camera,
                          const RefOptions& options = {});

// Peak signal-to-noise ratio in dB over all elements; +inf when a == b.
double psnr(const std::vector<float>& a, const std::vector<float>& b, double peak = 1.0);

}  // namespace pg::ref
