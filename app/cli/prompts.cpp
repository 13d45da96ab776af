// pointgauss prompts: the benchmark's click protocol as a prompts.json — for each ground-truth
// object, the view where it is largest and the first click at its most interior pixel, among
// the pixels a click can be lifted from: the object's mask where the scene's rendered opacity
// reaches seg::kMinLiftCoverage (a ray-cast mask also covers thin or translucent parts that the
// splats barely cover, and `segment` cannot lift a click there).
#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "app/cli/commands.h"
#include "dataset/clicks/click2d.h"
#include "dataset/clicks/view_choice.h"
#include "dataset/error.h"
#include "dataset/eval/label_files.h"
#include "dataset/eval/suite_info.h"
#include "dataset/formats/camera_io.h"
#include "dataset/formats/scene_io.h"
#include "dataset/prompts.h"
#include "engine/render/renderer.h"
#include "engine/segment/prompt_encoder.h"
#include "engine/vk/context.h"

namespace pg::app {

namespace fs = std::filesystem;

namespace {

struct PromptsArgs {
    std::string scene_dir, out;
    DeviceOptions device;
};

void run_prompts(const PromptsArgs& a) {
    fs::path dir(a.scene_dir);
    auto objects = data::eval::read_scene_instances(dir);
    if (objects.empty()) throw data::InputError((dir / "meta.json").string(), "lists no instances");
    auto views = data::eval::list_mask_views(dir / "masks");
    if (views.empty()) throw data::InputError((dir / "masks").string(), "holds no masks");
    const auto cloud = data::load_scene(dir / "scene.ply");
    const auto cameras = data::load_cameras((dir / "cameras.json").string());
    vk::ContextOptions co;
    co.device = a.device.device;
    co.quiet = true;
    vk::Context ctx(co);
    render::GpuScene scene(ctx, cloud);
    render::Renderer renderer(ctx);
    std::vector<std::vector<uint16_t>> masks;
    int w = 0, h = 0;
    for (auto& v : views) {
        auto m = data::eval::read_mask(dir / "masks" / (v + ".png"));
        w = m.width, h = m.height;
        auto cam = std::find_if(cameras.begin(), cameras.end(), [&](auto& c) { return c.name == v; });
        if (cam == cameras.end()) throw data::InputError((dir / "cameras.json").string(), "has no camera named '" + v + "'");
        if (cam->width != w || cam->height != h)
            throw data::InputError((dir / "masks" / (v + ".png")).string(), "is not the size of its camera");
        // Pixels a click cannot be lifted from leave every mask.
        renderer.render(scene, *cam, {});
        auto image = renderer.read();
        for (size_t p = 0; p < m.pixels.size(); ++p)
            if (!(image.rgba[4 * p + 3] >= seg::kMinLiftCoverage)) m.pixels[p] = 0;
        masks.push_back(std::move(m.pixels));
    }
    data::Prompts prompts;
    for (auto& obj : objects) {
        auto view = data::clicks::choose_view_for_object(masks, uint16_t(obj.id));
        if (!view) {
            std::fprintf(stderr, "warning: object %d (%s) is visible in no view; no prompt\n", obj.id, obj.name.c_str());
            continue;
        }
        std::vector<uint8_t> gt(masks[*view].size());
        for (size_t p = 0; p < gt.size(); ++p) gt[p] = masks[*view][p] == obj.id;
        auto click = data::clicks::first_click_2d(w, h, gt);
        data::ObjectPrompt op;
        op.name = obj.name.empty() ? "object_" + std::to_string(obj.id) : obj.name;
        op.id = obj.id;
        op.clicks.push_back({views[*view], double(click->u), double(click->v), std::nullopt, true});
        prompts.objects.push_back(op);
    }
    if (prompts.objects.empty()) throw data::InputError(a.scene_dir, "no object is visible in any view");
    data::write_prompts(prompts, a.out);
    std::printf("wrote prompts for %zu object(s) to %s\n", prompts.objects.size(), a.out.c_str());
}

}  // namespace

void register_prompts(CLI::App& app, std::function<void()>& run) {
    auto a = std::make_shared<PromptsArgs>();
    auto* cmd = app.add_subcommand("prompts", "Write the first benchmark click of every ground-truth object");
    cmd->add_option("scene", a->scene_dir, "A benchmark scene folder (meta.json, masks/)")->required();
    cmd->add_option("--out", a->out, "prompts.json to write")->required();
    add_device_option(*cmd, a->device);
    cmd->callback([a, &run] { run = [a] { run_prompts(*a); }; });
}

}  // namespace pg::app
