// pointgauss batch: many `segment` jobs, sharded by the scheduler the user already has (SLURM
// job arrays, Kubernetes Indexed Jobs) or by --shard; resumable, one process per job.
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include "app/cli/batch_jobs.h"
#include "app/cli/commands.h"
#include "app/common/progress.h"
#include "dataset/atomic_file.h"
#include "dataset/error.h"

extern char** environ;

namespace pg::app {

namespace fs = std::filesystem;

namespace {

struct BatchArgs {
    std::string jobs, out, shard, device;
    bool summary = false;
};

std::string host_name() {
    char buf[256] = {};
    return gethostname(buf, sizeof(buf) - 1) == 0 ? std::string(buf) : std::string("unknown");
}

std::string now_utc() {
    const std::time_t t = std::time(nullptr);
    char buf[32];
    std::strftime(buf, sizeof(buf), "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
    return buf;
}

// Runs this executable with `args`, stdout and stderr into `log`; the exit code, or 128 + the
// signal that ended it. A job is a process of its own: a crash or a lost device ends the job,
// not the shard.
int run_logged(const std::vector<std::string>& args, const fs::path& log) {
    const std::string self = fs::read_symlink("/proc/self/exe").string();
    std::vector<char*> argv{const_cast<char*>(self.c_str())};
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    posix_spawn_file_actions_t files;
    posix_spawn_file_actions_init(&files);
    posix_spawn_file_actions_addopen(&files, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&files, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&files, 1, 2);
    pid_t pid = 0;
    const int err = posix_spawn(&pid, self.c_str(), &files, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&files);
    if (err != 0) throw data::InputError(self, "cannot start a job's process: " + std::string(std::strerror(err)));
    int status = 0;
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR) throw data::InputError(self, "lost a job's process: " + std::string(std::strerror(errno)));
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

// The reason a job failed: its log's last "error: " line, else how it ended.
std::string failure_reason(const fs::path& log, int code) {
    std::ifstream in(log);
    std::string line, last;
    while (std::getline(in, line)) {
        const size_t at = line.rfind("error: ");
        if (at != std::string::npos) last = line.substr(at + 7);
    }
    if (!last.empty()) return last;
    return code > 128 ? "killed by signal " + std::to_string(code - 128) : "exit code " + std::to_string(code);
}

void write_json(const fs::path& path, const nlohmann::json& j) {
    data::write_atomically(path, [&](std::ostream& os) { os << j.dump(2) << "\n"; });
}

struct Outcome {
    std::string state;  // done, partial, failed, skipped
    std::string reason;
};

Outcome run_job(const BatchJob& job, const BatchPaths& paths, const Shard& shard, const std::string& device) {
    const std::string& name = job.name;
    if (fs::exists(paths.done(name))) return {"skipped", {}};
    // What an earlier, unfinished run of this job left: its temporary outputs, and its output
    // folder if it was being moved into place (the marker says it is ours to replace).
    for (const auto& e : fs::directory_iterator(paths.temporaries()))
        if (e.path().stem().string() == name) fs::remove_all(e.path());  // <name>.<pid>
    nlohmann::json record{{"job", name}, {"shard", shard.label()}, {"sharding", shard.source}, {"host", host_name()}};
    const fs::path moving = paths.state() / (name + ".moving");
    if (fs::exists(paths.job(name))) {
        if (!fs::exists(moving)) {
            record["state"] = "failed";
            record["reason"] = paths.job(name).string() + " exists and was not written by this batch; move it away";
            record["finished"] = now_utc();
            write_json(paths.failed(name), record);
            return {"failed", record["reason"]};
        }
        fs::remove_all(paths.job(name));
    }
    fs::remove(moving);

    const fs::path tmp = paths.temporary(name, long(getpid()));
    std::vector<std::string> args = job.args;
    args.push_back("--out"), args.push_back(tmp.string());
    if (!device.empty() && std::find(args.begin(), args.end(), "--device") == args.end())
        args.push_back("--device"), args.push_back(device);
    const auto t0 = std::chrono::steady_clock::now();
    const int code = run_logged(args, paths.log(name));
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    record["seconds"] = seconds;
    record["exit_code"] = code;
    record["log"] = paths.log(name).string();
    record["finished"] = now_utc();
    // segment's exit 2: some objects failed, the others were written; the job is complete.
    if ((code == 0 || code == 2) && fs::exists(tmp / "report.json")) {
        const auto report = nlohmann::json::parse(data::read_text_file(tmp / "report.json"));
        record["state"] = code == 0 ? "done" : "partial";
        record["objects"] = nlohmann::json::array();
        for (const auto& o : report.value("objects", nlohmann::json::array())) {
            nlohmann::json r{{"name", o.value("name", "")}, {"gaussians", o.value("gaussians", 0)}};
            if (o.contains("error")) r["error"] = o["error"];
            record["objects"].push_back(r);
        }
        // A semantic job labels classes, not objects: the classes it found and their Gaussians.
        for (const auto& c : report.value("classes", nlohmann::json::array()))
            if (c.value("gaussians", 0) > 0)
                record["classes"].push_back({{"name", c.value("name", "")}, {"gaussians", c.value("gaussians", 0)}});
        write_json(moving, {{"job", name}});
        fs::rename(tmp, paths.job(name));
        write_json(paths.done(name), record);  // last: the job counts as finished from here
        fs::remove(moving);
        fs::remove(paths.failed(name));
        return {record["state"], code == 0 ? std::string() : failure_reason(paths.log(name), code)};
    }
    fs::remove_all(tmp);
    record["state"] = "failed";
    record["reason"] = failure_reason(paths.log(name), code);
    write_json(paths.failed(name), record);
    return {"failed", record["reason"]};
}

void print_summary(const std::vector<BatchJob>& jobs, const BatchPaths& paths) {
    std::printf("| job | state | shard | host | seconds | objects | note |\n|---|---|---|---|---:|---:|---|\n");
    std::map<std::string, size_t> counts;
    for (const auto& job : jobs) {
        const auto r = read_record(paths, job.name);
        const std::string state = r ? r->value("state", std::string("?")) : std::string("pending");
        ++counts[state];
        std::string objects = "", note = r ? r->value("reason", std::string()) : std::string();
        if (r && r->contains("objects")) {
            size_t failed = 0;
            for (const auto& o : (*r)["objects"]) failed += o.contains("error");
            objects = std::to_string((*r)["objects"].size() - failed);
            if (failed) note = std::to_string(failed) + " object(s) failed";
        }
        if (r && r->contains("classes")) {
            objects = "-";
            note = "semantic: " + std::to_string((*r)["classes"].size()) + " classes";
        }
        char seconds[32] = "";
        if (r && r->contains("seconds")) std::snprintf(seconds, sizeof(seconds), "%.1f", (*r)["seconds"].get<double>());
        std::printf("| %s | %s | %s | %s | %s | %s | %s |\n", job.name.c_str(), state.c_str(),
                    r ? r->value("shard", std::string()).c_str() : "", r ? r->value("host", std::string()).c_str() : "",
                    seconds, objects.c_str(), note.c_str());
    }
    std::printf("\n%zu job(s):", jobs.size());
    for (const char* s : {"done", "partial", "failed", "pending"}) std::printf(" %zu %s", counts[s], s);
    std::printf("\n");
}

void run_batch(const BatchArgs& a) {
    const auto jobs = read_jobs(a.jobs);  // every problem with the file before any work
    const BatchPaths paths{fs::absolute(a.out).lexically_normal()};
    if (a.summary) {
        print_summary(jobs, paths);
        return;
    }
    const Shard shard = resolve_shard(a.shard);
    if (fs::exists(paths.out) && !fs::is_directory(paths.out)) throw data::InputError(a.out, "exists and is not a folder");
    fs::create_directories(paths.temporaries());
    fs::create_directories(paths.state() / "logs");
    std::vector<const BatchJob*> mine;
    for (size_t k = 0; k < jobs.size(); ++k)
        if (shard.runs(k)) mine.push_back(&jobs[k]);
    std::printf("shard %s (%s): %zu of %zu job(s)\n", shard.label().c_str(), shard.source.c_str(), mine.size(), jobs.size());
    std::fflush(stdout);
    Progress progress("batch shard " + shard.label(), mine.size());
    std::vector<std::string> failed;
    for (const BatchJob* job : mine) {
        progress.step(job->name);
        const Outcome o = run_job(*job, paths, shard, a.device);
        if (o.state == "failed" || o.state == "partial") failed.push_back(job->name + " (" + o.state + ": " + o.reason + ")");
        std::printf("%s: %s%s\n", job->name.c_str(), o.state == "skipped" ? "finished earlier, skipped" : o.state.c_str(),
                    o.reason.empty() ? "" : (": " + o.reason).c_str());
        std::fflush(stdout);
    }
    progress.finish();
    if (!failed.empty()) {
        std::string list;
        for (const auto& f : failed) list += (list.empty() ? "" : "; ") + f;
        throw PartialFailure(std::to_string(failed.size()) + " of " + std::to_string(mine.size()) +
                             " job(s) of this shard did not finish cleanly: " + list + " (logs in " +
                             (paths.state() / "logs").string() + ")");
    }
}

}  // namespace

void register_batch(CLI::App& app, std::function<void()>& run) {
    auto a = std::make_shared<BatchArgs>();
    auto* cmd = app.add_subcommand("batch", "Run many segment jobs from a JOBS.json, sharded across processes or machines (SLURM arrays, Kubernetes Indexed Jobs); resumable");
    cmd->add_option("jobs", a->jobs, "JOBS.json: {\"jobs\": [{\"name\", \"scene\", \"cameras\", \"prompts\", any segment option}, ...]}")->required();
    cmd->add_option("--out", a->out, "Output folder: each job writes <out>/<name>/ as segment would; records in <out>/.batch/")->required();
    cmd->add_option("--shard", a->shard, "I/N: run jobs k with k mod N = I (default: from SLURM_ARRAY_TASK_ID / SLURM_ARRAY_TASK_COUNT, else JOB_COMPLETION_INDEX / JOB_COMPLETIONS, else all)");
    cmd->add_flag("--summary", a->summary, "Print every job's state, shard, time and objects (whichever shards ran them) and exit");
    cmd->add_option("--device", a->device, "Vulkan device for jobs that name none (index or name substring)");
    cmd->callback([a, &run] { run = [a] { run_batch(*a); }; });
}

}  // namespace pg::app
