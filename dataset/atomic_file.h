#pragma once
// Output files appear whole or not at all: data goes to a temporary sibling, then rename.
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

namespace pg::data {

// Calls `write` with a stream on a temporary file next to `path`, then renames it over
// `path`. On any exception the temporary is removed and the exception propagates.
void write_atomically(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write);

// Reads a whole file; throws InputError(path, "cannot open ...") if it is missing.
std::vector<char> read_file(const std::filesystem::path& path);
std::string read_text_file(const std::filesystem::path& path);

}  // namespace pg::data
