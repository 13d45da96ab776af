#pragma once
// The interactive segmentation pipeline up to 3D labels: clicks are lifted to anchors, the
// prompt encoder weighs the Gaussians and crops the ROI column, the ROI is partitioned into
// batches for the decoder, and each Gaussian goes to the object that claims it with the
// highest probability (above 1/2, the paper's argmax of foreground vs background).
// With a graph decoder (see GraphUse) all objects are then solved together by a random walk
// over the Gaussians' kNN graph. An object whose clicks cannot be lifted (or whose ROI is
// empty) fails alone: its error is kept and the others are segmented.
#include <functional>
#include <list>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "dataset/camera.h"
#include "dataset/clicks/point_grid.h"
#include "dataset/gaussian_cloud.h"
#include "dataset/prompts.h"
#include "engine/render/renderer.h"
#include "engine/segment/cancel.h"
#include "engine/segment/column_index.h"
#include "engine/segment/decoder.h"
#include "engine/segment/knn_graph.h"
#include "engine/segment/object_splits.h"
#include "engine/segment/prompt_encoder.h"
#include "engine/segment/random_walker.h"
#include "engine/segment/seeded_forest.h"

namespace pg::seg {

// How the random-walk graph decoder takes part (`--decoder`): not at all (ptv3), alone (graph:
// every object's positive clicks seed its label, negative clicks and the Gaussians between
// the objects' ROIs and the margin around them seed the background), or with the network's
// probabilities as unary terms of the same solve (ptv3+graph).
enum class GraphUse { None, Alone, Unary };

// How the graph is solved (`--graph-solver`): the random walk's probabilities (walk), each
// Gaussian's widest path to a seed (forest, see seeded_forest.h), or the walk where it is sure
// and the forest's widest paths from there for the rest (walk+forest).
enum class GraphSolver { Walk, Forest, WalkForest };
GraphSolver parse_graph_solver(const std::string& name, const std::string& option = "graph solver");
const char* graph_solver_name(GraphSolver solver);

// "ptv3", "graph", "ptv3+graph"; InputError naming `option` otherwise.
GraphUse parse_graph_use(const std::string& name, const std::string& option = "decoder");
const char* graph_use_name(GraphUse use);

struct SegmentResult;

// The narrowest margin a click's budget takes a domain to (SegmentOptions::graph_budget). Every
// node of the margin seeds the background and the answer inside depends on the seeds next to
// the ROIs, so a narrow ring costs little (0.1 against 0.5 of the ROI per side, fresh seeds 6201
// and 5153: desk -0.2 / -0.6 points of 3D IoU, residence -0.4 / -0.9, vehicles +0.6 / -0.6)
// and holds a third of the nodes of a dense scene's domain.
inline constexpr double kNarrowMargin = 0.1;

struct SegmentOptions {
    glm::dvec3 up{0, -1, 0};     // the scene's up axis (see dataset/up_axis.h)
    double scale = 0;            // typical object size in scene units; 0: from the cameras
    double sigma = 0;            // click weight fall-off; 0: 0.4 * scale
    double roi_length = 0, roi_width = 0;  // 0: 2.5 * scale
    uint32_t max_batch = 8192;
    uint64_t seed = 1;
    render::RenderSettings render;  // tau and the like for click lifting
    LiftRule lift = LiftRule::Surface;  // where a click in a view lands (see LiftRule)
    bool strict = false;          // an object that fails stops the run (InputError) instead of failing alone
    GraphUse graph = GraphUse::None;
    GraphOptions graph_options;
    GraphSolver solver = GraphSolver::WalkForest;
    WalkOptions walk;
    ForestOptions forest;
    float walk_sure = 0.7f;       // walk+forest: the walk's label stands where its share reaches this
    ObjectSplitOptions object_splits;  // walk+forest: where two objects meet, the widest paths' split may stand
    double graph_margin = 0.5;    // the solve's domain: the largest ROI columns widened by this fraction per side
    // The background's boundary is each object's ROI scaled by each of these (the graph is built
    // once, over the largest); per object the answer of the smallest scale stands unless a larger
    // one's boundary contrast (see boundary_contrast.h) is below graph_scale_ratio times its own.
    // Largest first; a smaller scale whose ROIs hold every answer already found is not solved.
    std::vector<double> graph_scales{1.0, 2.0};
    double graph_scale_ratio = 0.25;
    float unary = 1.0f;           // ptv3+graph: a node's unary strength, in units of its degree,
    float unary_confidence = 0.97f;  // where the network's most likely label has at least this probability
    // ptv3+graph: where the graph alone's answer cuts no edge (it is whole graph components: a
    // house, the car parked against it and the crowns over its roof, all apart from the terrain),
    // the graph holds no evidence of the object's boundary; there the network's answer stands if
    // its own boundary contrast is below this (a clean cut, not one through the object's inside).
    double unary_clean = 0.1;
    // Most nodes one graph may hold (0: what the device's largest binding allows, about 1.6 M at
    // k 10 on lavapipe). A larger domain is solved on every n-th node (see solve_decimated).
    uint64_t graph_max_nodes = 0;
    // A click's budget in nodes. Past it the margin first narrows to kNarrowMargin, then the
    // larger scales are left out, all before any decimation: a click on a scene of millions
    // costs about what the ROIs at scale 1 hold (0: no budget, only graph_max_nodes).
    uint64_t graph_budget = 600000;
    // A domain of more nodes than this (within the budget) is first solved on its coarse graph
    // (the coarse answer's rule on every 2 x coarse_stride-th node, at its largest ROI scale); the
    // fine graph then covers only each object's coarse support, its box grown by graph_focus_grow
    // of its extent per side (within the ROI), and the margin the domain was taken at around that,
    // which seeds the background (0: never). A click's cost then follows the object, not the scene
    // around it. Where objects fill the domain the focus is refused after its coarse solve, which
    // the click then paid for nothing: seed 8317's residences (227-349 k nodes) refuse it on all
    // ten scenes, 0.2-0.45 s each; forced on every suite scene, 29 of 30 refuse it.
    uint64_t graph_focus = 200000;
    double graph_focus_grow = 0.25;
    float graph_focus_support = 0.2f;  // a coarse node is the object's where its walk reaches this
    uint32_t coarse_stride = 8;   // walk: a first solve on every n-th node starts the fine one (1: none);
                                  // with multigrid only where the fine graph's component holds no seed
                                  // or prior (what the coarse graph joins to the rest and labels)
    // Set (by another thread): segment() stops with Cancelled at its next check (between objects,
    // network batches, walk checks and forest rounds). The viewer's newer click does this.
    const std::atomic<bool>* cancel = nullptr;
    // Called with a coarse answer before a walk's cold solve (no warm start on this graph): the
    // coarse graph's solution (see coarse_stride) carried to every node by its nearest coarse
    // node. What the viewer shows while the full solve runs; the final result does not change.
    std::function<void(const SegmentResult&)> on_coarse;
};

struct ObjectResult {
    int id = 0;
    std::string name;
    std::vector<Anchor> anchors;
    RoiBox roi;
    double sigma = 0;
    size_t roi_gaussians = 0, batches = 0, labelled = 0;
    // Gaussians the decoder gave this object with P(foreground) > 1/2, and that probability.
    std::vector<std::pair<uint32_t, float>> claims;
    std::string error;            // why the object failed (no labels); empty if it was segmented
    // Graph decoders: the ROI scale whose answer stood (SegmentOptions::graph_scales), and that
    // answer's boundary contrast (0 where graph_scales holds a single scale).
    double graph_scale = 0, boundary_contrast = 0;
    // Every scale solved, largest first: (scale, its answer's boundary contrast, Gaussians claimed).
    std::vector<std::tuple<double, double, size_t>> scale_answers;
    // ptv3+graph: whether the network's probabilities were used (it agreed with the object's
    // clicks: P(foreground) > 1/2 at its positive clicks on average).
    bool network_trusted = false;
    // ptv3+graph: whether the answer solved with the network's prior stood (its boundary cut the
    // graph no harder than the graph alone's answer did, or cleanly where that answer cut
    // nothing; see network_stands), not the graph's own.
    bool network_answer = false;
    size_t fallback_clicks() const;
};

struct GraphReport {
    size_t nodes = 0, seeds = 0;
    size_t unreached = 0, unreached_components = 0;  // Gaussians (and components) with no seed or prior: unlabelled
    GraphSolver solver = GraphSolver::Walk;
    uint32_t iterations = 0;     // the walk's conjugate-gradient iterations
    uint32_t levels = 0;         // the walk's multigrid levels (0: Jacobi preconditioner)
    uint32_t jacobi_retries = 0; // column batches multigrid made no progress on, solved again with Jacobi
    uint32_t range_retries = 0;  // of those, batches whose answer left [0, 1] (the maximum principle)
    uint64_t out_of_range = 0;   // walk values still outside [0, 1] after Jacobi, clamped
    uint32_t rounds = 0;         // the forest's relaxation rounds on the GPU (0: flooded on the host)
    size_t forest_free = 0;      // nodes the forest had to label (no seed, the walk not sure)
    uint32_t widened_clicks = 0; // clicks on a fragment of a surface that also seeded its neighbours (seed_clicks)
    uint32_t object_splits = 0;  // pairs of objects split by the widest paths instead (object_splits.h)
    double residual = 0, cell = 0, spacing = 0;
    // The graph holds every stride-th node of the domain (in Morton order) and the clicked ones;
    // the rest take their nearest graph node's label. 1: the whole domain. More only where the
    // domain's graph would not fit the device (SegmentOptions::graph_max_nodes).
    uint32_t stride = 1;
    size_t domain = 0;           // Gaussians in the solve's domain
    double margin = 0;           // the margin it was taken with (narrower than asked past graph_budget)
    bool focused = false;        // the domain is the objects' coarse answers' boxes (SegmentOptions::graph_focus)
};

struct SegmentResult {
    std::vector<int32_t> labels;       // object id per Gaussian, 0 for none
    std::vector<float> probability;    // the winning probability (0 where unlabelled)
    std::vector<ObjectResult> objects;
    std::map<std::string, double> stage_ms;  // wall ms per stage, summed over objects
    std::optional<GraphReport> graph;
    size_t failed() const;

