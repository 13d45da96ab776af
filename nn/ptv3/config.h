#pragma once
// The PTv3 configuration: the subset of Pointcept's PointTransformerV3 arguments that shape
// the network. It travels as JSON in a model file's __metadata__["config"], with the keys
// of Pointcept's constructor (in_channels, enc_channels, ...) plus grid_size.
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace pg::nn {

struct Ptv3Config {
    int in_channels = 2;
    int num_classes = 2;
    std::vector<std::string> order{"z", "z-trans", "hilbert", "hilbert-trans"};
    std::vector<int> stride{2, 2, 2, 2};
    std::vector<int> enc_depths, enc_channels, enc_num_head, enc_patch_size;
    std::vector<int> dec_depths, dec_channels, dec_num_head, dec_patch_size;
    int mlp_ratio = 4;
    bool qkv_bias = true;
    double qk_scale = 0;  // 0: head_dim^-0.5
    double grid_size = 0.02;
    // Coordinates the network expects: "world" (as given, e.g. metres: converted Pointcept
    // checkpoints) or "roi" (dataset/roi_frame.h: centred on the first click, z up, in
    // units of the object scale; the models `pointgauss train` writes).
    std::string input_frame = "world";
    // "tile" (the semantic model, dataset/semantic/scene_tiles.h): a tile column's frame, in units
    // of tile_size world units. The feature groups it reads (dataset/semantic/gaussian_features.h)
    // and its class names travel with it; interactive models leave all three empty (features:
    // positive and negative click weights).
    double tile_size = 0;
    std::vector<std::string> features;
    // Interactive models with a log_scale group: the lower quartile of scale_spacing
    // (gaussian_features.h) over the batches it was trained on. A batch whose Gaussians are
    // smaller than that against its spacing (a denser capture, an ROI split into more batches)
    // has its log scales raised to it before the forward; batches like most of its training data
    // are left as they are. 0: never.
    double scale_spacing = 0;
    std::vector<std::string> class_names;
    bool semantic() const { return input_frame == "tile"; }

    int stages() const { return int(enc_channels.size()); }
    // The paper's interactive model (46.15 M parameters) and the reduced config of the golden fixture.
    static Ptv3Config paper();
    static Ptv3Config small();
    // The golden fixture's tiny config (240k parameters, head dimension 8, patch 48): tests and
    // quick training runs on CPU drivers.
    static Ptv3Config tiny();
    // paper, small or tiny; std::invalid_argument otherwise.
    static Ptv3Config named(const std::string& name);
    // Throws std::invalid_argument naming the key when a value is missing, inconsistent or unsupported
    // (cls_mode, RPE, post-norm and PDNorm are not implemented).
    static Ptv3Config from_json(const nlohmann::json& j);
    nlohmann::json to_json() const;
    // Trainable parameters of the network this config describes (checks a checkpoint's size).
    long long parameter_count() const;
    void validate() const;
};

}  // namespace pg::nn
