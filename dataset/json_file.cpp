#include "dataset/json_file.h"

#include "dataset/atomic_file.h"
#include "dataset/error.h"

namespace pg::data {

nlohmann::json read_json_file(const std::filesystem::path& path) {
    try {
        return nlohmann::json::parse(read_text_file(path));
    } catch (const nlohmann::json::exception& e) {
        throw InputError(path.string(), std::string("invalid JSON: ") + e.what());
    }
}

}  // namespace pg::data
