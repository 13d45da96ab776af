#include <catch2/catch.hpp>
#include <cstring>

#include "nn/train/initial_weights.h"
#include "nn/train/trainer.h"
#include "tests/gpu_fixture.h"
#include "tests/nn_grad/grad_test_util.h"
#include "tests/nn/ptv3_fixture.h"
#include "tests/nn_train/train_scene.h"

using namespace pg;

namespace {

double accuracy(const std::vector<float>& logits, const std::vector<int32_t>& labels) {
    size_t right = 0;
    for (size_t i = 0; i < labels.size(); ++i) right += (logits[2 * i + 1] > logits[2 * i]) == (labels[i] == 1);
    return double(right) / double(labels.size());
}

}  // namespace

TEST_CASE("training drives the loss down on a tiny two-box scene", "[train]") {
    auto pool = nn::Pool::create(test::gpu());
    const nn::Ptv3Config config = test::tiny_config();
    nn::train::TrainOptions options;
    options.drop_path = 0.1;
    nn::train::Trainer trainer(*pool, nn::Ptv3Weights::from_host(*pool, config, nn::train::initial_weights(config, 7), "init"),
                               options);
    const test::TrainCase scene = test::box_scene(3, 1);
    nn::train::OneCycle schedule;
    schedule.max_lr = 0.01;
    schedule.total_steps = 30;
    schedule.pct_start = 0.2;
    std::vector<double> losses;
    nn::train::StepResult last;
    for (int64_t s = 0; s < schedule.total_steps; ++s) {
        last = trainer.step(scene.input, scene.labels, schedule.lr(s), schedule.beta1(s));
        losses.push_back(last.loss);
    }
    INFO("first loss " << losses.front() << ", last " << losses.back());
    CHECK(std::isfinite(losses.back()));
    CHECK(losses.back() < 0.3 * losses.front());
    // The model learnt the clicked box, not just the floor: inference on the trained weights,
    // once the running statistics caught up with them (30 steps at momentum 0.01 would not).
    trainer.calibrate_batch_norm({scene.input});
    nn::Ptv3 model(*pool, trainer.weights());
    const auto out = model.forward(scene.input);
    CHECK(accuracy(out.logits, scene.labels) > 0.95);
    // ...and it transfers to a scene it did not see (boxes moved, another click).
    const test::TrainCase other = test::box_scene(11, 1);
    CHECK(accuracy(model.forward(other.input).logits, other.labels) > 0.8);
}

TEST_CASE("training steps are deterministic for a seed", "[train]") {
    auto pool = nn::Pool::create(test::gpu());
    const nn::Ptv3Config config = test::tiny_config();
    const test::TrainCase scene = test::box_scene(5, 1);
    auto run = [&] {
        nn::train::Trainer t(*pool, nn::Ptv3Weights::from_host(*pool, config, nn::train::initial_weights(config, 1), "init"));
        t.step(scene.input, scene.labels, 1e-3, 0.9);
        nn::train::StepResult r = t.gradients(scene.input, scene.labels);
        std::vector<float> all;
        for (const std::string& name : t.parameter_names()) {
            const auto g = test::down(*pool, r.grads.at(name));
            all.insert(all.end(), g.begin(), g.end());
        }
        return all;
    };
    CHECK(test::same_bits(run(), run()));
}

namespace {

// One training-mode step of the fixture's weights and two clouds against PyTorch autograd
// (tools/make_ptv3_train_fixture.py): loss, logits and every parameter's gradient.
void check_against_autograd(double lovasz_weight, const char* grads_file) {
    const auto dir = test::fixtures() / "ptv3" / "train";
    auto pool = nn::Pool::create(test::gpu());
    nn::train::TrainOptions options;
    options.drop_path = 0;
    options.lovasz_weight = lovasz_weight;
    nn::train::Trainer trainer(*pool, nn::Ptv3Weights::load(*pool, test::fixtures() / "ptv3" / "small" / "weights.safetensors"),
                               options);
    const nn::Ptv3Input input = test::read_ptv3_input(dir, 2);
    const std::vector<float> raw_labels = test::read_f32_file(dir / "labels.bin");
    std::vector<int32_t> labels(raw_labels.size());
    std::memcpy(labels.data(), raw_labels.data(), labels.size() * 4);
    const nn::SafeTensors want = nn::SafeTensors::load(dir / grads_file);

    std::map<std::string, std::string> file_name;  // canonical -> the fixture's (release) name
    for (const auto& [name, info] : want.tensors()) file_name[nn::Ptv3Weights::canonical_name(name)] = name;
    auto wanted = [&](const std::string& canonical) { return want.f32(file_name.at(canonical)); };

    const nn::train::StepResult r = trainer.gradients(input, labels);
    CHECK(r.counted == 473);
    CHECK(r.loss == Approx(want.f32("loss")[0]).epsilon(1e-5));
    CHECK((lovasz_weight > 0) == (r.lovasz > 0));
    if (lovasz_weight == 0) CHECK(test::relative_max_error(r.logits, want.f32("logits")) < 1e-4);

    // Per tensor, relative to its largest gradient; a floor of 1e-3 of the largest gradient
    // overall for the tensors whose exact gradient is zero (their values are rounding noise).
    double global = 0;
    for (const std::string& name : trainer.parameter_names())
        for (float v : wanted(name)) global = std::max(global, double(std::abs(v)));
    double worst = 0;
    std::string worst_name;
    for (const std::string& name : trainer.parameter_names()) {
        const std::vector<float> g = test::down(*pool, r.grads.at(name)), w = wanted(name);
        REQUIRE(g.size() == w.size());
        double diff = 0, scale = 1e-3 * global;
        for (size_t i = 0; i < g.size(); ++i) {
            diff = std::max(diff, std::abs(double(g[i]) - double(w[i])));
            scale = std::max(scale, std::abs(double(w[i])));
        }
        if (diff / scale > worst) worst = diff / scale, worst_name = name;
    }
    INFO("worst gradient " << worst_name << ": " << worst);
    CHECK(worst < 1e-4);
    if (lovasz_weight > 0) return;
    // BatchNorm running statistics moved as PyTorch moves them (momentum 0.01, unbiased variance).
    for (const char* bn : {"embedding.stem.norm", "enc.enc4.down.norm.0", "dec.dec0.up.proj_skip.1"})
        for (const char* stat : {".running_mean", ".running_var"}) {
            const std::string name = std::string(bn) + stat;
            CHECK(test::relative_max_error(test::down(*pool, trainer.weights()[name]), wanted(name)) < 1e-5);
        }
}

}  // namespace

TEST_CASE("training-mode gradients match PyTorch autograd on the tiny config (two clouds)", "[train]") {
    check_against_autograd(0, "grads.safetensors");
}

TEST_CASE("training-mode gradients with the Lovasz loss added match PyTorch autograd", "[train]") {
    check_against_autograd(1, "grads_lovasz.safetensors");
}
