#pragma once
// Output files appear whole or not at all: data goes to a temporary sibling, then rename.
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

namespace pg::data {

// Calls `write` with a stream on a temporary file next to `path`, then renames it over
// `path`. On any exception the temporary is removed and the exception propagates; a write that
// fails (disk full, a file size limit) is an InputError naming `path` and the system's reason.
void write_atomically(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write);

// SIGINT and SIGTERM remove the temporaries of writes under way before the process ends as the
// signal would end it, so an interrupted export or training run leaves no partial file; a file
// size limit (SIGXFSZ) becomes a failed write instead of a kill. Call once, early in main().
void remove_partial_files_on_signals();

// Reads a whole file; throws InputError(path, "cannot open ...") if it is missing.
std::vector<char> read_file(const std::filesystem::path& path);
std::string read_text_file(const std::filesystem::path& path);

}  // namespace pg::data
