#include "engine/segment/semantic_labeler.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "dataset/random.h"
#include "dataset/semantic/gaussian_features.h"
#include "dataset/semantic/scene_tiles.h"
#include "engine/segment/cancel.h"
#include "engine/segment/partition.h"

namespace pg::seg {

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

}  // namespace

SemanticLabels label_by_class(const data::GaussianCloud& cloud, ClassNetwork& net, const SemanticLabelOptions& o) {
    const double tile = o.tile > 0 ? o.tile : net.tile_size();
    if (!(tile > 0)) throw std::invalid_argument("label_by_class: the tile size must be positive");
    if (!(glm::length(o.up) > 0)) throw std::invalid_argument("label_by_class: up must be non-zero");
    if (o.max_batch < 1) throw std::invalid_argument("label_by_class: max_batch must be positive");
    const int k = net.classes();
    const size_t n = cloud.size();
    SemanticLabels out;

    auto t0 = Clock::now();
    // The voxel follows the tile when --tile overrides it, as the frame's units do.
    const double voxel = net.voxel() * tile / net.tile_size();
    const std::vector<std::string> groups = net.features();
    const std::vector<float> features = data::semantic::gaussian_features(cloud, groups, o.up, voxel);
    const size_t channels = size_t(data::semantic::feature_channels(groups));
    out.stage_ms["features"] = ms_since(t0);

    t0 = Clock::now();
    const data::semantic::SceneTiling tiling(cloud.mean, o.up, tile);
    out.tiles = tiling.size();
    out.stage_ms["tiles"] = ms_since(t0);

    std::vector<float> votes(n * size_t(k), 0.0f);
    std::vector<ClassCloud> pending;
    std::vector<std::vector<uint32_t>> pending_members;
    size_t pending_points = 0, tiles_done = 0;
    double network_ms = 0;
    const auto loop = Clock::now();
    auto flush = [&] {
        if (pending.empty()) return;
        stop_if_cancelled(o.cancel);
        const auto t = Clock::now();
        const std::vector<float> p = net.probabilities(pending);
        network_ms += ms_since(t);
        size_t row = 0;
        for (const auto& members : pending_members)
            for (uint32_t g : members) {
                for (int c = 0; c < k; ++c) votes[size_t(g) * size_t(k) + size_t(c)] += p[row * size_t(k) + size_t(c)];
                ++row;
            }
        ++out.forwards;
        pending.clear();
        pending_members.clear();
        pending_points = 0;
        if (o.progress) o.progress(tiles_done, tiling.size());
    };
    for (size_t t = 0; t < tiling.size(); ++t) {
        const std::vector<uint32_t> members = tiling.members(t);
        const data::RoiFrame frame = tiling.frame(t, members);
        for (auto& batch : partition_roi(members, o.max_batch, data::derive_seed(o.seed, t))) {
            ClassCloud c;
            c.coord.reserve(3 * batch.size());
            c.feat.reserve(channels * batch.size());
            for (uint32_t g : batch) {
                const glm::vec3 q = frame.map(glm::dvec3(cloud.mean[g]));
                c.coord.insert(c.coord.end(), {q.x, q.y, q.z});
                c.feat.insert(c.feat.end(), features.begin() + std::ptrdiff_t(size_t(g) * channels),
                              features.begin() + std::ptrdiff_t((size_t(g) + 1) * channels));
            }
            if (pending_points + batch.size() > o.forward_points) flush();
            pending_points += batch.size();
            pending.push_back(std::move(c));
            pending_members.push_back(std::move(batch));
            ++out.batches;
        }
        ++tiles_done;
    }
    flush();
    out.stage_ms["tiles"] += ms_since(loop) - network_ms;  // gathering batches, summing votes
    out.stage_ms["network"] = network_ms;

    out.classes.assign(n, 0);
    out.confidence.assign(n, 0.0f);
    out.class_counts.assign(size_t(k), 0);
    for (size_t i = 0; i < n; ++i) {
        const float* v = &votes[i * size_t(k)];
        float sum = 0;
        for (int c = 0; c < k; ++c) sum += v[c];
        if (!(sum > 0)) {
            ++out.unvoted;
            ++out.class_counts[0];
            continue;
        }
        const int best = int(std::max_element(v, v + k) - v);
        out.classes[i] = best;
        out.confidence[i] = v[best] / sum;
        ++out.class_counts[size_t(best)];
    }
    return out;
}

}  // namespace pg::seg
