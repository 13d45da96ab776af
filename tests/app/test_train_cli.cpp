// `pointgauss train` end to end on a tiny synthetic suite: the model file, the log, chunked
// training that resumes to the same bytes, and clear errors.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "dataset/atomic_file.h"
#include "dataset/formats/image_io.h"
#include "nn/ptv3/weights.h"
#include "nn/safetensors.h"
#include "tests/app/cli_run.h"
#include "tests/test_paths.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

using pg::test::Run;
Run run(const std::string& args) { return pg::test::run_cli(args); }

fs::path train_suite() {
    static const fs::path dir = [] {
        fs::path d = pg::test::process_scratch("cli-train-suite");
        fs::remove_all(d);
        auto r = run("synth --suite desk --scenes 2 --seed 9 --density 0.05 --cameras 4 --width 64 --height 48 "
                     "--previews 1 --out " + d.string());
        INFO(r.out);
        REQUIRE(r.code == 0);
        return d;
    }();
    return dir;
}

std::string common_args(const fs::path& suite) {
    return "train --data " + suite.string() + " --val " + (suite / "desk_001").string() +
           " --config tiny --batch 2 --points 768 --clicks 1 --val-samples 2 --val-every 2 --calibration 2 --seed 4";
}

json safetensors_metadata(const fs::path& p) {
    const std::vector<char> bytes = pg::data::read_file(p);
    uint64_t n = 0;
    std::memcpy(&n, bytes.data(), 8);
    return json::parse(std::string(bytes.data() + 8, n))["__metadata__"];
}

}  // namespace

TEST_CASE("train writes an interactive model, its log and a checkpoint, chunks resume to the same model") {
    const fs::path suite = train_suite();
    const fs::path dir = pg::test::scratch("cli-train");
    fs::remove_all(dir);
    fs::create_directories(dir);

    Run whole = run(common_args(suite) + " --steps 4 --out " + (dir / "whole.safetensors").string());
    INFO(whole.out);
    REQUIRE(whole.code == 0);
    CHECK(whole.out.find("validation iou1") != std::string::npos);
    const json meta = safetensors_metadata(dir / "whole.safetensors");
    const json config = json::parse(meta["config"].get<std::string>());
    CHECK(config["input_frame"] == "roi");
    CHECK(config["in_channels"] == 2);
    CHECK(json::parse(meta["training"].get<std::string>())["steps"] == 4);
    std::ifstream log(dir / "whole.log.jsonl");
    int lines = 0;
    for (std::string line; std::getline(log, line); ++lines) {
        const json e = json::parse(line);
        CHECK(e["step"] == lines + 1);
        CHECK(std::isfinite(e["loss"].get<double>()));
    }
    CHECK(lines == 4);
    CHECK(fs::exists(dir / "whole.ckpt.safetensors"));
    // The run's picture: three panels (loss, validation IoU, learning rate).
    const pg::data::Image8 curves = pg::data::read_png8(dir / "whole.curves.png");
    CHECK(curves.width == 900);
    CHECK(curves.height == 3 * 260);
    // `curves` draws the same log to the same picture; bad arguments name themselves.
    Run drawn = run("curves " + (dir / "whole.log.jsonl").string() + " --out " + (dir / "drawn.png").string());
    INFO(drawn.out);
    REQUIRE(drawn.code == 0);
    CHECK(pg::data::read_file(dir / "drawn.png") == pg::data::read_file(dir / "whole.curves.png"));
    Run missing = run("curves " + (dir / "none.jsonl").string() + " --out " + (dir / "x.png").string());
    CHECK(missing.code != 0);
    CHECK(missing.out.find("none.jsonl") != std::string::npos);
    Run self = run("curves " + (dir / "whole.log.jsonl").string() + " --out " + (dir / "whole.log.jsonl").string());
    CHECK(self.code != 0);
    CHECK(self.out.find("--out") != std::string::npos);
    CHECK_FALSE(fs::exists(dir / "x.png"));

    // The same run in two chunks: stop after step 2, resume from the checkpoint.
    Run first = run(common_args(suite) + " --steps 4 --stop-at 2 --out " + (dir / "chunked.safetensors").string());
    INFO(first.out);
    REQUIRE(first.code == 0);
    CHECK_FALSE(fs::exists(dir / "chunked.safetensors"));
    Run second = run(common_args(suite) + " --steps 4 --resume " + (dir / "chunked.ckpt.safetensors").string() +
                     " --out " + (dir / "chunked.safetensors").string());
    INFO(second.out);
    REQUIRE(second.code == 0);
    CHECK(pg::data::read_file(dir / "chunked.safetensors") == pg::data::read_file(dir / "whole.safetensors"));

    // The model runs in the pipeline as its decoder.
    const fs::path scene = suite / "desk_000";
    Run prompts = run("prompts " + scene.string() + " --out " + (dir / "prompts.json").string());
    REQUIRE(prompts.code == 0);
    Run seg = run("segment " + (scene / "scene.ply").string() + " --cameras " + (scene / "cameras.json").string() +
                  " --prompts " + (dir / "prompts.json").string() + " --model " + (dir / "whole.safetensors").string() +
                  " --views none --out " + (dir / "seg").string());
    INFO(seg.out);
    CHECK(seg.code == 0);
}

