// pointgauss batch: shards started together write exactly what one unsharded run writes, a rerun
// changes nothing finished, an unfinished job is redone, a failing job fails alone.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <map>

#include <nlohmann/json.hpp>

#include "dataset/atomic_file.h"
#include "tests/app/cli_run.h"
#include "tests/test_paths.h"

namespace fs = std::filesystem;

namespace {

std::string sample() { return (pg::test::source_dir() / "assets/sample/desk_000").string(); }

// Every file under `dir` (paths relative to it) with its bytes.
std::map<std::string, std::vector<char>> files_under(const fs::path& dir) {
    std::map<std::string, std::vector<char>> out;
    for (const auto& e : fs::recursive_directory_iterator(dir))
        if (e.is_regular_file()) out[fs::relative(e.path(), dir).string()] = pg::data::read_file(e.path());
    return out;
}

// A job's outputs as compared between runs: everything but report.json (its timings differ).
std::map<std::string, std::vector<char>> outputs(const fs::path& job) {
    auto f = files_under(job);
    REQUIRE(f.erase("report.json") == 1);
    return f;
}

void write_text(const fs::path& path, const std::string& text) {
    std::ofstream(path) << text;
}

}  // namespace

TEST_CASE("batch: three shards at once write what one run writes, reruns skip finished jobs and redo unfinished ones") {
    auto dir = pg::test::process_scratch("cli-batch");
    fs::remove_all(dir);
    fs::create_directories(dir);
    // Paths relative to the jobs file, options as segment takes them, one job whose scene is missing.
    fs::copy_file(fs::path(sample()) / "prompts.json", dir / "clicks.json");
    const std::string scene = sample() + "/scene.ply", cameras = sample() + "/cameras.json";
    nlohmann::json jobs = {{"jobs",
                            {{{"name", "views01"}, {"scene", scene}, {"cameras", cameras}, {"prompts", "clicks.json"}, {"views", "0,1"}},
                             {{"name", "k12"}, {"scene", scene}, {"cameras", cameras}, {"prompts", "clicks.json"}, {"views", "2"},
                              {"graph-k", 12}, {"no-refine", true}},
                             {{"name", "missing"}, {"scene", "no-such/scene.ply"}, {"cameras", cameras}, {"prompts", "clicks.json"}},
                             {{"name", "none"}, {"scene", scene}, {"cameras", cameras}, {"prompts", "clicks.json"}, {"views", "none"},
                              {"decoder", "graph"}}}}};
    write_text(dir / "jobs.json", jobs.dump(1));
    const std::string cli = std::string(PG_CLI) + " batch " + (dir / "jobs.json").string() + " --out ";

    auto single = pg::test::run_command(cli + (dir / "single").string());
    INFO(single.out);
    CHECK(single.code == 2);  // the missing scene
    CHECK(single.out.find("no-such/scene.ply") != std::string::npos);

    // Three shards started together, each told its shard the way its scheduler tells it.
    const fs::path sharded = dir / "sharded";
    auto shards = pg::test::run_command(
        "(" + cli + sharded.string() + " --shard 0/3 > " + (dir / "s0.log").string() + " 2>&1; echo $? > " + (dir / "s0.rc").string() + ") & " +
        "(SLURM_ARRAY_TASK_ID=8 SLURM_ARRAY_TASK_MIN=7 SLURM_ARRAY_TASK_COUNT=3 " + cli + sharded.string() + " > " + (dir / "s1.log").string() +
        " 2>&1; echo $? > " + (dir / "s1.rc").string() + ") & " +
        "(JOB_COMPLETION_INDEX=2 JOB_COMPLETIONS=3 " + cli + sharded.string() + " > " + (dir / "s2.log").string() +
        " 2>&1; echo $? > " + (dir / "s2.rc").string() + ") & wait");
    REQUIRE(shards.code == 0);
    const std::string s0 = pg::data::read_text_file(dir / "s0.log"), s1 = pg::data::read_text_file(dir / "s1.log"),
                      s2 = pg::data::read_text_file(dir / "s2.log");
    INFO(s0 << s1 << s2);
    CHECK(pg::data::read_text_file(dir / "s0.rc") == "0\n");  // jobs 0 and 3
    CHECK(pg::data::read_text_file(dir / "s1.rc") == "0\n");  // job 1
    CHECK(pg::data::read_text_file(dir / "s2.rc") == "2\n");  // job 2, the missing scene
    CHECK(s1.find("SLURM") != std::string::npos);
    CHECK(s2.find("Kubernetes") != std::string::npos);
    for (const char* job : {"views01", "k12", "none"}) {
        INFO(job);
        REQUIRE(fs::exists(dir / "single" / job / "report.json"));
        REQUIRE(fs::exists(sharded / job / "report.json"));
        CHECK(outputs(dir / "single" / job) == outputs(sharded / job));
    }
    CHECK(fs::exists(sharded / "views01" / "masks" / "view_001.png"));
    CHECK(!fs::exists(sharded / "missing"));
    CHECK(fs::is_empty(sharded / ".batch" / "tmp"));

    // The summary reads every shard's records.
    auto summary = pg::test::run_command(cli + sharded.string() + " --summary");
    INFO(summary.out);
    CHECK(summary.code == 0);
    CHECK(summary.out.find("| missing | failed | 2/3 |") != std::string::npos);
    CHECK(summary.out.find("| k12 | done | 1/3 |") != std::string::npos);
    CHECK(summary.out.find("3 done 0 partial 1 failed 0 pending") != std::string::npos);

    // A finished shard run again touches nothing.
    std::map<std::string, fs::file_time_type> times;
    for (const auto& e : fs::recursive_directory_iterator(sharded))
        if (e.is_regular_file()) times[e.path().string()] = e.last_write_time();
    const auto before = files_under(sharded);
    auto again = pg::test::run_command(cli + sharded.string() + " --shard 0/3");
    INFO(again.out);
    CHECK(again.code == 0);
    CHECK(again.out.find("views01: finished earlier, skipped") != std::string::npos);
    CHECK(files_under(sharded) == before);
    for (const auto& e : fs::recursive_directory_iterator(sharded))
        if (e.is_regular_file()) CHECK(times[e.path().string()] == e.last_write_time());

    // A job caught between moving its outputs into place and its marker, with a temporary folder
    // left by a killed run: redone, and the leftovers are gone.
    fs::remove(sharded / ".batch" / "views01.done.json");
    write_text(sharded / ".batch" / "views01.moving", "{}");
    write_text(sharded / "views01" / "stale.txt", "from a killed run");
    fs::create_directories(sharded / ".batch" / "tmp" / "views01.4242");
    auto redo = pg::test::run_command(cli + sharded.string() + " --shard 0/3");
    INFO(redo.out);
    CHECK(redo.code == 0);
    CHECK(redo.out.find("views01: done") != std::string::npos);
    CHECK(outputs(sharded / "views01") == outputs(dir / "single" / "views01"));
    CHECK(fs::is_empty(sharded / ".batch" / "tmp"));
    CHECK(!fs::exists(sharded / ".batch" / "views01.moving"));

    // A folder the batch did not write is never replaced: that job fails, the others stand.
    fs::remove_all(sharded / "none");
    fs::remove(sharded / ".batch" / "none.done.json");
    fs::create_directories(sharded / "none");
    write_text(sharded / "none" / "mine.txt", "a user's file");
    auto foreign = pg::test::run_command(cli + sharded.string() + " --shard 0/3");
    INFO(foreign.out);
    CHECK(foreign.code == 2);
    CHECK(foreign.out.find("not written by this batch") != std::string::npos);
    CHECK(pg::data::read_text_file(sharded / "none" / "mine.txt") == "a user's file");
}

