#include "nn/train/trainer.h"

#include <stdexcept>

#include "nn/ops/elementwise.h"
#include "nn/ptv3/point.h"
#include "nn/ptv3/structure.h"
#include "nn/ptv3/training_pass.h"
#include "nn/train/grad_ops.h"

namespace pg::nn::train {

Trainer::Trainer(Pool& pool, Ptv3Weights weights, TrainOptions options)
    : pool_(pool),
      weights_(std::move(weights)),
      network_(weights_.config()),
      options_(options),
      adam_(pool, options.adamw),
      rng_(options.seed) {
    for (const auto& [name, shape] : Ptv3Weights::expected(config()))
        if (name.find("running_") == std::string::npos && name.find("num_batches_tracked") == std::string::npos)
            names_.push_back(name);
}

StepResult Trainer::gradients(const Ptv3Input& in, const std::vector<int32_t>& labels) {
    return run(in, labels, Mode::Gradients, 0, 0, options_.bn_momentum, options_.drop_path);
}

StepResult Trainer::step(const Ptv3Input& in, const std::vector<int32_t>& labels, double lr, double beta1) {
    return run(in, labels, Mode::Step, lr, beta1, options_.bn_momentum, options_.drop_path);
}

void Trainer::calibrate_batch_norm(const std::vector<Ptv3Input>& inputs) {
    // Momentum 1/(k+1) at batch k: a running mean of the batch statistics, the first replacing
    // whatever was there.
    for (size_t k = 0; k < inputs.size(); ++k)
        run(inputs[k], std::vector<int32_t>(inputs[k].size(), options_.ignore_label), Mode::Statistics, 0, 0,
            1.0 / double(k + 1), 0.0);
}

StepResult Trainer::run(const Ptv3Input& in, const std::vector<int32_t>& labels, Mode mode, double lr, double beta1,
                        double bn_momentum, double drop_path) {
    const Ptv3Config& c = config();
    Ptv3::validate(c, in);
    const int64_t n = int64_t(in.size());
    if (labels.size() != size_t(n))
        throw std::invalid_argument("PTv3 training: " + std::to_string(labels.size()) + " labels for " +
                                    std::to_string(n) + " points");
    vk::Context& ctx = pool_.context();
    vk::CommandList cmd(ctx);
    std::vector<vk::PassTiming> passes;

    Tensor feat = upload_tensor(pool_, in.feat, {n, c.in_channels}, DType::F32);
    Tensor labels_t = upload_tensor(pool_, labels, {n}, DType::I32);
    const Ptv3Structure st = build_structure(cmd, pool_, c, in, passes);
    TrainingPass pass(cmd, pool_, weights_, bn_momentum, drop_path, rng_);
    Ptv3Point point{&st, 0, std::move(feat)};
    network_.forward(pass, point);
    const Tensor logits = point.feat;

    cmd.begin_pass("loss");
    Tensor voxel_labels = ops::gather_rows(cmd, pool_, labels_t, st.vox.first);
    grad::CrossEntropy ce = grad::cross_entropy(cmd, pool_, logits, voxel_labels, options_.ignore_label);
    Tensor dlogits = ce.dlogits, lovasz_loss;
    if (options_.lovasz_weight > 0 && mode != Mode::Statistics) {  // statistics passes need no loss
        grad::Lovasz lv = grad::lovasz_softmax(cmd, pool_, logits, voxel_labels, options_.ignore_label,
                                               float(options_.lovasz_weight));
        dlogits = ops::add(cmd, pool_, ce.dlogits, lv.dlogits);
        lovasz_loss = lv.loss;
    }
    Tensor point_logits = ops::gather_rows(cmd, pool_, logits, st.vox.inverse);

    if (mode == Mode::Statistics) {
        cmd.submit_and_wait();
        return {};
    }

    Ptv3Point grad{&st, 0, dlogits};
    network_.backward(pass, grad);

    if (mode == Mode::Step) {
        cmd.begin_pass("optimizer");
        std::vector<Tensor> params, grads;
        for (const std::string& name : names_) {
            params.push_back(weights_[name]);
            grads.push_back(pass.grads.at(name));
        }
        adam_.step(cmd, params, grads, lr, beta1);
    }
    cmd.submit_and_wait();

    StepResult r;
    r.passes = std::move(passes);
    for (const auto& p : cmd.timings()) r.passes.push_back(p);
    r.voxels = st.vox.count;
    r.loss = download_tensor<float>(ctx, ce.loss)[0];
    if (lovasz_loss.defined()) {
        r.lovasz = download_tensor<float>(ctx, lovasz_loss)[0];
        r.loss += r.lovasz;
    }
    r.counted = int64_t(download_tensor<uint32_t>(ctx, ce.info)[0]);
    r.logits = download_tensor<float>(ctx, point_logits);
    r.logits.resize(size_t(n * c.num_classes));
    r.grads = std::move(pass.grads);
    return r;
}

}  // namespace pg::nn::train
