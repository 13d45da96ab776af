#pragma once
// What `pointgauss eval` prints and writes: the paper's table in Markdown (percentages)
// and a JSON document with every value (fractions in [0, 1], null where not computed).
// The mean row averages the scenes' values (scenes without the value are left out);
// the clicks mean pools the objects of all scenes.
#include <string>

#include <nlohmann/json.hpp>

#include "dataset/eval/suite_eval.h"

namespace pg::data::eval {

nlohmann::json report_json(const SuiteEval& e);

// Instance suites: | scene | 3D | 2D | OA |; semantic suites: | scene | <class> 3D |
// <class> 2D | ... | 3D | 2D | OA | (3D/2D there are mIoU over classes; the heading names a
// two-class view, whose classes are background and the kept one). A second table
// with IoU@k and NoC@t follows when any scene has clicks.json.
std::string report_markdown(const SuiteEval& e);

}  // namespace pg::data::eval
