#pragma once
// A tiny interactive-segmentation task for training tests: a floor patch with two boxes on it,
// a click on the first box (its positive click weight as the feature), labels 1 on that box.
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "nn/ptv3/model.h"
#include "nn/ptv3/weights.h"
#include "nn/safetensors.h"
#include "tests/test_paths.h"

namespace pg::test {

struct TrainCase {
    nn::Ptv3Input input;
    std::vector<int32_t> labels;
};

// `seed` moves the boxes and the click; spacing 0.025 keeps every point in its own 0.02 voxel.
inline TrainCase box_scene(uint64_t seed, int clouds = 1) {
    TrainCase t;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const double h = 0.025;
    for (int cloud = 0; cloud < clouds; ++cloud) {
        const double ax = 0.1 + 0.2 * u(rng), ay = 0.1 + 0.2 * u(rng);         // box A (the object)
        const double bx = 0.45 + 0.1 * u(rng), by = 0.35 + 0.15 * u(rng);      // box B (a distractor)
        const double size = 0.15;
        auto add = [&](double x, double y, double z, int label) {
            t.input.coord.insert(t.input.coord.end(), {float(x), float(y), float(z)});
            t.labels.push_back(label);
        };
        for (int i = 0; i < 28; ++i)
            for (int j = 0; j < 28; ++j) {
                const double x = i * h, y = j * h;
                const bool under_a = x >= ax && x < ax + size && y >= ay && y < ay + size;
                const bool under_b = x >= bx && x < bx + size && y >= by && y < by + size;
                if (!under_a && !under_b) add(x, y, 0.0, 0);
            }
        for (int box = 0; box < 2; ++box) {
            const double x0 = box ? bx : ax, y0 = box ? by : ay;
            const int k = int(size / h);
            for (int i = 0; i < k; ++i)
                for (int j = 0; j < k; ++j)
                    for (int l = 0; l < k; ++l)
                        if (i == 0 || j == 0 || l == 0 || i == k - 1 || j == k - 1 || l == k - 1)
                            add(x0 + i * h, y0 + j * h, l * h, box ? 0 : 1);
        }
        // The click: the top centre of box A; features = (positive weight, negative weight).
        const double cx = ax + size / 2, cy = ay + size / 2, cz = size, sigma = 0.1;
        const size_t first = t.input.feat.size() / 2;
        for (size_t p = first; p < t.labels.size(); ++p) {
            const double dx = t.input.coord[3 * p] - cx, dy = t.input.coord[3 * p + 1] - cy,
                         dz = t.input.coord[3 * p + 2] - cz;
            t.input.feat.push_back(float(std::exp(-(dx * dx + dy * dy + dz * dz) / (2 * sigma * sigma))));
            t.input.feat.push_back(0.0f);
        }
        // Clouds apart in space too, as the sampler's would be after cropping.
        if (clouds > 1) t.input.offsets.push_back(int64_t(t.labels.size()));
    }
    return t;
}

// The tiny config of the committed PTv3 fixture (5 levels, 240k parameters).
inline nn::Ptv3Config tiny_config() {
    return nn::Ptv3Weights::config_of(nn::SafeTensors::load(fixtures() / "ptv3" / "small" / "weights.safetensors"));
}

}  // namespace pg::test