TEST_CASE("batch: a bad jobs file or shard is one clear error before any work") {
    auto dir = pg::test::process_scratch("cli-batch-bad");
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string scene = sample() + "/scene.ply", cameras = sample() + "/cameras.json", prompts = sample() + "/prompts.json";
    auto job = [&](nlohmann::json extra) {
        nlohmann::json j = {{"name", "a"}, {"scene", scene}, {"cameras", cameras}, {"prompts", prompts}};
        for (auto it = extra.begin(); it != extra.end(); ++it) j[it.key()] = it.value();
        return j;
    };
    struct Case {
        std::string text, expect;
    };
    std::vector<Case> cases = {
        {"{\"jobs\": [", "not valid JSON"},
        {"{\"job\": []}", "expected {\"jobs\""},
        {nlohmann::json{{"jobs", {job({}), job({})}}}.dump(), "used by an earlier job"},
        {nlohmann::json{{"jobs", {job({{"name", "../up"}})}}}.dump(), "names a folder"},
        {nlohmann::json{{"jobs", {job({{"graph-kk", 3}})}}}.dump(), "graph-kk"},
        {nlohmann::json{{"jobs", {job({{"out", "x"}})}}}.dump(), "\"out\""},
        {nlohmann::json{{"jobs", {job({{"views", nlohmann::json::array()}})}}}.dump(), "\"views\""},
        {nlohmann::json{{"jobs", {{{"name", "a"}, {"scene", scene}, {"cameras", cameras}}}}}.dump(), "\"prompts\""},
        {nlohmann::json{{"jobs", {job({{"semantic", true}})}}}.dump(), "semantic"},
    };
    for (const auto& c : cases) {
        write_text(dir / "jobs.json", c.text);
        auto r = pg::test::run_cli("batch " + (dir / "jobs.json").string() + " --out " + (dir / "out").string());
        INFO(c.text << "\n" << r.out);
        CHECK(r.code == 1);
        CHECK(pg::test::count_lines(r.out) == 1);
        CHECK(r.out.find("jobs.json") != std::string::npos);
        CHECK(r.out.find(c.expect) != std::string::npos);
        CHECK(!fs::exists(dir / "out"));
    }
    // The README's sample jobs file is valid: its summary lists every job, none run yet.
    auto shipped = pg::test::run_cli("batch " + (pg::test::source_dir() / "assets/sample/jobs.json").string() + " --out " +
                                     (dir / "out").string() + " --summary");
    INFO(shipped.out);
    CHECK(shipped.code == 0);
    CHECK(shipped.out.find("3 job(s): 0 done 0 partial 0 failed 3 pending") != std::string::npos);
    CHECK(!fs::exists(dir / "out"));
    write_text(dir / "jobs.json", nlohmann::json{{"jobs", {job({})}}}.dump());
    for (const std::string env : {"", "JOB_COMPLETION_INDEX=1 "}) {
        const std::string shard = env.empty() ? " --shard 3/3" : "";
        auto r = pg::test::run_command(env + PG_CLI + " batch " + (dir / "jobs.json").string() + " --out " + (dir / "out").string() + shard);
        INFO(r.out);
        CHECK(r.code == 1);
        CHECK(r.out.find(env.empty() ? "--shard" : "JOB_COMPLETIONS") != std::string::npos);
        CHECK(!fs::exists(dir / "out"));
    }
}
