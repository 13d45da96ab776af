#pragma once
// The picture of a training run: loss, validation IoU and learning rate against the step,
// drawn from its log (M.log.jsonl, resumed runs included) beside the model as M.curves.png.
#include <filesystem>

namespace pg::data::report {

// Reads `log` and writes the chart to `png` (atomically). Lines that are not JSON objects with
// a step are skipped: a log cut off mid-line still plots.
void write_train_curves(const std::filesystem::path& log, const std::filesystem::path& png);

}  // namespace pg::data::report
