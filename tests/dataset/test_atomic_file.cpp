// Output files appear whole or not at all: a failed write, a full disk and an interrupt
// (SIGINT / SIGTERM in the middle of a write) leave the previous file intact and no temporary.
#include <catch2/catch.hpp>

#include <csignal>
#include <filesystem>
#include <string>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include "dataset/atomic_file.h"
#include "dataset/error.h"
#include "tests/test_paths.h"

namespace fs = std::filesystem;

namespace {

size_t files_in(const fs::path& dir) {
    size_t n = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++n;
    return n;
}

fs::path fresh_dir(const std::string& name) {
    auto dir = pg::test::scratch(name.c_str());
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

}  // namespace

TEST_CASE("an interrupted write leaves the previous file and no temporary") {
    for (int sig : {SIGTERM, SIGINT}) {
        const auto dir = fresh_dir("atomic-signal-" + std::to_string(sig));
        const auto file = dir / "scene.ply";
        pg::data::write_atomically(file, [](std::ostream& os) { os << "the previous export"; });
        const pid_t child = fork();
        REQUIRE(child >= 0);
        if (child == 0) {
            // As a CLI run: the handlers installed, then a signal half-way through a large write.
            pg::data::remove_partial_files_on_signals();
            pg::data::write_atomically(file, [sig](std::ostream& os) {
                const std::string block(1 << 20, 'x');
                for (int i = 0; i < 4; ++i) os << block;
                os.flush();
                std::raise(sig);
                for (int i = 0; i < 4; ++i) os << block;
            });
            _exit(0);  // not reached: the signal ends the process
        }
        int status = 0;
        REQUIRE(waitpid(child, &status, 0) == child);
        INFO("signal " << sig);
        CHECK(WIFSIGNALED(status));
        CHECK((WIFSIGNALED(status) && WTERMSIG(status) == sig));
        CHECK(files_in(dir) == 1);  // no scene.ply.tmpNNN beside it
        CHECK(pg::data::read_text_file(file) == "the previous export");
    }
}

TEST_CASE("a write past a file size limit (as a full disk) fails with the file's name and leaves nothing") {
    const auto dir = fresh_dir("atomic-size-limit");
    const auto file = dir / "big.bin";
    const pid_t child = fork();
    REQUIRE(child >= 0);
    if (child == 0) {
        pg::data::remove_partial_files_on_signals();  // SIGXFSZ ignored: the write fails instead
        rlimit limit{1 << 20, 1 << 20};
        setrlimit(RLIMIT_FSIZE, &limit);
        try {
            pg::data::write_atomically(file, [](std::ostream& os) {
                const std::string block(1 << 16, 'x');
                for (int i = 0; i < 64; ++i) os << block;  // 4 MiB
            });
        } catch (const pg::data::InputError& e) {
            const std::string what = e.what();
            _exit(what.find("big.bin") != std::string::npos && what.find("write failed") != std::string::npos ? 3 : 4);
        } catch (...) {
            _exit(5);
        }
        _exit(6);
    }
    int status = 0;
    REQUIRE(waitpid(child, &status, 0) == child);
    REQUIRE(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 3);  // the InputError, naming the file
    CHECK(files_in(dir) == 0);
}
