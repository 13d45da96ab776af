#include "engine/segment/partition.h"

#include <algorithm>
#include <stdexcept>

#include "dataset/random.h"

namespace pg::seg {

std::vector<std::vector<uint32_t>> partition_roi(const std::vector<uint32_t>& roi, uint32_t max_batch, uint64_t seed) {
    if (max_batch == 0) throw std::invalid_argument("partition_roi: max_batch must be positive");
    const size_t n = roi.size();
    if (n == 0) return {};
    const size_t batches = (n + max_batch - 1) / max_batch;
    if (batches == 1) return {roi};
    // Fisher-Yates with our own generator: portable, unlike std::shuffle's distribution.
    std::vector<uint32_t> order(roi);
    data::Rng rng(seed);
    for (size_t i = n - 1; i > 0; --i) std::swap(order[i], order[size_t(rng.next() % (i + 1))]);
    std::vector<std::vector<uint32_t>> out(batches);
    for (size_t b = 0, start = 0; b < batches; ++b) {
        size_t size = n / batches + (b < n % batches ? 1 : 0);
        out[b].assign(order.begin() + long(start), order.begin() + long(start + size));
        std::sort(out[b].begin(), out[b].end());
        start += size;
    }
    return out;
}

}  // namespace pg::seg
