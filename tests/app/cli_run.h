#pragma once
// Runs the pointgauss binary (PG_CLI), or any command, as a real process; stdout and stderr together.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cstdio>
#include <string>
#include <sys/wait.h>

namespace pg::test {

struct Run {
    int code;
    std::string out;
};

// Runs a shell command line; stdout and stderr together.
inline Run run_command(const std::string& command) {
    const std::string cmd = command + " 2>&1";
    Run r{0, {}};
    FILE* p = popen(cmd.c_str(), "r");
    REQUIRE(p);
    std::array<char, 4096> buf;
    size_t n;
    while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) r.out.append(buf.data(), n);
    int status = pclose(p);
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128;
    return r;
}

inline Run run_cli(const std::string& args) { return run_command(std::string(PG_CLI) + " " + args); }

inline size_t count_lines(const std::string& s) { return size_t(std::count(s.begin(), s.end(), '\n')); }

}  // namespace pg::test