    // Recomputes labels from the objects' claims: a Gaussian claimed twice goes to the higher
    // probability (ties: the earlier object).
    void assemble(size_t gaussian_count);
    // Drops an object; Gaussians it had won go to the next most confident claimant.
    bool remove_object(int id);
};

// The Gaussians a graph solve runs over: the objects' ROI columns widened by the margin.
struct GraphDomain {
    std::vector<uint32_t> domain;  // node -> Gaussian
    std::vector<int32_t> node_of;  // Gaussian -> node, -1 outside
    std::vector<uint8_t> in_roi;   // per node: inside an object's ROI (else it seeds the background)
    std::vector<uint8_t> in_base_roi;  // the same for the ROIs as the objects have them (scale 1)
    glm::vec3 lo{0.0f}, hi{0.0f};  // the nodes' bounding box
};

// What the host reads per node of a domain: centres and, with `appearance`, colours of the SH DC
// term and opacities (the bridges). The fine graph's is made once per graph.
struct DomainNodes {
    std::vector<glm::vec3> position;  // per node
    std::vector<float> appearance;    // per node: r, g, b, opacity (empty without `appearance`)
    DomainNodes(const data::GaussianCloud& cloud, const GraphDomain& d, bool appearance);
    // Per point the node whose centre is nearest (ties: the lowest node): a scan for a few points,
    // a hash grid of side `cell` for many.
    std::vector<uint32_t> nearest(const std::vector<glm::vec3>& points, float cell) const;
};

class Segmenter {
public:
    Segmenter(vk::Context& ctx, const data::GaussianCloud& cloud, const render::GpuScene& scene,
              const std::vector<data::Camera>& cameras, Decoder& decoder);
    // Without a network: only GraphUse::Alone works.
    Segmenter(vk::Context& ctx, const data::GaussianCloud& cloud, const render::GpuScene& scene,
              const std::vector<data::Camera>& cameras);