TEST_CASE("train --init fine-tunes a model file: its config and weights are where training starts") {
    const fs::path suite = train_suite();
    const fs::path dir = pg::test::scratch("cli-train-init");
    fs::remove_all(dir);
    fs::create_directories(dir);
    // A base model with per-Gaussian features, then one step at a vanishing learning rate from it:
    // every trained parameter stays the base's (the BatchNorm statistics settle again at the end).
    Run base = run(common_args(suite) + " --steps 2 --features rgb --out " + (dir / "base.safetensors").string());
    INFO(base.out);
    REQUIRE(base.code == 0);
    Run tuned = run(common_args(suite) + " --steps 1 --lr 1e-12 --weight-decay 0 --init " +
                    (dir / "base.safetensors").string() + " --out " + (dir / "tuned.safetensors").string());
    INFO(tuned.out);
    REQUIRE(tuned.code == 0);
    const json config = json::parse(safetensors_metadata(dir / "tuned.safetensors")["config"].get<std::string>());
    CHECK(config["features"] == json::array({"rgb"}));  // the base's, though --features was not given
    const auto a = pg::nn::Ptv3Weights::host_values(pg::nn::SafeTensors::load(dir / "base.safetensors"));
    const auto b = pg::nn::Ptv3Weights::host_values(pg::nn::SafeTensors::load(dir / "tuned.safetensors"));
    REQUIRE(a.size() == b.size());
    size_t compared = 0;
    for (const auto& [name, values] : a) {
        if (name.find("running_") != std::string::npos) continue;
        REQUIRE(b.count(name));
        const auto& other = b.at(name);
        REQUIRE(other.size() == values.size());
        float worst = 0;
        for (size_t i = 0; i < values.size(); ++i) worst = std::max(worst, std::abs(values[i] - other[i]));
        INFO(name);
        CHECK(worst < 1e-6f);
        ++compared;
    }
    CHECK(compared > 20);
    // From fresh weights the same step gives other parameters: the check above can fail.
    Run fresh = run(common_args(suite) + " --steps 1 --lr 1e-12 --weight-decay 0 --features rgb --out " +
                    (dir / "fresh.safetensors").string());
    REQUIRE(fresh.code == 0);
    const auto c = pg::nn::Ptv3Weights::host_values(pg::nn::SafeTensors::load(dir / "fresh.safetensors"));
    bool differs = false;
    for (const auto& [name, values] : a)
        if (name.find("running_") == std::string::npos && c.at(name) != values) differs = true;
    CHECK(differs);
    // A checkpoint holds its own weights: --init with --resume is an error naming --init.
    Run both = run(common_args(suite) + " --steps 3 --init " + (dir / "base.safetensors").string() + " --resume " +
                   (dir / "base.ckpt.safetensors").string() + " --out " + (dir / "both.safetensors").string());
    CHECK(both.code != 0);
    CHECK(both.out.find("--init") != std::string::npos);
    CHECK_FALSE(fs::exists(dir / "both.safetensors"));
}

TEST_CASE("train --lovasz adds the Lovasz loss and logs it") {
    const fs::path suite = train_suite();
    const fs::path dir = pg::test::scratch("cli-train-lovasz");
    fs::remove_all(dir);
    fs::create_directories(dir);
    Run r = run(common_args(suite) + " --steps 2 --lovasz 0.5 --out " + (dir / "m.safetensors").string());
    INFO(r.out);
    REQUIRE(r.code == 0);
    CHECK(json::parse(safetensors_metadata(dir / "m.safetensors")["training"].get<std::string>())["lovasz"] == 0.5);
    std::ifstream log(dir / "m.log.jsonl");
    int lines = 0;
    for (std::string line; std::getline(log, line); ++lines) {
        const json e = json::parse(line);
        // Half a Lovasz loss (in (0, 1]) inside the total.
        CHECK(e["lovasz"].get<double>() > 0);
        CHECK(e["lovasz"].get<double>() <= 0.5);
        CHECK(e["loss"].get<double>() > e["lovasz"].get<double>());
    }
    CHECK(lines == 2);
}

