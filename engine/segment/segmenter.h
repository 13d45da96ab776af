#pragma once
// The interactive segmentation pipeline up to 3D labels: clicks are lifted to anchors, the
// prompt encoder weighs the Gaussians and crops the ROI column, the ROI is partitioned into
// batches for the decoder, and each Gaussian goes to the object that claims it with the
// highest probability (above 1/2, the paper's argmax of foreground vs background).
#include <map>
#include <string>
#include <vector>

#include "dataset/camera.h"
#include "dataset/gaussian_cloud.h"
#include "dataset/prompts.h"
#include "engine/render/renderer.h"
#include "engine/segment/decoder.h"
#include "engine/segment/prompt_encoder.h"

namespace pg::seg {

struct SegmentOptions {
    glm::dvec3 up{0, -1, 0};     // the scene's up axis (see dataset/up_axis.h)
    double scale = 0;            // typical object size in scene units; 0: from the cameras
    double sigma = 0;            // click weight fall-off; 0: 0.4 * scale
    double roi_length = 0, roi_width = 0;  // 0: 2.5 * scale
    uint32_t max_batch = 8192;
    uint64_t seed = 1;
    render::RenderSettings render;  // tau and the like for click lifting
};

struct ObjectResult {
    int id = 0;
    std::string name;
    std::vector<Anchor> anchors;
    RoiBox roi;
    double sigma = 0;
    size_t roi_gaussians = 0, batches = 0, labelled = 0;
    // Gaussians the decoder gave this object with P(foreground) > 1/2, and that probability.
    std::vector<std::pair<uint32_t, float>> claims;
};

struct SegmentResult {
    std::vector<int32_t> labels;       // object id per Gaussian, 0 for none
    std::vector<float> probability;    // the winning probability (0 where unlabelled)
    std::vector<ObjectResult> objects;
    std::map<std::string, double> stage_ms;  // wall ms per stage, summed over objects

    // Recomputes labels from the objects' claims: a Gaussian claimed twice goes to the higher
    // probability (ties: the earlier object).
    void assemble(size_t gaussian_count);
    // Drops an object; Gaussians it had won go to the next most confident claimant.
    bool remove_object(int id);
};

class Segmenter {
public:
    Segmenter(vk::Context& ctx, const data::GaussianCloud& cloud, const render::GpuScene& scene,
              const std::vector<data::Camera>& cameras, Decoder& decoder);

    SegmentResult segment(const data::Prompts& prompts, const SegmentOptions& options);

    // Typical object size from the cameras: a quarter of their median distance to `target`.
    double scale_from_cameras(const glm::dvec3& target) const;

private:
    Anchor anchor_for(const data::PromptClick& click, const render::RenderSettings& settings, const std::string& what);

    vk::Context& ctx_;
    const data::GaussianCloud& cloud_;
    const render::GpuScene& scene_;
    const std::vector<data::Camera>& cameras_;
    Decoder& decoder_;
    render::Renderer renderer_;
    PromptEncoder encoder_;
    std::string rendered_view_;  // view and settings renderer_ holds: clicks in one view render it once
};

}  // namespace pg::seg
