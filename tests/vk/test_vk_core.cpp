#include <catch2/catch.hpp>

#include <algorithm>
#include <numeric>

#include "engine/vk/buffer.h"
#include "engine/vk/commands.h"
#include "engine/vk/context.h"
#include "shaders/common/common_shared.h"
#include "tests/gpu_fixture.h"

using namespace pg;

using vk::gpu::FillPush;
using vk::gpu::IndirectArgsPush;

namespace {
// A quiet context of its own with validation on, its device memory unified or split as a
// discrete GPU's (host-visible staging, unmapped device buffers).
vk::ContextOptions validated(bool discrete_memory) {
    vk::ContextOptions o;
    o.validation = true;
    o.quiet = true;
    o.discrete_memory = discrete_memory;
    return o;
}
}  // namespace

TEST_CASE("the context picks a device and reports it") {
    auto& ctx = test::gpu();
    CHECK_FALSE(ctx.info().name.empty());
    CHECK(ctx.info().max_group_count[0] >= 65535);
    CHECK(ctx.info().max_storage_buffer_range > 0);
}

TEST_CASE("an unknown --device name is one clear error listing the devices") {
    vk::ContextOptions o;
    o.device = "no-such-gpu-xyz";
    o.quiet = true;
    try {
        vk::Context ctx(o);
        FAIL("expected an error");
    } catch (const std::runtime_error& e) {
        std::string msg = e.what();
        CHECK(msg.find("no-such-gpu-xyz") != std::string::npos);
        CHECK(msg.find("have:") != std::string::npos);
    }
}

TEST_CASE("buffers round-trip through every memory use") {
    auto& ctx = test::gpu();
    std::vector<uint32_t> data(1000);
    std::iota(data.begin(), data.end(), 7u);
    for (auto use : {vk::MemoryUse::Device, vk::MemoryUse::Upload, vk::MemoryUse::Readback}) {
        vk::Buffer b(ctx, data.size() * 4, use, "roundtrip");
        vk::upload(ctx, b, data.data(), data.size() * 4);
        CHECK(vk::download_vector<uint32_t>(ctx, b, data.size()) == data);
        // Partial windows with offsets.
        auto part = vk::download_vector<uint32_t>(ctx, b, 10, 40);
        CHECK(part[0] == data[10]);
    }
    vk::Buffer empty(ctx, 0, vk::MemoryUse::Device, "empty");
    CHECK(empty.valid());
}

TEST_CASE("with discrete memory emulated, device buffers are not mapped and data goes through staging") {
    vk::Context ctx(validated(true));
    CHECK_FALSE(ctx.info().unified_memory);
    std::vector<uint32_t> data(5000);
    std::iota(data.begin(), data.end(), 3u);
    vk::Buffer dev(ctx, data.size() * 4, vk::MemoryUse::Device, "device");
    CHECK_FALSE(dev.mapped());
    CHECK(vk::Buffer(ctx, 64, vk::MemoryUse::Readback, "readback").mapped());
    vk::upload(ctx, dev, data.data(), data.size() * 4);
    // A GPU copy between two unmapped buffers, then a download through staging.
    vk::Buffer other(ctx, data.size() * 4, vk::MemoryUse::Device, "other");
    vk::CommandList cmd(ctx);
    cmd.copy(dev, other, data.size() * 4);
    cmd.submit_and_wait();
    CHECK(vk::download_vector<uint32_t>(ctx, other, data.size()) == data);
    CHECK(vk::download_vector<uint32_t>(ctx, other, 5, 400)[0] == data[100]);
}

TEST_CASE("uploads recorded in a command list land before its later commands, staged or mapped, list after list") {
    for (const bool discrete : {false, true}) {
        vk::Context ctx(validated(discrete));
        // Larger than the list's first staging chunk (1 MiB), so a second chunk is taken.
        std::vector<uint32_t> small(5000), big(600000);
        vk::Buffer a(ctx, small.size() * 4, vk::MemoryUse::Device, "a"), b(ctx, big.size() * 4, vk::MemoryUse::Device, "b");
        vk::Buffer copied(ctx, small.size() * 4, vk::MemoryUse::Device, "copied");
        vk::CommandList cmd(ctx);
        for (uint32_t round = 0; round < 3; ++round) {
            std::iota(small.begin(), small.end(), 11u * round);
            std::iota(big.begin(), big.end(), 1000u + round);
            cmd.upload(a, small.data(), small.size() * 4);
            cmd.upload(b, big.data(), big.size() * 4);
            cmd.copy(a, copied, small.size() * 4);
            std::vector<uint32_t> patch(10, 77u + round);
            cmd.upload(b, patch.data(), 40, 400);  // over part of b, after its first upload
            cmd.submit_and_wait();
            CHECK(vk::download_vector<uint32_t>(ctx, copied, small.size()) == small);
            auto got = vk::download_vector<uint32_t>(ctx, b, big.size());
            std::copy(patch.begin(), patch.end(), big.begin() + 100);
            CHECK(std::mismatch(got.begin(), got.end(), big.begin()).first - got.begin() == ptrdiff_t(big.size()));
        }
        CHECK(vk::Context::validation_message_count() == 0);
    }
}

