// PlayCanvas SOG: every layout and version decodes to what splat-transform decodes from the
// same file (tests/fixtures/sog, written by tools/make_sog_fixtures.sh), within 1e-4.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "dataset/error.h"
#include "dataset/formats/scene_io.h"
#include "dataset/formats/sog.h"
#include "dataset/formats/webp_image.h"
#include "tests/test_paths.h"

namespace fs = std::filesystem;
using pg::data::GaussianCloud;
using pg::data::InputError;

namespace {

fs::path sog_dir() { return pg::test::fixtures() / "sog"; }

// Largest |a - b| per attribute, Gaussian i of `a` against Gaussian order[i] of `b`.
struct Diff {
    double mean = 0, scale = 0, rotation = 0, opacity = 0, sh = 0;
    double worst() const { return std::max({mean, scale, rotation, opacity, sh}); }
};

Diff compare(const GaussianCloud& a, const GaussianCloud& b, const std::vector<size_t>& order) {
    Diff d;
    const size_t ca = size_t(a.coeffs()) * 3, cb = size_t(b.coeffs()) * 3;
    for (size_t i = 0; i < a.size(); ++i) {
        const size_t j = order[i];
        for (int k = 0; k < 3; ++k) {
            d.mean = std::max(d.mean, double(std::abs(a.mean[i][k] - b.mean[j][k])));
            d.scale = std::max(d.scale, double(std::abs(a.log_scale[i][k] - b.log_scale[j][k])));
        }
        for (int k = 0; k < 4; ++k) d.rotation = std::max(d.rotation, double(std::abs(a.rotation[i][k] - b.rotation[j][k])));
        d.opacity = std::max(d.opacity, double(std::abs(a.opacity_logit[i] - b.opacity_logit[j])));
        for (size_t k = 0; k < std::min(ca, cb); ++k) d.sh = std::max(d.sh, double(std::abs(a.sh[i * ca + k] - b.sh[j * cb + k])));
    }
    return d;
}

std::vector<size_t> identity(size_t n) {
    std::vector<size_t> v(n);
    std::iota(v.begin(), v.end(), size_t(0));
    return v;
}

void check_matches_reference(const fs::path& sog, const fs::path& decoded, int sh_degree) {
    INFO(sog.string());
    const GaussianCloud ours = pg::data::load_scene(sog);
    const GaussianCloud ref = pg::data::read_ply(decoded);
    REQUIRE(ours.size() == ref.size());
    CHECK(ours.sh_degree == sh_degree);
    CHECK(ref.sh_degree == sh_degree);
    CHECK(ours.format == pg::data::SceneFormat::Sog);
    const Diff d = compare(ours, ref, identity(ref.size()));
    INFO("max |diff|: mean " << d.mean << " scale " << d.scale << " rotation " << d.rotation << " opacity "
                             << d.opacity << " sh " << d.sh);
    CHECK(d.worst() <= 1e-4);
}

// Index of each Gaussian of `a` in `b`, matched by position (the fixtures' means are distinct).
std::vector<size_t> match_by_position(const GaussianCloud& a, const GaussianCloud& b) {
    auto key = [](const glm::vec3& p) { return std::tuple(p.x, p.y, p.z); };
    std::vector<size_t> ib = identity(b.size());
    std::sort(ib.begin(), ib.end(), [&](size_t x, size_t y) { return key(b.mean[x]) < key(b.mean[y]); });
    std::vector<size_t> order(a.size());
    for (size_t i = 0; i < a.size(); ++i) {
        auto it = std::lower_bound(ib.begin(), ib.end(), a.mean[i],
                                   [&](size_t x, const glm::vec3& p) { return key(b.mean[x]) < key(p); });
        REQUIRE(it != ib.end());
        order[i] = *it;
    }
    return order;
}

GaussianCloud concat(const std::vector<fs::path>& plys) {
    GaussianCloud out;
    for (const auto& p : plys) {
        const GaussianCloud c = pg::data::read_ply(p);
        const size_t at = out.size();
        out.sh_degree = c.sh_degree;
        out.resize(at + c.size());
        std::copy(c.mean.begin(), c.mean.end(), out.mean.begin() + long(at));
        std::copy(c.log_scale.begin(), c.log_scale.end(), out.log_scale.begin() + long(at));
        std::copy(c.rotation.begin(), c.rotation.end(), out.rotation.begin() + long(at));
        std::copy(c.opacity_logit.begin(), c.opacity_logit.end(), out.opacity_logit.begin() + long(at));
        std::copy(c.sh.begin(), c.sh.end(), out.sh.begin() + long(at * size_t(c.coeffs()) * 3));
    }
    return out;
}

}  // namespace

TEST_CASE("sog: bundled v2 with SH 3 decodes as splat-transform does") {
    check_matches_reference(sog_dir() / "bundled_sh3.sog", sog_dir() / "bundled_sh3.decoded.ply", 3);
}

