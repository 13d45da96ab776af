// Model files: safetensors reading and writing, malformed files, and the PTv3 weight loader's
// name handling (release, Pointcept and DataParallel prefixes) and shape checks.
#include <fstream>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "nn/ptv3/seeded_weights.h"
#include "nn/ptv3/weights.h"
#include "nn/safetensors.h"
#include "tests/gpu_fixture.h"
#include "tests/test_paths.h"

using namespace pg;
using Catch::Matchers::Contains;

namespace {

void write_bytes(const std::filesystem::path& p, const std::string& bytes) {
    std::ofstream(p, std::ios::binary) << bytes;
}

std::string with_header(const std::string& header, const std::string& data) {
    std::string s(8, '\0');
    uint64_t n = header.size();
    std::memcpy(s.data(), &n, 8);
    return s + header + data;
}

// A full small-config model file written under `prefix` names with the head as `head`.
std::filesystem::path write_model(const std::string& file, const std::string& prefix, const std::string& head,
                                  const nn::Ptv3Config& c, bool drop_one = false, bool bad_shape = false) {
    auto values = nn::seeded_weights(c);
    std::vector<nn::SafeTensorEntry> entries;
    for (const auto& [name, shape] : nn::Ptv3Weights::expected(c)) {
        if (drop_one && name == "enc.enc1.block0.attn.proj.bias") continue;
        std::string n = name.rfind("head.", 0) == 0 ? head + name.substr(5) : prefix + name;
        auto sh = shape;
        if (bad_shape && name == "enc.enc0.block0.cpe.1.weight") sh = {sh[1], sh[0] + 1};
        auto v = values[name];
        if (bad_shape && name == "enc.enc0.block0.cpe.1.weight") v.resize(size_t(sh[0] * sh[1]));
        entries.push_back(nn::make_entry(n, "F32", sh, v));
    }
    entries.push_back(nn::make_entry(prefix + "embedding.stem.norm.num_batches_tracked", "I64", {},
                                     std::vector<int64_t>{7}));
    auto path = pg::test::scratch("model-files") / file;
    nn::write_safetensors(path, entries, {{"config", c.to_json().dump()}});
    return path;
}

nn::Ptv3Config tiny_config() {
    nn::Ptv3Config c;
    c.enc_depths = {1, 1};
    c.enc_channels = {8, 16};
    c.enc_num_head = {1, 2};
    c.enc_patch_size = {16, 16};
    c.dec_depths = {1};
    c.dec_channels = {8};
    c.dec_num_head = {1};
    c.dec_patch_size = {16};
    c.stride = {2};
    return c;
}

}  // namespace

TEST_CASE("safetensors: written tensors and metadata read back exactly") {
    auto path = pg::test::scratch("model-files") / "roundtrip.safetensors";
    std::vector<float> f = {1.5f, -2.0f, 3.25f, 0.0f, 1e-30f, -7.0f};
    std::vector<int64_t> i = {-1, 0, 1LL << 40};
    nn::write_safetensors(path, {nn::make_entry("a.weight", "F32", {2, 3}, f), nn::make_entry("b", "I64", {3}, i)},
                          {{"config", "{\"x\":1}"}});
    auto st = nn::SafeTensors::load(path);
    CHECK(st.metadata().at("config") == "{\"x\":1}");
    CHECK(st.info("a.weight").shape == std::vector<int64_t>{2, 3});
    CHECK(st.f32("a.weight") == f);
    CHECK(st.i64("b") == i);
    CHECK_THROWS_WITH(st.f32("missing"), Contains("no tensor named 'missing'"));
    CHECK_THROWS_WITH(st.f32("b"), Contains("expected a float type"));
}

