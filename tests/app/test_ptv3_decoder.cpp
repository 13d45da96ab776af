// The PTv3 decoder with a model that reads feature groups: segment feeds it exactly what
// training fed it (same frame, click weights and appearance rows), so its probabilities equal
// the network's on the training sample; a model whose channels do not match its groups is refused.
#include <catch2/catch.hpp>

#include <cmath>
#include <optional>

#include "app/common/ptv3_decoder.h"
#include "dataset/error.h"
#include "dataset/formats/scene_io.h"
#include "dataset/random.h"
#include "dataset/semantic/gaussian_features.h"
#include "dataset/train/sample_drawer.h"
#include "nn/ptv3/model.h"
#include "nn/train/batch.h"
#include "nn/train/checkpoint.h"
#include "nn/train/initial_weights.h"
#include "tests/gpu_fixture.h"
#include "tests/test_paths.h"

namespace {

pg::nn::Ptv3Config feature_config() {
    pg::nn::Ptv3Config c = pg::nn::Ptv3Config::tiny();
    c.features = pg::data::semantic::all_feature_groups();
    c.in_channels = 2 + pg::data::semantic::feature_channels(c.features);
    c.num_classes = 2;
    c.input_frame = "roi";
    return c;
}

}  // namespace

TEST_CASE("ptv3 decoder: a model with feature groups gets in segment what training gave it") {
    auto& ctx = pg::test::gpu();
    auto pool = pg::nn::Pool::create(ctx);
    const pg::nn::Ptv3Config config = feature_config();
    const auto weights = pg::nn::Ptv3Weights::from_host(*pool, config, pg::nn::train::initial_weights(config, 3), "initial");
    const auto model_file = pg::test::scratch("ptv3-decoder") / "features.safetensors";
    std::filesystem::create_directories(model_file.parent_path());
    pg::nn::train::save_model(model_file, *pool, weights);

    const auto dir = pg::test::source_dir() / "assets" / "sample" / "desk_000";
    const pg::data::GaussianCloud cloud = pg::data::load_scene(dir / "scene.ply");
    pg::data::train::SampleOptions o = pg::data::train::SampleOptions{}.without_augmentation();
    o.features = config.features;
    o.voxel = config.grid_size;
    o.max_points = 2048;
    const pg::data::train::SampleDrawer drawer({pg::data::train::load_train_scene(dir, std::nullopt, config.features)}, o);
    pg::data::Rng rng(21);
    const pg::data::train::Sample s = drawer.draw(rng);

    pg::nn::Ptv3 model(*pool, weights);
    const auto out = model.forward(pg::nn::train::sample_input(s));

    pg::app::Ptv3Decoder decoder(ctx, model_file.string(), &cloud);
    pg::seg::DecoderBatch batch;
    batch.frame = s.frame;
    for (size_t i = 0; i < s.size(); ++i) {
        batch.gaussians.push_back(s.gaussians[i]);
        batch.coords.push_back(cloud.mean[s.gaussians[i]]);
        batch.features.push_back({s.feat[10 * i], s.feat[10 * i + 1]});
    }
    const std::vector<float> p = decoder.predict(batch);
    REQUIRE(p.size() == s.size());
    for (size_t i = 0; i < s.size(); ++i) {
        const float expect = 1.0f / (1.0f + std::exp(out.logits[2 * i] - out.logits[2 * i + 1]));
        REQUIRE(p[i] == Approx(expect).margin(1e-4));
    }
    // Without the scene it cannot compute the groups: a clear logic error, not garbage.
    pg::app::Ptv3Decoder blind(ctx, model_file.string());
    CHECK_THROWS_AS(blind.predict(batch), std::logic_error);
}

TEST_CASE("ptv3 decoder: input channels must be the click weights plus the model's feature groups") {
    pg::nn::Ptv3Config c = feature_config();
    CHECK_NOTHROW(pg::app::check_interactive_config(c, "m.safetensors"));
    c.in_channels = 2;
    CHECK_THROWS_AS(pg::app::check_interactive_config(c, "m.safetensors"), pg::data::InputError);
    c.features.clear();
    CHECK_NOTHROW(pg::app::check_interactive_config(c, "m.safetensors"));  // the paper's 2-channel models
    c.features = {"rgb", "sparkle"};
    c.in_channels = 5;
    CHECK_THROWS_AS(pg::app::check_interactive_config(c, "m.safetensors"), pg::data::InputError);
}
