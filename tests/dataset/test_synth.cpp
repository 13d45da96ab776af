// SplatSeg-Synth scenes: determinism to the byte, ground-truth masks consistent with the
// labelled Gaussians, every instance visible, up axis and cameras, opacities like a trained
// capture, the suite index and the contact sheet. Small densities keep each case fast.
#include <algorithm>
#include <catch2/catch.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <set>

#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>
#include <stb/stb_image.h>

#include "dataset/atomic_file.h"
#include "dataset/error.h"
#include "dataset/formats/camera_io.h"
#include "dataset/formats/scene_io.h"
#include "dataset/report/palette.h"
#include "dataset/scene_stats.h"
#include "dataset/synth/contact_sheet.h"
#include "dataset/synth/synth.h"

namespace fs = std::filesystem;
using namespace pg::data;
using namespace pg::data::report;
using namespace pg::data::synth;

namespace {

SynthOptions small_options() {
    SynthOptions o;
    o.density = 0.06;
    o.cameras = 12;
    o.width = 96;
    o.height = 72;
    o.threads = 2;
    return o;
}

fs::path scratch(const std::string& name) {
    const fs::path p = fs::path(PG_BINARY_DIR) / "test-scratch" / "synth" / name;
    fs::remove_all(p);
    fs::create_directories(p);
    return p;
}

// Files under dir, relative, sorted.
std::vector<fs::path> list_files(const fs::path& dir) {
    std::vector<fs::path> out;
    for (const auto& e : fs::recursive_directory_iterator(dir))
        if (e.is_regular_file()) out.push_back(fs::relative(e.path(), dir));
    std::sort(out.begin(), out.end());
    return out;
}

// Where a world point lands in a camera: pixel coordinates and depth.
bool project(const Camera& c, const glm::dvec3& p, glm::dvec2& px, double& depth) {
    const glm::dvec3 q = c.R * p + c.t;
    if (q.z <= 1e-9) return false;
    px = glm::dvec2(c.fx * q.x / q.z + c.cx, c.fy * q.y / q.z + c.cy);
    depth = q.z;
    return true;
}

// A flat Gaussian's normal: the axis of its smallest scale.
glm::dvec3 splat_normal(const GaussianCloud& cloud, size_t i) {
    const glm::vec4 q = glm::normalize(cloud.rotation[i]);  // (w, x, y, z)
    const glm::dmat3 R = glm::mat3_cast(glm::quat(q.x, q.y, q.z, q.w));
    const glm::vec3 s = cloud.log_scale[i];
    return R[s.x <= s.y && s.x <= s.z ? 0 : (s.y <= s.z ? 1 : 2)];
}

}  // namespace

TEST_CASE("synth: the same seed gives the same bytes, another seed a different scene", "[synth]") {
    for (SuiteKind suite : {SuiteKind::Desk, SuiteKind::Residence, SuiteKind::Campus}) {
        const fs::path a = scratch("det_a"), b = scratch("det_b"), c = scratch("det_c");
        write_scene(make_suite_scene(suite, 1, 42, small_options()), a);
        SynthOptions four_threads = small_options();
        four_threads.threads = 4;  // the thread count must not matter
        write_scene(make_suite_scene(suite, 1, 42, four_threads), b);
        write_scene(make_suite_scene(suite, 1, 43, small_options()), c);
        const auto files = list_files(a);
        REQUIRE(files == list_files(b));
        CHECK(files.size() > 12);
        for (const fs::path& f : files) {
            INFO(suite_name(suite) << ": " << f.string());
            CHECK(read_file(a / f) == read_file(b / f));
        }
        CHECK(read_file(a / "scene.ply") != read_file(c / "scene.ply"));
        CHECK(read_file(a / "masks" / "view_000.png") != read_file(c / "masks" / "view_000.png"));
    }
}

