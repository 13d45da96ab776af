#pragma once
// Training of PTv3 without autograd: the network's training forward (nn/ptv3/network.h; each
// module keeps what its backward needs: BatchNorm on batch statistics, per-point drop path, no
// fused residuals), the loss, the modules' backwards in reverse order, then AdamW. One recorded
// stream per step; the host waits only where the structure needs a count (voxels, clusters) and
// at the end.
#include <cstdint>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "nn/ptv3/model.h"
#include "nn/ptv3/network.h"
#include "nn/ptv3/weights.h"
#include "nn/train/optimizer.h"

namespace pg::nn::train {

struct TrainOptions {
    // Drop path rate of the deepest block; rates grow linearly over the encoder's blocks and
    // the decoder's (Pointcept's schedule). 0 = off.
    double drop_path = 0.3;
    uint64_t seed = 1;  // drop path masks
    double bn_momentum = 0.01;  // BatchNorm running statistics (PTv3's BatchNorm1d)
    AdamWOptions adamw;
    int32_t ignore_label = -1;
    // Weight of the Lovasz-softmax loss added to the cross-entropy (Pointcept's PTv3 recipe: 1);
    // 0 = cross-entropy alone.
    double lovasz_weight = 0;
};

// One training-mode forward + backward.
struct StepResult {
    double loss = 0;             // mean cross-entropy over the counted voxels + the weighted Lovasz loss
    double lovasz = 0;           // the weighted Lovasz loss alone (0 when off)
    int64_t counted = 0;         // voxels with a label in [0, classes)
    int64_t voxels = 0;
    std::vector<float> logits;   // [n, classes] per input point (its voxel's)
    std::map<std::string, Tensor> grads;  // by canonical parameter name
    std::vector<vk::PassTiming> passes;   // GPU time per recorded pass (op families, "... bwd")
};

class Trainer {
public:
    Trainer(Pool& pool, Ptv3Weights weights, TrainOptions options = {});

    const Ptv3Config& config() const { return weights_.config(); }
    const TrainOptions& options() const { return options_; }
    // The parameters and running statistics, updated in place by step (share their buffers).
    const Ptv3Weights& weights() const { return weights_; }
    // Trainable tensors (not the running statistics), in state_dict order.
    const std::vector<std::string>& parameter_names() const { return names_; }

    // Loss and gradients for one batch (clouds by in.offsets); labels per input point (a voxel
    // takes its lowest-index point's label). Updates the BatchNorm running statistics.
    StepResult gradients(const Ptv3Input& in, const std::vector<int32_t>& labels);
    // gradients + one AdamW step with this learning rate and beta1.
    StepResult step(const Ptv3Input& in, const std::vector<int32_t>& labels, double lr, double beta1);

    // Replaces the BatchNorm running statistics by their average over these batches' statistics
    // (training-mode forwards only, no drop path): with momentum 0.01 the running statistics
    // trail the weights by ~100 steps, which matters after short trainings.
    void calibrate_batch_norm(const std::vector<Ptv3Input>& inputs);

    AdamW& optimizer() { return adam_; }
    Pool& pool() { return pool_; }
    std::mt19937_64& rng() { return rng_; }

private:
    enum class Mode { Statistics, Gradients, Step };
    StepResult run(const Ptv3Input& in, const std::vector<int32_t>& labels, Mode mode, double lr, double beta1,
                   double bn_momentum, double drop_path);

    Pool& pool_;
    Ptv3Weights weights_;
    Ptv3Network network_;
    TrainOptions options_;
    std::vector<std::string> names_;
    AdamW adam_;
    std::mt19937_64 rng_;
};

}  // namespace pg::nn::train
