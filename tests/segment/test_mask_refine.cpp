#include <catch2/catch.hpp>

#include <algorithm>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/segment/mask_refine.h"
#include "engine/vk/buffer.h"
#include "engine/vk/commands.h"
#include "engine/vk/context.h"
#include "tests/gpu_fixture.h"
#include "tests/reference/mask_refine_ref.h"

using namespace pg;

namespace {

struct Image {
    int w = 0, h = 0;
    std::vector<uint32_t> px;
    uint32_t at(int x, int y) const { return px[size_t(y) * size_t(w) + size_t(x)]; }
};

// Rows of '.' (background) and digits (instance ids).
Image parse(const std::vector<std::string>& rows) {
    Image im{int(rows[0].size()), int(rows.size()), {}};
    for (auto& row : rows)
        for (char c : row) im.px.push_back(c == '.' ? 0u : uint32_t(c - '0'));
    return im;
}

// `im` inside a frame of m background pixels: closings near the border would reach it.
Image pad(const Image& im, int m) {
    Image out{im.w + 2 * m, im.h + 2 * m, {}};
    out.px.assign(size_t(out.w) * size_t(out.h), 0);
    for (int y = 0; y < im.h; ++y)
        for (int x = 0; x < im.w; ++x) out.px[size_t(y + m) * size_t(out.w) + size_t(x + m)] = im.at(x, y);
    return out;
}

seg::RefineOptions stages(std::vector<int> radii, bool holes, bool largest) {
    seg::RefineOptions o;
    o.closing_radii = std::move(radii);
    o.fill_holes = holes;
    o.largest_component = largest;
    return o;
}

// One refiner for all tests: its buffers grow and are reused across image sizes.
seg::MaskRefiner& refiner() {
    static auto* r = new seg::MaskRefiner(test::gpu());  // leaked like the context
    return *r;
}

std::vector<uint32_t> gpu_refine(const Image& im, const seg::RefineOptions& o, bool in_place = false) {
    auto& ctx = test::gpu();
    vk::Buffer in = vk::upload_vector(ctx, im.px, "test labels");
    vk::Buffer out(ctx, im.px.size() * 4, vk::MemoryUse::Device, "test refined labels");
    vk::CommandList cmd(ctx);
    refiner().refine(cmd, in, in_place ? in : out, im.w, im.h, o);
    cmd.submit_and_wait();
    auto result = vk::download_vector<uint32_t>(ctx, in_place ? in : out, im.px.size());
    if (!in_place) CHECK(vk::download_vector<uint32_t>(ctx, in, im.px.size()) == im.px);  // input untouched
    return result;
}

std::vector<uint32_t> cpu_refine(const Image& im, const seg::RefineOptions& o) {
    return ref::refine_labels(im.px, im.w, im.h, o.closing_radii, o.fill_holes, o.largest_component);
}

// Index of the first differing pixel, for a readable failure; -1 when equal.
long first_difference(const std::vector<uint32_t>& a, const std::vector<uint32_t>& b) {
    if (a.size() != b.size()) return 0;
    for (size_t i = 0; i < a.size(); ++i)
        if (a[i] != b[i]) return long(i);
    return -1;
}

void check_matches_reference(const Image& im, const seg::RefineOptions& o, const std::string& what) {
    INFO(what << " " << im.w << "x" << im.h);
    const auto want = cpu_refine(im, o);
    const auto got = gpu_refine(im, o);
    const long d = first_difference(got, want);
    INFO("first difference at pixel " << d << " (x " << (d < 0 ? -1 : d % im.w) << ", y "
                                      << (d < 0 ? -1 : d / im.w) << "): gpu "
                                      << (d < 0 ? 0 : got[size_t(d)]) << ", reference "
                                      << (d < 0 ? 0 : want[size_t(d)]));
    CHECK(d == -1);
}

// Blobs (discs, ellipses, rings, bars with gaps), speckle noise and holes, with `ids`
// distinct instance ids drawn from a sparse set.
Image random_image(int w, int h, uint32_t seed, int ids) {
    std::mt19937 rng(seed);
    auto uni = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
    std::vector<uint32_t> pool;
    const uint32_t sparse[] = {1, 2, 3, 7, 12, 40, 41, 999, 1000, 65536, 123456789, 0xFFFFFFFFu};
    for (int i = 0; i < ids; ++i) pool.push_back(i < 12 ? sparse[i] : uint32_t(5000 + 17 * i));
    std::shuffle(pool.begin(), pool.end(), rng);
    Image im{w, h, std::vector<uint32_t>(size_t(w) * size_t(h), 0)};
    auto set = [&](int x, int y, uint32_t v) {
        if (x >= 0 && y >= 0 && x < w && y < h) im.px[size_t(y) * size_t(w) + size_t(x)] = v;
    };
    const int blobs = uni(3, 10);
    for (int b = 0; b < blobs; ++b) {
        const uint32_t id = pool[size_t(uni(0, ids - 1))];
        const int cx = uni(0, w - 1), cy = uni(0, h - 1), rx = uni(2, std::max(3, w / 5)), ry = uni(2, std::max(3, h / 5));
        const int kind = uni(0, 3);
        for (int y = cy - ry; y <= cy + ry; ++y)
            for (int x = cx - rx; x <= cx + rx; ++x) {
                const double u = double(x - cx) / rx, v = double(y - cy) / ry, d = u * u + v * v;
                if (d > 1.0) continue;
                if (kind == 1 && d < 0.3) continue;                 // ring: a hole in the middle
                if (kind == 2 && (x - cx + 1000) % 9 < uni(0, 4)) continue;  // gaps of 0-4 px
                set(x, y, id);
            }
        if (kind == 3)  // a second instance inside: a hole bordered by two instances
            for (int y = cy - ry / 3; y <= cy + ry / 3; ++y)
                for (int x = cx - rx / 3; x <= cx + rx / 3; ++x) set(x, y, x < cx ? 0u : pool[size_t(uni(0, ids - 1))]);
    }
    const int specks = uni(0, w * h / 30);
    for (int s = 0; s < specks; ++s) set(uni(0, w - 1), uni(0, h - 1), uni(0, 3) == 0 ? 0u : pool[size_t(uni(0, ids - 1))]);
    return im;
}

}  // namespace