TEST_CASE("synth: every instance is in the PLY and in some mask, files follow the contract", "[synth]") {
    for (SuiteKind suite : kAllSuites) {
        INFO(suite_name(suite));
        const SynthScene s = make_suite_scene(suite, 0, 7, small_options());
        const fs::path dir = scratch(std::string("contract_") + suite_name(suite));
        write_scene(s, dir);
        const bool semantic = suite_is_semantic(suite);

        const GaussianCloud cloud = load_scene(dir / "scene.ply");
        REQUIRE(cloud.size() == s.cloud.size());
        const auto instance = cloud.int_property("instance"), cls = cloud.int_property("class");
        REQUIRE(instance);
        REQUIRE(cls);
        std::set<int> in_ply(instance->begin(), instance->end());
        std::set<int> in_masks;
        REQUIRE(s.masks.size() == s.cameras.size());
        for (size_t v = 0; v < s.cameras.size(); ++v) {
            const Camera& cam = s.cameras[v];
            const auto bytes = read_file(dir / "masks" / (cam.name + ".png"));
            int w, h, ch;
            uint16_t* px = stbi_load_16_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()), int(bytes.size()), &w, &h, &ch, 1);
            REQUIRE(px);
            REQUIRE(w == cam.width);
            REQUIRE(h == cam.height);
            CHECK(std::equal(px, px + size_t(w) * h, s.masks[v].begin()));  // what is written is what was cast
            stbi_image_free(px);
            in_masks.insert(s.masks[v].begin(), s.masks[v].end());
        }
        const auto meta = nlohmann::json::parse(read_text_file(dir / "meta.json"));
        CHECK(meta["suite"] == suite_name(suite));
        CHECK(meta["task"] == (semantic ? "semantic" : "instance"));
        CHECK(meta["cameras"] == s.cameras.size());
        CHECK(meta["image_size"] == nlohmann::json::array({96, 72}));
        REQUIRE(meta["instances"].size() == s.instances.size());
        CHECK(s.instances.size() >= (suite == SuiteKind::Vehicles ? 3u : 5u));
        for (const auto& inst : meta["instances"]) {
            const int id = inst["id"], c = inst["class"];
            INFO("instance " << id);
            CHECK(in_ply.count(id));
            CHECK(inst["gaussians"].get<size_t>() > 0);
            CHECK(in_masks.count(semantic ? c : id));
        }
        for (int id : in_masks) CHECK((id == 0 || (semantic ? size_t(id) < s.classes.size() : in_ply.count(id))));
        if (semantic) {  // every class, the thin ones (lamp posts, cars) included, in both
            std::set<int> classes_in_ply(cls->begin(), cls->end());
            for (const ClassInfo& c : s.classes) {
                INFO("class " << c.id << " " << c.name);
                CHECK(classes_in_ply.count(c.id));
                CHECK(in_masks.count(c.id));
            }
        }
        const auto inria = load_cameras(dir / "cameras.json"), colmap = load_cameras(dir / "sparse" / "0");
        REQUIRE(inria.size() == s.cameras.size());
        REQUIRE(colmap.size() == s.cameras.size());
        CHECK(inria[0].name == "view_000");
        CHECK(glm::length(inria[5].position() - s.cameras[5].position()) < 1e-6 * (1.0 + glm::length(s.cameras[5].position())));
        CHECK(glm::length(colmap[5].forward() - s.cameras[5].forward()) < 1e-6);
    }
}

TEST_CASE("synth: masks agree with the labelled Gaussians that the cameras see", "[synth]") {
    for (SuiteKind suite : kAllSuites) {
        INFO(suite_name(suite));
        SynthOptions o = small_options();
        o.width = 160;
        o.height = 120;
        const SynthScene s = make_suite_scene(suite, 2, 11, o);
        const bool semantic = suite_is_semantic(suite);
        const auto label = *s.cloud.int_property(semantic ? "class" : "instance");
        const auto instance = *s.cloud.int_property("instance");
        size_t checked = 0, agree = 0, background = 0, off_rim = 0, occluded = 0;
        for (size_t v = 0; v < s.cameras.size(); v += 2) {
            const Camera& cam = s.cameras[v];
            for (size_t i = 0; i < s.cloud.size(); ++i) {
                if ((semantic ? label[i] : instance[i]) == 0) continue;  // campus: every class but sky and floaters
                glm::dvec2 px;
                double depth;
                const glm::dvec3 p(s.cloud.mean[i]);
                if (!project(cam, p, px, depth) || px.x < 1 || px.y < 1 || px.x >= cam.width - 1 || px.y >= cam.height - 1)
                    continue;
                // Seen from this camera only if nothing lies in front of the centre.
                const glm::dvec3 o_cam = cam.position(), to = p - o_cam;
                const double dist = glm::length(to);
                // Skip splats seen edge-on: at a silhouette the pixel centre may pass beside them.
                if (std::abs(glm::dot(splat_normal(s.cloud, i), to / dist)) < 0.3) continue;
                // Centres sit just inside their solid (the generator insets them so the rendered
                // outline fits the geometry): a hit within a few Gaussian sizes and pixel footprints
                // before the centre is the Gaussian's own surface, not an occluder.
                const glm::vec3 ls = s.cloud.log_scale[i];
                const double own = 3.0 * std::exp(double(std::max({ls.x, ls.y, ls.z}))) + 2.0 * dist / cam.fx;
                Hit hit;
                if (s.shapes.first_hit(Ray{o_cam, to / dist}, 0.0, kInf, hit) && hit.t < dist - own) {
                    ++occluded;
                    continue;
                }
                const int x = int(px.x), y = int(px.y);
                const auto mask_at = [&](int xx, int yy) { return int(s.masks[v][size_t(yy) * cam.width + size_t(xx)]); };
                ++checked;
                if (mask_at(x, y) != 0) {
                    agree += mask_at(x, y) == label[i];
                    continue;
                }
                // On background: fine if the pixel is on the object's rim (a neighbour has it).
                ++background;
                bool rim = false;
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) rim = rim || mask_at(x + dx, y + dy) == label[i];
                off_rim += !rim;
            }
        }
        INFO(checked << " visible labelled centres, " << agree << " agree, " << background << " on background ("
                     << off_rim << " off the rim), " << occluded << " occluded");
        REQUIRE(checked > 500);
        CHECK(double(agree) >= 0.95 * double(checked - background));
        CHECK(double(off_rim) <= 0.01 * double(checked));
        if (suite == SuiteKind::Desk) CHECK(occluded > checked / 50);  // objects hide each other
    }
}

