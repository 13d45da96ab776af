#pragma once
// The job thread's half of the viewer: lifts clicks to 3D, segments one object at a time
// through the same Segmenter as `pointgauss segment`, labels the scene by class as `segment
// --semantic` does, and writes exports.
#include <atomic>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "app/viewer/class_labels.h"
#include "app/viewer/document.h"
#include "app/viewer/session.h"
#include "dataset/camera.h"
#include "dataset/gaussian_cloud.h"
#include "engine/render/renderer.h"
#include "engine/segment/segmenter.h"
#include "engine/segment/semantic_labeler.h"

namespace pg::viewer {

struct SceneData {
    std::string scene_path, cameras_path;  // cameras_path empty: cameras were generated
    int lod = 0;                           // the streamed-SOG level scene_path was loaded at
    data::GaussianCloud cloud;
    std::vector<data::Camera> cameras;
    seg::SegmentOptions options;           // up, scale, seed: as `segment` would use them
    std::string up_spec;                   // how the up axis was found
    std::string model;                     // the network's file (empty: none; the graph decoder needs none)
    std::string semantic_model;            // the class network's file for label by class (empty: none found)
};

struct ExportRequest {
    std::filesystem::path folder;
    bool scene = true, objects = true, masks = true, prompts = true;
    std::shared_ptr<const std::vector<int32_t>> labels;
    DocumentState document;
    data::Prompts prompts_json;
    std::string decoder;
    std::map<std::string, double> stage_ms;
    std::shared_ptr<const ClassLabels> classes;  // written as the scene's `class` property (may be null)
    std::string format = "ply";                  // ply, or sog: scene.sog (no labels) and objects/NAME.sog
};

class JobEngine {
public:
    JobEngine(vk::Context& ctx, const SceneData& scene, const render::GpuScene& gpu_scene);

    // Builds the pipelines a graph click uses (seg::warm_up) and the segmenter `decoder` clicks
    // with, its column index made, so the first click costs what a later one does.
    void warm_up(const std::string& decoder);
    // A click at pixel (u, v) of `camera` -> where it lands; InputError when it hits nothing.
    seg::Anchor lift(const data::Camera& camera, double u, double v, bool positive);
    // A prompts.json click (in a view of the scene, or a 3D point) -> where it lands.
    seg::Anchor anchor(const data::PromptClick& click);
    // The job's objects, as `segment` computes them for those objects of prompts.json.
    // `cancel` and `coarse`: see segment_job.
    SegmentOutcome segment(const SegmentJob& job, std::map<std::string, double>& stage_ms,
                           const std::atomic<bool>* cancel = nullptr,
                           const std::function<void(SegmentOutcome)>& coarse = {});
    // Every Gaussian's class from the semantic model at `model`, as `segment --semantic` labels
    // the scene (its up axis, the model's tile); progress counts tiles. InputError for a
    // missing file or one that is not a semantic model; seg::Cancelled when `cancel` is set.
    ClassLabels label_by_class(const std::string& model, const std::atomic<bool>* cancel,
                               const std::function<void(size_t done, size_t total)>& progress,
                               std::map<std::string, double>& stage_ms);
    // Writes the chosen outputs; progress counts mask views.
    void write(const ExportRequest& request, std::atomic<size_t>& done, std::atomic<size_t>& total,
               const std::atomic<bool>& cancel);

private:
    seg::Segmenter& segmenter(const std::string& network);  // "": none, else a model file or ground-truth
    std::string network_for(const std::string& decoder) const;  // the network a viewer decoder segments with

    vk::Context& ctx_;
    const SceneData& scene_;
    const render::GpuScene& gpu_scene_;
    render::Renderer lift_renderer_;
    seg::PixelBins lift_bins_;  // the scene's Gaussians binned per clicked view
    std::map<std::string, std::unique_ptr<seg::Decoder>> decoders_;
    std::map<std::string, std::unique_ptr<seg::Segmenter>> segmenters_;
    std::unique_ptr<seg::ClassNetwork> classifier_;  // the last semantic model used, kept loaded
    std::string classifier_path_;
    std::vector<std::string> class_names_;
};

}  // namespace pg::viewer
