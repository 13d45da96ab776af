// The graph half of the Segmenter: the domain around the objects' ROIs, the kNN graph over it,
// the seeds from the clicks, the network's prior (ptv3+graph), and the walk / forest solves.
#include "engine/segment/segmenter.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <unordered_set>

#include <glm/gtc/quaternion.hpp>

#include "dataset/clicks/point_grid.h"
#include "dataset/semantic/gaussian_features.h"
#include "engine/segment/boundary_contrast.h"
#include "engine/segment/object_splits.h"
#include "engine/vk/context.h"

namespace pg::seg {

namespace {
using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

// Per node the root of its connected component in the kNN graph.
std::vector<uint32_t> component_roots(const KnnGraph& graph, const std::vector<uint32_t>& nbr) {
    const uint32_t n = graph.nodes(), k = graph.k();
    std::vector<uint32_t> parent(n);
    for (uint32_t i = 0; i < n; ++i) parent[i] = i;
    auto find = [&](uint32_t i) {
        while (parent[i] != i) i = parent[i] = parent[parent[i]];
        return i;
    };
    for (uint32_t i = 0; i < n; ++i)
        for (uint32_t t = 0; t < k; ++t)
            if (uint32_t j = nbr[size_t(i) * k + t]; j < n) {
                uint32_t a = find(i), b = find(j);
                if (a != b) parent[std::max(a, b)] = std::min(a, b);
            }
    for (uint32_t i = 0; i < n; ++i) parent[i] = find(i);
    return parent;
}

// Whether a node's component holds a seed or a unary term: the solve reaches it by itself.
std::vector<uint8_t> seeded_components(const std::vector<uint32_t>& root, const WalkProblem& pr) {
    std::vector<uint8_t> root_seeded(root.size(), 0), seeded(root.size(), 0);
    for (size_t i = 0; i < root.size(); ++i)
        if (pr.seed[i] >= 0 || (!pr.gamma.empty() && pr.gamma[i] > 0)) root_seeded[root[i]] = 1;
    for (size_t i = 0; i < root.size(); ++i) seeded[i] = root_seeded[root[i]];
    return seeded;
}

// Per node: whether its connected component holds a seed, a prior or a coarse start (the
// coarse graph, sparser, joins what the fine kNN graph splits); counts the others.
std::vector<uint8_t> reached_components(const std::vector<uint32_t>& root, const WalkProblem& pr,
                                        const LabelColumns& start, GraphReport& report) {
    const uint32_t n = uint32_t(root.size());
    auto find = [&](uint32_t i) { return root[i]; };
    std::vector<uint8_t> root_reached(n, 0), seen(n, 0), reached(n, 0);
    auto started = [&](uint32_t i) { return !start.empty() && start.any_positive(i); };
    for (uint32_t i = 0; i < n; ++i)
        if (pr.seed[i] >= 0 || (!pr.gamma.empty() && pr.gamma[i] > 0) || started(i)) root_reached[find(i)] = 1;
    for (uint32_t i = 0; i < n; ++i) {
        const uint32_t r = find(i);
        reached[i] = root_reached[r];
        if (!reached[i]) {
            ++report.unreached;
            if (!seen[r]) seen[r] = 1, ++report.unreached_components;
        }
    }
    return reached;
}

// What every solver reports of its graph and seeds.
GraphReport graph_report(const KnnGraph& graph, GraphSolver solver, const std::vector<int32_t>& seed) {
    GraphReport report;
    report.solver = solver;
    report.nodes = graph.nodes();
    report.seeds = size_t(std::count_if(seed.begin(), seed.end(), [](int32_t s) { return s >= 0; }));
    report.cell = graph.cell_side();
    report.spacing = graph.median_spacing();
    return report;
}

// Labels 0 background, 1 + j object j; every node outside the ROIs (the margin) seeds the background.
WalkProblem margin_problem(const GraphDomain& d, size_t objects) {
    WalkProblem pr;
    pr.labels = uint32_t(objects + 1);
    pr.seed.assign(d.domain.size(), -1);
    for (size_t i = 0; i < d.domain.size(); ++i)
        if (!d.in_roi[i]) pr.seed[i] = 0;
    return pr;
}

// The forest's seeds: the problem's (clicks, margin), plus the network's confident labels where
// it has a prior (its most likely label at every node with a unary term).
std::vector<int32_t> forest_seeds(const WalkProblem& pr) {
    std::vector<int32_t> seed = pr.seed;
    if (!pr.gamma.empty())
        for (size_t i = 0; i < seed.size(); ++i)
            if (seed[i] < 0 && pr.gamma[i] > 0) {
                const float* q = &pr.prior[i * pr.labels];
                seed[i] = int32_t(std::max_element(q, q + pr.labels) - q);
            }
    return seed;
}

// A node grid's cell before any graph exists: a few nodes per cell on average (the bounding box
// overstates the volume the nodes fill: coarser cells, still exact).
float node_cell(const GraphDomain& d) {
    const glm::vec3 size = glm::max(d.hi - d.lo, glm::vec3(1e-6f));
    return std::cbrt(4.0f * size.x * size.y * size.z / float(d.domain.size()));
}

// Numbers the domain's nodes in Morton order of their position: a node's neighbours get nearby
// numbers, so the passes' gathers stay in cache and a SIMD group's nodes share cells and row
// lengths. Fills node_of (sized to the cloud, -1 outside) and the bounding box.
void order_domain(const data::GaussianCloud& cloud, GraphDomain& d) {
    std::vector<uint32_t>& domain = d.domain;
    d.node_of.assign(cloud.size(), -1);
    if (domain.empty()) return;
    glm::vec3& lo = d.lo;
    glm::vec3& hi = d.hi;
    lo = hi = cloud.mean[domain[0]];
    for (uint32_t g : domain) lo = glm::min(lo, cloud.mean[g]), hi = glm::max(hi, cloud.mean[g]);
    const glm::vec3 to_grid = 1023.0f / glm::max(hi - lo, glm::vec3(1e-12f));
    auto spread = [](uint32_t v) {  // 10 bits -> every third bit
        v = (v | (v << 16)) & 0x030000FFu;
        v = (v | (v << 8)) & 0x0300F00Fu;
        v = (v | (v << 4)) & 0x030C30C3u;
        return (v | (v << 2)) & 0x09249249u;
    };
    std::vector<std::pair<uint32_t, uint32_t>> keyed(domain.size());
    for (size_t s = 0; s < domain.size(); ++s) {
        const glm::uvec3 q(glm::clamp((cloud.mean[domain[s]] - lo) * to_grid, glm::vec3(0.0f), glm::vec3(1023.0f)));
        keyed[s] = {spread(q.x) | spread(q.y) << 1 | spread(q.z) << 2, domain[s]};
    }
    std::sort(keyed.begin(), keyed.end());
    for (size_t s = 0; s < domain.size(); ++s) domain[s] = keyed[s].second, d.node_of[domain[s]] = int32_t(s);
}

// Which nodes the objects' ROIs (as the encoder took them) hold.
void mark_rois(const std::vector<std::vector<uint32_t>>& rois, GraphDomain& d) {
    d.in_base_roi.assign(d.domain.size(), 0);
    for (auto& roi : rois)
        for (uint32_t g : roi)
            if (d.node_of[g] >= 0) d.in_base_roi[size_t(d.node_of[g])] = 1;
    d.in_roi = d.in_base_roi;
}

// The domain's Gaussians: every one within a box's column scaled by `reach` (the largest ROI
// scale) and widened by the margin. Between the boxes and the margin lies the background's
// evidence of last resort: the object-scale rule's ROI. Unordered (graph_domain orders them).
std::vector<uint32_t> domain_gaussians(const data::GaussianCloud& cloud, const ColumnIndex& columns,
                                       const std::vector<RoiBox>& boxes, double margin, double reach) {
    std::vector<uint32_t> domain;
    std::vector<uint8_t> taken(cloud.size(), 0);
    const double factor = reach * (1 + 2 * margin);
    // Each box's column from the index's candidates.
    for (const RoiBox& box : boxes)
        for (uint32_t i : columns.candidates(box.centre, factor * box.length / 2, factor * box.width / 2, false))
            if (!taken[i] && in_column(box, glm::dvec3(cloud.mean[i]), factor)) {
                taken[i] = 1;
                domain.push_back(i);
            }
    return domain;
}

// The domain over those Gaussians: numbered, and the objects' ROIs marked.
GraphDomain graph_domain(const data::GaussianCloud& cloud, std::vector<uint32_t> gaussians,
                         const std::vector<std::vector<uint32_t>>& rois) {
    GraphDomain d;
    d.domain = std::move(gaussians);
    order_domain(cloud, d);
    mark_rois(rois, d);
    return d;
}

// Whether `p` lies in any of the boxes' columns scaled by `factor`.
bool in_columns(const std::vector<RoiBox>& boxes, const glm::dvec3& p, double factor) {
    return std::any_of(boxes.begin(), boxes.end(), [&](const RoiBox& box) { return in_column(box, p, factor); });
}

// The nodes inside the boxes scaled by `factor` (scale 1: the ROIs as the encoder took them).
void scale_rois(const data::GaussianCloud& cloud, const std::vector<RoiBox>& boxes, double factor, GraphDomain& d) {
    d.in_roi = d.in_base_roi;
    if (factor == 1.0) return;
    for (size_t i = 0; i < d.domain.size(); ++i) {
        const bool inside = in_columns(boxes, glm::dvec3(cloud.mean[d.domain[i]]), factor);
        d.in_roi[i] = factor > 1.0 ? d.in_base_roi[i] || inside : d.in_base_roi[i] && inside;
    }
}

// Per object, the box of its coarse support (`points`: where the coarse walk gives it at least
// SegmentOptions::graph_focus_support, or its coarse label) in its ROI's axes: from the `tail` to
// the 1 - `tail` quantile along each (a stray floater does not stretch it), holding the object's
// positive clicks, grown by `grow` of its extent per side and kept within the ROI column scaled
// by `reach`. An object with no support keeps its ROI.
std::vector<RoiBox> answer_boxes(const std::vector<ObjectResult*>& objects, const std::vector<std::vector<glm::vec3>>& points,
                                 double tail, double grow, double reach) {
    const size_t m = objects.size();
    std::vector<std::vector<double>> along(m), across(m);
    for (size_t j = 0; j < m; ++j)
        for (const glm::vec3& p : points[j]) {
            const RoiBox& r = objects[j]->roi;
            const glm::dvec3 rel = glm::dvec3(p) - r.centre;
            along[j].push_back(glm::dot(rel, r.length_axis));
            across[j].push_back(glm::dot(rel, r.width_axis));
        }
    auto quantile = [](std::vector<double>& v, double q) {
        auto it = v.begin() + std::ptrdiff_t(std::min(v.size() - 1, size_t(q * double(v.size()))));
        std::nth_element(v.begin(), it, v.end());
        return *it;
    };
    std::vector<RoiBox> boxes(m);
    for (size_t j = 0; j < m; ++j) {
        const RoiBox& r = objects[j]->roi;
        boxes[j] = r;
        if (along[j].empty()) continue;
        double l0 = quantile(along[j], tail), l1 = quantile(along[j], 1 - tail);
        double w0 = quantile(across[j], tail), w1 = quantile(across[j], 1 - tail);
        for (const Anchor& a : objects[j]->anchors)
            if (a.positive && a.gaussian >= 0) {
                const double u = glm::dot(a.position - r.centre, r.length_axis), v = glm::dot(a.position - r.centre, r.width_axis);
                l0 = std::min(l0, u), l1 = std::max(l1, u), w0 = std::min(w0, v), w1 = std::max(w1, v);
            }
        const double gl = grow * (l1 - l0), gw = grow * (w1 - w0);
        const double half_l = reach * r.length / 2, half_w = reach * r.width / 2;
        l0 = std::max(l0 - gl, -half_l), l1 = std::min(l1 + gl, half_l);
        w0 = std::max(w0 - gw, -half_w), w1 = std::min(w1 + gw, half_w);
        boxes[j].centre = r.centre + 0.5 * (l0 + l1) * r.length_axis + 0.5 * (w0 + w1) * r.width_axis;
        boxes[j].length = std::max(l1 - l0, 1e-9);
        boxes[j].width = std::max(w1 - w0, 1e-9);
    }
    return boxes;
}

// A focused domain over `gaussians`: numbered, its ROIs the boxes (scale 1).
GraphDomain focused_domain(const data::GaussianCloud& cloud, std::vector<uint32_t> gaussians,
                           const std::vector<RoiBox>& boxes) {
    GraphDomain d;
    d.domain = std::move(gaussians);
    order_domain(cloud, d);
    d.in_base_roi.resize(d.domain.size());
    for (size_t i = 0; i < d.domain.size(); ++i) d.in_base_roi[i] = in_columns(boxes, glm::dvec3(cloud.mean[d.domain[i]]), 1.0);
    d.in_roi = d.in_base_roi;
    return d;
}

// The ROI scales, largest first (at least one).
std::vector<double> roi_scales(const SegmentOptions& o) {
    std::vector<double> f;
    for (double x : o.graph_scales)
        if (x > 0 && std::find(f.begin(), f.end(), x) == f.end()) f.push_back(x);
    if (f.empty()) f.push_back(1.0);
    std::sort(f.begin(), f.end(), std::greater<>());
    return f;
}

// walk+forest: the walk's label stands where its share reaches `sure`; from there (and the
// seeds) the forest's widest paths settle the rest, object or background (the walk's pull
// towards the label with the most seeds takes parts of objects to the background), and where
// both name an object, the walk's. Per node: label (-1: none) and confidence (the walk's share
// where it agrees, else 1/2).
struct NodeLabels {
    std::vector<int32_t> label;
    std::vector<float> confidence;
    uint32_t rounds = 0;
    size_t free_nodes = 0;
};

// ptv3+graph's choice per object between the answer solved with the network's prior and the
// graph alone's, by their boundary contrasts: the network's stands where it cuts the graph no
// harder, or, where the graph's answer cuts nothing at all (whole components, no boundary
// evidence: seed 5153's residences lost houses to their cars and trees this way), where its cut
// is clean (SegmentOptions::unary_clean).
bool network_stands(double network, double graph, const SegmentOptions& o) {
    return network <= graph || (graph == 0 && network < o.unary_clean);
}

NodeLabels walk_then_forest(SeededForest& forest, const KnnGraph& graph, std::vector<int32_t> seed, const WalkLabels& w,
                            float sure, const ForestOptions& fo, const std::vector<uint8_t>* seeded = nullptr) {
    for (size_t i = 0; i < seed.size(); ++i)
        if (seed[i] < 0 && w.arg[i] >= 0 && w.share[i] >= sure) seed[i] = w.arg[i];
    // `seeded`: per node whether its component holds a seed. No widest path reaches the others:
    // they keep the walk's (bridged) label, or the background's, and are not the forest's to
    // flood (many of them would send it to the GPU's rounds for nothing).
    if (seeded)
        for (size_t i = 0; i < seed.size(); ++i)
            if (!(*seeded)[i] && seed[i] < 0) seed[i] = std::max(w.arg[i], 0);
    auto f = forest.solve(graph, seed, fo);
    NodeLabels out{std::move(f.label), std::vector<float>(seed.size(), 0.0f), f.rounds, f.free_nodes};
    for (size_t i = 0; i < seed.size(); ++i) {
        // A component the forest cannot reach (no seed, an answer bridged over) keeps the walk's label.
        if (out.label[i] < 0) out.label[i] = w.arg[i];
        // Between two objects the walk's label stands: neighbours that look alike (terraced houses
        // sharing a wall and a colour scheme) tie on widest paths, which the edge order then
        // decides, while the walk splits them by how far each click is (fresh seeds 6201, 6202,
        // 7301, 8811: residence 3D IoU +5.2 to +8.3 points, desk -3.2 to +1.9, their sum -0.1).
        if (w.arg[i] > 0 && out.label[i] > 0) out.label[i] = w.arg[i];
        out.confidence[i] = w.arg[i] == out.label[i] ? w.share[i] : 0.5f;
    }
    return out;
}

}  // namespace

Segmenter::CoarseSolve Segmenter::coarse_solve(const SegmentOptions& o, const std::vector<uint32_t>& domain,
                                               const WalkProblem& fine, bool spread_clicks, bool scene_order,
                                               bool walk, bool carry) {
    // The same problem on every coarse_stride-th node (and every object's click): a graph
    // with fewer hops across, solved in a fraction of the fine solve's iterations.
    // `scene_order`: every stride-th in scene order; else in the nodes' Morton order, a uniform
    // spatial subsample that keeps sparse and thin parts and thins dense ones. The fine solve's
    // start takes scene order: Morton order labels its unseeded components differently (seeds
    // 909 and 3131: 4 of 6 suite means 0.1-1.6 points lower).
    const uint32_t nodes = uint32_t(domain.size()), labels = fine.labels;
    CoarseSolve cs;
    std::vector<uint32_t> by_id(nodes), coarse_domain;
    for (uint32_t i = 0; i < nodes; ++i) by_id[i] = i;
    if (scene_order)
        std::sort(by_id.begin(), by_id.end(), [&](uint32_t a, uint32_t b) { return domain[a] < domain[b]; });
    for (uint32_t r = 0; r < nodes; ++r) {
        const uint32_t i = by_id[r];
        if (r % o.coarse_stride == 0 || fine.seed[i] > 0) {
            cs.members.push_back(i);
            coarse_domain.push_back(domain[i]);
        }
    }
    coarse_graph_.build(scene_, cloud_, coarse_domain, o.graph_options);
    WalkProblem cp;
    cp.labels = labels;
    const uint32_t m = uint32_t(cs.members.size());
    cp.seed.resize(m);
    for (uint32_t c = 0; c < m; ++c) cp.seed[c] = fine.seed[cs.members[c]];
    if (spread_clicks) {
        // Clicks seeded at one node each (no fine graph yet): their coarse neighbours too, as
        // seed_clicks does on the fine graph (a lone seed node may be weakly attached).
        const auto& cn = coarse_graph_.host_neighbours();
        const uint32_t ck = coarse_graph_.k();
        std::vector<int32_t> spread = cp.seed;
        for (uint32_t c = 0; c < m; ++c)
            if (cp.seed[c] > 0)
                for (uint32_t t = 0; t < ck; ++t)
                    if (uint32_t q = cn[size_t(c) * ck + t]; q < m && spread[q] < 0) spread[q] = cp.seed[c];
        cp.seed = std::move(spread);
    }
    if (!fine.gamma.empty()) {
        auto degree = vk::download_vector<float>(ctx_, coarse_graph_.degree_buffer(), m);
        cp.gamma.resize(m);
        cp.prior.resize(size_t(m) * labels);
        for (uint32_t c = 0; c < m; ++c) {
            cp.gamma[c] = fine.gamma[cs.members[c]] > 0 ? o.unary * degree[c] : 0.0f;
            std::copy_n(&fine.prior[size_t(cs.members[c]) * labels], labels, &cp.prior[size_t(c) * labels]);
        }
    }
    if (walk) cs.walk = walker_.solve(coarse_graph_, cp, cs.x, o.walk);
    cs.problem = std::move(cp);
    if (!carry) return cs;
    // Each fine node's nearest coarse node.
    std::vector<glm::vec3> positions(m);
    for (uint32_t c = 0; c < m; ++c) positions[c] = cloud_.mean[coarse_domain[c]];
    std::vector<uint32_t> all(m);
    for (uint32_t c = 0; c < m; ++c) all[c] = c;
    data::clicks::PointGrid grid(positions, all, std::max(coarse_graph_.cell_side(), 1e-6f));
    cs.nearest.assign(nodes, kNoCoarse);
    for (uint32_t i = 0; i < nodes; ++i) grid.nearest(cloud_.mean[domain[i]], 0xFFFFFFFFu, 64, &cs.nearest[i]);
    return cs;
}

LabelColumns Segmenter::coarse_start(const SegmentOptions& o, const std::vector<uint32_t>& domain,
                                     const WalkProblem& fine) {
    // Each fine node starts from its nearest coarse node's answer, so the fine solve only sharpens it.
    const CoarseSolve cs = coarse_solve(o, domain, fine, false, true);
    LabelColumns start(uint32_t(domain.size()), fine.labels, cs.x.sparse());
    for (uint32_t i = 0; i < domain.size(); ++i)
        if (cs.nearest[i] != kNoCoarse) start.copy_node(i, cs.x, cs.nearest[i]);
    return start;
}

uint64_t Segmenter::graph_capacity(const SegmentOptions& o) const {
    const uint64_t capacity = KnnGraph::max_nodes(ctx_, o.graph_options.k);
    return o.graph_max_nodes ? std::min(capacity, o.graph_max_nodes) : capacity;
}

void Segmenter::solve_graph(const SegmentOptions& o, std::vector<ObjectResult*>& objects,
                            const std::vector<std::vector<uint32_t>>& rois,
                            const std::vector<std::vector<float>>& probabilities, SegmentResult& result) {
    std::vector<double> scales = roi_scales(o);
    double margin = o.graph_margin;
    const uint64_t capacity = graph_capacity(o);
    const uint64_t budget = o.graph_budget ? std::min(capacity, o.graph_budget) : capacity;
    auto t0 = Clock::now();
    // The domain follows from the objects' ROI boxes and the options alone: a further click on
    // the same objects (the ROI comes from each object's first positive click) takes the last
    // one as it is (6 M tiled guitar: about 0.1 s a click of gathering and numbering).
    // A focused domain also follows from what makes the coarse answer.
    const GraphOptions& go = o.graph_options;
    std::vector<double> key{double(objects.size()), margin, double(capacity), double(budget), double(o.graph_focus),
                            o.graph_focus_grow, double(o.coarse_stride), double(int(o.solver)), o.walk_sure,
                            double(o.object_splits.clean), double(o.object_splits.ratio), double(o.object_splits.keep),
                            double(o.walk.tolerance), double(int(o.walk.preconditioner)), double(go.k), go.cell,
                            double(go.shells), go.colour, go.normal, go.distance, go.opacity};
    key.insert(key.end(), scales.begin(), scales.end());
    for (const auto* obj : objects) {
        const RoiBox& r = obj->roi;
        for (const glm::dvec3& v : {r.centre, r.length_axis, r.width_axis}) key.insert(key.end(), {v.x, v.y, v.z});
        key.insert(key.end(), {r.length, r.width});
    }
    // A focused domain holds each object's answer as the coarse solve found it: a positive click
    // outside it asks for a new one.
    bool clicks_inside = true;
    if (!domain_key_.empty() && domain_focused_)
        for (size_t j = 0; j < objects.size() && j < domain_boxes_.size(); ++j)
            for (const Anchor& a : objects[j]->anchors)
                if (a.positive && a.gaussian >= 0 && !in_column(domain_boxes_[j], a.position, 1.0)) clicks_inside = false;
    bool coarse_given = false;  // the focus handed on_coarse its answer
    if (key != domain_key_ || !clicks_inside) {
        domain_key_.clear();
        const ColumnIndex& index = columns(objects.front()->roi);
        std::vector<RoiBox> boxes;
        for (const auto* obj : objects) boxes.push_back(obj->roi);
        auto gaussians = [&] { return domain_gaussians(cloud_, index, boxes, margin, std::max(scales.front(), 1.0)); };
        std::vector<uint32_t> in_domain = gaussians();
        // Past the graph's limit or the click's budget, the margin narrows first (it costs least),
        // then the larger scales go: every node of a smaller domain beats every n-th node of a larger
        // one (2 M tiled guitar, lavapipe: a further click 10.2 s decimated at scale 2, 1.5 s at scale
        // 1 alone). Only the domain taken is numbered.
        if (in_domain.size() > budget && margin > kNarrowMargin) {
            margin = kNarrowMargin;
            in_domain = gaussians();
        }
        while (in_domain.size() > budget && scales.size() > 1) {
            scales.erase(scales.begin());
            in_domain = gaussians();
        }
        domain_ = graph_domain(cloud_, std::move(in_domain), rois);
        domain_focused_ = false;
        // Past graph_focus nodes the click's cost would follow the scene: the coarse answer over
        // this domain (at its largest ROI scale) bounds each object, and the fine graph covers the
        // objects' answer boxes and the same margin around them, seeded as background.
        // The boxes need the coarse answer's extent, not its detail: twice the coarse stride.
        SegmentOptions fo = o;
        fo.coarse_stride = 2 * o.coarse_stride;
        if (o.graph_focus && domain_.domain.size() > o.graph_focus && domain_.domain.size() <= capacity &&
            coarse_allowed(fo, domain_.domain.size())) {
            t0 = Clock::now();
            const double reach = std::max(scales.front(), 1.0);
            scale_rois(cloud_, boxes, reach, domain_);
            // The coarse answer carried to every node only for a viewer that shows it.
            const bool shown = o.on_coarse && o.graph == GraphUse::Alone;
            std::vector<std::vector<glm::vec3>> support;
            const auto [label, confidence] = coarse_labels(fo, objects, domain_, &support, shown);
            if (shown) {
                coarse_answer(o, objects, domain_.domain, label, confidence, result);
                coarse_given = true;
            }
            std::vector<RoiBox> focus = answer_boxes(objects, support, 0.01, o.graph_focus_grow, reach);
            std::vector<uint32_t> focused = domain_gaussians(cloud_, index, focus, margin, 1.0);
            if (focused.size() * 4 < domain_.domain.size() * 3) {
                domain_ = focused_domain(cloud_, std::move(focused), focus);
                boxes = std::move(focus);
                scales = {1.0};
                domain_focused_ = true;
            } else {
                domain_.in_roi = domain_.in_base_roi;
            }
            result.stage_ms["graph focus"] += ms_since(t0);
        }
        domain_boxes_ = std::move(boxes);
        domain_margin_ = margin;
        domain_scales_ = scales;
        domain_key_ = std::move(key);
    }
    margin = domain_margin_;
    scales = domain_scales_;
    GraphDomain& d = domain_;
    d.in_roi = d.in_base_roi;  // as graph_domain left it (the last solve scaled it)
    result.stage_ms["graph domain"] += ms_since(t0);
    if (d.domain.size() > capacity) {
        solve_decimated(o, objects, rois, probabilities, d, capacity, result);
        if (result.graph) result.graph->margin = margin;
        return;
    }
    const bool rebuild = d.domain != graph_domain_ || !(o.graph_options == graph_built_with_);
    // A cold solve's coarse answer, if wanted, comes first (then not again in solve_walk).
    SegmentOptions rest = o;
    if (coarse_given || (rebuild && early_coarse_answer(o, objects, d, result))) rest.on_coarse = nullptr;
    stop_if_cancelled(o.cancel);
    t0 = Clock::now();
    if (rebuild) {
        drop_graph();
        graph_.build(scene_, cloud_, d.domain, o.graph_options);
        graph_domain_ = d.domain;
        graph_built_with_ = o.graph_options;
        for (const auto& t : graph_.timings()) result.stage_ms["graph build gpu"] += t.ms;
    }
    if (!nodes_) nodes_.emplace(cloud_, d, true);
    result.stage_ms["graph build"] += ms_since(t0);

    const uint32_t nodes = uint32_t(d.domain.size());
    const auto& nbr = graph_.host_neighbours();
    const bool unary = o.graph == GraphUse::Unary;
    // Each object's answer from the graph alone at each scale, chosen between scales by boundary
    // contrast. With the network (ptv3+graph), one more solve at the largest scale with its prior
    // (its cuts make every answer's contrast high, so it takes no part in the choice between
    // scales): per object it stands where its boundary cuts the graph no harder than the graph's
    // answer does, or cleanly where that answer cuts nothing (network_stands). The network is confidently wrong on parts of objects unlike its training data
    // (a car's far end: fresh seed 6201, vehicles 3D IoU 95.2 with the prior always, 97.5 with
    // the rule, the graph alone 97.5) and right about what the graph cannot see (a tree against a
    // house's dark roof: residence 87.5, the graph alone 83.9).
    std::vector<std::vector<std::pair<uint32_t, float>>> best(objects.size());
    std::vector<double> best_contrast(objects.size(), 0.0);
    auto contrasts = [&]() {
        std::vector<int32_t> label(nodes, 0);
        for (size_t j = 0; j < objects.size(); ++j)
            for (auto [g, p] : objects[j]->claims) label[size_t(d.node_of[g])] = int32_t(j + 1);
        return boundary_contrast(graph_.host_adjacency(), label, uint32_t(objects.size() + 1));
    };
    uint32_t widened = 0;  // the same clicks at every scale
    // One solve with the margin's background seeds at ROI `scale` (and the network's prior if
    // asked): the objects' claims. Each kind of solve warm-starts only from its own last answer
    // (a further click on this graph), never from another scale's or from the prior's.
    auto solve_at = [&](double scale, bool prior) {
        stop_if_cancelled(o.cancel);
        t0 = Clock::now();
        scale_rois(cloud_, domain_boxes_, scale, d);
        WalkProblem pr = margin_problem(d, objects.size());
        widened = seed_clicks(objects, d, &nbr, *nodes_, graph_.cell_side(), pr, &graph_.host_adjacency());
        if (prior) network_prior(o, objects, rois, probabilities, d, &graph_.host_adjacency().degree, pr);
        result.stage_ms["graph seeds"] += ms_since(t0);
        for (auto* obj : objects) obj->claims.clear();
        WarmStart& warm = warm_[prior ? -scale : scale];
        if (o.solver == GraphSolver::Forest) solve_forest(o, objects, d.domain, nbr, pr, warm, result);
        else solve_walk(rest, objects, d.domain, nbr, pr, warm, result);
        rest.on_coarse = nullptr;
        result.stage_ms["graph solve"] += ms_since(t0);
    };
    for (size_t f = 0; f < scales.size(); ++f) {
        solve_at(scales[f], false);
        if (scales.size() == 1 && !unary) {
            for (size_t j = 0; j < objects.size(); ++j) objects[j]->graph_scale = scales[f], best[j] = std::move(objects[j]->claims);
            break;
        }
        // Per object, a smaller ROI's answer stands unless the larger one's boundary is far
        // weaker: a background seed on the object cuts it through strong edges (a car longer
        // than its ROI), while a larger ROI can let an object flood a surface it rests on.
        t0 = Clock::now();
        const auto contrast = contrasts();
        // Whether every answer lies within its ROI at the next smaller scale (all but 1 % of it):
        // then that scale's margin could only cut the answers further (on the sample and the real
        // guitar both scales gave every object the same answer), so it is not solved.
        bool fits = f + 1 < scales.size();
        for (size_t j = 0; j < objects.size(); ++j) {
            ObjectResult& obj = *objects[j];
            obj.scale_answers.emplace_back(scales[f], contrast[j + 1], obj.claims.size());
            if (fits) {
                size_t outside = 0;
                for (auto [g, p] : obj.claims) outside += !in_column(domain_boxes_[j], glm::dvec3(cloud_.mean[g]), scales[f + 1]);
                fits = outside * 100 <= obj.claims.size();
            }
            if (obj.claims.empty()) continue;  // no answer never wins
            if (f == 0 || best[j].empty() || !(best_contrast[j] < o.graph_scale_ratio * contrast[j + 1])) {
                best[j] = std::move(obj.claims);
                best_contrast[j] = contrast[j + 1];
                obj.graph_scale = scales[f];
            }
        }
        result.stage_ms["graph scales"] += ms_since(t0);
        if (fits) break;
    }
    // Where two of the graph's answers meet, the widest paths' split may stand (settle_splits),
    // before the network's answers are judged against them: the walk's cut through the real
    // guitar's stand (contrast 1.2) let the network's answers (0.1-0.25, half the guitar) stand.
    uint32_t splits = 0;
    const bool split = o.solver != GraphSolver::Walk && objects.size() > 1;
    if (split) {
        t0 = Clock::now();
        for (size_t j = 0; j < objects.size(); ++j)
            objects[j]->claims = std::move(best[j]), objects[j]->boundary_contrast = best_contrast[j];
        splits = settle_splits(o, objects, d, nbr);
        for (size_t j = 0; j < objects.size(); ++j)
            best[j] = std::move(objects[j]->claims), best_contrast[j] = objects[j]->boundary_contrast;
        result.stage_ms["graph splits"] += ms_since(t0);
    }
    if (unary) {
        solve_at(scales.front(), true);
        t0 = Clock::now();
        const auto contrast = contrasts();
        for (size_t j = 0; j < objects.size(); ++j) {
            ObjectResult& obj = *objects[j];
            obj.network_answer = !obj.claims.empty() && (best[j].empty() || network_stands(contrast[j + 1], best_contrast[j], o));
            if (obj.network_answer) {
                best[j] = std::move(obj.claims);
                best_contrast[j] = contrast[j + 1];
            }
        }
        result.stage_ms["graph scales"] += ms_since(t0);
    }
    for (size_t j = 0; j < objects.size(); ++j) {
        objects[j]->claims = std::move(best[j]);
        objects[j]->boundary_contrast = best_contrast[j];
    }
    if (split && unary) {  // the network's answers against the others
        t0 = Clock::now();
        splits += settle_splits(o, objects, d, nbr);
        result.stage_ms["graph splits"] += ms_since(t0);
    }
    if (result.graph) {
        result.graph->domain = d.domain.size(), result.graph->margin = margin, result.graph->focused = domain_focused_;
        result.graph->widened_clicks = widened, result.graph->object_splits = splits;
    }
}

uint32_t Segmenter::settle_splits(const SegmentOptions& o, std::vector<ObjectResult*>& objects, const GraphDomain& d,
                                  const std::vector<uint32_t>& nbr) {
    // The answers as they stand (a Gaussian claimed twice: the higher claim, as in labelling),
    // then where two of them meet, the widest paths' split from the clicks where it is far
    // cleaner than theirs (object_splits.h). After the choice between scales, not inside each
    // solve: a cleaner split at the larger scale would make a flooded answer look clean there.
    const uint32_t nodes = uint32_t(d.domain.size());
    std::vector<int32_t> label(nodes, 0);
    std::vector<float> best(nodes, -1.0f);
    for (size_t j = 0; j < objects.size(); ++j)
        for (auto [g, p] : objects[j]->claims)
            if (const int32_t i = d.node_of[g]; i >= 0 && p > best[size_t(i)]) best[size_t(i)] = p, label[size_t(i)] = int32_t(j + 1);
    WalkProblem clicks;
    clicks.seed.assign(nodes, -1);
    seed_clicks(objects, d, &nbr, *nodes_, graph_.cell_side(), clicks, &graph_.host_adjacency());
    std::vector<uint8_t> changed(nodes, 0);
    const std::vector<int32_t> before = label;
    const uint32_t taken = settle_object_splits(graph_.host_adjacency(), clicks.seed, label, o.object_splits, &changed);
    if (!taken) return 0;
    // The two objects of each split report their new answer's contrast.
    const auto contrast = boundary_contrast(graph_.host_adjacency(), label, uint32_t(objects.size() + 1));
    for (uint32_t i = 0; i < nodes; ++i)
        if (changed[i])
            for (int32_t l : {before[i], label[i]})
                if (l > 0) objects[size_t(l) - 1]->boundary_contrast = contrast[size_t(l)];
    // A moved Gaussian leaves every other claim and keeps the probability it had.
    for (size_t j = 0; j < objects.size(); ++j) {
        auto& claims = objects[j]->claims;
        std::erase_if(claims, [&](const std::pair<uint32_t, float>& c) {
            const int32_t i = d.node_of[c.first];
            return i >= 0 && changed[size_t(i)];
        });
    }
    for (uint32_t i = 0; i < nodes; ++i)
        if (changed[i] && label[i] > 0) objects[size_t(label[i]) - 1]->claims.push_back({d.domain[i], best[i]});
    return taken;
}

void Segmenter::drop_graph() {
    graph_domain_.clear();
    nodes_.reset();
    warm_.clear();
    roots_.clear();
    widened_.clear();
    bridges_.clear();
}

void Segmenter::forget_domain() {
    domain_key_.clear();
    drop_graph();
}

void Segmenter::solve_decimated(const SegmentOptions& o, std::vector<ObjectResult*>& objects,
                                const std::vector<std::vector<uint32_t>>& rois,
                                const std::vector<std::vector<float>>& probabilities, const GraphDomain& d,
                                uint64_t capacity, SegmentResult& result) {
    // The domain's graph would pass the device's largest binding. The same problem on a uniform
    // spatial subsample that fits (every stride-th node in Morton order, which keeps thin and
    // sparse parts, plus every clicked node), each node labelled as its nearest subsample node:
    // the coarse answer's rule, with the smallest stride that fits.
    SegmentOptions rest = o;
    if (early_coarse_answer(o, objects, d, result)) rest.on_coarse = nullptr;
    stop_if_cancelled(o.cancel);
    drop_graph();  // graph_ does not hold this domain: the next click builds again

    auto t0 = Clock::now();
    const uint32_t nodes = uint32_t(d.domain.size());
    WalkProblem pr = margin_problem(d, objects.size());
    seed_clicks(objects, d, nullptr, DomainNodes(cloud_, d, false), node_cell(d), pr);
    if (o.graph == GraphUse::Unary) network_prior(o, objects, rois, probabilities, d, nullptr, pr);
    const uint64_t clicked = uint64_t(std::count_if(pr.seed.begin(), pr.seed.end(), [](int32_t v) { return v > 0; }));
    if (clicked + 64 >= capacity)
        throw std::runtime_error("graph: " + std::to_string(clicked) + " clicked nodes leave no room in a graph of at most " +
                                 std::to_string(capacity) + " nodes");
    rest.coarse_stride = uint32_t(std::max<uint64_t>(2, (nodes + capacity - clicked - 1) / (capacity - clicked)));
    result.stage_ms["graph seeds"] += ms_since(t0);

    t0 = Clock::now();
    const bool walk = o.solver != GraphSolver::Forest;
    CoarseSolve cs = coarse_solve(rest, d.domain, pr, true, false, walk);  // the subsample's graph, and its walk
    const uint32_t m = uint32_t(cs.members.size());
    GraphReport report = graph_report(coarse_graph_, o.solver, cs.problem.seed);
    const auto root = component_roots(coarse_graph_, coarse_graph_.host_neighbours());
    // The subsample's labels for a problem (its walk's answer in x where walked), and which of its
    // nodes a seed or prior reaches; the solve's figures go to `rep`.
    struct Subsample {
        NodeLabels labels;
        std::vector<uint8_t> reached;
    };
    auto label_subsample = [&](const WalkProblem& problem, const LabelColumns& x, GraphReport& rep) {
        Subsample out;
        if (walk) {
            out.reached = reached_components(root, problem, LabelColumns(), rep);
            const WalkLabels w = x.most_likely(&out.reached);
            out.labels = {w.arg, w.share, 0, 0};
            if (o.solver == GraphSolver::WalkForest)
                out.labels = walk_then_forest(forest_, coarse_graph_, problem.seed, w, o.walk_sure, o.forest);
            rep.rounds = out.labels.rounds;
            rep.forest_free = out.labels.free_nodes;
        } else {
            WalkProblem seeds_only;
            seeds_only.labels = problem.labels;
            seeds_only.seed = forest_seeds(problem);
            out.reached = reached_components(root, seeds_only, LabelColumns(), rep);
            auto forest = forest_.solve(coarse_graph_, seeds_only.seed, o.forest);
            out.labels.label = std::move(forest.label);
            out.labels.confidence.assign(m, 1.0f);
            rep.rounds = forest.rounds;
            rep.forest_free = forest.free_nodes;
            rep.residual = forest.converged ? 0.0 : 1.0;
        }
        return out;
    };
    if (walk) {
        report.iterations = cs.walk.iterations;
        report.levels = cs.walk.levels;
        report.jacobi_retries = cs.walk.jacobi_retries;
        report.range_retries = cs.walk.range_retries;
        report.out_of_range = cs.walk.out_of_range;
        report.residual = cs.walk.residual;
    }
    const Subsample solved = label_subsample(cs.problem, cs.x, report);
    // ptv3+graph, as solve_graph has it (network_stands), on the subsample's graph.
    std::vector<const Subsample*> answer(objects.size(), &solved);
    Subsample bare;
    if (o.graph == GraphUse::Unary) {
        WalkProblem alone = cs.problem;
        alone.gamma.clear();
        alone.prior.clear();
        LabelColumns x;
        if (walk) walker_.solve(coarse_graph_, alone, x, o.walk);
        GraphReport scratch;
        bare = label_subsample(alone, x, scratch);
        const uint32_t labels_n = uint32_t(objects.size() + 1);
        const auto with_prior = boundary_contrast(coarse_graph_.host_adjacency(), solved.labels.label, labels_n);
        const auto without = boundary_contrast(coarse_graph_.host_adjacency(), bare.labels.label, labels_n);
        auto present = [&](const Subsample& sub) {  // per label: whether some node has it
            std::vector<uint8_t> has(labels_n, 0);
            for (int32_t l : sub.labels.label)
                if (l > 0 && uint32_t(l) < labels_n) has[size_t(l)] = 1;
            return has;
        };
        const auto in_solved = present(solved), in_bare = present(bare);
        for (size_t j = 0; j < objects.size(); ++j) {
            ObjectResult& obj = *objects[j];
            obj.network_answer = in_solved[j + 1] && (!in_bare[j + 1] || network_stands(with_prior[j + 1], without[j + 1], o));
            if (!obj.network_answer) answer[j] = &bare;
            obj.boundary_contrast = obj.network_answer ? with_prior[j + 1] : without[j + 1];
        }
    }
    // Every domain node as its nearest subsample node. (Choosing among that node and its graph
    // neighbours by colour and distance moved the sample's 3D IoU at stride 3 by 0.03 points: what
    // a stride loses is the subsample's weaker boundaries, not the carry.) `unreached` counts
    // Gaussians.
    report.unreached = 0;
    for (uint32_t i = 0; i < nodes; ++i) {
        const uint32_t c = cs.nearest[i];
        if (c == kNoCoarse || !solved.reached[c]) {
            ++report.unreached;
            continue;
        }
        // Each object claims the node where the answer it took labels it so.
        for (const Subsample* sub : {&solved, static_cast<const Subsample*>(&bare)}) {
            if (sub->reached.empty() || !sub->reached[c]) continue;
            const int32_t l = sub->labels.label[c];
            if (l > 0 && answer[size_t(l) - 1] == sub) objects[size_t(l) - 1]->claims.push_back({d.domain[i], sub->labels.confidence[c]});
        }
    }
    report.stride = rest.coarse_stride;
    report.domain = nodes;
    result.graph = report;
    result.stage_ms["graph solve"] += ms_since(t0);
}

DomainNodes::DomainNodes(const data::GaussianCloud& cloud, const GraphDomain& d, bool with_appearance)
    : position(d.domain.size()) {
    for (uint32_t i = 0; i < position.size(); ++i) position[i] = cloud.mean[d.domain[i]];
    // Neither group reads the up axis.
    if (with_appearance) appearance = data::semantic::raw_gaussian_features(cloud, d.domain, {"rgb", "opacity"}, {0, 0, 1});
}

std::vector<uint32_t> DomainNodes::nearest(const std::vector<glm::vec3>& points, float cell) const {
    std::vector<uint32_t> out(points.size(), 0);
    if (position.empty() || points.empty()) return out;
    // A scan costs nodes x points: for a few clicks less than building a hash grid over the nodes.
    if (points.size() <= 16) {
        std::vector<double> best(points.size(), 1e300);
        for (uint32_t i = 0; i < position.size(); ++i) {
            const glm::dvec3 p(position[i]);
            for (size_t c = 0; c < points.size(); ++c) {
                const glm::dvec3 e = p - glm::dvec3(points[c]);
                if (const double d2 = glm::dot(e, e); d2 < best[c]) best[c] = d2, out[c] = i;
            }
        }
        return out;
    }
    std::vector<uint32_t> all(position.size());
    for (uint32_t i = 0; i < all.size(); ++i) all[i] = i;
    const data::clicks::PointGrid grid(position, all, std::max(cell, 1e-6f));
    for (size_t c = 0; c < points.size(); ++c) grid.nearest(points[c], 0xFFFFFFFFu, 1 << 20, &out[c]);
    return out;
}

uint32_t Segmenter::seed_clicks(const std::vector<ObjectResult*>& objects, const GraphDomain& d,
                                const std::vector<uint32_t>* nbr, const DomainNodes& domain_nodes, float cell,
                                WalkProblem& pr, const HostAdjacency* adjacency) const {
    const uint32_t nodes = uint32_t(d.domain.size());
    const std::vector<int32_t>& node_of = d.node_of;
    // A click seeds the Gaussian whose centre is nearest to its 3D point and that Gaussian's graph
    // neighbours (about one spacing around it). The anchor itself may be a large Gaussian whose
    // footprint covers the pixel while its centre lies a metre away, or a faint one whose every
    // edge is weak; a seed like that loses its object in the forest. Seeds win over neighbours.
    const uint32_t k = graph_.k();
    struct ClickSeed {
        uint32_t node;
        int32_t label;
    };
    std::vector<ClickSeed> clicks;
    std::vector<glm::vec3> points;
    std::vector<int32_t> anchors;  // the clicked Gaussians
    uint32_t widened = 0;
    // The clicked Gaussian's extent: its 3-sigma ellipsoid (axes no thinner than the graph's cell),
    // as centre and a map to the unit ball.
    std::vector<std::pair<glm::vec3, glm::mat3>> extent;
    for (size_t j = 0; j < objects.size(); ++j)
        for (auto& a : objects[j]->anchors) {
            if (a.gaussian < 0 || node_of[size_t(a.gaussian)] < 0) continue;
            clicks.push_back({0, a.positive ? int32_t(j + 1) : 0});
            points.push_back(glm::vec3(a.position));
            anchors.push_back(a.gaussian);
            const glm::vec4 q = cloud_.rotation[size_t(a.gaussian)];
            const glm::mat3 rot = glm::mat3_cast(glm::normalize(glm::quat(q.x, q.y, q.z, q.w)));
            const glm::vec3 axes = 3.0f * glm::max(glm::exp(cloud_.log_scale[size_t(a.gaussian)]), glm::vec3(cell));
            extent.push_back({cloud_.mean[size_t(a.gaussian)], glm::mat3(glm::vec3(1.0f / axes.x, 0, 0), glm::vec3(0, 1.0f / axes.y, 0), glm::vec3(0, 0, 1.0f / axes.z)) * glm::transpose(rot)});
        }
    const std::vector<uint32_t> nearest = domain_nodes.nearest(points, cell);
    for (size_t c = 0; c < clicks.size(); ++c) clicks[c].node = nearest[c];
    if (nbr)
        for (auto [i, label] : clicks)
            for (uint32_t t = 0; t < k; ++t)
                if (uint32_t q = (*nbr)[size_t(i) * k + t]; q < nodes && pr.seed[q] < 0) pr.seed[q] = label;
    if (adjacency) {
        // A click whose node lies on a fragment of the surface it hit would hold its object to
        // that fragment: on the real guitar's back, large flat Gaussians up to 8 cm apart in pieces
        // of 3-80 nodes the kNN graph does not join, or a clump of Gaussians on one point whose
        // edges out have no weight. So where fewer than half the nodes within the clicked
        // Gaussian's 3-sigma ellipsoid are joined to the click's node inside it (along edges of
        // weight at least kJoined), the click also seeds the k nodes nearest to its point among
        // the others.
        constexpr float kJoined = 1e-3f;
        const HostAdjacency& g = *adjacency;
        std::vector<uint8_t> near, joined;
        for (size_t c = 0; c < clicks.size(); ++c) {
            const std::tuple<int32_t, float, float, float> click{anchors[c], points[c].x, points[c].y, points[c].z};
            auto found = widened_.find(click);
            if (found == widened_.end()) {
                if (near.empty()) near.assign(nodes, 0), joined.assign(nodes, 0);
                std::vector<uint32_t> in_reach;
                for (uint32_t i = 0; i < nodes; ++i) {
                    const glm::vec3 v = extent[c].second * (domain_nodes.position[i] - extent[c].first);
                    if (glm::dot(v, v) <= 1.0f) in_reach.push_back(i), near[i] = 1;
                }
                std::vector<uint32_t> stack;
                size_t reached = 0;
                if (near[clicks[c].node]) joined[clicks[c].node] = 1, reached = 1, stack.push_back(clicks[c].node);
                while (!stack.empty()) {
                    const uint32_t i = stack.back();
                    stack.pop_back();
                    for (uint32_t e = g.rows[i]; e < g.rows[i + 1]; ++e)
                        if (const uint32_t j = g.columns[e]; near[j] && !joined[j] && g.weights[e] >= kJoined)
                            joined[j] = 1, ++reached, stack.push_back(j);
                }
                std::vector<uint32_t> more;
                if (2 * reached < in_reach.size()) {
                    std::vector<std::pair<float, uint32_t>> others;
                    for (uint32_t i : in_reach)
                        if (!joined[i]) {
                            const glm::vec3 v = domain_nodes.position[i] - points[c];
                            others.push_back({glm::dot(v, v), i});
                        }
                    const size_t take = std::min<size_t>(k, others.size());
                    std::partial_sort(others.begin(), others.begin() + ptrdiff_t(take), others.end());
                    for (size_t t = 0; t < take; ++t) more.push_back(others[t].second);
                }
                for (uint32_t i : in_reach) near[i] = 0, joined[i] = 0;
                found = widened_.emplace(click, std::move(more)).first;
            }
            for (uint32_t i : found->second)
                if (pr.seed[i] < 0) pr.seed[i] = clicks[c].label;
            widened += !found->second.empty();
        }
    }
    for (auto [i, label] : clicks) pr.seed[i] = label;
    return widened;
}

bool Segmenter::coarse_allowed(const SegmentOptions& o, size_t nodes) {
    return o.solver != GraphSolver::Forest && o.coarse_stride >= 2 && nodes >= 64 * o.coarse_stride;
}

std::pair<std::vector<int32_t>, std::vector<float>> Segmenter::coarse_labels(const SegmentOptions& o,
                                                                             const std::vector<ObjectResult*>& objects,
                                                                             const GraphDomain& d,
                                                                             std::vector<std::vector<glm::vec3>>* support,
                                                                             bool carry) {
    // The seeds that need no fine graph, each click's nearest node and the margin; the full
    // solve's rule on the coarse graph (walk, and forest where the walk is unsure), carried to
    // every node by its nearest coarse node. The coarse nodes are every n-th in Morton order, a
    // uniform spatial subsample: thin parts keep their nodes (every n-th in scene order broke the
    // real guitar's stand into pieces the guitar took: 3D IoU 51 / 17 % against 94 / 51 % so).
    const uint32_t nodes = uint32_t(d.domain.size());
    WalkProblem early = margin_problem(d, objects.size());
    seed_clicks(objects, d, nullptr, DomainNodes(cloud_, d, false), node_cell(d), early);
    const CoarseSolve cs = coarse_solve(o, d.domain, early, true, false, true, carry);
    const WalkLabels w = cs.x.most_likely(nullptr);
    NodeLabels coarse{w.arg, w.share, 0};
    if (o.solver == GraphSolver::WalkForest)
        coarse = walk_then_forest(forest_, coarse_graph_, cs.problem.seed, w, o.walk_sure, o.forest);
    if (support) {
        support->assign(objects.size(), {});
        for (uint32_t c = 0; c < uint32_t(cs.members.size()); ++c)
            for (uint32_t l = 1; l < cs.x.labels(); ++l)
                if (coarse.label[c] == int32_t(l) || cs.x.at(c, l) >= o.graph_focus_support)
                    (*support)[l - 1].push_back(cloud_.mean[d.domain[cs.members[c]]]);
    }
    std::pair<std::vector<int32_t>, std::vector<float>> out;
    if (!carry) return out;
    out = {std::vector<int32_t>(nodes, -1), std::vector<float>(nodes, 0.0f)};
    for (uint32_t i = 0; i < nodes; ++i)
        if (const uint32_t c = cs.nearest[i]; c != kNoCoarse) out.first[i] = coarse.label[c], out.second[i] = coarse.confidence[c];
    return out;
}

bool Segmenter::early_coarse_answer(const SegmentOptions& o, const std::vector<ObjectResult*>& objects,
                                    const GraphDomain& d, SegmentResult& result) {
    // Before the fine graph (most of a cold click's wait). The network's prior needs the fine
    // graph's degrees, so ptv3+graph answers after it, in solve_walk.
    if (!o.on_coarse || o.graph != GraphUse::Alone || !coarse_allowed(o, d.domain.size())) return false;
    auto t0 = Clock::now();
    const auto [label, confidence] = coarse_labels(o, objects, d);
    result.stage_ms["graph coarse answer"] += ms_since(t0);
    coarse_answer(o, objects, d.domain, label, confidence, result);
    return true;
}

void Segmenter::network_prior(const SegmentOptions& o, std::vector<ObjectResult*>& objects,
                              const std::vector<std::vector<uint32_t>>& rois,
                              const std::vector<std::vector<float>>& probabilities, const GraphDomain& d,
                              const std::vector<float>* degree, WalkProblem& pr) {
    const uint32_t nodes = uint32_t(d.domain.size()), labels = pr.labels;
    const size_t m = objects.size();
    const std::vector<int32_t>& node_of = d.node_of;
    // The network's probabilities as a prior: q_j = p_j where object j's ROI holds the node,
    // background = the product of (1 - p_j), normalised; strength `unary` x the node's degree.
    // Outside every trusted network's ROI there is no prior: no network saw those nodes.
    // A network that calls the object's own clicked Gaussians background contradicts the user
    // (it happens on real captures unlike its training data): that object gets no prior and
    // is solved as by the graph alone.
    std::vector<float> fg(size_t(nodes) * labels, 0.0f), bg(nodes, 1.0f);
    // Inside an untrusted object's ROI the other networks' "not mine" is no evidence of
    // background: the object there is unknown to them. No background prior there.
    std::vector<uint8_t> unknown(nodes, 0), seen(nodes, 0);
    for (size_t j = 0; j < m; ++j) {
        double at_clicks = 0;
        size_t clicks = 0;
        for (size_t s = 0; s < rois[j].size(); ++s)
            for (auto& a : objects[j]->anchors)
                if (a.positive && a.gaussian == int32_t(rois[j][s])) at_clicks += probabilities[j][s], ++clicks;
        objects[j]->network_trusted = clicks > 0 && at_clicks / double(clicks) > 0.5;
        if (!objects[j]->network_trusted) {
            for (uint32_t g : rois[j])
                if (node_of[g] >= 0) unknown[size_t(node_of[g])] = 1;
            continue;
        }
        for (size_t s = 0; s < rois[j].size(); ++s) {
            int32_t i = node_of[rois[j][s]];
            if (i < 0) continue;
            fg[size_t(i) * labels + j + 1] = probabilities[j][s];
            bg[size_t(i)] *= 1.0f - probabilities[j][s];
            seen[size_t(i)] = 1;
        }
    }
    pr.gamma.assign(nodes, 0.0f);
    pr.prior = std::move(fg);
    for (uint32_t i = 0; i < nodes; ++i) {
        float* q = &pr.prior[size_t(i) * labels];
        q[0] = bg[i];
        float sum = 0, top = 0;
        for (uint32_t l = 0; l < labels; ++l) sum += q[l];
        for (uint32_t l = 0; l < labels; ++l) top = std::max(top, q[l] /= sum);
        // Only where the network is sure: elsewhere the graph decides.
        const bool background = q[0] >= top;
        pr.gamma[i] = seen[i] && top >= o.unary_confidence && !(background && unknown[i]) ? o.unary * (degree ? (*degree)[i] : 1.0f)
                                                                               : 0.0f;
    }
}

void Segmenter::coarse_answer(const SegmentOptions& o, const std::vector<ObjectResult*>& objects,
                              const std::vector<uint32_t>& domain, const std::vector<int32_t>& label,
                              const std::vector<float>& confidence, const SegmentResult& so_far) const {
    // The nodes' labels as the objects' claims.
    SegmentResult answer;
    answer.stage_ms = so_far.stage_ms;
    answer.objects.reserve(objects.size());
    for (const ObjectResult* obj : objects) {
        answer.objects.push_back(*obj);
        answer.objects.back().claims.clear();
    }
    for (size_t i = 0; i < domain.size(); ++i)
        if (label[i] > 0) answer.objects[size_t(label[i]) - 1].claims.push_back({domain[i], confidence[i]});
    answer.assemble(cloud_.size());
    o.on_coarse(answer);
}

void Segmenter::solve_walk(const SegmentOptions& o, std::vector<ObjectResult*>& objects,
                           const std::vector<uint32_t>& domain, const std::vector<uint32_t>& nbr, WalkProblem& pr,
                           WarmStart& warm_start, SegmentResult& result) {
    const uint32_t nodes = uint32_t(domain.size()), labels = pr.labels;
    const size_t m = objects.size();
    // Warm start: a label solved before on this graph starts from its last solution.
    std::vector<int> ids(labels, 0);
    for (size_t j = 0; j < m; ++j) ids[j + 1] = objects[j]->id;
    std::vector<int> last_column(labels, -1);  // per label: its column in warm.x, -1 none
    bool warm = false;
    for (uint32_t l = 0; l < labels; ++l) {
        auto it = std::find(warm_start.ids.begin(), warm_start.ids.end(), ids[l]);
        if (it != warm_start.ids.end()) last_column[l] = int(it - warm_start.ids.begin()), warm = true;
    }
    LabelColumns start;  // empty: the walk starts from the prior (or 0)
    if (warm) {
        start = LabelColumns(nodes, labels, labels > o.walk.dense_labels);
        std::vector<float> values(labels);
        for (uint32_t i = 0; i < nodes; ++i) {
            for (uint32_t l = 0; l < labels; ++l)
                values[l] = last_column[l] >= 0 ? warm_start.x.at(i, uint32_t(last_column[l]))
                                                : (pr.prior.empty() ? 0.0f : pr.prior[size_t(i) * labels + l]);
            start.set_node(i, values.data());
        }
    }
    auto t0 = Clock::now();
    if (roots_.empty()) roots_ = component_roots(graph_, nbr);  // per graph
    const std::vector<uint32_t>& root = roots_;
    result.stage_ms["graph components"] += ms_since(t0);
    if (!warm && o.coarse_stride > 1 && nodes >= 64 * o.coarse_stride) {
        // Jacobi starts from the coarse answer (it needs about an iteration per hop); multigrid
        // from the prior (its coarse levels carry the far-reaching part, and the coarse answer's
        // roughness costs it iterations), so there the coarse solve runs only for a caller that
        // shows its answer.
        const bool jacobi = o.walk.preconditioner == WalkPreconditioner::Jacobi;
        if (jacobi || o.on_coarse) {
            auto t1 = Clock::now();
            auto coarse = coarse_start(o, domain, pr);
            result.stage_ms["graph coarse start"] += ms_since(t1);
            if (o.on_coarse) {
                const WalkLabels w = coarse.most_likely(nullptr);
                coarse_answer(o, objects, domain, w.arg, w.share, result);
            }
            if (jacobi) start = std::move(coarse);
        }
    }
    GraphReport report = graph_report(graph_, GraphSolver::Walk, pr.seed);
    t0 = Clock::now();
    auto solution = walker_.solve(graph_, pr, start, o.walk);  // the start becomes the answer
    result.stage_ms["graph walk"] += ms_since(t0);
    t0 = Clock::now();
    const auto seeded = seeded_components(root, pr);
    bridge_components(o, domain, root, seeded, pr, start);
    result.stage_ms["graph bridges"] += ms_since(t0);
    // A component with no seed, prior or bridge within reach has no answer: it stays unlabelled
    // and is counted.
    const auto reached = reached_components(root, pr, start, report);

    report.iterations = solution.iterations;
    report.levels = solution.levels;
    report.jacobi_retries = solution.jacobi_retries;
    report.range_retries = solution.range_retries;
    report.out_of_range = solution.out_of_range;
    // Parts of "graph solve": the host's multigrid hierarchy, the walk's GPU passes.
    if (solution.levels) result.stage_ms["graph hierarchy"] += solution.hierarchy_ms;
    for (const auto& t : walker_.timings()) result.stage_ms["graph walk gpu"] += t.ms;
    report.residual = solution.residual;
    // Each reached node's most likely label and its share of the probability.
    const WalkLabels w = start.most_likely(&reached);
    warm_start = {std::move(start), ids};  // kept for the next click's warm start
    if (o.solver == GraphSolver::WalkForest) {
        // Where the walk is sure it stands; the forest's widest paths settle the rest, without
        // the walk's pull towards the label with the most seeds.
        const auto t0 = Clock::now();
        const NodeLabels settled = walk_then_forest(forest_, graph_, pr.seed, w, o.walk_sure, o.forest, &seeded);
        result.stage_ms["graph forest"] += ms_since(t0);
        report.solver = GraphSolver::WalkForest;
        report.rounds = settled.rounds;
        report.forest_free = settled.free_nodes;
        for (uint32_t i = 0; i < nodes; ++i)
            if (settled.label[i] > 0)
                objects[size_t(settled.label[i]) - 1]->claims.push_back({domain[i], settled.confidence[i]});
    } else {
        for (uint32_t i = 0; i < nodes; ++i)
            if (w.arg[i] > 0) objects[size_t(w.arg[i]) - 1]->claims.push_back({domain[i], w.share[i]});
    }
    result.graph = report;
}

const Segmenter::Bridges& Segmenter::bridges_for(const SegmentOptions& o, const std::vector<uint32_t>& domain,
                                                 const std::vector<uint32_t>& root, const std::vector<uint8_t>& seeded) {
    // The bridges depend on the graph and on which components hold a seed, not on the answer:
    // a further click on the same graph (seeds in the same components) reuses them.
    for (auto it = bridges_.begin(); it != bridges_.end(); ++it)
        if (it->seeded == seeded) {
            bridges_.splice(bridges_.begin(), bridges_, it);
            return bridges_.front();
        }
    Bridges made;  // kept only once whole
    made.seeded = seeded;
    auto keep = [&]() -> const Bridges& {
        if (bridges_.size() >= 2) bridges_.pop_back();  // one per ROI scale
        bridges_.push_front(std::move(made));
        return bridges_.front();
    };
    const uint32_t nodes = uint32_t(domain.size());
    // A component that no seed or prior reaches is a singular system the walk leaves as it
    // started. Each of its nodes is bridged to its nearest node in a seeded component (within 4
    // grid cells, about 10 spacings: past that the affinity is below e^-100), the bridge weighing
    // the edges' affinity (colour, distance in median spacings, opacity; no normal term); the
    // component takes the bridge-weighted mean of the answers at the far ends, as the walk would
    // if those bridges were its only edges out. Bridges that all vanish leave it unlabelled.
    std::vector<uint32_t> members;
    for (uint32_t i = 0; i < nodes; ++i)
        if (seeded[i]) members.push_back(i);
    if (members.empty() || members.size() == nodes) return keep();
    if (!nodes_ || nodes_->appearance.size() != size_t(nodes) * 4)
        throw std::logic_error("bridge_components: no node data for this domain");
    const std::vector<glm::vec3>& position = nodes_->position;
    const float* appearance = nodes_->appearance.data();  // r, g, b, opacity per node
    auto colour = [&](uint32_t i) { return glm::vec3(appearance[4 * i], appearance[4 * i + 1], appearance[4 * i + 2]); };
    auto opacity = [&](uint32_t i) { return appearance[4 * i + 3]; };
    const GraphOptions& go = o.graph_options;
    const double spacing = double(graph_.median_spacing()) * go.distance;
    constexpr int kReach = 4;  // grid cells
    const float cell = std::max(graph_.cell_side(), 1e-6f);
    // Blocks of kReach cells. An unseeded node with no seeded node in its block or the 26 about it
    // has no bridge, found without a search (most of a far, unseeded piece's nodes). The search
    // (kReach rings of cells: less than 2 blocks) indexes only the seeded nodes within 2 blocks of
    // an unseeded one: the answers of a search over all of them, at one set lookup per node.
    auto block_of = [&](const glm::vec3& p) { return glm::ivec3(glm::floor(p / (float(kReach) * cell))); };
    auto block_key = [](glm::ivec3 b) {
        return (uint64_t(uint32_t(b.x) & 0x1FFFFF) << 42) | (uint64_t(uint32_t(b.y) & 0x1FFFFF) << 21) | uint64_t(uint32_t(b.z) & 0x1FFFFF);
    };
    std::vector<uint64_t> block(nodes);
    std::unordered_set<uint64_t> seeded_blocks, unseeded_blocks;
    for (uint32_t i = 0; i < nodes; ++i) {
        block[i] = block_key(block_of(position[i]));
        (seeded[i] ? seeded_blocks : unseeded_blocks).insert(block[i]);
    }
    auto about = [&](const std::unordered_set<uint64_t>& blocks, int reach) {
        std::unordered_set<uint64_t> out;
        for (uint64_t key : blocks) {
            // The key's fields back to a block (21-bit two's complement), then its neighbours.
            auto field = [&](int shift) { return int32_t(uint32_t(key >> shift) << 11) >> 11; };
            const glm::ivec3 b(field(42), field(21), field(0));
            for (int z = -reach; z <= reach; ++z)
                for (int y = -reach; y <= reach; ++y)
                    for (int x = -reach; x <= reach; ++x) out.insert(block_key(b + glm::ivec3(x, y, z)));
        }
        return out;
    };
    const auto near_seeded = about(seeded_blocks, 1), near_unseeded = about(unseeded_blocks, 2);
    // members[0] first, wherever it lies: the grid's cells start at its first point, and the
    // search's reach (kReach rings of them) must be the full grid's.
    std::vector<uint32_t> ends{members[0]};
    for (uint32_t i : members)
        if (i != members[0] && near_unseeded.count(block[i])) ends.push_back(i);
    data::clicks::PointGrid grid(position, ends, cell);
    // Each unseeded node's bridge (far end, weight), then component by component (nodes grouped
    // by root): memory stays one label vector, whatever the number of labels and components.
    std::vector<uint32_t>& end = made.end;
    std::vector<uint32_t>& unseeded = made.unseeded;
    std::vector<double>& bridge = made.weight;
    end.assign(nodes, 0);
    bridge.assign(nodes, 0.0);
    for (uint32_t i = 0; i < nodes; ++i) {
        if (seeded[i]) continue;
        unseeded.push_back(i);
        if (!near_seeded.count(block[i])) continue;
        const double d2 = grid.nearest(position[i], 0xFFFFFFFFu, kReach, &end[i]);
        if (d2 < 0) continue;
        const glm::vec3 dc = colour(i) - colour(end[i]);
        bridge[i] = std::exp(-double(go.colour) * glm::dot(dc, dc) - d2 / (spacing * spacing)) *
                    std::pow(double(std::min(opacity(i), opacity(end[i]))), double(go.opacity));
    }
    std::stable_sort(unseeded.begin(), unseeded.end(), [&](uint32_t a, uint32_t b) { return root[a] < root[b]; });
    return keep();
}

void Segmenter::bridge_components(const SegmentOptions& o, const std::vector<uint32_t>& domain,
                                  const std::vector<uint32_t>& root, const std::vector<uint8_t>& seeded,
                                  const WalkProblem& pr, LabelColumns& x) {
    const Bridges& b_set = bridges_for(o, domain, root, seeded);
    const std::vector<uint32_t>& unseeded = b_set.unseeded;
    const std::vector<uint32_t>& end = b_set.end;
    const std::vector<double>& bridge = b_set.weight;
    const uint32_t labels = pr.labels;
    std::vector<double> sum(labels);
    std::vector<float> values(labels);
    for (size_t b = 0; b < unseeded.size();) {
        size_t e = b;
        double weight = 0;
        std::fill(sum.begin(), sum.end(), 0.0);
        for (; e < unseeded.size() && root[unseeded[e]] == root[unseeded[b]]; ++e) {
            const uint32_t i = unseeded[e];
            if (!(bridge[i] > 0)) continue;
            weight += bridge[i];
            for (uint32_t l = 0; l < labels; ++l) sum[l] += bridge[i] * x.at(end[i], l);
        }
        if (weight > 0) {
            for (uint32_t l = 0; l < labels; ++l) values[l] = float(sum[l] / weight);
            for (size_t t = b; t < e; ++t) x.set_node(unseeded[t], values.data());
        }
        b = e;
    }
}

void Segmenter::solve_forest(const SegmentOptions& o, std::vector<ObjectResult*>& objects,
                             const std::vector<uint32_t>& domain, const std::vector<uint32_t>& nbr, const WalkProblem& pr,
                             WarmStart& warm, SegmentResult& result) {
    // The network's confident labels (the walk's unary terms) seed the forest like clicks.
    const uint32_t nodes = uint32_t(domain.size()), labels = pr.labels;
    std::vector<int32_t> seed = forest_seeds(pr);
    auto forest = forest_.solve(graph_, seed, o.forest);
    warm = {};  // the walk's warm start does not apply to hard labels

    GraphReport report = graph_report(graph_, GraphSolver::Forest, seed);
    report.rounds = forest.rounds;
    report.forest_free = forest.free_nodes;
    report.residual = forest.converged ? 0.0 : 1.0;
    WalkProblem seeds_only;
    seeds_only.labels = labels;
    seeds_only.seed = std::move(seed);
    if (roots_.empty()) roots_ = component_roots(graph_, nbr);
    reached_components(roots_, seeds_only, LabelColumns(), report);
    for (uint32_t i = 0; i < nodes; ++i)
        if (forest.label[i] > 0) objects[size_t(forest.label[i]) - 1]->claims.push_back({domain[i], 1.0f});
    result.graph = report;
}

}  // namespace pg::seg
