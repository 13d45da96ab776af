#include "nn/ptv3/network.h"

#include <numeric>
#include <type_traits>

#include "nn/ptv3/inference_pass.h"
#include "nn/ptv3/training_pass.h"

namespace pg::nn {

Ptv3Network::Ptv3Network(const Ptv3Config& c) : embedding_(c) {
    // Drop path rates grow linearly over the encoder's blocks, and over the decoder's with each
    // stage's slice reversed (Pointcept's schedule).
    const int enc_blocks = std::accumulate(c.enc_depths.begin(), c.enc_depths.end(), 0);
    const int dec_blocks = std::accumulate(c.dec_depths.begin(), c.dec_depths.end(), 0);
    for (int s = 0, slot = 0; s < c.stages(); ++s) {
        const size_t k = size_t(s);
        EncoderStage& stage = encoder_.emplace_back();
        stage.name = "enc.enc" + std::to_string(s);
        if (s > 0) stage.down.emplace(stage.name + ".down");
        for (int i = 0; i < c.enc_depths[k]; ++i, ++slot)
            stage.blocks.emplace_back(c, stage.name + ".block" + std::to_string(i), c.enc_channels[k],
                                      c.enc_num_head[k], c.enc_patch_size[k], i, slot, enc_blocks);
    }
    for (int s = c.stages() - 2; s >= 0; --s) {
        const size_t k = size_t(s);
        const std::string name = "dec.dec" + std::to_string(s);
        DecoderStage& stage = decoder_.emplace_back(DecoderStage{name, Unpooling(name + ".up"), {}});
        const int first = std::accumulate(c.dec_depths.begin(), c.dec_depths.begin() + s, 0);
        for (int i = 0; i < c.dec_depths[k]; ++i)
            stage.blocks.emplace_back(c, name + ".block" + std::to_string(i), c.dec_channels[k], c.dec_num_head[k],
                                      c.dec_patch_size[k], i, first + c.dec_depths[k] - 1 - i, dec_blocks);
    }
}

template <class Pass> void Ptv3Network::forward(Pass& pass, Ptv3Point& point) const {
    // Stage outputs are traced under the stage's name; training traces nothing.
    auto stage_done = [&](const std::string& name) {
        if constexpr (std::is_same_v<Pass, InferencePass>) pass.emit(name + "/feat", point.feat);
    };
    embedding_.forward(pass, point);
    for (const EncoderStage& stage : encoder_) {
        if (stage.down) stage.down->forward(pass, point);
        for (const Block& block : stage.blocks) block.forward(pass, point);
        stage_done(stage.name);
    }
    for (const DecoderStage& stage : decoder_) {
        stage.up.forward(pass, point);
        for (const Block& block : stage.blocks) block.forward(pass, point);
        stage_done(stage.name);
    }
    head_.forward(pass, point);
}

template void Ptv3Network::forward(InferencePass&, Ptv3Point&) const;
template void Ptv3Network::forward(TrainingPass&, Ptv3Point&) const;

void Ptv3Network::backward(TrainingPass& pass, Ptv3Point& grad) const {
    head_.backward(pass, grad);
    for (auto stage = decoder_.rbegin(); stage != decoder_.rend(); ++stage) {
        for (auto block = stage->blocks.rbegin(); block != stage->blocks.rend(); ++block) block->backward(pass, grad);
        stage->up.backward(pass, grad);
    }
    for (auto stage = encoder_.rbegin(); stage != encoder_.rend(); ++stage) {
        for (auto block = stage->blocks.rbegin(); block != stage->blocks.rend(); ++block) block->backward(pass, grad);
        if (stage->down) stage->down->backward(pass, grad);
    }
    embedding_.backward(pass, grad);
}

}  // namespace pg::nn
