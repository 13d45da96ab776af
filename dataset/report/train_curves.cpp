#include "dataset/report/train_curves.h"

#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "dataset/formats/image_io.h"
#include "dataset/report/chart.h"

namespace pg::data::report {

namespace {

// Mean of the last `window` values at every point: single steps are too noisy to read.
std::vector<std::pair<double, double>> running_mean(const std::vector<std::pair<double, double>>& pts, size_t window) {
    std::vector<std::pair<double, double>> out;
    double sum = 0;
    for (size_t i = 0; i < pts.size(); ++i) {
        sum += pts[i].second;
        if (i >= window) sum -= pts[i - window].second;
        out.push_back({pts[i].first, sum / double(std::min(i + 1, window))});
    }
    return out;
}

}  // namespace

void write_train_curves(const std::filesystem::path& log, const std::filesystem::path& png) {
    std::vector<std::pair<double, double>> loss, lovasz, accuracy, lr, iou1, iou3, miou, oa;
    std::ifstream in(log);
    for (std::string line; std::getline(in, line);) {
        const auto e = nlohmann::json::parse(line, nullptr, false);
        if (!e.is_object() || !e.contains("step") || !e["step"].is_number()) continue;
        const double step = e["step"].get<double>();
        auto add = [&](const char* key, std::vector<std::pair<double, double>>& to) {
            if (e.contains(key) && e[key].is_number()) to.push_back({step, e[key].get<double>()});
        };
        add("loss", loss);
        add("lovasz", lovasz);
        add("accuracy", accuracy);
        add("lr", lr);
        add("val_iou1", iou1);
        add("val_iou3", iou3);
        add("val_miou", miou);  // the semantic task's
        add("val_oa", oa);
    }
    // The cross-entropy alone: the logged loss includes the Lovasz term where one was added.
    std::vector<std::pair<double, double>> ce = loss;
    for (size_t i = 0, j = 0; i < ce.size(); ++i) {
        while (j < lovasz.size() && lovasz[j].first < ce[i].first) ++j;
        if (j < lovasz.size() && lovasz[j].first == ce[i].first) ce[i].second -= lovasz[j].second;
    }
    const size_t window = 50;
    ChartPanel losses{"training loss, mean of 50 steps", "", {{"cross-entropy", {200, 60, 40}, running_mean(ce, window)}},
                            0.0, {}};
    if (!lovasz.empty()) losses.series.push_back({"Lovasz", {230, 150, 40}, running_mean(lovasz, window)});
    const bool semantic = !miou.empty() && iou1.empty();
    ChartPanel quality{semantic ? "validation mIoU and OA (held-out samples), training accuracy"
                                : "validation IoU (held-out samples), training accuracy",
                       "",
                       {},
                       0.0,
                       1.0};
    if (semantic) {
        quality.series.push_back({"mIoU", {40, 90, 200}, miou, true});
        quality.series.push_back({"OA", {40, 160, 90}, oa, true});
    } else {
        quality.series.push_back({"IoU, 1 click", {40, 90, 200}, iou1, true});
        quality.series.push_back({"IoU, 3 clicks", {40, 160, 90}, iou3, true});
    }
    quality.series.push_back({"accuracy, mean of 50", {150, 150, 150}, running_mean(accuracy, window)});
    ChartPanel rate{"learning rate (OneCycle)", "step", {{"", {110, 70, 170}, lr}}, 0.0, {}};
    const data::Image8 img = draw_chart({losses, quality, rate}, 900, 260);
    data::write_png8(png, img.width, img.height, img.channels, img.pixels);
}

}  // namespace pg::data::report
