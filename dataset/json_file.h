#pragma once
// Reading a JSON file with the one error every reader gives for a missing or malformed one.
#include <filesystem>

#include <nlohmann/json.hpp>

namespace pg::data {

// Throws InputError naming the file: "no such file", or "invalid JSON: <parser message>".
nlohmann::json read_json_file(const std::filesystem::path& path);

}  // namespace pg::data
