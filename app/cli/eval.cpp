// pointgauss eval --gt SUITE_DIR --pred PRED_DIR [--split test|train|all] [--json OUT.json]:
// scores predictions against a synthetic benchmark suite, in the paper's table layout.
#include <cstdio>
#include <memory>

#include "app/cli/commands.h"
#include "dataset/atomic_file.h"
#include "dataset/eval/report.h"
#include "dataset/eval/suite_eval.h"

namespace pg::app {

namespace {

struct EvalArgs {
    std::string gt, pred, split = "test", json;
};

void run_eval(const EvalArgs& a) {
    const auto result = data::eval::evaluate_suite(a.gt, a.pred, a.split);
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
    cmd->add_option("--json", args->json, "Also write every value (per object, per view) to this JSON file");
    cmd->callback([args, &run] { run = [args] { run_eval(*args); }; });
}

}  // namespace pg::app
