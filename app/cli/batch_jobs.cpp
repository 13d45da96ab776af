#include "app/cli/batch_jobs.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <functional>
#include <set>

#include <CLI/CLI.hpp>

#include "app/cli/commands.h"
#include "dataset/atomic_file.h"
#include "dataset/error.h"

namespace pg::app {

namespace fs = std::filesystem;

namespace {

bool usable_name(const std::string& name) {
    if (name.empty() || name.size() > 200 || name[0] == '.') return false;
    for (char c : name)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.')) return false;
    return true;
}

// A path as the job gives it, relative to the jobs file's folder.
std::string resolved(const fs::path& base, const std::string& path) {
    const fs::path p(path);
    return (p.is_absolute() ? p : base / p).lexically_normal().string();
}

// segment's own parser over a job's arguments: an option segment does not take, or a value it
// rejects, fails here, before any job runs.
void check_with_segment_parser(const std::vector<std::string>& args) {
    CLI::App app;
    std::function<void()> unused;
    register_segment(app, unused);
    std::vector<std::string> argv = args;
    argv.push_back("--out"), argv.push_back("unused");
    std::reverse(argv.begin(), argv.end());  // CLI11 takes a vector last argument first
    app.parse(argv);
}

}  // namespace

std::vector<BatchJob> read_jobs(const fs::path& file) {
    const std::string where = file.string();
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(data::read_text_file(file));
    } catch (const nlohmann::json::exception& e) {
        throw data::InputError(where, std::string("is not valid JSON: ") + e.what());
    }
    if (!j.is_object() || !j.contains("jobs") || !j["jobs"].is_array())
        throw data::InputError(where, "expected {\"jobs\": [ ... ]}");
    if (j["jobs"].empty()) throw data::InputError(where, "lists no jobs");
    const fs::path base = fs::absolute(file).parent_path();
    std::vector<BatchJob> jobs;
    std::set<std::string> names;
    for (size_t k = 0; k < j["jobs"].size(); ++k) {
        const auto& job = j["jobs"][k];
        const std::string at = where + ": job " + std::to_string(k);
        if (!job.is_object()) throw data::InputError(at, "is not an object");
        if (!job.contains("name") || !job["name"].is_string()) throw data::InputError(at, "has no \"name\" string");
        BatchJob b;
        b.name = job["name"].get<std::string>();
        const std::string named = at + " ('" + b.name + "')";
        if (!usable_name(b.name))
            throw data::InputError(named, "name must be letters, digits, '_', '-' or '.', not starting with '.' (it names a folder)");
        if (!names.insert(b.name).second) throw data::InputError(named, "name is used by an earlier job");
        // A semantic job labels the whole scene by class: no clicks.
        const bool semantic = job.contains("semantic") && job["semantic"].is_boolean() && job["semantic"].get<bool>();
        if (semantic && job.contains("prompts"))
            throw data::InputError(named, "is a semantic job and gives \"prompts\": the semantic mode takes no clicks");
        for (const char* key : {"scene", "cameras", "prompts"})
            if ((!semantic || std::string(key) != "prompts") && (!job.contains(key) || !job[key].is_string()))
                throw data::InputError(named, std::string("has no \"") + key + "\" path");
        b.args = {"segment", resolved(base, job["scene"].get<std::string>())};
        for (auto it = job.begin(); it != job.end(); ++it) {
            const std::string& key = it.key();
            if (key == "name" || key == "scene") continue;
            if (key == "out") throw data::InputError(named, "sets \"out\": the batch writes each job to --out DIR/<name>");
            const auto& v = it.value();
            const std::string flag = "--" + key;
            if (v.is_boolean()) {
                if (v.get<bool>()) b.args.push_back(flag);
            } else if (v.is_string()) {
                std::string s = v.get<std::string>();
                const bool path = key == "cameras" || key == "prompts" || (key == "model" && s != "ground-truth");
                b.args.push_back(flag), b.args.push_back(path ? resolved(base, s) : s);
            } else if (v.is_number()) {
                b.args.push_back(flag), b.args.push_back(v.dump());
            } else {
                throw data::InputError(named, "option \"" + key + "\" must be a string, a number or true/false");
            }
        }
        try {
            check_with_segment_parser(b.args);
        } catch (const CLI::ParseError& e) {
            throw data::InputError(named, std::string("segment rejects its options: ") + e.what());
        }
        jobs.push_back(std::move(b));
    }
    return jobs;
}

Shard resolve_shard(const std::string& flag) {
    auto number = [](const std::string& text, const std::string& what) {
        char* end = nullptr;
        const long v = std::strtol(text.c_str(), &end, 10);
        if (text.empty() || *end != '\0' || v < 0 || v > 1000000)
            throw data::InputError(what, "expected a non-negative integer, got '" + text + "'");
        return uint32_t(v);
    };
    auto env = [](const char* name) -> std::optional<std::string> {
        const char* v = std::getenv(name);
        return v && *v ? std::optional<std::string>(v) : std::nullopt;
    };
    Shard s;
    if (!flag.empty()) {
        const size_t slash = flag.find('/');
        if (slash == std::string::npos) throw data::InputError("--shard", "expected I/N, got '" + flag + "'");
        s.index = number(flag.substr(0, slash), "--shard");
        s.count = number(flag.substr(slash + 1), "--shard");
        s.source = "--shard";
    } else if (auto id = env("SLURM_ARRAY_TASK_ID")) {
        auto count = env("SLURM_ARRAY_TASK_COUNT");
        if (!count) throw data::InputError("SLURM_ARRAY_TASK_COUNT", "is not set beside SLURM_ARRAY_TASK_ID");
        const uint32_t min = number(env("SLURM_ARRAY_TASK_MIN").value_or("0"), "SLURM_ARRAY_TASK_MIN");
        const uint32_t step = number(env("SLURM_ARRAY_TASK_STEP").value_or("1"), "SLURM_ARRAY_TASK_STEP");
        const uint32_t task = number(*id, "SLURM_ARRAY_TASK_ID");
        if (task < min || step == 0) throw data::InputError("SLURM_ARRAY_TASK_ID", "is below SLURM_ARRAY_TASK_MIN");
        s.index = (task - min) / step;
        s.count = number(*count, "SLURM_ARRAY_TASK_COUNT");
        s.source = "SLURM job array";
    } else if (auto index = env("JOB_COMPLETION_INDEX")) {
        auto count = env("JOB_COMPLETIONS");
        if (!count)
            throw data::InputError("JOB_COMPLETIONS", "is not set beside JOB_COMPLETION_INDEX (set it to the Indexed Job's spec.completions)");
        s.index = number(*index, "JOB_COMPLETION_INDEX");
        s.count = number(*count, "JOB_COMPLETIONS");
        s.source = "Kubernetes Indexed Job";
    }
    if (s.count == 0 || s.index >= s.count)
        throw data::InputError(s.source, "shard " + std::to_string(s.index) + " of " + std::to_string(s.count) +
                                             ": the index must be below the count");
    return s;
}

std::optional<nlohmann::json> read_record(const BatchPaths& paths, const std::string& name) {
    for (const fs::path& p : {paths.done(name), paths.failed(name)}) {
        std::error_code ec;
        if (!fs::exists(p, ec)) continue;
        try {
            return nlohmann::json::parse(data::read_text_file(p));
        } catch (const std::exception& e) {
            throw data::InputError(p.string(), std::string("is not a batch record: ") + e.what());
        }
    }
    return std::nullopt;
}

}  // namespace pg::app