TEST_CASE("refine: a ring of one instance gets its hole filled") {
    const Image im = parse({
        "..........",
        "..33333...",
        "..3...3...",
        "..3...3...",
        "..33333...",
        "..........",
    });
    const auto out = gpu_refine(im, stages({}, true, false));
    const Image want = parse({
        "..........",
        "..33333...",
        "..33333...",
        "..33333...",
        "..33333...",
        "..........",
    });
    CHECK(out == want.px);
    CHECK(ref::fill_label_holes(im.px, im.w, im.h) == want.px);
}

TEST_CASE("refine: a hole bordered by two instances stays, one open to the border too") {
    const Image im = parse({
        "..........",
        ".1111222..",
        ".1.....2..",
        ".1111222..",
        "......4...",
        "....44.44.",
        "....4...4.",
        "....4...4.",
    });
    // The 1|2 hole touches both instances; the gap in the 4-ring runs to the bottom border.
    CHECK(gpu_refine(im, stages({}, true, false)) == im.px);
    CHECK(ref::fill_label_holes(im.px, im.w, im.h) == im.px);
}

TEST_CASE("refine: holes are 4-connected, diagonal leaks do not open them") {
    const Image im = parse({
        ".....",
        ".555.",
        ".5.5.",
        ".55..",
        ".....",
    });
    // The 0 at (2,2) touches the outside only diagonally: a hole. The 0 at (3,3) is outside.
    auto want = im.px;
    want[2 * 5 + 2] = 5;
    CHECK(gpu_refine(im, stages({}, true, false)) == want);
}

TEST_CASE("refine: of two blobs of one instance only the larger stays, a tie keeps the lower index") {
    const Image larger_second = parse({
        "11.......",
        "11....111",
        "......111",
        "2.....111",
        ".2.......",
    });
    // The 8-connected diagonal pair of 2s is one component.
    const auto out = gpu_refine(larger_second, stages({}, false, true));
    const Image want = parse({
        ".........",
        "......111",
        "......111",
        "2.....111",
        ".2.......",
    });
    CHECK(out == want.px);

    const Image tie = parse({
        "......",
        ".77...",
        "......",
        "....77",
        "......",
    });
    const Image tie_want = parse({
        "......",
        ".77...",
        "......",
        "......",
        "......",
    });
    CHECK(gpu_refine(tie, stages({}, false, true)) == tie_want.px);
    // The first component in row-major order is not always the one with the leftmost pixel.
    const Image tie2 = parse({
        "....8",
        "8...8",
        "8....",
    });
    const Image tie2_want = parse({
        "....8",
        "....8",
        ".....",
    });
    CHECK(gpu_refine(tie2, stages({}, false, true)) == tie2_want.px);
}