    // `lifted`: anchors the caller has for the prompts' clicks (an object without them, or with
    // a different count, has its clicks lifted here).
    SegmentResult segment(const data::Prompts& prompts, const SegmentOptions& options,
                          const LiftedClicks& lifted = {});

    // Typical object size from the cameras: a quarter of their median distance to `target`.
    double scale_from_cameras(const glm::dvec3& target) const;
    // The next click solves from scratch, as a click on new objects does: the graph domain, its
    // graph and warm starts go; what follows the scene alone (the column index, the clicked
    // views' pixel bins) stays.
    void forget_domain();
    // Bins the scene's Gaussians across `up` now, as the first click would (a pass over every
    // Gaussian: ~0.25 s at 6 M on two cores): a viewer does it while the scene loads.
    void index_columns(const glm::dvec3& up);

private:
    // A walk's answer kept for the next solve's start: a column per label id in `ids` (0: background).
    struct WarmStart {
        LabelColumns x;
        std::vector<int> ids;
    };
    // Lifts, scales and encodes one object and runs the network over its ROI; InputError if it fails.
    void prepare(const data::ObjectPrompt& prompt, size_t index, const std::vector<Anchor>* lifted,
                 const SegmentOptions& o, ObjectResult& obj,
                 std::vector<float>& roi_probability, std::vector<uint32_t>& roi, SegmentResult& result);
    // The graph decoders (segmenter_graph.cpp): every object that did not fail, solved together.
    void solve_graph(const SegmentOptions& o, std::vector<ObjectResult*>& objects,
                     const std::vector<std::vector<uint32_t>>& rois, const std::vector<std::vector<float>>& probabilities,
                     SegmentResult& result);
    // Each click seeds its nearest node (of d's `domain_nodes`) and that node's neighbours with its
    // object's label (with `nbr` null: the nearest nodes alone); `cell` sizes a search grid.
    // With the graph's `adjacency`, a click on a fragment of the surface it hit (most nodes within
    // the clicked Gaussian's extent are not joined to its node) also seeds the nearest of the
    // others. Returns how many clicks were widened so.
    uint32_t seed_clicks(const std::vector<ObjectResult*>& objects, const GraphDomain& d, const std::vector<uint32_t>* nbr,
                         const DomainNodes& domain_nodes, float cell, WalkProblem& pr,
                         const HostAdjacency* adjacency = nullptr) const;
    // Where two objects' final answers meet, the widest paths' split from the clicks may replace
    // theirs (object_splits.h); claims move with their probability.
    // Returns how many pairs of objects took the widest paths' split.
    uint32_t settle_splits(const SegmentOptions& o, std::vector<ObjectResult*>& objects, const GraphDomain& d,
                           const std::vector<uint32_t>& nbr);
    // The coarse answer before the fine graph is built, where the options want one and the
    // decoder allows it (graph alone, a walk); false if it was not given.
    bool early_coarse_answer(const SegmentOptions& o, const std::vector<ObjectResult*>& objects, const GraphDomain& d,
                             SegmentResult& result);
    // Whether the coarse solve serves these options on a domain of `nodes` (a walk, a stride).
    static bool coarse_allowed(const SegmentOptions& o, size_t nodes);
    // Per node of d: the coarse solve's label (-1: none, 0: background) and confidence, from the
    // clicks' nearest nodes and the margin (d.in_roi as it stands). `support`: per object the
    // coarse nodes' centres that its walk reaches with graph_focus_support, or that it labels.
    // Without `carry` the per-node labels are left empty (no node looks up its coarse node).
    std::pair<std::vector<int32_t>, std::vector<float>> coarse_labels(const SegmentOptions& o,
                                                                      const std::vector<ObjectResult*>& objects,
                                                                      const GraphDomain& d,
                                                                      std::vector<std::vector<glm::vec3>>* support = nullptr,
                                                                      bool carry = true);
    // ptv3+graph: the networks' confident probabilities as unary terms (and which networks are
    // trusted), each of strength `unary` x the node's degree in `degree` (null: `unary` alone, for a
    // problem the coarse graph solves with its own degrees).
    void network_prior(const SegmentOptions& o, std::vector<ObjectResult*>& objects,
                       const std::vector<std::vector<uint32_t>>& rois,
                       const std::vector<std::vector<float>>& probabilities, const GraphDomain& d,
                       const std::vector<float>* degree, WalkProblem& pr);
    // A domain too large for one graph on this device: the problem on every n-th node (n as small
    // as fits), the rest labelled by their nearest solved node. No warm start for a further click.
    void solve_decimated(const SegmentOptions& o, std::vector<ObjectResult*>& objects,
                         const std::vector<std::vector<uint32_t>>& rois,
                         const std::vector<std::vector<float>>& probabilities, const GraphDomain& d, uint64_t capacity,
                         SegmentResult& result);
    // The random walk (warm or coarse start), then the forest where the walk is unsure (walk+forest).
    void solve_walk(const SegmentOptions& o, std::vector<ObjectResult*>& objects, const std::vector<uint32_t>& domain,
                    const std::vector<uint32_t>& nbr, WalkProblem& pr, WarmStart& warm, SegmentResult& result);
    // The same problem by widest paths: the seeds, plus the network's confident labels.
    void solve_forest(const SegmentOptions& o, std::vector<ObjectResult*>& objects, const std::vector<uint32_t>& domain,
                      const std::vector<uint32_t>& neighbours, const WalkProblem& problem, WarmStart& warm,
                      SegmentResult& result);
    // Hands options.on_coarse the objects' claims from per-node labels (-1: none) over `domain`.
    void coarse_answer(const SegmentOptions& o, const std::vector<ObjectResult*>& objects,
                       const std::vector<uint32_t>& domain, const std::vector<int32_t>& label,
                       const std::vector<float>& confidence, const SegmentResult& so_far) const;
    // The same problem on every coarse_stride-th node (in scene order, or else in the nodes'
    // Morton order) and the clicks' nodes, walked on coarse_graph_; `spread_clicks`: the fine
    // problem seeds each click at one node, seed its coarse neighbours too; without `carry` no
    // fine node looks up its nearest coarse node (`nearest` stays empty).
    static constexpr uint32_t kNoCoarse = 0xFFFFFFFFu;
    struct CoarseSolve {
        std::vector<uint32_t> members;  // coarse node -> fine node
        WalkProblem problem;            // per coarse node: seeds, and the prior where the fine one has one
        WalkResult walk;                // over the coarse nodes; its answer in x (none if not walked)
        LabelColumns x;
        std::vector<uint32_t> nearest;  // fine node -> its nearest coarse node (kNoCoarse: none)
    };
    CoarseSolve coarse_solve(const SegmentOptions& o, const std::vector<uint32_t>& domain, const WalkProblem& fine,
                             bool spread_clicks, bool scene_order, bool walk = true, bool carry = true);
    // A starting point for the fine solve: each node starts from its nearest coarse node's answer.
    LabelColumns coarse_start(const SegmentOptions& o, const std::vector<uint32_t>& domain, const WalkProblem& fine);
    // After a walk: each graph component that no seed or prior reaches takes the bridge-weighted
    // mean of the answers at its nodes' nearest seeded-component nodes (`root`: component roots;
    // `seeded`: per node, whether its component holds a seed or prior).
    void bridge_components(const SegmentOptions& o, const std::vector<uint32_t>& domain,
                           const std::vector<uint32_t>& root, const std::vector<uint8_t>& seeded,
                           const WalkProblem& pr, LabelColumns& x);
    // Each unseeded node's bridge: its far end and weight (0: none), and the unseeded nodes
    // grouped by component; made once per graph and set of seeded components.
    struct Bridges {
        std::vector<uint8_t> seeded;
        std::vector<uint32_t> unseeded, end;
        std::vector<double> weight;
    };
    const Bridges& bridges_for(const SegmentOptions& o, const std::vector<uint32_t>& domain,
                               const std::vector<uint32_t>& root, const std::vector<uint8_t>& seeded);
    Anchor anchor_for(const data::PromptClick& click, const SegmentOptions& o, const std::string& what);
    // The scene's Gaussians binned across up in the ROI's axes (made on the first click, and
    // again only if the axes change).
    const ColumnIndex& columns(const RoiBox& roi);
    // The most nodes one graph may hold (the device's binding, or graph_max_nodes).
    uint64_t graph_capacity(const SegmentOptions& o) const;
    // graph_ holds no domain any more: what was made from it goes too.
    void drop_graph();

