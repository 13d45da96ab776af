// pointgauss eval --gt SUITE_DIR --pred PRED_DIR [--split test|train|all] [--two-class CLASS]
// [--json OUT.json] [--plot OUT.png]: scores predictions against a synthetic benchmark suite, in
// the paper's table layout; --two-class scores one class of a semantic suite against all the
// others as background (the paper's building/background table); the plot shows IoU against
// the number of clicks of the click sessions.
#include <cstdio>
#include <filesystem>
#include <memory>

#include "app/cli/commands.h"
#include "dataset/atomic_file.h"
#include "dataset/error.h"
#include "dataset/eval/report.h"
#include "dataset/eval/suite_eval.h"
#include "dataset/report/chart.h"

namespace pg::app {

namespace {

struct EvalArgs {
    std::string gt, pred, split = "test", two_class, json, plot;
};

// Mean IoU after k = 1..20 clicks: over all objects (bold), and per scene.
void write_clicks_plot(const data::eval::SuiteEval& result, const std::string& path) {
    namespace ev = data::eval;
    auto curve = [](const std::vector<const ev::ObjectClicks*>& objects) {
        std::vector<std::pair<double, double>> pts;
        for (int k = 1; k <= ev::kMaxClicks; ++k) {
            double sum = 0;
            for (const auto* o : objects) sum += ev::iou_after_clicks(*o, k);
            pts.push_back({double(k), sum / double(objects.size())});
        }
        return pts;
    };
    const std::array<std::array<uint8_t, 3>, 6> palette{{{230, 120, 40}, {40, 160, 90}, {150, 80, 190},
                                                          {200, 60, 60}, {40, 160, 180}, {160, 140, 40}}};
    data::report::ChartPanel panel{result.info.suite + " (" + result.split + " split): mean IoU after k clicks", "clicks", {}, 0.0, 1.0};
    std::vector<const ev::ObjectClicks*> all;
    for (const auto& scene : result.scenes) {
        std::vector<const ev::ObjectClicks*> objects;
        for (const auto& o : scene.clicks) objects.push_back(&o);
        if (objects.empty()) continue;
        all.insert(all.end(), objects.begin(), objects.end());
        if (result.scenes.size() > 1)
            panel.series.push_back({scene.name, palette[panel.series.size() % palette.size()], curve(objects)});
    }
    if (all.empty()) throw data::InputError("--plot", "the predictions hold no clicks.json (run `pointgauss clicks` first)");
    panel.series.push_back({"all " + std::to_string(all.size()) + " objects", {40, 70, 200}, curve(all), true});
    const data::Image8 img = data::report::draw_chart({panel}, 760, 380);
    data::write_png8(path, img.width, img.height, img.channels, img.pixels);
}

void run_eval(const EvalArgs& a) {
    if (!a.plot.empty() && std::filesystem::path(a.plot).extension() != ".png")
        throw data::InputError("--plot", "must end in .png");
    const auto result = data::eval::evaluate_suite(a.gt, a.pred, a.split, a.two_class);
    if (!a.plot.empty()) write_clicks_plot(result, a.plot);
    if (!a.json.empty()) {
        const std::string text = data::eval::report_json(result).dump(2) + "\n";
        data::write_atomically(a.json, [&](std::ostream& out) { out << text; });
    }
    std::fputs(data::eval::report_markdown(result).c_str(), stdout);
}

}  // namespace

void register_eval(CLI::App& app, std::function<void()>& run) {
    auto args = std::make_shared<EvalArgs>();
    auto* cmd = app.add_subcommand("eval", "Score predictions against a benchmark suite: 3D IoU, 2D mIoU, OA, clicks");
    cmd->add_option("--gt", args->gt, "Suite folder written by `pointgauss synth` (holds suite.json)")->required();
    cmd->add_option("--pred", args->pred, "Prediction folder: <scene>/scene.ply, <scene>/masks/*.png, <scene>/clicks.json")
        ->required();
    cmd->add_option("--split", args->split, "Scenes to score: test (default), train or all")
        ->check(CLI::IsMember({"test", "train", "all"}));
    cmd->add_option("--two-class", args->two_class,
                    "Semantic suites: score this class (name or id) against all others as background, the paper's table");
    cmd->add_option("--json", args->json, "Also write every value (per object, per view) to this JSON file");
    cmd->add_option("--plot", args->plot, "Also draw IoU against the number of clicks (needs clicks.json) to this PNG");
    cmd->callback([args, &run] { run = [args] { run_eval(*args); }; });
}

}  // namespace pg::app