TEST_CASE("synth: up axis, upright cameras that all see the scene centre", "[synth]") {
    std::set<std::vector<double>> ups;
    for (SuiteKind suite : kAllSuites)
        for (int index = 0; index < 3; ++index) {
            SynthOptions o = small_options();
            o.masks = false;
            o.density = 0.02;
            const SynthScene s = make_suite_scene(suite, index, 5, o);
            INFO(s.name);
            const bool minus_y = glm::length(s.up - glm::dvec3(0, -1, 0)) < 1e-9, plus_z = glm::length(s.up - glm::dvec3(0, 0, 1)) < 1e-9;
            CHECK((minus_y || plus_z));
            if (suite == SuiteKind::Desk) CHECK(minus_y);
            else ups.insert({std::round(s.up.x), std::round(s.up.y), std::round(s.up.z)});
            for (const Camera& cam : s.cameras) {
                glm::dvec2 px;
                double depth;
                REQUIRE(project(cam, s.centre, px, depth));
                CHECK(px.x > 0);
                CHECK(px.y > 0);
                CHECK(px.x < cam.width);
                CHECK(px.y < cam.height);
                CHECK(glm::dot(cam.up(), s.up) > 0.3);  // world up appears up in the image
                CHECK_FALSE(s.shapes.inside(cam.position()));
            }
            // The scene lies mostly below the cameras: ground and objects under them along up.
            double below = 0;
            for (const auto& m : s.cloud.mean) below += glm::dot(glm::dvec3(m) - s.centre, s.up) < 0.5 * s.scale;
            CHECK(below > 0.6 * double(s.cloud.size()));
        }
    CHECK(ups.size() == 2);  // both up axes occur among the outdoor scenes
}

TEST_CASE("synth: Gaussians look like a trained capture", "[synth]") {
    for (SuiteKind suite : kAllSuites) {
        SynthOptions o = small_options();
        o.masks = false;
        const SynthScene s = make_suite_scene(suite, 0, 3, o);
        INFO(s.name);
        const SceneStats st = compute_stats(s.cloud);
        CHECK(st.non_finite == 0);
        CHECK(st.opacity.p(50) > 0.8f);
        CHECK(st.opacity.p(5) < 0.3f);
        CHECK(s.cloud.sh_degree == (suite == SuiteKind::Desk || suite == SuiteKind::Vehicles ? 3 : 1));
        // Flat and surface-aligned: the thinnest axis 5-20% of the in-plane ones, except for
        // foliage (thicker) and floaters.
        size_t flat = 0, flattish = 0;
        for (const auto& ls : s.cloud.log_scale) {
            const glm::vec3 sc = glm::exp(ls);
            const float lo = std::min({sc.x, sc.y, sc.z}), mid = sc.x + sc.y + sc.z - lo - std::max({sc.x, sc.y, sc.z});
            flat += lo <= 0.21f * mid;
            flattish += lo <= 0.6f * mid;
        }
        CHECK(double(flat) > 0.75 * double(s.cloud.size()));
        CHECK(double(flattish) > 0.97 * double(s.cloud.size()));
        // Sizes vary with detail: a wide spread of Gaussian sizes.
        CHECK(st.max_scale.p(95) > 4.0f * st.max_scale.p(5));
    }
}