TEST_CASE("safetensors: malformed files give one error naming the file") {
    auto dir = pg::test::scratch("model-files");
    struct Case {
        const char* name;
        std::string bytes;
        const char* reason;
    };
    const std::string ok_header = R"({"t":{"dtype":"F32","shape":[2],"data_offsets":[0,8]}})";
    std::vector<Case> cases = {
        {"empty", "", "shorter than its 8-byte header"},
        {"short", "abc", "shorter than its 8-byte header"},
        {"huge_header", with_header("", "").substr(0, 7) + "\x7f", "exceeds the file size"},
        {"header_past_end", std::string("\xff\x00\x00\x00\x00\x00\x00\x00", 8) + "{}", "exceeds the file size"},
        {"not_json", with_header("{nope", ""), "not valid JSON"},
        {"not_object", with_header("[1,2]", ""), "not a JSON object"},
        {"no_offsets", with_header(R"({"t":{"dtype":"F32","shape":[2]}})", std::string(8, '\0')), "lacks dtype"},
        {"bad_dtype", with_header(R"({"t":{"dtype":"Q7","shape":[2],"data_offsets":[0,8]}})", std::string(8, '\0')),
         "unknown dtype"},
        {"negative_shape", with_header(R"({"t":{"dtype":"F32","shape":[-2],"data_offsets":[0,8]}})", std::string(8, '\0')),
         "bad shape"},
        {"offsets_out", with_header(ok_header, std::string(4, '\0')), "outside the file"},
        {"size_mismatch", with_header(R"({"t":{"dtype":"F32","shape":[3],"data_offsets":[0,8]}})", std::string(8, '\0')),
         "shape needs 12"},
        {"bad_metadata", with_header(R"({"__metadata__":{"config":5}})", ""), "is not a string"},
    };
    for (const auto& c : cases) {
        auto p = dir / (std::string(c.name) + ".safetensors");
        write_bytes(p, c.bytes);
        INFO(c.name);
        CHECK_THROWS_WITH(nn::SafeTensors::load(p), Contains(p.string()) && Contains(c.reason));
    }
    CHECK_THROWS_WITH(nn::SafeTensors::load(dir / "absent.safetensors"), Contains("cannot open"));
}

TEST_CASE("ptv3 weights: release, Pointcept and DataParallel names load the same model") {
    auto pool = nn::Pool::create(pg::test::gpu());
    const auto c = tiny_config();
    auto release = nn::Ptv3Weights::load(*pool, write_model("release.safetensors", "", "cls_head.0.", c));
    auto pointcept = nn::Ptv3Weights::load(*pool, write_model("pointcept.safetensors", "module.backbone.", "seg_head.", c));
    CHECK(release.parameter_count() == c.parameter_count());
    CHECK(pointcept.parameter_count() == c.parameter_count());
    auto a = nn::download_tensor<float>(pg::test::gpu(), release["head.weight"]);
    auto b = nn::download_tensor<float>(pg::test::gpu(), pointcept["head.weight"]);
    CHECK(a == b);
    CHECK(nn::Ptv3Weights::canonical_name("module.backbone.enc.enc0.block0.cpe.0.weight") == "enc.enc0.block0.cpe.0.weight");
}

TEST_CASE("ptv3 weights: a missing tensor, a wrong shape or a missing config is named") {
    auto pool = nn::Pool::create(pg::test::gpu());
    const auto c = tiny_config();
    CHECK_THROWS_WITH(nn::Ptv3Weights::load(*pool, write_model("missing.safetensors", "", "cls_head.0.", c, true)),
                      Contains("missing tensor 'enc.enc1.block0.attn.proj.bias'"));
    CHECK_THROWS_WITH(nn::Ptv3Weights::load(*pool, write_model("shape.safetensors", "", "cls_head.0.", c, false, true)),
                      Contains("'enc.enc0.block0.cpe.1.weight' has shape [8,9]") &&
                          Contains("needs [8,8]"));
    auto path = pg::test::scratch("model-files") / "noconfig.safetensors";
    nn::write_safetensors(path, {nn::make_entry("x", "F32", {1}, std::vector<float>{1})});
    CHECK_THROWS_WITH(nn::Ptv3Weights::load(*pool, path), Contains("tools/convert_checkpoint.py"));
    auto bad = pg::test::scratch("model-files") / "badconfig.safetensors";
    auto j = c.to_json();
    // scale_spacing travels with the config, absent (0) unless set.
    CHECK_FALSE(j.contains("scale_spacing"));
    auto spaced = c;
    spaced.scale_spacing = 0.38;
    CHECK(nn::Ptv3Config::from_json(spaced.to_json()).scale_spacing == 0.38);
    j["enc_num_head"] = {3, 2};
    nn::write_safetensors(bad, {nn::make_entry("x", "F32", {1}, std::vector<float>{1})}, {{"config", j.dump()}});
    CHECK_THROWS_WITH(nn::Ptv3Weights::load(*pool, bad), Contains("not divisible by heads"));
}
