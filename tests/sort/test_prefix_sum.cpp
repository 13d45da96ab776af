#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <random>
#include <vector>

#include "engine/sort/prefix_sum.h"
#include "engine/vk/buffer.h"
#include "engine/vk/commands.h"
#include "engine/vk/context.h"
#include "tests/gpu_fixture.h"

using namespace pg;

namespace {

// Random values; `bound` 0 means the full 32-bit range, whose sums wrap like uint32 does.
std::vector<uint32_t> random_values(size_t n, uint64_t seed, uint32_t bound) {
    std::mt19937_64 rng(seed);
    std::vector<uint32_t> v(n);
    for (auto& x : v) x = bound ? uint32_t(rng() % bound) : uint32_t(rng());
    return v;
}

size_t first_difference(const std::vector<uint32_t>& a, const std::vector<uint32_t>& b) {
    if (a.size() != b.size()) return 0;
    return size_t(std::mismatch(a.begin(), a.end(), b.begin()).first - a.begin());
}

// Scans `values` on the GPU (in place or into a second buffer, with the total at
// `total_offset` of a separate buffer) and compares with std::exclusive_scan.
void check_scan(vk::Context& ctx, sort::PrefixSum& scan, const std::vector<uint32_t>& values, bool in_place,
                VkDeviceSize total_offset) {
    const uint32_t n = uint32_t(values.size());
    INFO("n = " << n << (in_place ? ", in place" : "") << ", total at byte " << total_offset);
    vk::Buffer in = vk::upload_vector(ctx, values, "scan in");
    vk::Buffer out(ctx, in_place ? 16 : VkDeviceSize(n) * 4, vk::MemoryUse::Device, "scan out");
    vk::Buffer total(ctx, total_offset + 64, vk::MemoryUse::Device, "scan total");
    vk::CommandList cmd(ctx);
    cmd.fill(total, 0xFFFFFFFFu);
    scan.exclusive(cmd, in, in_place ? in : out, n, &total, total_offset);
    cmd.submit_and_wait();
    std::vector<uint32_t> want(n);
    std::exclusive_scan(values.begin(), values.end(), want.begin(), 0u);
    const uint32_t want_total = std::accumulate(values.begin(), values.end(), 0u);
    CHECK(first_difference(vk::download_vector<uint32_t>(ctx, in_place ? in : out, n), want) == n);
    auto totals = vk::download_vector<uint32_t>(ctx, total, 3, total_offset - 4 * (total_offset >= 4));
    CHECK(totals[total_offset >= 4 ? 1 : 0] == want_total);
    if (total_offset >= 4) CHECK(totals[0] == 0xFFFFFFFFu);  // neighbours untouched
    CHECK(totals[total_offset >= 4 ? 2 : 1] == 0xFFFFFFFFu);
}

}  // namespace

TEST_CASE("exclusive scan matches std::exclusive_scan for sizes around the block size") {
    auto& ctx = test::gpu();
    sort::PrefixSum scan(ctx);
    // Blocks hold 3072 values: one level up to 3072, two up to 3072^2, three past that.
    std::vector<uint32_t> sizes = {1, 2, 999};
    for (uint32_t base : {1u << 8, 1u << 11, 1u << 12, 1u << 13, 1u << 16, 3072u, 6144u})
        for (int d : {-1, 0, 1}) sizes.push_back(base + uint32_t(d));
    for (uint32_t n : sizes) {
        check_scan(ctx, scan, random_values(n, n, 1000), false, 0);
        check_scan(ctx, scan, random_values(n, n + 1, 0), true, 4);
    }
    check_scan(ctx, scan, random_values(3072u * 3072u, 1, 0), false, 0);
    check_scan(ctx, scan, random_values(3072u * 3072u + 1u, 2, 0), true, 0);
}

TEST_CASE("exclusive scan of nothing writes a zero total") {
    auto& ctx = test::gpu();
    sort::PrefixSum scan(ctx);
    check_scan(ctx, scan, {}, false, 0);
    check_scan(ctx, scan, {}, true, 300);
}

TEST_CASE("exclusive scan writes the total at any aligned offset, without a total too") {
    auto& ctx = test::gpu();
    sort::PrefixSum scan(ctx);
    for (VkDeviceSize offset : {4u, 252u, 256u, 300u, 4100u}) check_scan(ctx, scan, random_values(5000, offset, 7), true, offset);
    // No total buffer.
    const auto values = random_values(70001, 5, 0);
    vk::Buffer buf = vk::upload_vector(ctx, values, "scan");
    vk::CommandList cmd(ctx);
    scan.exclusive(cmd, buf, buf, uint32_t(values.size()));
    cmd.submit_and_wait();
    std::vector<uint32_t> want(values.size());
    std::exclusive_scan(values.begin(), values.end(), want.begin(), 0u);
    CHECK(vk::download_vector<uint32_t>(ctx, buf, values.size()) == want);
}

TEST_CASE("exclusive scan of 2^26 values works past one storage-buffer range") {
    auto& ctx = test::gpu();
    sort::PrefixSum scan(ctx);
    // 256 MiB: more than lavapipe's 128 MiB maxStorageBufferRange, so it runs in windows there.
    check_scan(ctx, scan, random_values((size_t(1) << 26) + 5, 26, 0), true, 8);
}

TEST_CASE("exclusive scan works when dispatches are folded over a small group-count limit") {
    vk::ContextOptions o;
    o.validation = true;
    o.quiet = true;
    o.max_group_count_override = 2;
    vk::Context ctx(o);
    sort::PrefixSum scan(ctx);
    for (uint32_t n : {6144u, 6145u, 20000u, 3072u * 3072u + 3u}) check_scan(ctx, scan, random_values(n, n, 0), true, 0);
    CHECK(vk::Context::validation_message_count() == 0);
}

TEST_CASE("exclusive scan rejects buffers too small for n") {
    auto& ctx = test::gpu();
    sort::PrefixSum scan(ctx);
    vk::Buffer small(ctx, 64, vk::MemoryUse::Device, "tiny");
    vk::CommandList cmd(ctx);
    CHECK_THROWS_WITH(scan.exclusive(cmd, small, small, 17), Catch::Contains("tiny"));
}