TEST_CASE("refine: a 1-px gap in a bar closes at r=1") {
    const Image im = pad(parse({
                             "11111.1111",
                             "11111.1111",
                             "11111.1111",
                         }),
                         3);
    const Image want = pad(parse({
                               "1111111111",
                               "1111111111",
                               "1111111111",
                           }),
                           3);
    CHECK(gpu_refine(im, stages({1}, false, false)) == want.px);
}

TEST_CASE("refine: a 3-px gap stays at r=1 and closes at r=2") {
    const Image im = pad(parse({
                             "1111...111",
                             "1111...111",
                             "1111...111",
                         }),
                         4);
    CHECK(gpu_refine(im, stages({1}, false, false)) == im.px);
    const Image want = pad(parse({
                               "1111111111",
                               "1111111111",
                               "1111111111",
                           }),
                           4);
    CHECK(gpu_refine(im, stages({2}, false, false)) == want.px);
    CHECK(gpu_refine(im, stages({1, 2}, false, false)) == want.px);
    CHECK(ref::close_labels(im.px, im.w, im.h, 2) == want.px);
}

TEST_CASE("refine: closing never overwrites another instance, and the smaller id wins a 0-pixel") {
    const Image im = parse({
        "..........",
        ".222.2222.",
        ".2229.222.",
        ".222.2222.",
        "..........",
    });
    // The 9 in the gap stays; the gap's 0s above and below it are closed by 2.
    const auto out = gpu_refine(im, stages({1}, false, false));
    CHECK(out == ref::close_labels(im.px, im.w, im.h, 1));
    CHECK(out[2 * 10 + 4] == 9);
    CHECK(out[1 * 10 + 4] == 2);
    CHECK(out[3 * 10 + 4] == 2);

    // The middle pixel is in the closing of 5 (left and right) and of 3 (above and below).
    const Image both = parse({
        ".......",
        "...3...",
        "..5.5..",
        "...3...",
        ".......",
    });
    const auto closed = gpu_refine(both, stages({1}, false, false));
    CHECK(closed == ref::close_labels(both.px, both.w, both.h, 1));
    CHECK(closed[2 * 7 + 3] == 3);
    CHECK(closed[1 * 7 + 2] == 0);
}

TEST_CASE("refine: the border neither erodes nor blocks closing, gaps to it up to r close") {
    Image im{20, 10, std::vector<uint32_t>(200, 0)};
    for (int y = 3; y <= 6; ++y)
        for (int x = 2; x <= 10; ++x) im.px[size_t(y * 20 + x)] = 4;
    for (int x = 0; x < 20; ++x) im.px[size_t(9 * 20 + x)] = 6;  // along the bottom border
    im.px[size_t(9 * 20 + 7)] = 0;                                // a 1-px notch in it
    const auto out = gpu_refine(im, stages({2}, false, false));
    CHECK(out == ref::close_labels(im.px, im.w, im.h, 2));
    for (int y = 3; y <= 6; ++y) {
        CHECK(out[size_t(y * 20 + 0)] == 4);  // the 2-px gap to the left border is closed
        CHECK(out[size_t(y * 20 + 1)] == 4);
    }
    CHECK(out[size_t(2 * 20 + 0)] == 0);   // above the object's rows: not closed
    CHECK(out[size_t(9 * 20 + 7)] == 6);   // the notch on the border closes
    CHECK(out[size_t(3 * 20 + 11)] == 0);  // the object's own corners grow nothing
    // At r=1 the 2-px gap to the left border stays open.
    const auto out1 = gpu_refine(im, stages({1}, false, false));
    CHECK(out1 == ref::close_labels(im.px, im.w, im.h, 1));
    CHECK(out1[size_t(4 * 20 + 0)] == 0);
}

