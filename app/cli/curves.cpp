// pointgauss curves M.log.jsonl --out M.curves.png: draws a training log (loss, validation IoU,
// learning rate against the step), as `train` does at its end; for a run still going or one
// trained before the curves existed.
#include <cstdio>
#include <filesystem>
#include <memory>

#include "app/cli/commands.h"
#include "dataset/error.h"
#include "dataset/report/train_curves.h"

namespace pg::app {

namespace {

struct CurvesArgs {
    std::string log, out;
};

void run_curves(const CurvesArgs& a) {
    namespace fs = std::filesystem;
    if (!fs::is_regular_file(a.log)) throw data::InputError(a.log, "is not a file");
    if (fs::path(a.out).extension() != ".png") throw data::InputError("--out", "must end in .png");
    if (fs::exists(a.out) && fs::equivalent(a.log, a.out)) throw data::InputError("--out", "is the log itself");
    data::report::write_train_curves(a.log, a.out);
    std::printf("wrote %s\n", a.out.c_str());
}

}  // namespace

void register_curves(CLI::App& app, std::function<void()>& run) {
    auto a = std::make_shared<CurvesArgs>();
    auto* cmd = app.add_subcommand("curves", "Draw a training log (M.log.jsonl) as a PNG of loss, validation IoU and learning rate");
    cmd->add_option("log", a->log, "Training log written by train (M.log.jsonl)")->required();
    cmd->add_option("--out", a->out, "PNG to write")->required();
    cmd->callback([a, &run] { run = [a] { run_curves(*a); }; });
}

}  // namespace pg::app
