#pragma once
// A PTv3 transformer block (Pointcept's Block, pre-norm): x += LayerNorm(Linear(SubMConv3x3x3(x)))
// (the CPE), x += Proj(SerializedAttention(LayerNorm(x))), x += MLP(LayerNorm(x)). Training
// drops the two residual branches per point (drop path).
#include <string>

#include "nn/ptv3/config.h"
#include "nn/ptv3/point.h"
#include "nn/ptv3/weights.h"

namespace pg::nn {

class InferencePass;
class TrainingPass;

class Block {
public:
    // Block `index` of its stage (it attends in the stage's serialization order index % orders);
    // its drop path rate is the deepest rate x drop_slot / (drop_slots - 1), Pointcept's linspace.
    Block(const Ptv3Config& config, std::string name, int channels, int heads, int patch, int index, int drop_slot,
          int drop_slots);

    struct Tape {
        bool separate_cpe_input = false;  // the CPE convolved point.conv_feat
        Tensor cpe_in, h1, h2, x1, n1, qkv, a, x2, n2, pre, f1;
        Tensor keep_attn, keep_mlp;  // drop path row scales (undefined: no drop path)
    };
    void forward(InferencePass& pass, Ptv3Point& point) const;
    void forward(TrainingPass& pass, Ptv3Point& point) const;
    // A separate CPE input's gradient goes to grad.conv_feat.
    void backward(TrainingPass& pass, Ptv3Point& grad) const;

private:
    Tensor cpe_weight(const Ptv3Weights& weights) const;
    double drop_rate(double deepest) const;

    std::string name_;
    int channels_, heads_, patch_, index_, drop_slot_, drop_slots_;
    bool qkv_bias_;
    float scale_;
};

}  // namespace pg::nn