TEST_CASE("refine: GPU equals the CPU reference on random images, each stage alone and all together") {
    const int sizes[][2] = {{160, 120}, {97, 61}};
    for (auto& s : sizes)
        for (uint32_t seed = 1; seed <= 4; ++seed) {
            const int ids = 1 + int((seed * 5 + uint32_t(s[0])) % 12);
            const Image im = random_image(s[0], s[1], seed, ids);
            const std::string tag = "seed " + std::to_string(seed) + ", " + std::to_string(ids) + " ids";
            check_matches_reference(im, stages({1, 2, 3}, false, false), "closing, " + tag);
            check_matches_reference(im, stages({}, true, false), "holes, " + tag);
            check_matches_reference(im, stages({}, false, true), "largest component, " + tag);
            check_matches_reference(im, stages({1, 2, 3}, true, true), "all, " + tag);
        }
}

TEST_CASE("refine: more than 32 instances near a tile are taken in batches") {
    // Dense speckle of 300 ids: each tile's window sees hundreds of instances.
    std::mt19937 rng(7);
    Image im{83, 47, std::vector<uint32_t>(83 * 47, 0)};
    for (auto& p : im.px) p = rng() % 3 == 0 ? 0u : 1u + rng() % 300;
    check_matches_reference(im, stages({1, 3}, false, false), "dense closing");
    // 17 to 32 instances near a tile: two batches from one collection pass.
    for (auto& p : im.px) p = rng() % 3 == 0 ? 0u : 1u + rng() % 25;
    check_matches_reference(im, stages({1, 2}, false, false), "25 ids");
    im = random_image(83, 47, 77, 30);
    check_matches_reference(im, stages({1, 3}, false, false), "30 ids in blobs");
    for (auto& p : im.px) p = rng() % 3 == 0 ? 0u : 1u + rng() % 300;
    check_matches_reference(im, stages({2}, true, true), "dense all");
    // Thousands of distinct ids: the largest-component table holds them all.
    for (size_t i = 0; i < im.px.size(); ++i) im.px[i] = i % 2 ? 0u : uint32_t(10 + i * 7919);
    check_matches_reference(im, stages({1}, true, true), "distinct ids");
}

TEST_CASE("refine: every pixel its own instance, a few 0-pixels: the densest closing") {
    // Each tile's window holds up to thousands of instances: many batches per tile.
    auto dense = [](int w, int h) {
        Image im{w, h, std::vector<uint32_t>(size_t(w) * size_t(h), 0)};
        for (size_t i = 0; i < im.px.size(); ++i)
            im.px[i] = (i * 7 + i / size_t(w) * 13) % 61 == 0 ? 0u : uint32_t(3 * i + 1);
        return im;
    };
    const Image big = dense(140, 75), small = dense(60, 45);
    check_matches_reference(big, stages({1}, false, false), "r=1");
    check_matches_reference(big, stages({3}, false, false), "r=3");
    check_matches_reference(small, stages({12}, false, false), "r=12");
}

TEST_CASE("refine: components that wind across many tiles: diagonals, a spiral, percolation") {
    // 8-connected only through diagonal steps, crossing tile corners.
    Image diag{101, 67, std::vector<uint32_t>(101 * 67, 0)};
    for (int y = 0; y < diag.h; ++y)
        for (int x = 0; x < diag.w; ++x) {
            if ((x + y) % 6 == 0 && (x * 7 + y) % 53 != 0) diag.px[size_t(y * diag.w + x)] = 1;
            if ((x - y + 600) % 9 == 0 && x % 31 != 0) diag.px[size_t(y * diag.w + x)] = 2;
        }
    check_matches_reference(diag, stages({}, true, true), "diagonals");
    // A square spiral of instance 5, its corridor a hole only where it is closed off.
    Image spiral{90, 90, std::vector<uint32_t>(90 * 90, 0)};
    for (int k = 0; k < 22; k += 2) {
        const int lo = 2 * k + 1, hi = 89 - 2 * k - 1;
        for (int t = lo; t <= hi; ++t) {
            spiral.px[size_t(lo * 90 + t)] = 5;
            spiral.px[size_t(hi * 90 + t)] = 5;
            spiral.px[size_t(t * 90 + hi)] = 5;
            if (t > lo + 2) spiral.px[size_t(t * 90 + lo)] = 5;
        }
    }
    check_matches_reference(spiral, stages({}, true, true), "spiral");
    check_matches_reference(spiral, stages({1, 2}, true, true), "spiral closed");
    // Near the percolation threshold: giant, ragged components and holes of every shape.
    for (uint32_t seed : {31u, 32u, 33u}) {
        std::mt19937 rng(seed);
        Image perc{150, 110, std::vector<uint32_t>(150 * 110, 0)};
        for (auto& p : perc.px) p = rng() % 100 < 58 ? 1u + rng() % (seed == 31u ? 1u : 2u) : 0u;
        check_matches_reference(perc, stages({}, true, false), "percolation holes");
        check_matches_reference(perc, stages({}, false, true), "percolation components");
        check_matches_reference(perc, stages({1}, true, true), "percolation all");
    }
}

