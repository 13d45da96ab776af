// pointgauss-viewer: click-to-segment in a window, over the same engine as `pointgauss`.
#include <cstdio>
#include <exception>

#include <CLI/CLI.hpp>

#include "app/common/memory_arg.h"
#include "app/viewer/viewer.h"
#include "dataset/atomic_file.h"

int main(int argc, char** argv) {
    pg::data::remove_partial_files_on_signals();
    pg::viewer::ViewerOptions o;
    CLI::App app{"PointGauss viewer: click objects in a 3DGS scene to segment them"};
    app.add_option("scene", o.scene,
                   "Scene file: 3DGS/2DGS PLY, compressed PLY, .splat, .spz, or PlayCanvas SOG (.sog, meta.json or "
                   "its folder, lod-meta.json)")
        ->required();
    app.add_option("--lod", o.lod, "Level of a streamed SOG (lod-meta.json): 0, the finest (default), or coarser")
        ->check(CLI::NonNegativeNumber);
    app.add_option("--cameras", o.cameras,
                   "Camera file or COLMAP folder (default: cameras.json, transforms.json or sparse/0 beside the "
                   "scene; none: an orbit is made)");
    app.add_option("--model", o.model, "Decoder: a PTv3 model file (default: the shipped model), or ground-truth");
    app.add_option("--semantic-model", o.semantic_model,
                   "Label by class: a semantic PTv3 model file (default: PG_SEMANTIC_MODEL, else the shipped "
                   "assets/models/semantic.safetensors)");
    app.add_option("--up", o.up, "Up axis: auto (from the cameras; -y, the COLMAP frame, for a scene without cameras), cameras, ground "
                   "(plane fit), or x,y,z / -y ...")
        ->capture_default_str();
    app.add_option("--decoder", o.decoder, "graph, ptv3+graph, ptv3 or ground-truth (default: as segment: graph, or "
                   "ptv3+graph when --model is given)");
    app.add_option("--lift", o.lift, "Where a click lands: surface (the pixel's dominant surface) or tau (the paper's rule)")
        ->capture_default_str();
    app.add_option("--prompts", o.prompts, "Start from a prompts.json (a segment input or an earlier export)");
    app.add_option("--out", o.out, "Export folder (default: SCENE-segmentation)");
    app.add_option("--max-device-memory", o.max_device_memory,
                   "Device memory the scene may use (e.g. 512M, 2G); past it, or past the device's largest binding, the "
                   "scene is streamed in depth slabs (slower frames)");
    app.add_flag("--half-sh", o.half_sh, "Keep SH coefficients on the device as fp16 (half their memory)");
    app.add_option("--device", o.device, "Vulkan device (substring of its name; default: PG_DEVICE, else the best)");
    app.add_option("--size", [&o](const std::vector<std::string>& v) {
        return std::sscanf(v[0].c_str(), "%dx%d", &o.width, &o.height) == 2 && o.width >= 400 && o.height >= 300;
    }, "Window size WxH (default 1400x860)");
    app.add_option("--render-scale", o.render_scale, "Picture resolution relative to the window (default: 1 on a "
                                                     "GPU, 0.5 on a CPU device)");
    app.add_option("--script", o.script, "Replay actions.json (clicks, UI actions, screenshots), then quit");
    app.add_option("--script-log", o.script_log,
                   "With --script: after each action settles, a JSON line of host RSS and live device memory (a soak's record)");
    app.add_option("--screenshot", o.screenshot, "Save the window as PNG once everything has settled, then quit");
    CLI11_PARSE(app, argc, argv);
    try {
        pg::app::scene_budget(o.max_device_memory, o.half_sh);  // a bad size fails before the window opens
        // "Open" in the panel (or a script's "open") ends a viewer; the next opens on the scene
        // it names, without the first one's cameras, prompts or script (a --screenshot carries over).
        for (;;) {
            std::optional<pg::viewer::Viewer::Reopen> next;
            {
                pg::viewer::Viewer viewer(o);
                const int code = viewer.run();
                if (!viewer.reopen()) return code;
                next = viewer.reopen();
            }
            o.scene = next->scene;
            o.lod = next->lod;
            o.cameras.clear();
            o.prompts.clear();
            o.script.clear();
            o.script_log.clear();
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
}
