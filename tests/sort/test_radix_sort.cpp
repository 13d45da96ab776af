#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdlib>
#include <cstdint>
#include <numeric>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "engine/sort/radix_sort.h"
#include "engine/vk/buffer.h"
#include "engine/vk/commands.h"
#include "engine/vk/context.h"
#include "tests/gpu_fixture.h"

using namespace pg;
using sort::KeyWidth;

namespace {

template <class Key> constexpr KeyWidth width_of() { return sizeof(Key) == 8 ? KeyWidth::Bits64 : KeyWidth::Bits32; }

template <class Key> std::vector<Key> random_keys(size_t n, uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::vector<Key> keys(n);
    for (auto& k : keys) k = Key(rng());
    return keys;
}

// Only three distinct values in the low bits, random bits above them.
template <class Key> std::vector<Key> three_valued_keys(size_t n, uint64_t seed, uint32_t key_bits) {
    std::mt19937_64 rng(seed);
    const Key low[3] = {Key(5), Key(0), Key(Key(1) << (key_bits - 1))};
    std::vector<Key> keys(n);
    for (auto& k : keys) {
        const Key above = key_bits >= 8 * sizeof(Key) ? Key(0) : Key(rng()) << key_bits;
        k = above | low[rng() % 3];
    }
    return keys;
}

template <class Key> Key low_mask(uint32_t key_bits) {
    return key_bits >= 8 * sizeof(Key) ? ~Key(0) : Key((Key(1) << key_bits) - 1);
}

// The CPU reference: std::stable_sort on the masked keys, the original index as the value.
template <class Key>
void reference_sort(const std::vector<Key>& keys, uint32_t count, uint32_t key_bits, std::vector<Key>& sorted_keys,
                    std::vector<uint32_t>& sorted_values) {
    const Key mask = low_mask<Key>(key_bits);
    std::vector<std::pair<Key, uint32_t>> items(count);
    for (uint32_t i = 0; i < count; ++i) items[i] = {Key(keys[i] & mask), i};
    std::stable_sort(items.begin(), items.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    sorted_keys.resize(count);
    sorted_values.resize(count);
    for (uint32_t i = 0; i < count; ++i) {
        sorted_values[i] = items[i].second;
        sorted_keys[i] = keys[items[i].second];  // bits above key_bits come along unchanged
    }
}

template <class T> size_t first_difference(const std::vector<T>& a, const std::vector<T>& b) {
    if (a.size() != b.size()) return 0;
    return size_t(std::mismatch(a.begin(), a.end(), b.begin()).first - a.begin());
}

// Sorts `keys` (values: their indices) with `sorter` and compares with the reference.
template <class Key>
void check_sort(vk::Context& ctx, sort::RadixSort& sorter, const std::vector<Key>& keys, uint32_t key_bits) {
    const uint32_t n = uint32_t(keys.size());
    INFO("n = " << n << ", key_bits = " << key_bits << ", key width " << 8 * sizeof(Key));
    std::vector<uint32_t> values(n);
    std::iota(values.begin(), values.end(), 0u);
    vk::Buffer key_buf = vk::upload_vector(ctx, keys, "keys");
    vk::Buffer value_buf = vk::upload_vector(ctx, values, "values");
    vk::CommandList cmd(ctx);
    sorter.sort(cmd, key_buf, value_buf, n, key_bits, width_of<Key>());
    cmd.submit_and_wait();
    std::vector<Key> want_keys;
    std::vector<uint32_t> want_values;
    reference_sort(keys, n, key_bits, want_keys, want_values);
    const auto got_keys = vk::download_vector<Key>(ctx, key_buf, n);
    const auto got_values = vk::download_vector<uint32_t>(ctx, value_buf, n);
    CHECK(first_difference(got_values, want_values) == n);
    CHECK(first_difference(got_keys, want_keys) == n);
}

// Sizes 0, 1, odd, 2^k - 1, 2^k, 2^k + 1, around one and two blocks (3072 items) and the
// one-workgroup sort's limit.
std::vector<uint32_t> sizes_around_block() {
    std::vector<uint32_t> sizes = {0, 1, 2, 3, 999};
    // PG_SORT_SMALL (2560): the largest sort CPU devices do in one workgroup (sort/radix_sort_block).
    for (uint32_t base : {1u << 8, 1u << 11, 1u << 12, 1u << 13, 1u << 16, 2560u, 3072u, 6144u})
        for (int d : {-1, 0, 1}) sizes.push_back(base + uint32_t(d));
    return sizes;
}

// Sets an environment variable for one scope (the sorter reads PG_SORT_SCATTER when built).
class ScopedEnv {
public:
    ScopedEnv(const char* name, const char* value) : name_(name) {
        if (const char* old = std::getenv(name)) old_ = old;
        setenv(name, value, 1);
    }
    ~ScopedEnv() {
        if (old_.empty()) unsetenv(name_);
        else setenv(name_, old_.c_str(), 1);
    }

private:
    const char* name_;
    std::string old_;
};

}  // namespace

TEST_CASE("radix sort orders 32-bit keys stably for sizes around the block size") {
    auto& ctx = test::gpu();
    sort::RadixSort sorter(ctx);
    for (uint32_t n : sizes_around_block()) {
        check_sort(ctx, sorter, random_keys<uint32_t>(n, 100 + n), 32);
        check_sort(ctx, sorter, random_keys<uint32_t>(n, 200 + n), 13);
    }
}

TEST_CASE("radix sort orders 64-bit keys stably for sizes around the block size") {
    auto& ctx = test::gpu();
    sort::RadixSort sorter(ctx);
    for (uint32_t n : sizes_around_block()) {
        check_sort(ctx, sorter, random_keys<uint64_t>(n, 300 + n), 64);
        check_sort(ctx, sorter, random_keys<uint64_t>(n, 400 + n), 37);
    }
}

TEST_CASE("radix sort keeps heavily duplicated keys in input order") {
    auto& ctx = test::gpu();
    sort::RadixSort sorter(ctx);
    for (uint32_t n : {5000u, 65537u}) {
        check_sort(ctx, sorter, three_valued_keys<uint32_t>(n, 1, 32), 32);
        check_sort(ctx, sorter, three_valued_keys<uint32_t>(n, 2, 13), 13);
        check_sort(ctx, sorter, three_valued_keys<uint64_t>(n, 3, 64), 64);
        check_sort(ctx, sorter, three_valued_keys<uint64_t>(n, 4, 44), 44);
        check_sort(ctx, sorter, std::vector<uint64_t>(n, 0xDEADBEEF12345678ull), 63);
    }
}

TEST_CASE("radix sort ignores key bits above key_bits for order and keeps them in the output") {
    auto& ctx = test::gpu();
    sort::RadixSort sorter(ctx);
    // Odd pass counts (1, 5, 9, 11) end with the copy back from scratch; 0 bits is the identity.
    // 2500 items: every pass in one workgroup on CPU devices.
    for (uint32_t n : {20011u, 2500u}) {
        for (uint32_t bits : {0u, 1u, 4u, 5u, 13u, 20u, 31u})
            check_sort(ctx, sorter, random_keys<uint32_t>(n, 500 + bits), bits);
        for (uint32_t bits : {1u, 13u, 32u, 33u, 36u, 37u, 44u, 63u})
            check_sort(ctx, sorter, random_keys<uint64_t>(n, 600 + bits), bits);
    }
}

TEST_CASE("radix sort_indirect reads the count on the GPU and leaves items past it alone") {
    auto& ctx = test::gpu();
    sort::RadixSort sorter(ctx);
    const VkDeviceSize count_offset = 260;  // not on a binding alignment
    vk::Buffer count_buf(ctx, 512, vk::MemoryUse::Device, "count");
    // A capacity of 2000 sorts in one workgroup on CPU devices, whatever the count.
    for (uint32_t capacity : {10000u, 2000u})
    for (uint32_t key_bits : {32u, 44u}) {
        const bool wide = key_bits > 32;
        for (uint32_t count : {0u, 1u, 2u, 1999u, 2000u, 2047u, 2048u, 2049u, 5000u, 9999u, 10000u, 12345u}) {
            INFO("count = " << count << ", capacity = " << capacity << ", key_bits = " << key_bits);
            const uint32_t n = std::min(count, capacity);
            auto keys = random_keys<uint64_t>(capacity, 700 + count);
            std::vector<uint32_t> keys32(keys.begin(), keys.end());
            std::vector<uint32_t> values(capacity);
            std::iota(values.begin(), values.end(), 0u);
            vk::Buffer key_buf = wide ? vk::upload_vector(ctx, keys, "keys") : vk::upload_vector(ctx, keys32, "keys");
            vk::Buffer value_buf = vk::upload_vector(ctx, values, "values");
            vk::CommandList cmd(ctx);
            cmd.update(count_buf, &count, 4, count_offset);
            sorter.sort_indirect(cmd, key_buf, value_buf, count_buf, count_offset, capacity, key_bits,
                                 wide ? KeyWidth::Bits64 : KeyWidth::Bits32);
            cmd.submit_and_wait();
            std::vector<uint32_t> want_values, got_values = vk::download_vector<uint32_t>(ctx, value_buf, capacity);
            if (wide) {
                std::vector<uint64_t> want_keys;
                reference_sort(keys, n, key_bits, want_keys, want_values);
                want_keys.insert(want_keys.end(), keys.begin() + n, keys.end());
                CHECK(first_difference(vk::download_vector<uint64_t>(ctx, key_buf, capacity), want_keys) == capacity);
            } else {
                std::vector<uint32_t> want_keys;
                reference_sort(keys32, n, key_bits, want_keys, want_values);
                want_keys.insert(want_keys.end(), keys32.begin() + n, keys32.end());
                CHECK(first_difference(vk::download_vector<uint32_t>(ctx, key_buf, capacity), want_keys) == capacity);
            }
            want_values.insert(want_values.end(), values.begin() + n, values.end());
            CHECK(first_difference(got_values, want_values) == capacity);
        }
    }
}

TEST_CASE("one radix sorter is reused across calls, sizes and key widths") {
    auto& ctx = test::gpu();
    sort::RadixSort sorter(ctx);
    check_sort(ctx, sorter, random_keys<uint64_t>(50000, 1), 44);
    check_sort(ctx, sorter, random_keys<uint32_t>(3000, 2), 32);
    check_sort(ctx, sorter, random_keys<uint64_t>(200000, 3), 63);
    check_sort(ctx, sorter, random_keys<uint32_t>(1, 4), 32);
    check_sort(ctx, sorter, random_keys<uint32_t>(0, 5), 32);
    check_sort(ctx, sorter, random_keys<uint32_t>(70000, 6), 30);

    // Two sorts in one command list, the second growing the scratch the first one uses.
    sort::RadixSort fresh(ctx);
    const auto small = random_keys<uint32_t>(1000, 7), large = random_keys<uint32_t>(100000, 8);
    std::vector<uint32_t> small_values(small.size()), large_values(large.size());
    std::iota(small_values.begin(), small_values.end(), 0u);
    std::iota(large_values.begin(), large_values.end(), 0u);
    vk::Buffer small_keys = vk::upload_vector(ctx, small, "small keys");
    vk::Buffer small_vals = vk::upload_vector(ctx, small_values, "small values");
    vk::Buffer large_keys = vk::upload_vector(ctx, large, "large keys");
    vk::Buffer large_vals = vk::upload_vector(ctx, large_values, "large values");
    vk::CommandList cmd(ctx);
    fresh.sort(cmd, small_keys, small_vals, uint32_t(small.size()), 32, KeyWidth::Bits32);
    fresh.sort(cmd, large_keys, large_vals, uint32_t(large.size()), 32, KeyWidth::Bits32);
    cmd.submit_and_wait();
    std::vector<uint32_t> want_keys, want_values;
    reference_sort(small, uint32_t(small.size()), 32, want_keys, want_values);
    CHECK(vk::download_vector<uint32_t>(ctx, small_keys, small.size()) == want_keys);
    CHECK(vk::download_vector<uint32_t>(ctx, small_vals, small.size()) == want_values);
    reference_sort(large, uint32_t(large.size()), 32, want_keys, want_values);
    CHECK(vk::download_vector<uint32_t>(ctx, large_keys, large.size()) == want_keys);
    CHECK(vk::download_vector<uint32_t>(ctx, large_vals, large.size()) == want_values);
}

TEST_CASE("both scatter variants, shared-memory exchange (GPUs) and direct (CPUs), are exact") {
    auto& ctx = test::gpu();
    for (const char* mode : {"exchange", "direct"}) {
        INFO("PG_SORT_SCATTER=" << mode);
        ScopedEnv env("PG_SORT_SCATTER", mode);
        sort::RadixSort sorter(ctx);
        for (uint32_t n : {1u, 999u, 3071u, 3072u, 3073u, 65537u}) {
            check_sort(ctx, sorter, random_keys<uint32_t>(n, 800 + n), 32);
            check_sort(ctx, sorter, random_keys<uint64_t>(n, 900 + n), 64);
        }
        check_sort(ctx, sorter, three_valued_keys<uint32_t>(40000, 12, 20), 20);
        check_sort(ctx, sorter, three_valued_keys<uint64_t>(40000, 13, 44), 44);
        check_sort(ctx, sorter, random_keys<uint64_t>(40000, 14), 37);
    }
    ScopedEnv bad("PG_SORT_SCATTER", "fastest");
    CHECK_THROWS_WITH(sort::RadixSort(ctx), Catch::Contains("PG_SORT_SCATTER"));
}

TEST_CASE("radix sort of ten million 32-bit pairs is exact") {
    auto& ctx = test::gpu();
    sort::RadixSort sorter(ctx);
    check_sort(ctx, sorter, random_keys<uint32_t>(10'000'000, 42), 32);
}

TEST_CASE("radix sort of ten million 64-bit pairs is exact") {
    auto& ctx = test::gpu();
    sort::RadixSort sorter(ctx);
    check_sort(ctx, sorter, random_keys<uint64_t>(10'000'003, 43), 64);
}

TEST_CASE("radix sort works when dispatches are folded over a small group-count limit") {
    vk::ContextOptions o;
    o.validation = true;
    o.quiet = true;
    o.max_group_count_override = 3;  // anything over 3 blocks (9216 items) is folded into 2D
    vk::Context ctx(o);
    sort::RadixSort sorter(ctx);
    check_sort(ctx, sorter, random_keys<uint32_t>(20000, 9), 32);
    check_sort(ctx, sorter, random_keys<uint64_t>(14337, 10), 37);

    const uint32_t capacity = 30000, count = 25001;
    auto keys = random_keys<uint32_t>(capacity, 11);
    std::vector<uint32_t> values(capacity);
    std::iota(values.begin(), values.end(), 0u);
    vk::Buffer key_buf = vk::upload_vector(ctx, keys, "keys");
    vk::Buffer value_buf = vk::upload_vector(ctx, values, "values");
    vk::Buffer count_buf = vk::upload_vector(ctx, std::vector<uint32_t>{count}, "count");
    vk::CommandList cmd(ctx);
    sorter.sort_indirect(cmd, key_buf, value_buf, count_buf, 0, capacity, 21, KeyWidth::Bits32);
    cmd.submit_and_wait();
    std::vector<uint32_t> want_keys, want_values;
    reference_sort(keys, count, 21, want_keys, want_values);
    CHECK(vk::download_vector<uint32_t>(ctx, key_buf, count) == want_keys);
    CHECK(vk::download_vector<uint32_t>(ctx, value_buf, count) == want_values);
    CHECK(vk::Context::validation_message_count() == 0);
}

TEST_CASE("radix sort rejects key_bits wider than the keys and buffers too small") {
    auto& ctx = test::gpu();
    sort::RadixSort sorter(ctx);
    vk::Buffer keys(ctx, 400, vk::MemoryUse::Device, "small keys"), values(ctx, 400, vk::MemoryUse::Device, "v");
    vk::CommandList cmd(ctx);
    CHECK_THROWS_AS(sorter.sort(cmd, keys, values, 10, 33, KeyWidth::Bits32), std::invalid_argument);
    CHECK_THROWS_AS(sorter.sort(cmd, keys, values, 10, 65, KeyWidth::Bits64), std::invalid_argument);
    CHECK_THROWS_WITH(sorter.sort(cmd, keys, values, 60, 64, KeyWidth::Bits64), Catch::Contains("small keys"));
}