TEST_CASE("train --features writes a model that reads the feature groups, and segment runs it") {
    const fs::path suite = train_suite();
    const fs::path dir = pg::test::scratch("cli-train-features");
    fs::remove_all(dir);
    fs::create_directories(dir);
    Run r = run(common_args(suite) + " --steps 2 --features rgb,verticality --out " + (dir / "m.safetensors").string());
    INFO(r.out);
    REQUIRE(r.code == 0);
    const json config = json::parse(safetensors_metadata(dir / "m.safetensors")["config"].get<std::string>());
    CHECK(config["in_channels"] == 6);  // click weights, rgb, verticality
    CHECK(config["features"] == json::array({"rgb", "verticality"}));
    const fs::path scene = suite / "desk_000";
    Run prompts = run("prompts " + scene.string() + " --out " + (dir / "prompts.json").string());
    REQUIRE(prompts.code == 0);
    Run seg = run("segment " + (scene / "scene.ply").string() + " --cameras " + (scene / "cameras.json").string() +
                  " --prompts " + (dir / "prompts.json").string() + " --model " + (dir / "m.safetensors").string() +
                  " --decoder ptv3 --views none --out " + (dir / "seg").string());
    INFO(seg.out);
    CHECK(seg.code == 0);
    CHECK(fs::exists(dir / "seg" / "report.json"));
}

TEST_CASE("train: bad arguments are one clear error and nothing is written") {
    const fs::path suite = train_suite();
    const fs::path dir = pg::test::scratch("cli-train-bad");
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string out = " --out " + (dir / "m.safetensors").string();
    struct Case {
        std::string args, names;
    } cases[] = {
        {"train --data " + (dir / "missing").string() + out, "missing"},
        {common_args(suite) + " --out " + (dir / "m.bin").string(), "--out"},
        {common_args(suite) + " --config huge" + out, "--config"},
        {common_args(suite) + " --steps 0" + out, "--steps"},
        {common_args(suite) + " --lovasz -1" + out, "--lovasz"},
        {common_args(suite) + " --features rgb,sparkle" + out, "--features"},
        {common_args(suite) + " --resume " + (suite / "suite.json").string() + out, "--resume"},
        {common_args(suite) + " --init " + (suite / "suite.json").string() + out, "--init"},
    };
    for (const auto& c : cases) {
        Run r = run(c.args);
        INFO(c.args << "\n" << r.out);
        CHECK(r.code != 0);
        CHECK(r.out.find(c.names) != std::string::npos);
    }
    CHECK(fs::is_empty(dir));
}

TEST_CASE("train with the device out of memory: one error, exit 1, no model, and its last checkpoint resumes to the same model") {
    // PG_FAULT_DEVICE_ALLOCATIONS=N fails every device allocation after the first N. Bisection
    // finds an N that fails after a checkpoint was written (most allocations are the first step's).
    const fs::path suite = train_suite();
    const fs::path dir = pg::test::scratch("cli-train-oom");
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string args = common_args(suite) + " --steps 3 --checkpoint-every 1";
    Run whole = run(args + " --out " + (dir / "whole.safetensors").string());
    INFO(whole.out);
    REQUIRE(whole.code == 0);
    auto faulted = [&](int n) {
        fs::remove_all(dir / "f");
        fs::create_directories(dir / "f");
        return pg::test::run_command("PG_FAULT_DEVICE_ALLOCATIONS=" + std::to_string(n) + " " + std::string(PG_CLI) + " " +
                                     args + " --out " + (dir / "f" / "m.safetensors").string());
    };
    int fails = 0, passes = 4096;
    while (faulted(passes).code != 0 && passes < (1 << 20)) fails = passes, passes *= 2;
    Run late{-1, ""};
    while (passes - fails > 1) {
        const int mid = (fails + passes) / 2;
        Run r = faulted(mid);
        if (r.code == 0) {
            passes = mid;
            continue;
        }
        fails = mid;
        if (fs::exists(dir / "f" / "m.ckpt.safetensors")) {
            late = r;
            break;
        }
    }
    INFO("failing after " << fails << " allocations left a checkpoint: " << late.out);
    REQUIRE(fs::exists(dir / "f" / "m.ckpt.safetensors"));
    for (int n : {fails, 0}) {
        auto r = n == fails ? late : faulted(n);
        INFO("after " << n << " allocations: " << r.out);
        CHECK(r.code == 1);
        CHECK(r.out.find("VK_ERROR_OUT_OF_DEVICE_MEMORY") != std::string::npos);
        CHECK(r.out.find("error: ") == r.out.rfind("error: "));
        CHECK_FALSE(fs::exists(dir / "f" / "m.safetensors"));
        for (const auto& e : fs::directory_iterator(dir / "f"))
            CHECK(e.path().filename().string().find(".tmp") == std::string::npos);
    }
    // Back to the late failure: its checkpoint is whole, and resuming it gives the uninterrupted model.
    REQUIRE(faulted(fails).code == 1);
    REQUIRE(fs::exists(dir / "f" / "m.ckpt.safetensors"));
    Run resumed = run(args + " --resume " + (dir / "f" / "m.ckpt.safetensors").string() + " --out " +
                      (dir / "f" / "m.safetensors").string());
    INFO(resumed.out);
    REQUIRE(resumed.code == 0);
    CHECK(pg::data::read_file(dir / "f" / "m.safetensors") == pg::data::read_file(dir / "whole.safetensors"));
}