    vk::Context& ctx_;
    const data::GaussianCloud& cloud_;
    const render::GpuScene& scene_;
    const std::vector<data::Camera>& cameras_;
    Decoder* decoder_;
    render::Renderer renderer_;
    PromptEncoder encoder_;
    KnnGraph graph_, coarse_graph_;
    RandomWalker walker_;
    SeededForest forest_;
    // The last graph domain, the ROI boxes and options it came from (domain_key_, empty: none)
    // and the margin and scales it was taken at.
    GraphDomain domain_;
    std::vector<double> domain_key_, domain_scales_;
    double domain_margin_ = 0;
    std::vector<RoiBox> domain_boxes_;  // per object the box its ROI scales are of: its ROI, or its focus
    bool domain_focused_ = false;       // SegmentOptions::graph_focus
    std::vector<uint32_t> graph_domain_;  // the domain graph_ was built over, and with which options
    GraphOptions graph_built_with_;
    std::optional<DomainNodes> nodes_;    // graph_'s nodes, made once per graph
    std::vector<uint32_t> roots_;         // graph_'s components (per node, its root), once per graph
    // seed_clicks' widened clicks on graph_: per click (its Gaussian and 3D point) the further
    // nodes it seeds, empty where it is not widened. A scan of the domain per click, once per graph.
    mutable std::map<std::tuple<int32_t, float, float, float>, std::vector<uint32_t>> widened_;
    std::list<Bridges> bridges_;          // graph_'s bridges, the last used first (one per ROI scale)
    std::optional<ColumnIndex> columns_;
    PixelBins lift_bins_;  // the views clicked last: their Gaussians binned by pixel
    // Per ROI scale, the last walk's answer (a column per label id in ids, 0: background), for
    // warm starts: a scale starts from its own last answer, never from another scale's.
    std::map<double, WarmStart> warm_;
};

}  // namespace pg::seg
