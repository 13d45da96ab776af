// Texel-buffer bindings (engine/vk/spirv_bindings.h): what a shader declares decides each
// binding's descriptor type and view format; the data a kernel reads through them is the data a
// storage buffer would give (the graph and walk tests check whole kernels against CPU references).
#include <catch2/catch.hpp>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "engine/vk/buffer.h"
#include "engine/vk/commands.h"
#include "engine/vk/context.h"
#include "engine/vk/spirv_bindings.h"
#include "shaders/segment/graph_shared.h"
#include "shaders/shaders.h"
#include "tests/gpu_fixture.h"

using namespace pg;

TEST_CASE("a shader's texel buffers are read from its SPIR-V, with their formats") {
    const auto kinds = vk::spirv_bindings(shaders::spirv("segment/walk_apply_v1"), 8);
    REQUIRE(kinds.size() == 8);
    const VkFormat want[6] = {VK_FORMAT_R32_UINT,   VK_FORMAT_R32_UINT, VK_FORMAT_R32_SFLOAT,
                              VK_FORMAT_R32_SFLOAT, VK_FORMAT_R32_SINT, VK_FORMAT_R32G32B32A32_SFLOAT};
    for (uint32_t b = 0; b < 6; ++b) {
        INFO("binding " << b);
        CHECK(kinds[b].type == VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER);
        CHECK(kinds[b].format == want[b]);
        CHECK(kinds[b].texel_bytes == (b == 5 ? 16u : 4u));
    }
    CHECK(kinds[6].type == VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);  // written
    CHECK(kinds[7].type == VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);

    for (const auto& k : vk::spirv_bindings(shaders::spirv("segment/graph_cells"), 3))
        CHECK(k.type == VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);

    // The header, then an instruction that claims to run past the module's end.
    const auto code = shaders::spirv("segment/walk_apply_v1");
    std::vector<uint32_t> cut(code.begin(), code.begin() + 5);
    cut.push_back(0xFFFF0000u | 71u);
    CHECK_THROWS_AS(vk::spirv_bindings(cut, 8), std::runtime_error);
}

TEST_CASE("graph_weights reads through texel views what was uploaded, and refuses a misaligned view") {
    auto& ctx = test::gpu();
    // Two nodes, one slot each pointing at the other: the weight is a closed form of the inputs.
    const std::vector<float> pos = {0, 0, 0, 0.5f, 1, 0, 0, 0.25f};
    const std::vector<float> colour = {0.1f, 0.2f, 0.3f, 0, 0.2f, 0.2f, 0.1f, 0};
    const std::vector<float> normal = {0, 0, 1, 0, 0, 0, 1, 0};
    const std::vector<uint32_t> nbr = {1, 0};
    const std::vector<float> dist = {1, 1}, spacing = {0.5f, 2.0f};
    auto b_pos = vk::upload_vector(ctx, pos), b_colour = vk::upload_vector(ctx, colour), b_normal = vk::upload_vector(ctx, normal);
    auto b_nbr = vk::upload_vector(ctx, nbr), b_dist = vk::upload_vector(ctx, dist), b_spacing = vk::upload_vector(ctx, spacing);
    vk::Buffer b_weight(ctx, 2 * sizeof(float));
    seg::gpu::GraphWeightsPush push{};
    push.beta = {2.0f, 0.0f, 1.0f, 1.0f};
    push.size = {2, 1, 0, 0};
    {
        vk::CommandList cmd(ctx);
        cmd.dispatch("segment/graph_weights", {b_pos, b_colour, b_normal, b_nbr, b_dist, b_spacing, b_weight}, push, 1);
        cmd.submit_and_wait();
    }
    const auto got = vk::download_vector<float>(ctx, b_weight, 2);
    // exp(-2 |dc|^2 - (d / sqrt(s_i s_j))^2) * min opacity; |dc|^2 = 0.01 + 0 + 0.04, s = 1.
    const double want = std::exp(-2.0 * 0.05 - 1.0) * 0.25;
    CHECK(got[0] == Approx(want).epsilon(1e-5));
    CHECK(got[1] == Approx(want).epsilon(1e-5));

    vk::Buffer big(ctx, 64);
    vk::CommandList cmd(ctx);
    CHECK_THROWS_AS(cmd.dispatch("segment/graph_weights",
                                 {vk::BufferRange(big, 1, 32), b_colour, b_normal, b_nbr, b_dist, b_spacing, b_weight},
                                 push, 1),
                    std::logic_error);
}
