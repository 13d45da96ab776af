#pragma once
// Validation during training: named scores on fixed held-out samples, inference mode
// (running statistics), as the pipeline runs the model.
#include <string>
#include <utility>
#include <vector>

namespace pg::nn::train {

struct Validation {
    // In the order a task reports them: the interactive task "iou1" and "iou3" (mean IoU after
    // the first click and after two more), the semantic task "miou" and "oa".
    std::vector<std::pair<std::string, double>> scores;

    double get(const std::string& name) const {
        for (const auto& [n, v] : scores)
            if (n == name) return v;
        return 0;
    }
    std::string text() const;  // "iou1 0.612, iou3 0.745"
};

}  // namespace pg::nn::train