TEST_CASE("sog: unbundled v2 with SH 1 decodes as splat-transform does, by meta.json or by folder") {
    check_matches_reference(sog_dir() / "unbundled_sh1" / "meta.json", sog_dir() / "unbundled_sh1.decoded.ply", 1);
    check_matches_reference(sog_dir() / "unbundled_sh1", sog_dir() / "unbundled_sh1.decoded.ply", 1);
}

TEST_CASE("sog: v1 (per-attribute min/max) with SH 2 decodes as splat-transform's v1 reader does") {
    check_matches_reference(sog_dir() / "v1_sh2" / "meta.json", sog_dir() / "v1_sh2.decoded.ply", 2);
}

TEST_CASE("sog: a streamed scene gathers each level from its chunks, plus the environment") {
    const fs::path lod_meta = sog_dir() / "streamed" / "lod-meta.json";
    const fs::path ref = sog_dir() / "streamed_decoded";
    struct Level {
        int lod;
        std::vector<fs::path> chunks;
    };
    for (const Level& level : {Level{0, {ref / "0_0.ply", ref / "0_1.ply", ref / "env.ply"}},
                               Level{1, {ref / "1_0.ply", ref / "env.ply"}}}) {
        INFO("level " << level.lod);
        const GaussianCloud ours = pg::data::load_scene(lod_meta, {}, level.lod);
        const GaussianCloud expected = concat(level.chunks);
        REQUIRE(ours.size() == expected.size());
        const Diff d = compare(ours, expected, match_by_position(ours, expected));
        INFO("max |diff| " << d.worst());
        CHECK(d.worst() <= 1e-4);
    }
    // The default is the finest level, also when the folder is given.
    CHECK(pg::data::load_scene(sog_dir() / "streamed").size() == 2314 + 96);
    CHECK(pg::data::load_scene(lod_meta, {}, 1).size() == 386 + 96);
}

TEST_CASE("sog: a LOD level a scene does not have is one clear error") {
    const fs::path lod_meta = sog_dir() / "streamed" / "lod-meta.json";
    try {
        pg::data::load_scene(lod_meta, {}, 2);
        FAIL("level 2 loaded");
    } catch (const InputError& e) {
        CHECK(std::string(e.what()).find("LOD level 2 asked for; the scene has 2 (0 to 1)") != std::string::npos);
    }
    CHECK_THROWS_WITH(pg::data::load_scene(sog_dir() / "bundled_sh3.sog", {}, 1),
                      Catch::Contains("only a streamed SOG (lod-meta.json) has levels"));
    CHECK_THROWS_WITH(pg::data::load_scene(sog_dir() / "bundled_sh3.decoded.ply", {}, 1),
                      Catch::Contains("only a streamed SOG (lod-meta.json) has levels"));
}

TEST_CASE("sog: describe_sog gives layout, version, count, SH degree and levels without decoding") {
    using pg::data::SogLayout;
    auto s = pg::data::describe_sog(sog_dir() / "bundled_sh3.sog");
    CHECK(s.layout == SogLayout::Bundled);
    CHECK(s.version == 2);
    CHECK(s.count == 1158);
    CHECK(s.sh_degree == 3);
    CHECK(s.lod_levels == 1);
    s = pg::data::describe_sog(sog_dir() / "unbundled_sh1");
    CHECK(s.layout == SogLayout::Unbundled);
    CHECK(s.sh_degree == 1);
    s = pg::data::describe_sog(sog_dir() / "v1_sh2" / "meta.json");
    CHECK(s.version == 1);
    CHECK(s.count == 1158);
    CHECK(s.sh_degree == 2);
    s = pg::data::describe_sog(sog_dir() / "streamed" / "lod-meta.json");
    CHECK(s.layout == SogLayout::Streamed);
    CHECK(s.lod_levels == 2);
    CHECK(s.lod_counts == std::vector<uint64_t>{2314, 386});
    CHECK(s.environment == 96);
    CHECK(s.count == 2314 + 96);
}

TEST_CASE("sog: WebP round trip is lossless and a huge claimed canvas is refused before decoding") {
    pg::data::RgbaImage img;
    img.width = 7, img.height = 5;
    for (size_t i = 0; i < img.pixels() * 4; ++i) img.rgba.push_back(uint8_t(i * 37 % 256));
    img.rgba[3] = 0;  // RGB under zero alpha must survive (opacity 0 keeps its colour bytes)
    const auto bytes = pg::data::encode_webp_lossless(img);
    const auto back = pg::data::decode_webp(bytes, 35, "t.webp");
    CHECK(back.width == 7);
    CHECK(back.height == 5);
    CHECK(back.rgba == img.rgba);
    CHECK_THROWS_WITH(pg::data::decode_webp(bytes, 34, "t.webp"), Catch::Contains("refused before decoding"));
}