TEST_CASE("synth: suite index with a deterministic 80/20 split", "[synth]") {
    std::vector<std::string> names;
    for (int i = 0; i < 10; ++i) names.push_back(scene_name(SuiteKind::Vehicles, i));
    CHECK(names[3] == "vehicles_003");
    const SuiteSplit split = split_suite(names, 9);
    CHECK(split.test.size() == 2);
    CHECK(split.train.size() == 8);
    CHECK(split_suite(names, 9).test == split.test);
    CHECK(split_suite({"a"}, 1).test.empty());
    CHECK(split_suite({"a", "b"}, 1).test.size() == 1);
    const fs::path dir = scratch("index");
    write_suite_index(SuiteKind::Campus, 9, names, dir);
    const auto j = nlohmann::json::parse(read_text_file(dir / "suite.json"));
    CHECK(j["suite"] == "campus");
    CHECK(j["task"] == "semantic");
    CHECK(j["seed"] == 9);
    CHECK(j["scenes"].size() == 10);
    CHECK(j["split"]["test"].size() == 2);
    const std::vector<std::string> classes = {"other", "building", "road", "vegetation", "vehicle", "street furniture", "other ground"};
    REQUIRE(j["classes"].size() == classes.size());
    for (size_t c = 0; c < classes.size(); ++c) {
        CHECK(j["classes"][c]["id"] == c);
        CHECK(j["classes"][c]["name"] == classes[c]);
    }
}

TEST_CASE("synth: bad options and names are refused", "[synth]") {
    CHECK_THROWS_AS(parse_suite("kitchen"), InputError);
    SynthOptions o = small_options();
    o.width = 0;
    CHECK_THROWS_AS(make_suite_scene(SuiteKind::Desk, 0, 1, o), InputError);
    o = small_options();
    o.density = -1;
    CHECK_THROWS_AS(make_suite_scene(SuiteKind::Desk, 0, 1, o), InputError);
    o = small_options();
    o.sh_degree = 4;
    CHECK_THROWS_AS(make_suite_scene(SuiteKind::Desk, 0, 1, o), InputError);
    CHECK_THROWS_AS(make_suite_scene(SuiteKind::Desk, -1, 1, small_options()), InputError);
}

TEST_CASE("synth: contact sheet tiles views and colourised masks", "[synth]") {
    CHECK(mask_colour(0) == glm::u8vec3(0));
    std::set<std::tuple<int, int, int>> colours;
    for (uint16_t id = 1; id <= 20; ++id) {
        const glm::u8vec3 c = mask_colour(id);
        colours.insert({c.x, c.y, c.z});
        CHECK(int(c.x) + c.y + c.z > 100);
    }
    CHECK(colours.size() == 20);
    const Image8 mask = colourise_mask({0, 1, 2, 0, 0, 3}, 3, 2);
    CHECK(mask.channels == 3);
    CHECK(mask.pixels[0] == 0);
    CHECK(mask.pixels[3] == mask_colour(1).x);
    const Image8 rgb{3, 2, 3, std::vector<uint8_t>(18, 200)};
    const Image8 sheet = make_contact_sheet({rgb, rgb}, {mask, mask}, 2, 1);
    CHECK(sheet.width == 1 + 2 * (3 + 1));
    CHECK(sheet.height == 1 + 2 * (2 + 1));
    CHECK(sheet.pixels[(size_t(1) * sheet.width + 1) * 3] == 200);  // first tile: the view
    CHECK(sheet.pixels[(size_t(1) * sheet.width + 5) * 3] == 0);    // second: its mask
    CHECK_THROWS_AS(make_contact_sheet({}, {}, 2), InputError);
    CHECK_THROWS_AS(colourise_mask({1, 2}, 3, 2), InputError);
}

TEST_CASE("synth: per-suite counts (printed)", "[synth]") {
    for (SuiteKind suite : kAllSuites) {
        SynthOptions o = small_options();
        o.density = 0.1;
        const auto t0 = std::chrono::steady_clock::now();
        const SynthScene s = make_suite_scene(suite, 0, 1, o);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        size_t labelled = 0;
        for (const auto& i : s.instances) labelled += i.gaussians;
        std::printf("synth %-9s density 0.1: %7zu Gaussians (%zu labelled), %zu instances, %zu shapes, up (%g %g %g), "
                    "scale %.3g, %.2f s\n",
                    suite_name(suite), s.cloud.size(), labelled, s.instances.size(), s.shapes.size(), s.up.x, s.up.y,
                    s.up.z, s.scale, seconds);
        CHECK(s.cloud.size() > 5000);
        CHECK(labelled > s.cloud.size() / 20);
    }
}
