// The warm-up: after it, a first click on a real scene builds no pipeline of its own.
#include <catch2/catch.hpp>

#include <algorithm>
#include <iterator>

#include "dataset/formats/camera_io.h"
#include "dataset/formats/scene_io.h"
#include "dataset/prompts.h"
#include "dataset/up_axis.h"
#include "engine/render/gpu_scene.h"
#include "engine/segment/segmenter.h"
#include "engine/segment/warm_up.h"
#include "tests/gpu_fixture.h"
#include "tests/test_paths.h"

using namespace pg;

namespace {

std::vector<std::string> added(const std::vector<std::string>& before, const std::vector<std::string>& after) {
    std::vector<std::string> out;
    std::set_difference(after.begin(), after.end(), before.begin(), before.end(), std::back_inserter(out));
    return out;
}

std::string joined(const std::vector<std::string>& names) {
    std::string s;
    for (auto& n : names) s += (s.empty() ? "" : ", ") + n;
    return s;
}

}  // namespace

TEST_CASE("warm-up: the bundled sample's first clicks, one object or all ten, build no pipeline the warm-up did not") {
    test::gpu();  // the shared context's validation check at exit
    const auto dir = test::source_dir() / "assets" / "sample" / "desk_000";
    const auto cloud = data::load_scene(dir / "scene.ply");
    const auto cameras = data::load_cameras(dir / "cameras.json");
    const auto all = data::read_prompts(dir / "prompts.json");
    REQUIRE(all.objects.size() == 10);
    data::Prompts first = all;  // every object's first click: the bench's unit of work
    for (auto& obj : first.objects) obj.clicks.resize(1);
    data::Prompts one;          // a viewer's first click: one object
    one.objects.push_back(first.objects.front());

    seg::SegmentOptions o;
    o.up = data::up_from_cameras(cameras);
    o.graph = seg::GraphUse::Alone;
    o.on_coarse = [](const seg::SegmentResult&) {};  // as the viewer asks on a CPU device

    for (const data::Prompts* prompts : {&one, &first}) {
        INFO(prompts->objects.size() << " object(s)");
        vk::ContextOptions co;  // a context of its own: no pipeline from another test case
        co.validation = true;
        co.quiet = true;
        vk::Context ctx(co);
        render::GpuScene scene(ctx, cloud);
        const auto cold = ctx.pipeline_names();
        CHECK(seg::warm_up(ctx, o, prompts->objects.size()) > 0);
        const auto warmed = ctx.pipeline_names();
        // What the click would otherwise build itself: the graph's and the lift's.
        const auto built = added(cold, warmed);
        for (const char* name : {"segment/graph_knn_k10", "render/pick_pixel"}) {
            INFO(name);
            CHECK(std::find(built.begin(), built.end(), name) != built.end());
        }
        seg::Segmenter segmenter(ctx, cloud, scene, cameras);
        const auto r = segmenter.segment(*prompts, o);
        CHECK(r.failed() == 0);
        const auto missing = added(warmed, ctx.pipeline_names());
        INFO("built by the click: " << joined(missing));
        CHECK(missing.empty());
    }
}
