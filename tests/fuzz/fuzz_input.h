#pragma once
// What every fuzz target shares: the input written to a file of its own (the readers take
// paths, as the program gives them), and the one outcome a malformed input may have besides
// success: the readers' own error naming the file. Anything else (another exception, a crash,
// a sanitizer report, a hang) is a finding.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "dataset/error.h"
#include "nn/safetensors.h"

namespace pg::fuzz {

// A folder of this process alone (libFuzzer's -jobs run several).
inline const std::filesystem::path& scratch() {
    static const std::filesystem::path dir = [] {
        const char* tmp = std::getenv("TMPDIR");
        auto p = std::filesystem::path(tmp && *tmp ? tmp : "/tmp") / ("pg-fuzz-" + std::to_string(::getpid()));
        std::filesystem::create_directories(p);
        return p;
    }();
    return dir;
}

inline std::filesystem::path write_input(const uint8_t* data, size_t size, const std::string& name) {
    const auto path = scratch() / name;
    std::ofstream(path, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data), std::streamsize(size));
    return path;
}

// Runs a reader; an InputError / FormatError must name the file it was given.
template <class F>
void expect_clean(const std::filesystem::path& path, F&& read) {
    auto names_file = [&](const std::exception& e) {
        if (std::string(e.what()).find(path.parent_path().string()) != std::string::npos) return;
        std::fprintf(stderr, "error without the file's name: %s\n", e.what());
        std::abort();
    };
    try {
        read();
    } catch (const data::InputError& e) {
        names_file(e);
    } catch (const nn::FormatError& e) {
        names_file(e);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "unexpected exception: %s\n", e.what());
        std::abort();
    }
}

// Two files from one input: a 4-byte little-endian length, the first file, the second.
inline void split_input(const uint8_t* data, size_t size, const std::filesystem::path& a, const std::filesystem::path& b) {
    uint32_t first = 0;
    for (size_t i = 0; i < 4 && i < size; ++i) first |= uint32_t(data[i]) << (8 * i);
    const size_t rest = size > 4 ? size - 4 : 0;
    const size_t cut = std::min<size_t>(first, rest);
    const char* body = reinterpret_cast<const char*>(data) + std::min<size_t>(size, 4);
    std::ofstream(a, std::ios::binary | std::ios::trunc).write(body, std::streamsize(cut));
    std::ofstream(b, std::ios::binary | std::ios::trunc).write(body + cut, std::streamsize(rest - cut));
}

}  // namespace pg::fuzz
