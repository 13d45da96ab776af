#include "dataset/prompts.h"

#include <cmath>
#include <set>

#include <nlohmann/json.hpp>

#include "dataset/atomic_file.h"
#include "dataset/error.h"
#include "dataset/json_file.h"

namespace pg::data {

Prompts read_prompts(const std::filesystem::path& path) {
    const std::string where = path.string();
    const nlohmann::json j = read_json_file(path);
    if (!j.is_object() || !j.contains("objects") || !j["objects"].is_array())
        throw InputError(where, "expected an object with an \"objects\" array");
    Prompts p;
    std::set<int> ids;
    int next_id = 1;
    for (size_t o = 0; o < j["objects"].size(); ++o) {
        const auto& jo = j["objects"][o];
        const std::string at = "object " + std::to_string(o);
        if (!jo.is_object()) throw InputError(where, at + " is not an object");
        ObjectPrompt obj;
        try {
            obj.name = jo.value("name", "object_" + std::to_string(o + 1));
            obj.id = jo.value("id", next_id);
            if (obj.id < 1 || obj.id > 65535) throw InputError(where, at + ": id must be in 1..65535");
            if (!ids.insert(obj.id).second) throw InputError(where, at + ": id " + std::to_string(obj.id) + " is used twice");
            next_id = std::max(next_id, obj.id + 1);
            if (!jo.contains("clicks") || !jo["clicks"].is_array() || jo["clicks"].empty())
                throw InputError(where, at + " (" + obj.name + ") has no clicks");
            for (size_t c = 0; c < jo["clicks"].size(); ++c) {
                const auto& jc = jo["clicks"][c];
                const std::string cat = at + " click " + std::to_string(c);
                PromptClick click;
                click.positive = jc.value("positive", true);
                if (jc.contains("point")) {
                    auto pt = jc["point"].get<std::vector<double>>();
                    if (pt.size() != 3 || !std::isfinite(pt[0] + pt[1] + pt[2]))
                        throw InputError(where, cat + ": point must be 3 finite numbers");
                    click.point = glm::dvec3(pt[0], pt[1], pt[2]);
                } else {
                    if (!jc.contains("view") || !jc.contains("u") || !jc.contains("v"))
                        throw InputError(where, cat + ": needs \"view\", \"u\" and \"v\", or a \"point\"");
                    click.view = jc["view"].get<std::string>();
                    click.u = jc["u"].get<double>();
                    click.v = jc["v"].get<double>();
                    if (!std::isfinite(click.u) || !std::isfinite(click.v))
                        throw InputError(where, cat + ": u and v must be finite");
                }
                obj.clicks.push_back(std::move(click));
            }
        } catch (const nlohmann::json::exception& e) {
            throw InputError(where, at + ": " + e.what());
        }
        if (!std::any_of(obj.clicks.begin(), obj.clicks.end(), [](auto& c) { return c.positive; }))
            throw InputError(where, at + " (" + obj.name + ") has no positive click");
        p.objects.push_back(std::move(obj));
    }
    if (p.objects.empty()) throw InputError(where, "no objects");
    return p;
}

void write_prompts(const Prompts& prompts, const std::filesystem::path& path) {
    nlohmann::json j;
    j["objects"] = nlohmann::json::array();
    for (const auto& o : prompts.objects) {
        nlohmann::json jo{{"name", o.name}, {"id", o.id}, {"clicks", nlohmann::json::array()}};
        for (const auto& c : o.clicks) {
            nlohmann::json jc{{"positive", c.positive}};
            if (c.point) jc["point"] = {c.point->x, c.point->y, c.point->z};
            else jc["view"] = c.view, jc["u"] = c.u, jc["v"] = c.v;
            jo["clicks"].push_back(jc);
        }
        j["objects"].push_back(jo);
    }
    write_atomically(path, [&](std::ostream& os) { os << j.dump(2) << "\n"; });
}

}  // namespace pg::data