TEST_CASE("refine: large radii (global scratch closing) match the reference") {
    for (uint32_t seed : {11u, 12u}) {
        const Image im = random_image(97, 61, seed, 6);
        check_matches_reference(im, stages({12}, false, false), "r=12: shared memory, smallest tile");
        check_matches_reference(im, stages({13, 4}, false, false), "r=13 (global scratch) then r=4");
    }
    Image small = random_image(40, 30, 3, 4);
    check_matches_reference(small, stages({100}, false, false), "r above the image size");
}

TEST_CASE("refine: an all-background image, a single pixel and a one-row image") {
    Image empty{64, 48, std::vector<uint32_t>(64 * 48, 0)};
    CHECK(gpu_refine(empty, seg::RefineOptions{}) == empty.px);
    for (uint32_t v : {0u, 5u}) {
        Image one{1, 1, {v}};
        CHECK(gpu_refine(one, seg::RefineOptions{}) == one.px);
    }
    const Image row = parse({"11.1.22..2.1"});
    check_matches_reference(row, seg::RefineOptions{}, "one row");
    Image column{1, 9, {0, 3, 0, 3, 3, 0, 0, 3, 0}};
    check_matches_reference(column, seg::RefineOptions{}, "one column");
}

TEST_CASE("refine: in place, no stages, and bad arguments") {
    const Image im = random_image(70, 50, 21, 5);
    const auto want = cpu_refine(im, seg::RefineOptions{});
    CHECK(gpu_refine(im, seg::RefineOptions{}, true) == want);
    CHECK(gpu_refine(im, stages({2}, false, false), true) == cpu_refine(im, stages({2}, false, false)));
    CHECK(gpu_refine(im, stages({}, false, false)) == im.px);
    CHECK(gpu_refine(im, stages({0}, false, false)) == im.px);

    auto& ctx = test::gpu();
    vk::Buffer small(ctx, 16, vk::MemoryUse::Device, "too small");
    vk::Buffer out(ctx, 70 * 50 * 4, vk::MemoryUse::Device, "out");
    vk::CommandList cmd(ctx);
    CHECK_THROWS_WITH(refiner().refine(cmd, small, out, 70, 50, {}), Catch::Contains("too small"));
    CHECK_THROWS_AS(refiner().refine(cmd, out, out, 0, 50, {}), std::invalid_argument);
    CHECK_THROWS_WITH(refiner().refine(cmd, out, out, 70, 50, stages({-1}, false, false)),
                      Catch::Contains("radius -1"));
}

TEST_CASE("refine: two refinements in one command list, stages as named passes") {
    auto& ctx = test::gpu();
    const Image a = random_image(97, 61, 41, 7), b = random_image(160, 120, 42, 9);
    vk::Buffer in_a = vk::upload_vector(ctx, a.px, "a"), in_b = vk::upload_vector(ctx, b.px, "b");
    vk::Buffer out_a(ctx, a.px.size() * 4, vk::MemoryUse::Device, "out a");
    vk::Buffer out_b(ctx, b.px.size() * 4, vk::MemoryUse::Device, "out b");
    seg::MaskRefiner local(ctx);  // its buffers grow between the two calls
    seg::RefineOptions o;
    o.pass_prefix = "refine ";
    vk::CommandList cmd(ctx);
    local.refine(cmd, in_a, out_a, a.w, a.h, o);
    local.refine(cmd, in_b, out_b, b.w, b.h, o);
    cmd.submit_and_wait();
    CHECK(vk::download_vector<uint32_t>(ctx, out_a, a.px.size()) == cpu_refine(a, o));
    CHECK(vk::download_vector<uint32_t>(ctx, out_b, b.px.size()) == cpu_refine(b, o));
    if (ctx.info().timestamps) {
        REQUIRE(cmd.timings().size() == 6);
        CHECK(cmd.timings()[0].name == "refine closing");
        CHECK(cmd.timings()[1].name == "refine holes");
        CHECK(cmd.timings()[2].name == "refine components");
    }
}
