#include "app/common/staged_output.h"

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <string>
#include <system_error>
#include <vector>

#include <unistd.h>

#include "dataset/error.h"

namespace pg::app {

namespace fs = std::filesystem;

namespace {
constexpr const char* kPrefix = ".pointgauss-partial-";

// Staging folders of processes that no longer run (killed before they could clean up).
void remove_stale(const fs::path& out) {
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(out, ec)) {
        const std::string name = e.path().filename().string();
        if (name.rfind(kPrefix, 0) != 0) continue;
        const long pid = std::strtol(name.c_str() + std::char_traits<char>::length(kPrefix), nullptr, 10);
        if (pid > 0 && (::kill(pid_t(pid), 0) == 0 || errno != ESRCH)) continue;  // alive, or not ours to judge
        fs::remove_all(e.path(), ec);
    }
}
}  // namespace

StagedOutput::StagedOutput(const fs::path& out) : out_(out) {
    std::error_code ec;
    if (fs::exists(out_, ec) && !fs::is_directory(out_, ec)) throw data::InputError(out_.string(), "exists and is not a folder");
    fs::create_directories(out_, ec);
    if (ec) throw data::InputError(out_.string(), "cannot create the output folder: " + ec.message());
    remove_stale(out_);
    staging_ = out_ / (kPrefix + std::to_string(::getpid()));
    fs::remove_all(staging_, ec);
    fs::create_directories(staging_, ec);
    if (ec) throw data::InputError(out_.string(), "cannot write into the output folder: " + ec.message());
}

StagedOutput::~StagedOutput() {
    if (committed_) return;
    std::error_code ec;
    fs::remove_all(staging_, ec);
}

void StagedOutput::commit() {
    std::vector<fs::path> files;
    for (const auto& e : fs::recursive_directory_iterator(staging_))
        if (e.is_regular_file()) files.push_back(e.path());
    for (const auto& from : files) {
        const fs::path to = out_ / fs::relative(from, staging_);
        std::error_code ec;
        fs::create_directories(to.parent_path(), ec);
        if (!ec) fs::rename(from, to, ec);
        if (ec) throw data::InputError(to.string(), "cannot move into place: " + ec.message());
    }
    std::error_code ec;
    fs::remove_all(staging_, ec);
    committed_ = true;
}

}  // namespace pg::app
