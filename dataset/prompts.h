#pragma once
// prompts.json: the objects a user wants segmented and their clicks. A click is a pixel of a
// named view (u = column, v = row, the ray goes through the pixel's centre) or a 3D point.
//
// {"objects": [{"name": "mug", "id": 3,
//               "clicks": [{"view": "view_003", "u": 120, "v": 88, "positive": true},
//                          {"point": [0.1, -0.2, 0.3], "positive": false}]}]}
//
// "id" is optional (default: 1, 2, ... in file order) and becomes the object's label in
// every output; "positive" defaults to true.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace pg::data {

struct PromptClick {
    std::string view;                 // empty for a 3D point
    double u = 0, v = 0;              // pixel (column, row) of `view`
    std::optional<glm::dvec3> point;  // a click given directly in 3D
    bool positive = true;
    bool operator==(const PromptClick&) const = default;
};

struct ObjectPrompt {
    std::string name;
    int id = 0;
    std::vector<PromptClick> clicks;
};

struct Prompts {
    std::vector<ObjectPrompt> objects;
};

Prompts read_prompts(const std::filesystem::path& path);
void write_prompts(const Prompts& prompts, const std::filesystem::path& path);

}  // namespace pg::data
