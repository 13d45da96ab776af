#include "dataset/train/semantic_drawer.h"

#include <algorithm>
#include <cmath>

#include "dataset/error.h"
#include "dataset/formats/scene_io.h"
#include "dataset/semantic/gaussian_features.h"
#include "dataset/semantic/scene_tiles.h"
#include "dataset/train/train_scene.h"

namespace pg::data::train {

namespace fs = std::filesystem;

SemanticScene load_semantic_scene(const fs::path& path, const SemanticOptions& options) {
    const SceneFiles files = read_scene_files(path);
    SemanticScene s;
    s.name = files.name;
    const GaussianCloud cloud = load_scene(files.ply);
    auto classes = cloud.int_property("class");
    if (!classes) throw InputError(files.ply.string(), "has no integer \"class\" property (per-Gaussian classes)");
    s.classes = std::move(*classes);
    s.positions = cloud.mean;
    s.up = scene_up(files.cameras, cloud);
    s.features = semantic::gaussian_features(cloud, options.features, s.up, options.unit());
    return s;
}

SemanticDrawer::SemanticDrawer(std::vector<SemanticScene> scenes, int classes, SemanticOptions options)
    : scenes_(std::move(scenes)), classes_(classes), options_(std::move(options)) {
    if (scenes_.empty()) throw InputError("--data", "holds no scenes");
    for (const auto& s : scenes_) {
        if (s.size() == 0) throw InputError(s.name, "has no Gaussians");
        std::vector<std::vector<uint32_t>> members(size_t(classes_), std::vector<uint32_t>{});
        for (size_t i = 0; i < s.size(); ++i) {
            const int32_t c = s.classes[i];
            if (c < 0 || c >= classes_)
                throw InputError(s.name, "has class " + std::to_string(c) + ", outside the model's " +
                                             std::to_string(classes_) + " classes");
            members[size_t(c)].push_back(uint32_t(i));
        }
        std::erase_if(members, [](const auto& m) { return m.empty(); });
        by_class_.push_back(std::move(members));
    }
}

SemanticSample SemanticDrawer::draw(Rng& rng) const {
    const SemanticOptions& o = options_;
    SemanticSample out;
    out.scene = size_t(rng.below(int(scenes_.size())));
    const SemanticScene& sc = scenes_[out.scene];
    size_t pick = size_t(rng.next() % sc.size());
    if (o.balance > 0 && rng.chance(o.balance)) {
        const auto& classes = by_class_[out.scene];
        const auto& members = classes[size_t(rng.below(int(classes.size())))];
        pick = members[size_t(rng.next() % members.size())];
    }
    const glm::dvec3 anchor(sc.positions[pick]);
    const glm::dvec2 plane = semantic::plane_coords(anchor, sc.up) +
                             glm::dvec2(rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5)) * o.tile;
    const std::vector<uint32_t> column = semantic::column_members(sc.positions, sc.up, plane, o.tile);
    const RoiFrame frame = semantic::tile_frame(sc.positions, column, sc.up, plane, o.tile);
    out.column_points = column.size();

    // One batch of the pipeline's partition: ceil(n / batches) points drawn uniformly, ascending.
    const size_t n = column.size();
    std::vector<uint32_t> slots(n);
    for (uint32_t i = 0; i < n; ++i) slots[i] = i;
    if (n > o.max_points) {
        const size_t batches = (n + o.max_points - 1) / o.max_points, m = (n + batches - 1) / batches;
        for (size_t i = 0; i < m; ++i) std::swap(slots[i], slots[i + size_t(rng.next() % (n - i))]);
        slots.resize(m);
        std::sort(slots.begin(), slots.end());
    }

    glm::mat3 m(1.0f);
    if (o.rotate) {
        const double a = rng.uniform(0.0, 6.283185307179586);
        const float c = float(std::cos(a)), sn = float(std::sin(a));
        m[0][0] = c, m[0][1] = sn, m[1][0] = -sn, m[1][1] = c;
    }
    if (o.flip) {
        if (rng.chance(0.5)) m[0] = -m[0];
        if (rng.chance(0.5)) m[1] = -m[1];
    }
    if (o.scale) m *= float(rng.uniform(o.scale_min, o.scale_max));
    glm::vec3 tint(1.0f);
    if (o.colour) {
        const float b = float(rng.uniform(1.0 - o.brightness, 1.0 + o.brightness));
        for (int c = 0; c < 3; ++c) tint[c] = b * float(rng.uniform(1.0 - o.tint, 1.0 + o.tint));
    }
    const size_t channels = sc.features.size() / sc.size();
    const bool has_rgb = !o.features.empty() && o.features.front() == "rgb";

    out.gaussians.reserve(slots.size());
    out.coord.reserve(3 * slots.size());
    out.feat.reserve(channels * slots.size());
    for (uint32_t k : slots) {
        const uint32_t g = column[k];
        out.gaussians.push_back(g);
        out.labels.push_back(sc.classes[g]);
        const glm::vec3 p = m * frame.map(glm::dvec3(sc.positions[g]));
        for (int a = 0; a < 3; ++a) {
            float v = p[a];
            if (o.jitter) v += float(std::clamp(rng.normal(0.0, o.jitter_sigma), -o.jitter_clip, o.jitter_clip));
            out.coord.push_back(v);
        }
        const float* f = &sc.features[size_t(g) * channels];
        for (size_t c = 0; c < channels; ++c)
            out.feat.push_back(has_rgb && c < 3 ? std::clamp(f[c] * tint[int(c)], 0.0f, 1.0f) : f[c]);
    }
    return out;
}

}  // namespace pg::data::train