TEST_CASE("transfers larger than the staging memory go in chunks, offsets kept") {
    vk::Context ctx(validated(true));
    // 40 MiB + a bit: past the 32 MiB the context keeps for staging.
    const size_t n = (size_t(40) << 18) + 77;
    std::vector<uint32_t> data(n);
    std::iota(data.begin(), data.end(), 5u);
    vk::Buffer dev(ctx, (n + 16) * 4, vk::MemoryUse::Device, "device");
    vk::upload(ctx, dev, data.data(), n * 4, 64);
    auto got = vk::download_vector<uint32_t>(ctx, dev, n, 64);
    CHECK(std::mismatch(got.begin(), got.end(), data.begin()).first - got.begin() == ptrdiff_t(n));
    CHECK(vk::download_vector<uint32_t>(ctx, dev, 3, 64 + 4 * (n - 3))[2] == data[n - 1]);
}

TEST_CASE("a buffer larger than the device allows is a clear error, and >4 GiB works where allowed") {
    auto& ctx = test::gpu();
    const VkDeviceSize five_gib = 5ull << 30;
    const auto& info = ctx.info();
    if (five_gib > info.max_allocation_size || five_gib > info.max_buffer_size) {
        try {
            vk::Buffer b(ctx, five_gib, vk::MemoryUse::Device, "huge");
            FAIL("expected an error");
        } catch (const std::runtime_error& e) {
            CHECK(std::string(e.what()).find("huge") != std::string::npos);
        }
    } else if (info.device_memory_bytes > 2 * five_gib) {
        vk::Buffer b(ctx, five_gib, vk::MemoryUse::Device, "huge");
        CHECK(b.size() >= five_gib);
        // Write past 4 GiB and read it back: 64-bit offsets all the way.
        vk::CommandList cmd(ctx);
        cmd.fill(b, 0xABCD1234u, (4ull << 30) + 64, 64);
        cmd.submit_and_wait();
        CHECK(vk::download_vector<uint32_t>(ctx, b, 1, (4ull << 30) + 64)[0] == 0xABCD1234u);
    }
}

TEST_CASE("dispatches over the group-count limit are split, never refused") {
    vk::ContextOptions o;
    o.validation = true;
    o.quiet = true;
    o.max_group_count_override = 7;  // 64-wide groups: anything over 448 items is folded
    vk::Context ctx(o);
    for (uint32_t n : {1u, 63u, 64u, 448u, 449u, 1000u, 4099u}) {
        vk::Buffer b(ctx, n * 4, vk::MemoryUse::Device, "fill");
        vk::CommandList cmd(ctx);
        cmd.fill(b, 0);
        cmd.dispatch("common/fill_u32", {b}, FillPush{n, 5}, vk::ceil_div(n, 64));
        cmd.submit_and_wait();
        auto out = vk::download_vector<uint32_t>(ctx, b, n);
        for (uint32_t i = 0; i < n; ++i) REQUIRE(out[i] == 5 + i);
    }
    CHECK(vk::Context::validation_message_count() == 0);
}

TEST_CASE("indirect dispatch from a GPU-written count needs no host round trip") {
    vk::ContextOptions o;
    o.validation = true;
    o.quiet = true;
    o.max_group_count_override = 5;
    vk::Context ctx(o);
    const uint32_t capacity = 2000;
    vk::Buffer counts(ctx, 16, vk::MemoryUse::Device, "counts");
    vk::Buffer args(ctx, 16, vk::MemoryUse::Device, "args");
    vk::Buffer data(ctx, capacity * 4, vk::MemoryUse::Device, "data");
    for (uint32_t n : {0u, 1u, 320u, 321u, 1999u}) {
        vk::CommandList cmd(ctx);
        cmd.fill(data, 0xFFFFFFFFu);
        cmd.update(counts, &n, 4);
        cmd.dispatch("common/indirect_args", {counts, args}, IndirectArgsPush{0, 64, ctx.max_group_count_x(), 0, 0}, 1);
        cmd.dispatch_indirect("common/fill_u32", {data}, FillPush{n, 0}, args);
        cmd.submit_and_wait();
        auto out = vk::download_vector<uint32_t>(ctx, data, capacity);
        for (uint32_t i = 0; i < capacity; ++i) REQUIRE(out[i] == (i < n ? i : 0xFFFFFFFFu));
    }
    CHECK(vk::Context::validation_message_count() == 0);
}

TEST_CASE("dependent passes are ordered by automatic barriers and timed") {
    auto& ctx = test::gpu();
    const uint32_t n = 5000;
    vk::Buffer a(ctx, n * 4, vk::MemoryUse::Device, "a"), b(ctx, n * 4, vk::MemoryUse::Device, "b");
    vk::CommandList cmd(ctx);
    cmd.begin_pass("fill");
    cmd.dispatch("common/fill_u32", {a}, FillPush{n, 1}, vk::ceil_div(n, 64));
    cmd.begin_pass("copy");
    cmd.copy(a, b, n * 4);
    cmd.begin_pass("overwrite");
    cmd.dispatch("common/fill_u32", {a}, FillPush{n, 100}, vk::ceil_div(n, 64));
    cmd.end_pass();
    cmd.submit_and_wait();
    auto vb = vk::download_vector<uint32_t>(ctx, b, n);
    auto va = vk::download_vector<uint32_t>(ctx, a, n);
    CHECK(vb[n - 1] == 1 + n - 1);
    CHECK(va[n - 1] == 100 + n - 1);
    if (ctx.info().timestamps) {
        REQUIRE(cmd.timings().size() == 3);
        CHECK(cmd.timings()[0].name == "fill");
        for (auto& t : cmd.timings()) CHECK(t.ms >= 0.0);
    }
}
