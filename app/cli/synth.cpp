// pointgauss synth: generates a SplatSeg-Synth suite, renders previews on the GPU for each
// scene's contact sheet, and measures how well the ray-cast masks agree with the Gaussians'
// labels as the renderer sees them (the label of the Gaussian that saturates each pixel), per
// class too on semantic suites.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "app/cli/commands.h"
#include "app/common/progress.h"
#include "app/common/staged_output.h"
#include "dataset/atomic_file.h"
#include "dataset/error.h"
#include "dataset/report/palette.h"
#include "dataset/synth/contact_sheet.h"
#include "dataset/synth/synth.h"
#include "engine/render/renderer.h"
#include "engine/vk/context.h"

namespace pg::app {

namespace fs = std::filesystem;

namespace {

struct SynthArgs {
    std::string suite = "desk", out;
    int scenes = 5, preview_views = 4;
    uint64_t seed = 1;
    data::synth::SynthOptions options;
    DeviceOptions device;
};

struct Agreement {
    uint64_t pixels = 0, agree = 0;     // over pixels where the renderer reaches tau
    uint64_t labelled_gt = 0, labelled_both = 0;
    // Semantic suites: per class id, mask pixels (where tau is reached) and those rendered the same.
    std::vector<uint64_t> class_pixels, class_agree;
};

// Renders every view and compares the label of each pixel's tau Gaussian with the mask.
Agreement measure_agreement(render::Renderer& renderer, const render::GpuScene& gpu,
                            const data::synth::SynthScene& scene, const std::vector<int32_t>& labels,
                            std::vector<data::Image8>* previews, int preview_views) {
    Agreement a;
    if (data::synth::suite_is_semantic(scene.suite)) {
        int ids = 0;
        for (const auto& c : scene.classes) ids = std::max(ids, c.id + 1);
        a.class_pixels.assign(size_t(ids), 0);
        a.class_agree.assign(size_t(ids), 0);
    }
    size_t stride = std::max<size_t>(1, scene.cameras.size() / size_t(std::max(1, preview_views)));
    for (size_t v = 0; v < scene.cameras.size(); ++v) {
        const auto& cam = scene.cameras[v];
        renderer.render(gpu, cam, {});
        auto img = renderer.read();
        const auto& mask = scene.masks[v];
        for (size_t p = 0; p < mask.size(); ++p) {
            int32_t id = img.tau_id[p];
            if (id < 0) continue;
            int32_t rendered = labels[size_t(id)];
            ++a.pixels;
            a.agree += rendered == int32_t(mask[p]);
            if (mask[p] < a.class_pixels.size()) {
                ++a.class_pixels[mask[p]];
                a.class_agree[mask[p]] += rendered == int32_t(mask[p]);
            }
            if (mask[p] != 0) {
                ++a.labelled_gt;
                a.labelled_both += rendered == int32_t(mask[p]);
            }
        }
        if (previews && v % stride == 0 && previews->size() < size_t(preview_views)) {
            data::Image8 rgb{img.width, img.height, 3, {}};
            rgb.pixels.resize(size_t(img.width) * img.height * 3);
            for (size_t p = 0; p < size_t(img.width) * img.height; ++p)
                for (int c = 0; c < 3; ++c)
                    rgb.pixels[p * 3 + c] = uint8_t(std::clamp(img.rgba[p * 4 + c], 0.0f, 1.0f) * 255.0f + 0.5f);
            previews->push_back(std::move(rgb));
        }
    }
    return a;
}

// Semantic suites: per class, its Gaussians, its mask pixels where the renderer reaches tau and
// the fraction of those rendered with the same class.
nlohmann::json class_report(const data::synth::SynthScene& scene, const std::vector<int32_t>& labels, const Agreement& a) {
    nlohmann::json out = nlohmann::json::array();
    for (const auto& c : scene.classes) {
        const uint64_t pixels = a.class_pixels[size_t(c.id)];
        out.push_back({{"id", c.id},
                       {"name", c.name},
                       {"gaussians", std::count(labels.begin(), labels.end(), c.id)},
                       {"mask_pixels", pixels},
                       {"rendered_agreement", pixels ? double(a.class_agree[size_t(c.id)]) / double(pixels) : 0.0}});
    }
    return out;
}

void run_synth(const SynthArgs& a) {
    auto suite = data::synth::parse_suite(a.suite);
    if (a.scenes < 1 || a.scenes > 10000) throw data::InputError("--scenes", "must be between 1 and 10000");
    if (a.preview_views < 1 || a.preview_views > 64) throw data::InputError("--previews", "must be between 1 and 64");
    // The suite appears whole or not at all: a failure part-way (the device or the disk full, an
    // interrupt) leaves OUT as it was.
    StagedOutput staged{fs::path(a.out)};
    const fs::path& out = staged.dir();

    vk::ContextOptions co;
    co.device = a.device.device;
    vk::Context ctx(co);
    render::Renderer renderer(ctx);
    const bool semantic = data::synth::suite_is_semantic(suite);
    std::vector<std::string> names;
    nlohmann::json report;
    report["suite"] = a.suite;
    report["seed"] = a.seed;
    Progress progress("synth " + a.suite, size_t(a.scenes));
    for (int i = 0; i < a.scenes; ++i) {
        auto t0 = std::chrono::steady_clock::now();
        auto scene = data::synth::make_suite_scene(suite, i, a.seed, a.options);
        double gen_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        fs::path dir = out / scene.name;
        data::synth::write_scene(scene, dir);

        render::GpuScene gpu(ctx, scene.cloud);
        auto labels = *scene.cloud.int_property(semantic ? "class" : "instance");
        std::vector<data::Image8> previews, masks;
        Agreement agree = measure_agreement(renderer, gpu, scene, labels, &previews, a.preview_views);
        size_t stride = std::max<size_t>(1, scene.cameras.size() / size_t(a.preview_views));
        for (size_t v = 0; v < scene.cameras.size() && masks.size() < previews.size(); v += stride)
            masks.push_back(data::report::colourise_mask(scene.masks[v], scene.cameras[v].width, scene.cameras[v].height));
        data::synth::write_contact_sheet(dir / "contact_sheet.png",
                                         data::synth::make_contact_sheet(previews, masks, 4));
        double total_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

        double pixel_agreement = agree.pixels ? double(agree.agree) / double(agree.pixels) : 0.0;
        double object_agreement = agree.labelled_gt ? double(agree.labelled_both) / double(agree.labelled_gt) : 0.0;
        report["scenes"].push_back({{"name", scene.name},
                                    {"gaussians", scene.cloud.size()},
                                    {"cameras", scene.cameras.size()},
                                    {"instances", scene.instances.size()},
                                    {"generate_seconds", gen_s},
                                    {"total_seconds", total_s},
                                    {"label_agreement", pixel_agreement},
                                    {"object_pixel_agreement", object_agreement}});
        if (semantic) report["scenes"].back()["classes"] = class_report(scene, labels, agree);
        names.push_back(scene.name);
        progress.step(scene.name);
        if (!isatty(2) || std::getenv("CI")) {
            std::printf("%s: %zu Gaussians, %zu cameras, %zu instances, %.1f s (generate %.1f s), rendered labels agree "
                        "with the masks on %.2f%% of pixels (%.2f%% of object pixels)\n",
                        scene.name.c_str(), scene.cloud.size(), scene.cameras.size(), scene.instances.size(), total_s,
                        gen_s, 100 * pixel_agreement, 100 * object_agreement);
            if (semantic) {
                std::printf("  per class: Gaussians, agreement on its mask pixels:");
                for (const auto& c : report["scenes"].back()["classes"])
                    std::printf(" %s %zu %.1f%%;", c["name"].get<std::string>().c_str(), c["gaussians"].get<size_t>(),
                                100.0 * c["rendered_agreement"].get<double>());
                std::printf("\n");
            }
            std::fflush(stdout);  // as it happens, also into a log file
        }
    }
    progress.finish();
    data::synth::write_suite_index(suite, a.seed, names, out);
    data::write_atomically(out / "synth_report.json", [&](std::ostream& os) { os << report.dump(2) << "\n"; });
    staged.commit();
    std::printf("wrote %zu %s scene(s) to %s\n", names.size(), a.suite.c_str(), a.out.c_str());
}

}  // namespace

void register_synth(CLI::App& app, std::function<void()>& run) {
    auto a = std::make_shared<SynthArgs>();
    auto* cmd = app.add_subcommand("synth", "Generate a SplatSeg-Synth benchmark suite with exact 2D/3D ground truth");
    cmd->add_option("--suite", a->suite, "desk, vehicles, residence or campus")->capture_default_str();
    cmd->add_option("--scenes", a->scenes, "Number of scenes")->capture_default_str();
    cmd->add_option("--seed", a->seed, "Seed: the same seed gives the same bytes")->capture_default_str();
    cmd->add_option("--out", a->out, "Suite folder")->required();
    cmd->add_option("--cameras", a->options.cameras, "Cameras per scene (0: the suite's default)");
    cmd->add_option("--width", a->options.width, "Image width")->capture_default_str();
    cmd->add_option("--height", a->options.height, "Image height")->capture_default_str();
    cmd->add_option("--density", a->options.density, "Gaussian count factor")->capture_default_str();
    cmd->add_option("--sh-degree", a->options.sh_degree, "SH degree 0-3 (-1: the suite's default)");
    cmd->add_option("--previews", a->preview_views, "Views on each contact sheet")->capture_default_str();
    add_device_option(*cmd, a->device);
    cmd->callback([a, &run] { run = [a] { run_synth(*a); }; });
}

}  // namespace pg::app
