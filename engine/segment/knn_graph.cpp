#include "engine/segment/knn_graph.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "dataset/clicks/kd_tree.h"
#include "dataset/error.h"
#include "engine/vk/context.h"
#include "shaders/segment/graph_shared.h"

namespace pg::seg {

namespace {


uint32_t bits_for(uint32_t cells) {
    uint32_t b = 0;
    while ((1ull << b) < cells) ++b;
    return b;
}

// Median distance from a node to its nearest other node, over a sample of about 1000 nodes
// (queried against the nodes outside the sample, so a query never finds itself). From 4000 nodes
// a Gaussian is in the sample when its index hashes into one of `step` buckets: the sample follows
// the Gaussians, not their rank in the domain. (Every step-th in scene order shifted the whole
// sample when a click's ROI added one Gaussian to the domain; the median, and with it the grid
// cell, moved by up to 9 % on a desk, which changed which neighbours the kNN found.) Below that
// the sample is every other node in scene order, as before: with half the nodes out of the tree a
// hashed half leaves a node's nearest neighbour in the sample at random (on a 1,158-Gaussian
// scene the spacing moved enough that a click took the whole scene), while scene order, spatially
// sorted in most files, keeps neighbours on both sides.
float spacing_of(const std::vector<glm::vec3>& p, const std::vector<uint32_t>& domain) {
    const size_t n = p.size();
    if (n < 2) return 1.0f;
    const uint32_t step = uint32_t(std::max<size_t>(2, n / 1000));
    std::vector<uint32_t> rest;
    std::vector<size_t> queries;
    rest.reserve(n);
    if (n >= 4000) {
        for (uint32_t i = 0; i < n; ++i) {
            uint32_t h = domain[i] * 0x9E3779B1u;  // Fibonacci hashing: neighbouring indices spread over the buckets
            h ^= h >> 15;
            (h % step == 0 ? queries.push_back(i) : rest.push_back(i));
        }
    } else {
        // The nodes in scene order without a comparison sort (ids are distinct Gaussian indices).
        const uint32_t top = *std::max_element(domain.begin(), domain.end());
        std::vector<uint32_t> slot(size_t(top) + 1, 0xFFFFFFFFu);
        for (uint32_t i = 0; i < n; ++i) slot[domain[i]] = i;
        size_t r = 0;
        for (uint32_t node : slot)
            if (node != 0xFFFFFFFFu) (r++ % step == 0 ? queries.push_back(node) : rest.push_back(node));
    }
    if (queries.empty() || rest.empty()) return 1e-6f;
    data::clicks::KdTree tree(p, rest, 512);  // ~1000 queries: a shallow tree builds in a third of the time
    std::vector<double> d;
    for (size_t q : queries) d.push_back(std::sqrt(tree.nearest2(glm::dvec3(p[q]), 1e30)));
    std::nth_element(d.begin(), d.begin() + long(d.size() / 2), d.end());
    double m = d[d.size() / 2];
    return m > 0 && std::isfinite(m) ? float(m) : 1e-6f;
}

// The kNN search built for the shortest neighbour lists that hold k (shaders/CMakeLists.txt).
std::string knn_kernel(uint32_t k) {
    for (uint32_t bound : {4u, 6u, 8u, 10u, 12u})
        if (k <= bound) return "segment/graph_knn_k" + std::to_string(bound);
    return "segment/graph_knn_k" + std::to_string(gpu::kGraphMaxK);
}

}  // namespace

KnnGraph::KnnGraph(vk::Context& ctx) : ctx_(ctx), cmd_(ctx), sort_(ctx), scan_(ctx) {
    for (auto* b : {&domain_buf_, &pos_, &colour_, &normal_, &keys_, &values_, &nbr_, &dist_, &spacing_, &weight_, &reverse_count_,
                    &columns_, &adjacency_weights_,
                    &rows_, &degree_, &row_start_, &sorted_, &short_})
        *b = vk::Buffer(ctx, 16, vk::MemoryUse::Device, "graph");
}

uint64_t KnnGraph::max_nodes(const vk::Context& ctx, uint32_t k) {
    // 2 k uint32 adjacency columns (and weights) per node; the walker's label columns, up to 4 vec4s.
    const uint64_t widest = std::max<uint64_t>(8ull * k, 64);
    return ctx.info().max_storage_buffer_range / widest;
}

void KnnGraph::build(const render::GpuScene& scene, const data::GaussianCloud& cloud,
                     const std::vector<uint32_t>& domain, const GraphOptions& o) {
    if (o.k < 1 || o.k > gpu::kGraphMaxK)
        throw data::InputError("graph-k", "must be 1.." + std::to_string(gpu::kGraphMaxK) + ", got " + std::to_string(o.k));
    if (o.shells < 1 || o.shells > gpu::kGraphMaxShells)
        throw data::InputError("graph-shells", "must be 1.." + std::to_string(gpu::kGraphMaxShells) + ", got " +
                                                   std::to_string(o.shells));
    if (!(o.cell > 0) || !(o.distance > 0) || !(o.colour >= 0) || !(o.normal >= 0) || !(o.opacity >= 0))
        throw data::InputError("graph weights", "cell and distance must be positive, colour, normal and opacity >= 0");
    domain_ = domain;
    host_nbr_.clear();
    // Emptied, not freed: the next download reuses the memory (fresh pages fault on first touch).
    host_adjacency_.rows.clear();
    host_adjacency_.columns.clear();
    host_adjacency_.weights.clear();
    host_adjacency_.degree.clear();
    nodes_ = uint32_t(domain.size());
    k_ = o.k;
    const uint32_t n = nodes_, k = k_;
    if (n == 0) return;
    const uint64_t entries = 2ull * n * k;
    if (n > max_nodes(ctx_, k))
        throw std::runtime_error("graph: " + std::to_string(n) + " nodes of " + std::to_string(k) +
                                 " neighbours pass the device's largest binding (at most " +
                                 std::to_string(max_nodes(ctx_, k)) + ")");
    if (entries >= 0xFFFFFFFFull) throw std::runtime_error("graph: too many nodes for 32-bit edge ids");

    // The grid: robust bounds (outliers clamp into the border cells) and a cell side from the spacing.
    std::vector<glm::vec3> p(n);
    for (uint32_t i = 0; i < n; ++i) p[i] = cloud.mean[domain[i]];
    median_spacing_ = spacing_of(p, domain);
    glm::vec3 lo(0.0f), hi(0.0f);
    std::vector<float> axis(n);
    for (int a = 0; a < 3; ++a) {
        for (uint32_t i = 0; i < n; ++i) axis[i] = p[i][a];
        auto at = [&](double q) {
            auto it = axis.begin() + long(q * double(n - 1));
            std::nth_element(axis.begin(), it, axis.end());
            return *it;
        };
        lo[a] = at(0.005);
        hi[a] = at(0.995);
    }
    cell_ = o.cell * median_spacing_;
    glm::uvec3 dims, bits;
    // The row table (a start per row of cells along x) stays within a few entries per node.
    const uint64_t most_rows = std::max<uint64_t>(4ull * n, 1ull << 20);
    for (;;) {
        for (int a = 0; a < 3; ++a) {
            dims[a] = uint32_t(std::min(1e6, std::floor(double(hi[a] - lo[a]) / cell_) + 1.0));
            bits[a] = bits_for(dims[a]);
        }
        if (bits.x + bits.y + bits.z <= 32 && uint64_t(dims.y) * dims.z <= most_rows) break;
        cell_ *= 1.25f;  // a grid too fine for 32-bit keys or the row table: coarser cells stay exact, only slower
    }
    const uint32_t grid_rows = dims.y * dims.z;

    const uint64_t nk = uint64_t(n) * k;
    domain_buf_.ensure(uint64_t(n) * 4);
    vk::upload(ctx_, domain_buf_, domain.data(), uint64_t(n) * 4);
    pos_.ensure(uint64_t(n) * 16);
    colour_.ensure(uint64_t(n) * 16);
    normal_.ensure(uint64_t(n) * 16);
    keys_.ensure(std::max<uint64_t>(n, entries) * 4);
    values_.ensure(uint64_t(n) * 4);
    nbr_.ensure(nk * 4);
    dist_.ensure(nk * 4);
    spacing_.ensure(uint64_t(n) * 4);
    row_start_.ensure(uint64_t(grid_rows + 1) * 4);
    sorted_.ensure(uint64_t(n) * 16);
    weight_.ensure(nk * 4);
    rows_.ensure(uint64_t(n + 1) * 4);
    reverse_count_.ensure(uint64_t(n) * 4);
    adjacency_weights_.ensure(entries * 4);
    degree_.ensure(uint64_t(n) * 4);

    gpu::GraphNodesPush nodes_push{{n, scene.sh_words(), scene.half_sh() ? 1u : 0u, 0}};
    gpu::GraphGridPush grid{glm::vec4(lo, 1.0f / cell_), glm::uvec4(dims, o.shells), glm::uvec4(bits.x, bits.y, n, k), {0, 0, 0, 0}};
    gpu::GraphGridPush further = grid;
    further.pass.x = 1;
    short_.ensure((4ull + n) * 4);
    gpu::GraphWeightsPush wpush{glm::vec4(o.colour, o.normal, o.distance, o.opacity), {n, k, 0, 0}};
    gpu::GraphEdgesPush epush{{n, k, uint32_t(entries), 0}};
    const auto graph_groups = [](uint64_t items) { return vk::ceil_div(items, gpu::kGraphGroup); };

    cmd_.begin_pass("graph nodes");
    if (!scene.streamed()) {
        cmd_.dispatch("segment/graph_nodes", {scene.means, scene.shapes, scene.sh, domain_buf_, pos_, colour_, normal_},
                      nodes_push, graph_groups(n));
    } else {
        // The domain's Gaussians a slab at a time (each slab must wait for the last to be read);
        // slab node i is slab Gaussian i.
        if (!slab_) slab_ = std::make_unique<render::SceneSlab>(ctx_, "graph slab");
        const uint32_t chunk = scene.chunk();
        std::vector<uint32_t> iota(std::min(chunk, n)), ids;
        for (uint32_t i = 0; i < iota.size(); ++i) iota[i] = i;
        vk::upload(ctx_, domain_buf_, iota.data(), iota.size() * 4);
        for (uint32_t off = 0; off < n; off += chunk) {
            const uint32_t m = std::min(chunk, n - off);
            ids.assign(domain.begin() + off, domain.begin() + off + m);
            slab_->load(scene, ids);
            const gpu::GraphNodesPush push{{m, scene.sh_words(), scene.half_sh() ? 1u : 0u, 0}};
            cmd_.dispatch("segment/graph_nodes",
                          {slab_->means, slab_->shapes, slab_->sh, domain_buf_, vk::BufferRange(pos_, off * 16ull, m * 16ull),
                           vk::BufferRange(colour_, off * 16ull, m * 16ull), vk::BufferRange(normal_, off * 16ull, m * 16ull)},
                          push, graph_groups(m));
            cmd_.submit_and_wait();
        }
        vk::upload(ctx_, domain_buf_, domain.data(), uint64_t(n) * 4);
    }
    cmd_.begin_pass("graph cells");
    cmd_.fill(row_start_, 0, 0, uint64_t(grid_rows + 1) * 4);
    cmd_.dispatch("segment/graph_cells", {pos_, keys_, values_, row_start_}, grid, graph_groups(n));
    sort_.sort(cmd_, keys_, values_, n, std::max(1u, bits.x + bits.y + bits.z), sort::KeyWidth::Bits32);
    scan_.exclusive(cmd_, row_start_, row_start_, grid_rows + 1);
    cmd_.dispatch("segment/graph_sorted", {pos_, values_, sorted_}, grid, graph_groups(n));
    cmd_.begin_pass("graph knn");
    // The first shell for every node, then the further shells for those it left short of k.
    const uint32_t second_pass[4] = {0, 1, 1, 0};
    cmd_.update(short_, second_pass, sizeof second_pass);
    cmd_.dispatch(knn_kernel(k), {sorted_, keys_, row_start_, nbr_, dist_, spacing_, short_}, grid, graph_groups(n));
    if (o.shells > 1) cmd_.dispatch_indirect(knn_kernel(k), {sorted_, keys_, row_start_, nbr_, dist_, spacing_, short_}, further, short_);
    cmd_.begin_pass("graph weights");
    cmd_.dispatch("segment/graph_weights", {pos_, colour_, normal_, nbr_, dist_, spacing_, weight_}, wpush, graph_groups(nk));
    // W + W^T with each pair once: a row is the node's own slots (already grouped) and the slots
    // of nodes that list it and that it does not list, counted per row, placed by a prefix sum of
    // the row lengths and sorted within the row. The columns go to keys_, which then becomes columns_.
    cmd_.begin_pass("graph adjacency");
    cmd_.fill(reverse_count_, 0, 0, uint64_t(n) * 4);
    // dist_ (read by graph_weights only) holds each slot's twin.
    cmd_.dispatch("segment/graph_twins", {nbr_, dist_, reverse_count_}, epush, graph_groups(nk));
    cmd_.dispatch("segment/graph_row_counts", {nbr_, reverse_count_, rows_}, epush, graph_groups(uint64_t(n) + 1));
    scan_.exclusive(cmd_, rows_, rows_, n + 1);
    cmd_.dispatch("segment/graph_reverse", {nbr_, dist_, rows_, reverse_count_, keys_}, epush, graph_groups(nk));
    cmd_.dispatch("segment/graph_rows", {nbr_, dist_, weight_, rows_, keys_, adjacency_weights_, degree_}, epush, graph_groups(n));
    cmd_.end_pass();
    cmd_.submit_and_wait();
    std::swap(keys_, columns_);
    timings_ = cmd_.timings();
}

std::vector<uint32_t> KnnGraph::neighbours() const {
    return vk::download_vector<uint32_t>(ctx_, nbr_, uint64_t(nodes_) * k_);
}

std::vector<float> KnnGraph::weights() const { return vk::download_vector<float>(ctx_, weight_, uint64_t(nodes_) * k_); }

const std::vector<uint32_t>& KnnGraph::host_neighbours() const {
    if (host_nbr_.empty() && nodes_ > 0) host_nbr_ = neighbours();
    return host_nbr_;
}

const HostAdjacency& KnnGraph::host_adjacency() const {
    if (!host_adjacency_.rows.empty() || nodes_ == 0) return host_adjacency_;
    HostAdjacency& a = host_adjacency_;
    auto into = [&](auto& v, const vk::Buffer& from, size_t count) {
        v.resize(count);
        if (count) vk::download(ctx_, from, v.data(), count * sizeof(v[0]));
    };
    into(a.rows, rows_, size_t(nodes_) + 1);
    into(a.columns, columns_, a.rows[nodes_]);
    into(a.weights, adjacency_weights_, a.rows[nodes_]);
    into(a.degree, degree_, nodes_);
    return a;
}

}  // namespace pg::seg
