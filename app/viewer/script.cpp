#include "app/viewer/script.h"

#include <set>

#include "dataset/error.h"
#include "dataset/json_file.h"

namespace pg::viewer {

namespace {

const std::set<std::string> kKinds = {"snap",   "orbit",   "pan",      "zoom",   "frame",      "new_object",
                                      "click",  "click_pixel", "pick", "select", "rename", "recolour", "hide",
                                      "delete", "isolate", "tints",    "mask",   "decoder",    "undo",
                                      "redo",   "export",  "screenshot", "label_by_class", "class_tints",
                                      "object_from_class", "open"};
const std::set<std::string> kOptions = {"negative", "view", "wait"};

void need(bool ok, const std::string& where, const std::string& what) {
    if (!ok) throw data::InputError(where, what);
}

bool numbers(const nlohmann::json& v, size_t n) {
    if (!v.is_array() || v.size() != n) return false;
    for (auto& x : v)
        if (!x.is_number()) return false;
    return true;
}

}  // namespace

std::vector<Action> read_script(const std::filesystem::path& path) {
    const nlohmann::json j = data::read_json_file(path);
    need(j.is_object() && j.contains("actions") && j["actions"].is_array(), path.string(),
         "expected {\"actions\": [...]}");
    std::vector<Action> actions;
    for (size_t i = 0; i < j["actions"].size(); ++i) {
        const auto& a = j["actions"][i];
        const std::string where = path.string() + ": action " + std::to_string(i);
        need(a.is_object(), where, "is not an object");
        Action act;
        act.where = where;
        act.extra = a;
        for (auto& [key, value] : a.items()) {
            if (kOptions.count(key)) continue;
            need(kKinds.count(key), where, "unknown action '" + key + "'");
            need(act.kind.empty(), where, "names two actions ('" + act.kind + "' and '" + key + "')");
            act.kind = key;
            act.value = value;
        }
        need(!act.kind.empty(), where, "names no action");
        const auto& v = act.value;
        const std::string& k = act.kind;
        if (k == "click" || k == "click_pixel" || k == "pick" || k == "orbit" || k == "pan")
            need(numbers(v, 2), where, "'" + k + "' expects two numbers");
        else if (k == "recolour")
            need(numbers(v, 3), where, "'recolour' expects [r, g, b] in 0..1");
        else if (k == "zoom")
            need(v.is_number() && v.get<double>() > 0, where, "'zoom' expects a factor > 0");
        else if (k == "snap")
            need(v.is_number_integer() || v.is_string(), where, "'snap' expects a camera index or name");
        else if (k == "select" || k == "undo" || k == "redo")
            need(v.is_number_integer(), where, "'" + k + "' expects an integer");
        else if (k == "new_object" || k == "rename" || k == "decoder")
            need(v.is_string(), where, "'" + k + "' expects a string");
        else if (k == "screenshot")
            need(v.is_string() && !v.get<std::string>().empty(), where, "'screenshot' expects a file name");
        else if (k == "label_by_class")
            need((v.is_boolean() && v.get<bool>()) || (v.is_string() && !v.get<std::string>().empty()), where,
                 "'label_by_class' expects true or a semantic model file");
        else if (k == "object_from_class")
            need(v.is_string() || v.is_number_integer() || numbers(v, 2), where,
                 "'object_from_class' expects a class name or id, or a point [x, y] of the picture");
        else if (k == "open")
            need(v.is_string() || (v.is_object() && v.contains("scene") && v["scene"].is_string() &&
                                   (!v.contains("lod") || v["lod"].is_number_unsigned())),
                 where, "'open' expects a scene path or {\"scene\": ..., \"lod\": N}");
        else if (k == "export")
            need(v.is_string() || (v.is_object() && v.contains("folder") && v["folder"].is_string() &&
                                   (!v.contains("format") || v["format"] == "ply" || v["format"] == "sog")),
                 where, "'export' expects a folder or {\"folder\": ..., \"format\": \"ply\" or \"sog\"}");
        else
            need(v.is_boolean(), where, "'" + k + "' expects true or false");
        actions.push_back(std::move(act));
    }
    return actions;
}

}  // namespace pg::viewer
