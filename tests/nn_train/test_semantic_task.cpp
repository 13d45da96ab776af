// The semantic training task's inputs: no cloud so small that a training-mode BatchNorm sees a
// single voxel (a lone floater's tile), and calibration inputs of a batch's size.
#include <catch2/catch.hpp>

#include "dataset/random.h"
#include "nn/train/training_task.h"

using namespace pg;

TEST_CASE("semantic task: lone-floater tiles are redrawn and calibration packs tiles to a batch's points") {
    data::Rng rng(2);
    data::train::SemanticScene scene;
    scene.name = "floaters";
    for (int i = 0; i < 3000; ++i) {  // a dense 20 m field
        scene.positions.push_back({float(rng.uniform(0, 20)), float(rng.uniform(0, 20)), 0.0f});
        scene.classes.push_back(1);
    }
    for (int i = 0; i < 3000; ++i) {  // as many lone floaters, each in a tile of its own
        scene.positions.push_back({1000.0f + 100.0f * float(i), 0.0f, 5.0f});
        scene.classes.push_back(0);
    }
    scene.features.assign(scene.size(), 0.5f);
    data::train::SemanticOptions o;
    o.tile = 10.0;
    o.max_points = 1000;
    o.features = {"opacity"};
    const data::train::SemanticDrawer drawer({scene}, 2, o);
    // Half the draws land on a floater; none of the batch's clouds may be one.
    size_t tiny = 0;
    for (int i = 0; i < 40; ++i) {
        data::Rng r(uint64_t(100 + i));
        if (drawer.draw(r).size() < 64) ++tiny;
    }
    REQUIRE(tiny > 5);
    nn::train::SemanticTask task(drawer, nullptr);
    for (int i = 0; i < 20; ++i) {
        data::Rng r(uint64_t(100 + i));
        const auto batch = task.draw_batch(nullptr, r, 2, 0);
        int64_t start = 0;
        for (int64_t end : batch.input.offsets) {
            CHECK(end - start >= 64);
            start = end;
        }
    }
    data::Rng r(7);
    const nn::Ptv3Input calibration = task.calibration_input(r);
    CHECK(calibration.size() >= o.max_points);
    CHECK(!calibration.offsets.empty());
    CHECK(int64_t(calibration.size()) == calibration.offsets.back());
}
