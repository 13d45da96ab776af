// PTv3 logits and every traced stage against golden outputs of PyTorch implementations: the
// release's own model.py (../shared, when present) and our fixtures in tests/fixtures/ptv3.
#include <fstream>
#include <map>

#include <catch2/catch.hpp>

#include "nn/ptv3/model.h"
#include "nn/ptv3/seeded_weights.h"
#include "nn/safetensors.h"
#include "tests/gpu_fixture.h"
#include "tests/nn/ptv3_fixture.h"
#include "tests/test_paths.h"

using namespace pg;

namespace {

struct StageCheck {
    std::string name;
    double error;
};

// Runs the model with tracing and compares each traced feature tensor that the golden trace
// also holds. Level-0 rows are mapped from voxel order to input order.
std::vector<StageCheck> compare_trace(nn::Ptv3& model, const nn::Ptv3Input& in, const nn::SafeTensors& golden,
                                      std::vector<float>& logits) {
    std::vector<StageCheck> checks;
    std::map<std::string, std::vector<float>> ours;
    auto out = model.forward(in, [&](const std::string& name, const nn::Tensor& t) {
        if (golden.contains(name)) ours[name] = nn::download_tensor<float>(pg::test::gpu(), t);
    });
    logits = out.logits;
    const auto& voxel_points = model.voxel_points();
    for (auto& [name, mine] : ours) {
        std::vector<float> ref = golden.f32(name);
        const auto& shape = golden.info(name).shape;
        const size_t rows = size_t(shape[0]), cols = ref.size() / rows;
        if (rows == in.size() && voxel_points.size() == rows) {  // level 0: voxel order -> input order
            std::vector<float> mapped(ref.size());
            for (size_t v = 0; v < rows; ++v)
                std::memcpy(&mapped[size_t(voxel_points[v]) * cols], &mine[v * cols], cols * sizeof(float));
            mine = mapped;
        }
        mine.resize(ref.size());
        checks.push_back({name, pg::test::relative_max_error(mine, ref)});
    }
    return checks;
}

// Every traced stage within 2e-4 and the logits within 1e-4 of a fixture folder's golden files.
void check_fixture(nn::Ptv3& model, const nn::Ptv3Input& in, const std::filesystem::path& dir) {
    auto golden = nn::SafeTensors::load(dir / "trace.safetensors");
    std::vector<float> logits;
    auto checks = compare_trace(model, in, golden, logits);
    CHECK(checks.size() >= 40);
    for (const auto& c : checks) {
        INFO(c.name << " relative error " << c.error);
        CHECK(c.error < 2e-4);
    }
    const double err = pg::test::relative_max_error(logits, pg::test::read_f32_file(dir / "logits.bin"));
    INFO("logits relative error " << err);
    CHECK(err < 1e-4);
}

}  // namespace

TEST_CASE("ptv3: parameter counts of the paper and small configs match the release") {
    CHECK(nn::Ptv3Config::paper().parameter_count() == 46150402);
    CHECK(nn::Ptv3Config::small().parameter_count() == 5179922);
}

TEST_CASE("ptv3: logits and every traced stage match the release's model.py (shared small fixture)") {
    const auto dir = pg::test::shared_dir() / "fixtures" / "ptv3-small";
    if (!std::filesystem::exists(dir / "weights.safetensors")) {
        WARN("skipped: " << dir << " is absent (it is not part of a user's clone)");
        return;
    }
    auto pool = nn::Pool::create(pg::test::gpu());
    auto weights = nn::Ptv3Weights::load(*pool, dir / "weights.safetensors");
    CHECK(weights.parameter_count() == 5179922);
    nn::Ptv3 model(*pool, std::move(weights));
    auto in = pg::test::read_ptv3_input(dir, model.config().in_channels);
    REQUIRE(in.size() == 8192);
    check_fixture(model, in, dir);
}

