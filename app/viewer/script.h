#pragma once
// Scripted sessions (`--script actions.json`): the viewer replays clicks and UI actions, waiting
// for all work to finish after each one, and can save screenshots. Tests and README pictures
// use it under Xvfb.
//
// {"actions": [
//   {"snap": 0},                          dataset camera by index or name
//   {"orbit": [30, -10]},                 yaw, pitch degrees ("pan": [x, y], "zoom": factor, "frame": true)
//   {"new_object": "mug"},
//   {"click": [0.5, 0.4]},                where, as fractions of the picture (x right, y down)
//   {"click_pixel": [120, 88], "negative": true},   a pixel of the snapped dataset camera
//   {"select": 2}, {"pick": [0.5, 0.4]} (the object under that point), {"rename": "cup"}, {"recolour": [1, 0.5, 0]}, {"hide": true}, {"delete": true},
//   {"isolate": true}, {"tints": true}, {"mask": false}, {"decoder": "ground-truth"},
//   {"label_by_class": true} (or a semantic model file), {"class_tints": false},
//   {"object_from_class": "building"} (a class by name or id: all of it; or [0.5, 0.4]: the
//                                          connected region of the class under that point),
//   {"undo": 1}, {"redo": 1},
//   {"export": "out/dir"} or {"export": {"folder": "out/dir", "masks": false, ...}},
//   {"screenshot": "a.png"}               the window; {"screenshot": "v.png", "view": true}: the picture only
// ]}
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace pg::viewer {

struct Action {
    std::string kind;      // the key naming the action
    nlohmann::json value;  // its value
    nlohmann::json extra;  // the whole object (for options beside the key)
    std::string where;     // "FILE: action N" for errors
};

// Reads and checks a script; InputError naming the file and the action on anything unknown.
std::vector<Action> read_script(const std::filesystem::path& path);

}  // namespace pg::viewer
