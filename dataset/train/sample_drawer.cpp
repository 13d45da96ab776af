#include "dataset/train/sample_drawer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

#include "dataset/clicks/click3d.h"
#include "dataset/clicks/point_grid.h"
#include "dataset/error.h"
#include "dataset/semantic/gaussian_features.h"
#include "dataset/train/first_click.h"

namespace pg::data::train {

namespace {

void check_options(const SampleOptions& o) {
    auto fail = [](const std::string& what) { throw std::invalid_argument("SampleOptions: " + what); };
    if (o.max_points == 0) fail("max_points must be positive");
    if (!(o.roi_min > 0 && o.roi_min <= o.roi_max)) fail("need 0 < roi_min <= roi_max");
    if (!(o.sigma_factor > 0)) fail("sigma_factor must be positive");
    if (!(o.camera_scale_factor > 0)) fail("camera_scale_factor must be positive");
    if (!(o.scale_min > 0 && o.scale_min <= o.scale_max)) fail("need 0 < scale_min <= scale_max");
    if (!(o.jitter_sigma >= 0 && o.jitter_clip >= 0)) fail("jitter sigma and clip must be non-negative");
    if (!(o.voxel > 0)) fail("voxel must be positive");
    if (!(o.colour_gain >= 0 && o.colour_gain < 1 && o.colour_shift >= 0)) fail("colour gain must be in [0, 1), shift >= 0");
    semantic::feature_channels(o.features);  // names an unknown group
}

// Size of the horizontal bounding box's larger side.
double horizontal_extent(std::span<const glm::vec3> positions, std::span<const uint32_t> members, glm::dvec3 up) {
    glm::dvec3 l, w;
    horizontal_axes(up, l, w);
    glm::dvec2 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (uint32_t i : members) {
        const glm::dvec3 p(positions[i]);
        const glm::dvec2 q(glm::dot(p, l), glm::dot(p, w));
        lo = glm::min(lo, q);
        hi = glm::max(hi, q);
    }
    return std::max(hi.x - lo.x, hi.y - lo.y);
}

}  // namespace

SampleDrawer::SampleDrawer(std::vector<TrainScene> scenes, SampleOptions options)
    : scenes_(std::move(scenes)), options_(options), objects_(scenes_.size()) {
    check_options(options_);
    for (size_t s = 0; s < scenes_.size(); ++s) {
        const TrainScene& scene = scenes_[s];
        if (scene.feature_groups != options_.features)
            throw std::invalid_argument("SampleDrawer: scene '" + scene.name + "' was loaded with other feature groups");
        if (scene.instance.size() != scene.positions.size())
            throw std::invalid_argument("SampleDrawer: scene '" + scene.name + "' has " +
                                        std::to_string(scene.instance.size()) + " labels for " +
                                        std::to_string(scene.positions.size()) + " Gaussians");
        std::map<int32_t, size_t> counts;  // ordered: objects in id order, deterministically
        for (int32_t id : scene.instance)
            if (id > 0) ++counts[id];
        // The benchmark clicker's link radius, so parts are the ones its clicks see.
        float link = clicks::kLinkSpacings * clicks::median_spacing(scene.positions);
        if (!(link > 0)) link = 1e-6f;
        std::vector<uint8_t> mask(scene.size());
        for (auto [id, count] : counts) {
            if (count < options_.min_object_points) continue;
            for (size_t i = 0; i < scene.size(); ++i) mask[i] = scene.instance[i] == id;
            FirstClickSet set = first_click_set(scene.positions, mask, link);
            Object obj;
            obj.id = id;
            obj.candidates = std::move(set.candidates);
            obj.extent = std::max(1e-6, horizontal_extent(scene.positions, set.part, scene.up));
            objects_[s].push_back(std::move(obj));
        }
        if (!objects_[s].empty()) drawable_.push_back(s);
    }
    if (drawable_.empty())
        throw InputError("training scenes", "no scene has an object of at least " +
                                                std::to_string(options_.min_object_points) + " Gaussians");
}

size_t SampleDrawer::object_count() const {
    size_t n = 0;
    for (const auto& objs : objects_) n += objs.size();
    return n;
}

double SampleDrawer::scale_for(const TrainScene& scene, const Object& object, glm::dvec3 anchor) const {
    if (!scene.has_cameras()) return object.extent;
    // Segmenter::scale_from_cameras: the upper median of the camera distances.
    std::vector<double> d;
    d.reserve(scene.camera_positions.size());
    for (const glm::dvec3& c : scene.camera_positions) d.push_back(glm::length(c - anchor));
    std::nth_element(d.begin(), d.begin() + long(d.size() / 2), d.end());
    return std::max(1e-6, options_.camera_scale_factor * d[d.size() / 2]);
}

Sample SampleDrawer::draw(Rng& rng) const {
    const size_t si = drawable_[size_t(rng.below(int(drawable_.size())))];
    const TrainScene& scene = scenes_[si];
    const auto& objs = objects_[si];
    const Object& obj = objs[size_t(rng.below(int(objs.size())))];
    const uint32_t clicked = obj.candidates[size_t(rng.below(int(obj.candidates.size())))];
    const glm::dvec3 anchor(scene.positions[clicked]);

    Sample s;
    s.scene = si;
    s.object = obj.id;
    s.frame = RoiFrame::around(anchor, scene.up, scale_for(scene, obj, anchor));
    s.sigma = float(options_.sigma_factor);
    s.roi = glm::vec2(float(rng.uniform(options_.roi_min, options_.roi_max)),
                      float(rng.uniform(options_.roi_min, options_.roi_max)));

    // The ROI column: within half the length and half the width, any height.
    std::vector<uint32_t> roi;
    std::vector<glm::vec3> mapped;
    for (size_t i = 0; i < scene.size(); ++i) {
        const glm::vec3 q = s.frame.map(glm::dvec3(scene.positions[i]));
        if (std::abs(q.x) <= 0.5f * s.roi.x && std::abs(q.y) <= 0.5f * s.roi.y) {
            roi.push_back(uint32_t(i));
            mapped.push_back(q);
        }
    }
    s.roi_points = roi.size();

    // One batch of the pipeline's partition: ceil(n / N_max) batches, so ceil(n / batches)
    // points drawn uniformly (the object is not favoured), kept in ascending order.
    const size_t n = roi.size();
    std::vector<uint32_t> slots(n);
    for (uint32_t i = 0; i < n; ++i) slots[i] = i;
    if (n > options_.max_points) {
        const size_t batches = (n + options_.max_points - 1) / options_.max_points;
        const size_t m = (n + batches - 1) / batches;
        for (size_t i = 0; i < m; ++i) std::swap(slots[i], slots[i + size_t(rng.next() % (n - i))]);
        slots.resize(m);
        std::sort(slots.begin(), slots.end());
    }

    s.gaussians.reserve(slots.size());
    s.position.reserve(slots.size());
    s.labels.reserve(slots.size());
    for (uint32_t k : slots) {
        s.gaussians.push_back(roi[k]);
        s.position.push_back(mapped[k]);
        s.labels.push_back(scene.instance[roi[k]] == obj.id ? 1 : 0);
    }
    s.clicks.push_back({s.frame.map(anchor), true, clicked});
    if (!options_.features.empty()) {
        const size_t c = size_t(semantic::feature_channels(options_.features));
        s.appearance.resize(s.size() * c);
        for (size_t i = 0; i < s.size(); ++i)
            std::copy_n(&scene.features[size_t(s.gaussians[i]) * c], c, &s.appearance[i * c]);
        const double unit = options_.voxel * s.frame.scale;
        semantic::finish_gaussian_features(s.appearance, options_.features, unit);
        if (options_.scale_spacing != 0) {
            std::vector<glm::vec3> world(s.size());
            for (size_t i = 0; i < s.size(); ++i) world[i] = scene.positions[s.gaussians[i]];
            semantic::raise_scale_spacing(s.appearance, options_.features, world, unit, options_.scale_spacing);
        }
        if (options_.colour) augment_colour(s, rng);
    }
    compose_features(s);
    augment(s, rng);
    return s;
}

void SampleDrawer::compose_features(Sample& s) const {
    const std::vector<float> w = click_weights(s.position, s.clicks, s.sigma);
    if (s.appearance.empty()) {
        s.feat = w;
        return;
    }
    const size_t c = s.appearance.size() / s.size(), row = 2 + c;
    s.feat.resize(s.size() * row);
    for (size_t i = 0; i < s.size(); ++i) {
        s.feat[i * row] = w[2 * i];
        s.feat[i * row + 1] = w[2 * i + 1];
        std::copy_n(&s.appearance[i * c], c, &s.feat[i * row + 2]);
    }
}

void SampleDrawer::augment_colour(Sample& s, Rng& rng) const {
    const int rgb = semantic::group_offset(options_.features, "rgb");
    if (rgb < 0) return;
    int perm[3] = {0, 1, 2};
    for (int i = 2; i > 0; --i) std::swap(perm[i], perm[rng.below(i + 1)]);
    float gain[3];
    for (float& g : gain) g = float(rng.uniform(1.0 - options_.colour_gain, 1.0 + options_.colour_gain));
    const float shift = float(rng.uniform(-options_.colour_shift, options_.colour_shift));
    const size_t c = s.appearance.size() / s.size();
    for (size_t i = 0; i < s.size(); ++i) {
        float* p = &s.appearance[i * c + size_t(rgb)];
        const float in[3] = {p[0], p[1], p[2]};
        for (int k = 0; k < 3; ++k) p[k] = std::clamp(gain[k] * in[perm[k]] + shift, 0.0f, 1.0f);
    }
}

void SampleDrawer::augment(Sample& s, Rng& rng) const {
    const SampleOptions& o = options_;
    glm::mat3 m(1.0f);
    if (o.rotate) {  // about z, the frame's up
        const double a = rng.uniform(0.0, 6.283185307179586);
        const float c = float(std::cos(a)), sn = float(std::sin(a));
        glm::mat3 r(1.0f);  // column-major: r[col][row]
        r[0][0] = c, r[0][1] = sn, r[1][0] = -sn, r[1][1] = c;
        m = r * m;
    }
    if (o.flip) {
        glm::mat3 f(1.0f);
        if (rng.chance(0.5)) f[0][0] = -1.0f;
        if (rng.chance(0.5)) f[1][1] = -1.0f;
        m = f * m;
    }
    if (o.scale) m = float(rng.uniform(o.scale_min, o.scale_max)) * m;
    s.augment = m;

    s.coord.resize(3 * s.size());
    for (size_t i = 0; i < s.size(); ++i) {
        const glm::vec3 p = m * s.position[i];
        for (int a = 0; a < 3; ++a) {
            float v = p[a];
            if (o.jitter) v += float(std::clamp(rng.normal(0.0, o.jitter_sigma), -o.jitter_clip, o.jitter_clip));
            s.coord[3 * i + size_t(a)] = v;
        }
    }
}

bool SampleDrawer::add_click(Sample& s, std::span<const uint8_t> prediction) const {
    std::vector<uint8_t> gt(s.size());
    for (size_t i = 0; i < s.size(); ++i) gt[i] = s.labels[i] != 0;
    const clicks::Clicker3D clicker(s.position);
    std::vector<size_t> clicked;  // sample-local indices of the earlier clicks' Gaussians
    for (const TrainClick& c : s.clicks) {
        const auto it = std::lower_bound(s.gaussians.begin(), s.gaussians.end(), c.gaussian);
        if (it != s.gaussians.end() && *it == c.gaussian) clicked.push_back(size_t(it - s.gaussians.begin()));
    }
    const auto click = clicker.next_click(gt, prediction, clicked);
    if (!click) return false;
    s.clicks.push_back({s.position[click->index], click->positive, s.gaussians[click->index]});
    compose_features(s);
    return true;
}

}  // namespace pg::data::train
