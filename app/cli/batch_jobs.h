#pragma once
// pointgauss batch: the jobs file, the shard a process runs, and the records a job leaves.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace pg::app {

// One job of JOBS.json: `segment` arguments (paths resolved against the file's folder), without
// --out, which the batch decides.
struct BatchJob {
    std::string name;
    std::vector<std::string> args;  // "segment", the scene, then options
};

// Reads and checks JOBS.json as a whole before any work: every job an object with a unique
// name usable as a folder, scene / cameras / prompts, option values that `segment` accepts
// (parsed by segment's own parser). Any problem is one InputError naming the file and the job.
std::vector<BatchJob> read_jobs(const std::filesystem::path& file);

// Which shard this process runs: --shard I/N, else a SLURM job array (SLURM_ARRAY_TASK_ID
// relative to SLURM_ARRAY_TASK_MIN, over SLURM_ARRAY_TASK_COUNT), else a Kubernetes Indexed Job
// (JOB_COMPLETION_INDEX, over JOB_COMPLETIONS, which the manifest sets to spec.completions),
// else 0/1. `source` says which.
struct Shard {
    uint32_t index = 0, count = 1;
    std::string source = "no sharding";
    bool runs(size_t job) const { return job % count == index; }
    std::string label() const { return std::to_string(index) + "/" + std::to_string(count); }
};
Shard resolve_shard(const std::string& flag);

// Where a job's files go under the batch's --out folder DIR: its outputs in DIR/<name>/ (as
// `segment --out DIR/<name>` would write them), and, in DIR/.batch/, the completion marker
// (written last), the failure record, the log of its last run and its temporary output folder.
struct BatchPaths {
    std::filesystem::path out;
    std::filesystem::path job(const std::string& name) const { return out / name; }
    std::filesystem::path state() const { return out / ".batch"; }
    std::filesystem::path done(const std::string& name) const { return state() / (name + ".done.json"); }
    std::filesystem::path failed(const std::string& name) const { return state() / (name + ".failed.json"); }
    std::filesystem::path log(const std::string& name) const { return state() / "logs" / (name + ".log"); }
    std::filesystem::path temporaries() const { return state() / "tmp"; }
    std::filesystem::path temporary(const std::string& name, long pid) const {
        return temporaries() / (name + "." + std::to_string(pid));
    }
};

// A job's record: its done marker, else its failure record, else nothing (pending).
std::optional<nlohmann::json> read_record(const BatchPaths& paths, const std::string& name);

}  // namespace pg::app
