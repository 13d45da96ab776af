#pragma once
// Paths the tests read from: the committed fixtures and the optional ../shared data.
#include <cstdlib>
#include <filesystem>
#include <string>

#include <unistd.h>

namespace pg::test {
inline std::filesystem::path fixtures() { return std::filesystem::path(PG_TEST_DIR) / "fixtures"; }
inline std::filesystem::path source_dir() { return PG_SOURCE_DIR; }
inline std::filesystem::path binary_dir() { return PG_BINARY_DIR; }
// ../shared beside the checkout; absent in a user's clone, so tests that need it skip.
inline std::filesystem::path shared_dir() { return std::filesystem::path(PG_SOURCE_DIR) / ".." / "shared"; }
// The discrete-memory reruns (PG_DISCRETE_MEMORY) get their own root: CTest may run a test case
// and its rerun at the same time.
inline std::filesystem::path scratch(const char* name) {
    const char* discrete = std::getenv("PG_DISCRETE_MEMORY");
    const bool rerun = discrete && *discrete && std::string(discrete) != "0";
    auto p = std::filesystem::path(PG_BINARY_DIR) / (rerun ? "test-scratch-discrete" : "test-scratch") / name;
    std::filesystem::create_directories(p);
    return p;
}
// A scratch folder of this process alone: CTest runs test cases of one binary as parallel
// processes, and data one process makes once must not be remade under another's feet.
inline std::filesystem::path process_scratch(const char* name) {
    return scratch((std::string(name) + "-" + std::to_string(::getpid())).c_str());
}
}  // namespace pg::test
