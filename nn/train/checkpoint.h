#pragma once
// Model files and training checkpoints as .safetensors.
// - A model file holds the weights under canonical names and the config in
//   __metadata__["config"] (what Ptv3Weights::load reads), plus free-form metadata.
// - A checkpoint holds the weights ("model." prefix), AdamW's moments ("adam_m." / "adam_v.")
//   and the step count, so `pointgauss train --resume` continues where it stopped.
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "nn/ptv3/config.h"
#include "nn/ptv3/weights.h"

namespace pg::nn::train {

class Trainer;

// Writes atomically (a temporary file renamed into place).
void save_model(const std::filesystem::path& path, Pool& pool, const Ptv3Weights& weights,
                const std::map<std::string, std::string>& metadata = {});
void save_checkpoint(const std::filesystem::path& path, Trainer& trainer, int64_t step,
                     const std::map<std::string, std::string>& metadata = {});

struct Checkpoint {
    Ptv3Config config;
    std::map<std::string, std::vector<float>> weights;  // canonical names, running statistics included
    std::vector<std::vector<float>> adam_m, adam_v;     // per Trainer::parameter_names() entry
    int64_t step = 0;
    std::map<std::string, std::string> metadata;
};
// Throws FormatError naming the file and what is missing.
Checkpoint load_checkpoint(const std::filesystem::path& path);
// Puts the checkpoint's moments and step count into the trainer's optimizer (its weights come
// from Checkpoint::weights at construction).
void restore_optimizer(Trainer& trainer, const Checkpoint& checkpoint);

}  // namespace pg::nn::train
