#include "engine/segment/partition.h"

#include <algorithm>
#include <stdexcept>

namespace pg::seg {

std::vector<std::vector<uint32_t>> partition_roi(const std::vector<uint32_t>& roi, uint32_t max_batch, uint64_t seed) {
    if (max_batch == 0) throw std::invalid_argument("partition_roi: max_batch must be positive");
    const size_t n = roi.size();
    if (n == 0) return {};
    const size_t batches = (n + max_batch - 1) / max_batch;
    if (batches == 1) return {roi};
    // Fisher-Yates with splitmix64: portable, unlike std::shuffle's distribution.
    std::vector<uint32_t> order(roi);
    uint64_t s = seed;
    for (size_t i = n - 1; i > 0; --i) {
        uint64_t z = (s += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        z ^= z >> 31;
        std::swap(order[i], order[size_t(z % (i + 1))]);
    }
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
