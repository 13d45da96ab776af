// pointgauss: the command-line front end. Errors surface here, once: one line naming the
// file or argument and the reason, and a non-zero exit.
#include <cstdio>
#include <exception>
#include <functional>

#include <CLI/CLI.hpp>

#include "app/cli/commands.h"
#include "dataset/atomic_file.h"
#include "dataset/error.h"
#include "engine/vk/check.h"

int main(int argc, char** argv) {
    pg::data::remove_partial_files_on_signals();
    CLI::App app{"PointGauss: segment 3D Gaussian Splatting scenes on any Vulkan device", "pointgauss"};
    app.require_subcommand(1);
    std::function<void()> run;
    pg::app::register_info(app, run);
    pg::app::register_render(app, run);
    pg::app::register_convert(app, run);
    pg::app::register_bench(app, run);
    pg::app::register_cameras(app, run);
    pg::app::register_synth(app, run);
    pg::app::register_eval(app, run);
    pg::app::register_segment(app, run);
    pg::app::register_prompts(app, run);
    pg::app::register_infer(app, run);
    pg::app::register_clicks(app, run);
    pg::app::register_batch(app, run);
    pg::app::register_train(app, run);
    pg::app::register_curves(app, run);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    }
    try {
        run();
        return 0;
    } catch (const pg::app::PartialFailure& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 2;
    } catch (const pg::data::InputError& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
    } catch (const pg::vk::VulkanError& e) {
        std::fprintf(stderr, "error: Vulkan: %s\n", e.what());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
    }
    return 1;
}
