#pragma once
// The graph decoder's graph on the GPU: the k nearest neighbours of every Gaussian of a domain
// (a uniform grid over the domain's robust bounds, cell side a multiple of the median spacing,
// the 27 surrounding cells searched, further shells for a node short of k if asked), an affinity
// per edge from colour, distance relative to
// the local spacing, normals of the flattest axes and opacity, and the symmetric adjacency
// W + W^T as CSR rows (columns and weights, each pair once) with each node's degree.
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "dataset/gaussian_cloud.h"
#include "engine/render/gpu_scene.h"
#include "engine/segment/host_adjacency.h"
#include "engine/sort/prefix_sum.h"
#include "engine/sort/radix_sort.h"
#include "engine/vk/buffer.h"
#include "engine/vk/commands.h"

namespace pg::seg {

struct GraphOptions {
    uint32_t k = 10;            // neighbours per node (at most 16)
    float cell = 2.5f;          // grid cell side in median nearest-neighbour distances
    uint32_t shells = 2;        // shells of cells searched around a node's own; beyond the first only
                                // by a node short of k (at most kGraphMaxShells). More joins sparse
                                // Gaussians to the rest, but floaters then bridge objects.
    float colour = 3.0f;        // beta_c: weight exp(-beta_c |rgb_i - rgb_j|^2), rgb in [0, 1]
    float normal = 2.0f;        // beta_n: exp(-beta_n f_i f_j (1 - (n_i . n_j)^2))
    float distance = 1.0f;      // beta_d: exp(-(d / (beta_d s))^2), s the local spacing
    float opacity = 1.0f;       // beta_o: min(o_i, o_j)^beta_o (0: opacity plays no part)
    bool operator==(const GraphOptions&) const = default;
};

class KnnGraph {
public:
    explicit KnnGraph(vk::Context& ctx);

    // Most nodes a graph of k neighbours per node holds on this device: its widest arrays (the
    // symmetric adjacency's 2 k edge keys per node; the walk's label columns) within one binding.
    static uint64_t max_nodes(const vk::Context& ctx, uint32_t k);

    // Builds the graph over `domain` (scene indices, as the node order); `cloud` is the host
    // copy of the scene, for the bounds and spacing that size the grid. More than max_nodes()
    // nodes is an error.
    void build(const render::GpuScene& scene, const data::GaussianCloud& cloud, const std::vector<uint32_t>& domain,
               const GraphOptions& options);

    uint32_t nodes() const { return nodes_; }
    uint32_t k() const { return k_; }
    const std::vector<uint32_t>& domain() const { return domain_; }
    float cell_side() const { return cell_; }
    float median_spacing() const { return median_spacing_; }
    const std::vector<vk::PassTiming>& timings() const { return timings_; }

    // Host copies, for tests and component counts: k per node, kGraphNone for an empty slot.
    std::vector<uint32_t> neighbours() const;
    std::vector<float> weights() const;
    // The same, downloaded once per build and kept: the solves of further clicks on this graph
    // (seeding, components, the host forest) read them without waiting on the device again.
    const std::vector<uint32_t>& host_neighbours() const;
    const HostAdjacency& host_adjacency() const;

    // Device buffers the random walker reads.
    // W + W^T, each pair once (a pair that lists each other weighs both slots): CSR rows.
    const vk::Buffer& rows() const { return rows_; }  // n + 1 starts into the next two
    const vk::Buffer& columns() const { return columns_; }
    const vk::Buffer& adjacency_weights() const { return adjacency_weights_; }
    const vk::Buffer& degree_buffer() const { return degree_; }

private:
    vk::Context& ctx_;
    vk::CommandList cmd_;
    sort::RadixSort sort_;
    sort::PrefixSum scan_;
    std::unique_ptr<render::SceneSlab> slab_;  // a streamed scene's domain, a slab at a time
    vk::Buffer domain_buf_, pos_, colour_, normal_, keys_, values_, nbr_, dist_, spacing_, weight_, rows_, degree_;
    vk::Buffer reverse_count_;  // per node: slots of the reverse half its row receives
    vk::Buffer row_start_, sorted_;  // the grid's rows of cells along x, nodes in cell order
    vk::Buffer short_;               // graph_knn's second pass: its dispatch, then the nodes short of k
    vk::Buffer columns_, adjacency_weights_;
    std::vector<uint32_t> domain_;
    mutable std::vector<uint32_t> host_nbr_;      // empty until asked for after a build
    mutable HostAdjacency host_adjacency_;
    uint32_t nodes_ = 0, k_ = 0;
    float cell_ = 0, median_spacing_ = 0;
    std::vector<vk::PassTiming> timings_;
};

}  // namespace pg::seg
