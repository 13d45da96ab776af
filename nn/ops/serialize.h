#pragma once
// Serialization of voxel grids (PTv3's point orders): Pointcept's 64-bit z-order and Hilbert
// codes, and the stable argsort that turns codes into an order and its inverse.
#include <bit>
#include <cstdint>
#include <initializer_list>
#include <vector>

#include "engine/sort/prefix_sum.h"
#include "engine/sort/radix_sort.h"
#include "nn/tensor.h"

namespace pg::nn::ops {

enum class Order { Z, ZTrans, Hilbert, HilbertTrans };

// Bits per axis of the codes: bit_length of the largest grid entry over the batch (the
// standalone PTv3 release; newer Pointcept uses bit_length(max + 1)).
inline int serialization_depth(int max_grid_entry) {
    return max_grid_entry <= 0 ? 0 : int(std::bit_width(unsigned(max_grid_entry)));
}

// 64-bit serialization codes (batch << 3*depth) | curve(grid) for grid [N,3] int32 >= 0,
// batch [N] int32; grid bits at and above `depth` are ignored, as in Pointcept. Bit-exact with
// Pointcept (z: bit i of x->3i+2, y->3i+1, z->3i; *Trans swaps x and y first; hilbert: Skilling
// transpose + MSB-first interleave + Gray decode). depth in [0, 21]; batch bits shifted past
// bit 63 are lost (Pointcept asserts 3*depth + bits of the batch count <= 63). Result U64 [N].
Tensor serialize_codes(vk::CommandList& cmd, Pool& pool, const Tensor& grid, const Tensor& batch, Order order,
                       int depth);

// Stable argsort of U64 codes [N] on their low key_bits bits: order[j] = index of the j-th
// smallest (ties by index), inverse[order[j]] = j (both I32 [N]).
struct Sorted {
    Tensor order, inverse;
};
Sorted sort_codes(vk::CommandList& cmd, Pool& pool, const Tensor& codes, int key_bits);

// Frees the sorter state the structure ops keep in the context (see detail::IndexState) early;
// the context frees it anyway. Work recorded earlier must have completed.
void release_index_state(vk::Context& ctx);

namespace detail {
// What the structure ops keep between calls, per context: the sort and scan (their scratch
// buffers must outlive the command lists they were recorded into, so they cannot be locals)
// and a host-visible buffer for the counts read back after a wait.
struct IndexState {
    explicit IndexState(vk::Context& ctx);
    sort::RadixSort sort;
    sort::PrefixSum scan;
    vk::Buffer readback;
};
IndexState& index_state(vk::Context& ctx);

// Throws std::invalid_argument naming the op unless t has the dtype and shape (-1: any size).
void expect(const char* op, const char* name, const Tensor& t, DType dtype, std::initializer_list<int64_t> shape);
uint64_t groups(uint64_t threads);
// A U32 [PG_INFO_WORDS] info tensor, zeroed in the stream.
Tensor info_tensor(vk::CommandList& cmd, Pool& pool);
// Copies the info words to the host: records the copy, submits, waits (the one host wait).
std::vector<uint32_t> submit_and_read_info(vk::CommandList& cmd, IndexState& state, const Tensor& info);
}  // namespace detail

}  // namespace pg::nn::ops
