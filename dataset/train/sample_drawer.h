#pragma once
// Training samples for the interactive model, drawn the way the pipeline builds its inputs
// (engine/segment/segmenter.cpp): a first positive click inside an object, the ROI column
// around it, one partition batch's worth of its Gaussians, click weights as features, and
// per-point labels (1 = the clicked object). Later clicks follow the benchmark protocol
// (Clicker3D) on the model's own predictions.
//
// Geometry is in the RoiFrame (x length, y width, z up, units of the scale). Augmentation
// moves only the network's coordinates (`coord`); click weights are computed on the
// un-augmented frame positions, exactly as inference computes them.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "dataset/random.h"
#include "dataset/roi_frame.h"
#include "dataset/train/click_weights.h"
#include "dataset/train/train_scene.h"

namespace pg::data::train {

struct SampleOptions {
    uint32_t max_points = 8192;               // N_max: the pipeline's batch limit
    double roi_min = 1.8, roi_max = 3.2;      // ROI length and width, each uniform in [min, max] x scale
    double sigma_factor = 0.4;                // click weight sigma, x scale (the pipeline's 0.4)
    double camera_scale_factor = 0.25;        // scale = this x median camera distance to the click
    uint32_t min_object_points = 30;          // smaller objects are never drawn

    // Augmentation of the network coordinates.
    bool rotate = true;                       // about up (+z), uniform angle
    bool scale = true;                        // isotropic, uniform in [scale_min, scale_max]
    double scale_min = 0.9, scale_max = 1.1;
    bool flip = true;                         // x and y each negated with probability 1/2
    bool jitter = true;                       // per coordinate, normal, clipped
    double jitter_sigma = 0.002, jitter_clip = 0.01;  // frame units
    // Appearance features after the click weights (semantic/gaussian_features.h groups; the
    // scenes must be loaded with the same groups), their unit the model's voxel: `voxel` frame
    // units (the config's grid size) times the frame's scale, as Ptv3Decoder computes them.
    std::vector<std::string> features;
    double voxel = 0.02;
    // The model's scale_spacing (nn/ptv3/config.h; 0: none): a sample below it has its log scales
    // raised to it, as Ptv3Decoder does at inference (a model fine-tuned from one that has it).
    double scale_spacing = 0;
    // Colour augmentation of the rgb group: a random permutation of the channels, then per
    // channel a gain in [1 - colour_gain, 1 + colour_gain] and a common offset of at most
    // colour_shift, clamped to [0, 1]; the model learns colour contrast, not a palette.
    bool colour = true;
    double colour_gain = 0.2, colour_shift = 0.1;

    // The same options with every augmentation off (coord = the frame positions).
    SampleOptions without_augmentation() const {
        SampleOptions o = *this;
        o.rotate = o.scale = o.flip = o.jitter = o.colour = false;
        return o;
    }
};

struct Sample {
    // Per point (n of them), the scene's Gaussians in ascending index order.
    std::vector<float> coord;          // n x 3: augmented network coordinates, the model's input
    std::vector<float> feat;           // n x (2 + C): max positive and negative click weight, appearance
    std::vector<float> appearance;     // n x C: the feature groups' rows (C = 0 without them)
    std::vector<int32_t> labels;       // n: 1 = the object's Gaussian, 0 = other
    std::vector<glm::vec3> position;   // n: frame positions before augmentation
    std::vector<uint32_t> gaussians;   // n: scene indices

    size_t scene = 0;                  // index into the drawer's scenes
    int32_t object = 0;                // instance id
    // The first is positive and at the frame origin; its Gaussian may be missing from the
    // points when the batch subset leaves it out, as in the pipeline (the anchor still counts).
    std::vector<TrainClick> clicks;
    RoiFrame frame;                    // centred on the first click
    float sigma = 0;                   // click weight sigma in frame units (= sigma_factor)
    glm::vec2 roi{0};                  // ROI length and width, frame units
    size_t roi_points = 0;             // Gaussians in the ROI before taking the batch subset
    glm::mat3 augment{1.0f};           // coord = augment * position + jitter

    size_t size() const { return gaussians.size(); }
    // A frame position (e.g. a click's) in the network's augmented coordinates, less jitter.
    glm::vec3 augmented(glm::vec3 p) const { return augment * p; }
};

class SampleDrawer {
public:
    // Finds each scene's objects with at least min_object_points Gaussians and their first-
    // click candidates (see first_click.h). Throws InputError when no scene has one.
    SampleDrawer(std::vector<TrainScene> scenes, SampleOptions options = {});

    const std::vector<TrainScene>& scenes() const { return scenes_; }
    const SampleOptions& options() const { return options_; }
    size_t object_count() const;  // drawable objects over all scenes

    // A scene uniformly among those with a drawable object, an object uniformly within it,
    // then the first click, ROI, batch subset, features, labels and augmentation. The same
    // generator state gives the same sample.
    Sample draw(Rng& rng) const;

    // The benchmark's next click for `prediction` (1 byte per sample point, non-zero =
    // object): positive on the largest missed part, negative on the largest wrongly taken
    // one; the features are recomputed with every click. False (sample unchanged) when the
    // prediction equals the labels. Throws InputError if the prediction's size is wrong.
    // draw and add_click are const: threads may share a drawer, each with its own Rng.
    bool add_click(Sample& sample, std::span<const uint8_t> prediction) const;

private:
    struct Object {
        int32_t id = 0;
        std::vector<uint32_t> candidates;  // first-click Gaussians
        double extent = 0;                 // horizontal size of its largest part (no-camera scale)
    };
    double scale_for(const TrainScene& scene, const Object& object, glm::dvec3 anchor) const;
    void augment(Sample& s, Rng& rng) const;
    void augment_colour(Sample& s, Rng& rng) const;
    void compose_features(Sample& s) const;

    std::vector<TrainScene> scenes_;
    SampleOptions options_;
    std::vector<std::vector<Object>> objects_;  // per scene
    std::vector<size_t> drawable_;              // scenes with at least one object
};

}  // namespace pg::data::train