TEST_CASE("ptv3: logits and traced stages match our PyTorch reference (tiny config, two clouds)") {
    const auto dir = pg::test::fixtures() / "ptv3" / "small";
    auto pool = nn::Pool::create(pg::test::gpu());
    nn::Ptv3 model(*pool, nn::Ptv3Weights::load(*pool, dir / "weights.safetensors"));
    auto in = pg::test::read_ptv3_input(dir, model.config().in_channels);
    REQUIRE(in.offsets == std::vector<int64_t>{700, 1000});
    check_fixture(model, in, dir);
}

TEST_CASE("ptv3: duplicate voxels take the logits of their voxel's lowest-index point") {
    const auto dir = pg::test::fixtures() / "ptv3" / "small";
    auto pool = nn::Pool::create(pg::test::gpu());
    nn::Ptv3 model(*pool, nn::Ptv3Weights::load(*pool, dir / "weights.safetensors"));
    auto in = pg::test::read_ptv3_input(dir, model.config().in_channels, "dup_input");
    REQUIRE(in.size() == 1120);
    auto out = model.forward(in);
    CHECK(out.voxels == 1000);
    const double err = pg::test::relative_max_error(out.logits, pg::test::read_f32_file(dir / "dup_logits.bin"));
    INFO("logits relative error " << err);
    CHECK(err < 1e-4);
}

TEST_CASE("ptv3: seeded weights reproduce the paper fixture's generator") {
    const auto probe = nlohmann::json::parse(std::ifstream(pg::test::fixtures() / "ptv3" / "paper" / "weights_probe.json"));
    const auto values = nn::seeded_weights(nn::Ptv3Config::paper());
    size_t checked = 0;
    for (const auto& t : probe["tensors"]) {
        const std::string name = nn::Ptv3Weights::canonical_name(t["name"].get<std::string>());
        if (name.find("num_batches_tracked") != std::string::npos) continue;
        INFO(name);
        REQUIRE(values.count(name));
        const auto& v = values.at(name);
        for (size_t k = 0; k < t["first"].size(); ++k) CHECK(v[k] == t["first"][k].get<float>());
        CHECK(v.back() == t["last"].get<float>());
        ++checked;
    }
    CHECK(checked == values.size());
}

TEST_CASE("ptv3: the paper config matches our PyTorch reference (one cloud of 3000, two of 1000 + 500)") {
    const auto dir = pg::test::fixtures() / "ptv3" / "paper";
    auto pool = nn::Pool::create(pg::test::gpu());
    const auto config = nn::Ptv3Config::paper();
    nn::Ptv3 model(*pool, nn::Ptv3Weights::from_host(*pool, config, nn::seeded_weights(config), "seeded paper"));
    for (auto [input, logits] : {std::pair{"input", "logits.bin"}, std::pair{"input2", "logits2.bin"}}) {
        auto in = pg::test::read_ptv3_input(dir, config.in_channels, input);
        auto out = model.forward(in);
        const double err = pg::test::relative_max_error(out.logits, pg::test::read_f32_file(dir / logits));
        INFO(input << ": logits relative error " << err);
        CHECK(err < 1e-4);
    }
}

TEST_CASE("ptv3: given order permutations reproduce a shuffled PyTorch run") {
    const auto dir = pg::test::fixtures() / "ptv3" / "small";
    auto pool = nn::Pool::create(pg::test::gpu());
    nn::Ptv3 model(*pool, nn::Ptv3Weights::load(*pool, dir / "weights.safetensors"));
    auto in = pg::test::read_ptv3_input(dir, model.config().in_channels);
    in.perms = nlohmann::json::parse(std::ifstream(dir / "perm.json"))["perms"].get<std::vector<std::vector<int>>>();
    auto out = model.forward(in);
    const double err = pg::test::relative_max_error(out.logits, pg::test::read_f32_file(dir / "perm_logits.bin"));
    INFO("logits relative error " << err);
    CHECK(err < 1e-4);
    in.perms = {{0, 1, 2, 3}};
    CHECK_THROWS_WITH(model.forward(in), Catch::Matchers::Contains("one order permutation per level"));
    in.perms.assign(5, {0, 1, 1, 3});
    CHECK_THROWS_WITH(model.forward(in), Catch::Matchers::Contains("must reorder 0..3"));
}
