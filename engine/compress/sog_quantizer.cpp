#include "engine/compress/sog_quantizer.h"

#include "engine/compress/kmeans.h"

namespace pg::compress {

data::SogQuantizer gpu_sog_quantizer(vk::Context& ctx, int iterations, uint64_t seed) {
    data::SogQuantizer q;
    q.codebook = [&ctx, iterations](const std::vector<float>& values) {
        Clusters c = codebook_1d(ctx, values, 256, iterations);
        return data::SogClusters{std::move(c.centroids), std::move(c.labels)};
    };
    q.kmeans = [&ctx, iterations, seed](const std::vector<float>& points, size_t dims, size_t k) {
        Clusters c = kmeans(ctx, points, dims, k, iterations, seed);
        return data::SogClusters{std::move(c.centroids), std::move(c.labels)};
    };
    return q;
}

SogFileWriter gpu_sog_writer(vk::Context& ctx, int iterations, uint64_t seed) {
    return [quantizer = gpu_sog_quantizer(ctx, iterations, seed)](const data::GaussianCloud& cloud,
                                                                 const std::filesystem::path& path) {
        data::write_sog(cloud, path, quantizer);
    };
}

}  // namespace pg::compress
