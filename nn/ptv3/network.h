#pragma once
// The PTv3 network, defined once (Pointcept's PointTransformerV3 backbone and a linear head):
// the embedding, the encoder stages (a pooling before every stage but the first, then blocks),
// the decoder stages (an unpooling, then blocks) and the head, walked over a Ptv3Point. The
// same walk records inference (InferencePass) and training forwards (TrainingPass, which
// keeps the tape); the backward walks it in reverse.
#include <optional>
#include <string>
#include <vector>

#include "nn/ptv3/block.h"
#include "nn/ptv3/config.h"
#include "nn/ptv3/embedding.h"
#include "nn/ptv3/head.h"
#include "nn/ptv3/pooling.h"
#include "nn/ptv3/unpooling.h"

namespace pg::nn {

class Ptv3Network {
public:
    explicit Ptv3Network(const Ptv3Config& config);

    // point.feat: the input features per point in, the logits per level-0 voxel out.
    // Pass: InferencePass or TrainingPass.
    template <class Pass> void forward(Pass& pass, Ptv3Point& point) const;
    // grad.feat: the loss gradient of the logits in. Walks back through the tape of the
    // pass's forward, writing pass.grads.
    void backward(TrainingPass& pass, Ptv3Point& grad) const;

private:
    struct EncoderStage {
        std::string name;
        std::optional<Pooling> down;  // all but the first
        std::vector<Block> blocks;
    };
    struct DecoderStage {
        std::string name;
        Unpooling up;
        std::vector<Block> blocks;
    };
    Embedding embedding_;
    std::vector<EncoderStage> encoder_;
    std::vector<DecoderStage> decoder_;  // in the order they run: coarse to fine
    Head head_;
};

}  // namespace pg::nn
