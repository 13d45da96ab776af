#pragma once
// The SOG writer's clustering on the GPU: codebooks and the SH palette through kmeans.h.
#include <cstdint>
#include <filesystem>
#include <functional>

#include "dataset/formats/sog_writer.h"
#include "engine/vk/context.h"

namespace pg::compress {

// `iterations` Lloyd steps for the SH palette (splat-transform's default, 10) and for the 1-D
// codebooks; `seed` picks the palette's first centroids, so a scene gives the same file each time.
data::SogQuantizer gpu_sog_quantizer(vk::Context& ctx, int iterations = 10, uint64_t seed = 1);

// write_sog with that clustering, as a cloud writer (the shape of segment's CloudWriter).
using SogFileWriter = std::function<void(const data::GaussianCloud&, const std::filesystem::path&)>;
SogFileWriter gpu_sog_writer(vk::Context& ctx, int iterations = 10, uint64_t seed = 1);

}  // namespace pg::compress
