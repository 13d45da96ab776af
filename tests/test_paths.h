#pragma once
// Paths the tests read from: the committed fixtures and the optional ../shared data.
#include <filesystem>

namespace pg::test {
inline std::filesystem::path fixtures() { return std::filesystem::path(PG_TEST_DIR) / "fixtures"; }
inline std::filesystem::path source_dir() { return PG_SOURCE_DIR; }
inline std::filesystem::path binary_dir() { return PG_BINARY_DIR; }
// ../shared beside the checkout; absent in a user's clone, so tests that need it skip.
inline std::filesystem::path shared_dir() { return std::filesystem::path(PG_SOURCE_DIR) / ".." / "shared"; }
inline std::filesystem::path scratch(const char* name) {
    auto p = std::filesystem::path(PG_BINARY_DIR) / "test-scratch" / name;
    std::filesystem::create_directories(p);
    return p;
}
}  // namespace pg::test
