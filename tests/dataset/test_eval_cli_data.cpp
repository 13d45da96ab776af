// Evaluation from folders (pg::data::eval::evaluate_suite and its reports): tiny GT and
// prediction folders written here, hand-computed numbers checked in the JSON and Markdown.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "dataset/error.h"
#include "dataset/eval/report.h"
#include "dataset/eval/suite_eval.h"
#include "dataset/formats/image_io.h"
#include "dataset/formats/scene_io.h"
#include "dataset/gaussian_cloud.h"
#include "tests/test_paths.h"

namespace fs = std::filesystem;
using nlohmann::json;
using Ids = std::vector<int32_t>;
using Px = std::vector<uint16_t>;

namespace {

fs::path fresh(const std::string& name) {
    fs::remove_all(pg::test::binary_dir() / "test-scratch" / name);
    return pg::test::scratch(name.c_str());
}

void write_text(const fs::path& p, const std::string& text) {
    fs::create_directories(p.parent_path());
    std::ofstream(p) << text;
}

void write_labels(const fs::path& ply, const std::string& property, const Ids& labels) {
    pg::data::GaussianCloud c;
    c.resize(labels.size());
    for (size_t i = 0; i < labels.size(); ++i) c.mean[i] = glm::vec3(float(i), 0.0f, 0.0f);
    if (!property.empty()) c.set_int_property(property, labels);
    fs::create_directories(ply.parent_path());
    pg::data::write_ply(c, ply);
}

struct View {
    std::string name;
    Px gt, pred;
};

// GT scene folder (scene.ply, masks, meta.json) and the matching prediction folder.
struct SceneFiles {
    std::string name;
    Ids gt, pred;  // per Gaussian; pred empty: no predicted scene.ply
    std::vector<View> views;
    int width = 3, height = 2;
    bool pred_masks = true;
    std::string clicks;  // clicks.json text, empty: none
};

void write_scene(const fs::path& suite, const fs::path& preds, const std::string& property, const SceneFiles& s) {
    const fs::path g = suite / s.name, p = preds / s.name;
    fs::create_directories(g / "masks");
    write_labels(g / "scene.ply", property, s.gt);
    json meta{{"name", s.name}, {"instances", json::array()}};
    for (int32_t k = 1; k <= 3; ++k) meta["instances"].push_back({{"id", k}, {"class", 1}, {"name", "obj" + std::to_string(k)}});
    write_text(g / "meta.json", meta.dump());
    for (const auto& v : s.views) pg::data::write_png16(g / "masks" / (v.name + ".png"), s.width, s.height, v.gt);
    if (preds.empty()) return;
    fs::create_directories(p);
    if (!s.pred.empty()) write_labels(p / "scene.ply", property, s.pred);
    if (s.pred_masks) {
        fs::create_directories(p / "masks");
        for (const auto& v : s.views) pg::data::write_png16(p / "masks" / (v.name + ".png"), s.width, s.height, v.pred);
    }
    if (!s.clicks.empty()) write_text(p / "clicks.json", s.clicks);
}

void write_suite_json(const fs::path& suite, const std::string& name, const std::string& task,
                      const std::vector<std::string>& train, const std::vector<std::string>& test, const json& classes) {
    std::vector<std::string> all = train;
    all.insert(all.end(), test.begin(), test.end());
    json j{{"suite", name}, {"seed", 7}, {"task", task}, {"scenes", all},
           {"split", {{"train", train}, {"test", test}}}, {"classes", classes}};
    write_text(suite / "suite.json", j.dump(2));
}

// The 3D and 2D cases of test_metrics.cpp, as files: 3D mIoU 5/18, 2D mIoU 25/36, OA 5/6.
SceneFiles hand_scene(const std::string& name) {
    SceneFiles s;
    s.name = name;
    s.gt = {0, 1, 1, 1, 2, 2, 0, 0, 0, 3};
    s.pred = {0, 1, 1, 0, 2, 1, 2, -1, 9, 0};
    s.views = {{"view_a", {0, 1, 1, 2, 2, 0}, {0, 1, 0, 2, 2, 2}},
               {"view_b", {0, 0, 1, 1, 1, 0}, {0, 0, 1, 1, 1, 0}},
               {"view_c", {0, 0, 0, 2, 2, 2}, {1, 0, 0, 2, 2, 2}},
               {"view_d", {0, 0, 0, 0, 0, 0}, {7, 0, 0, 0, 0, 0}}};
    return s;
}

SceneFiles perfect_scene(const std::string& name) {
    SceneFiles s;
    s.name = name;
    s.gt = s.pred = {0, 1, 1, 2, 0, 3};
    s.views = {{"v0", {0, 1, 1, 2, 0, 0}, {}}, {"v1", {3, 3, 0, 0, 2, 2}, {}}};
    for (auto& v : s.views) v.pred = v.gt;
    s.clicks = R"({"objects": [{"id": 1, "iou_per_click": [1.0]}, {"id": 2, "iou_per_click": [1.0]}]})";
    return s;
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

TEST_CASE("eval folders: hand-computed 3D and 2D and OA and clicks in the JSON and Markdown table", "[eval]") {
    const fs::path root = fresh("eval-hand"), gt = root / "suite", pred = root / "pred";
    write_suite_json(gt, "desk", "instance", {"desk_002"}, {"desk_000", "desk_001", "desk_003"}, json::array());
    SceneFiles a = hand_scene("desk_000");
    a.clicks = R"({"objects": [{"id": 1, "iou_per_click": [0.5, 0.7, 0.85, 0.92]}, {"id": 2, "iou_per_click": []}]})";
    write_scene(gt, pred, "instance", a);
    SceneFiles b = perfect_scene("desk_001");
    b.pred.clear();  // masks only: no 3D score
    b.clicks.clear();
    write_scene(gt, pred, "instance", b);
    write_scene(gt, pred, "instance", perfect_scene("desk_002"));  // train: not scored
    write_scene(gt, "", "instance", perfect_scene("desk_003"));   // no prediction: skipped

    const auto result = pg::data::eval::evaluate_suite(gt, pred, "test");
    const json j = pg::data::eval::report_json(result);
    INFO(j.dump(1));
    REQUIRE(j["scenes"].size() == 2);
    CHECK(j["skipped"] == json::array({"desk_003"}));
    const json& s0 = j["scenes"][0];
    CHECK(s0["name"] == "desk_000");
    CHECK(s0["3d"]["miou"].get<double>() == Approx(5.0 / 18.0));
    CHECK(s0["3d"]["oa"].get<double>() == Approx(0.4));
    CHECK(s0["3d"]["objects"][0]["name"] == "obj1");
    CHECK(s0["3d"]["objects"][1]["iou"].get<double>() == Approx(1.0 / 3.0));
    CHECK(s0["2d"]["miou"].get<double>() == Approx(25.0 / 36.0));
    CHECK(s0["2d"]["oa"].get<double>() == Approx(5.0 / 6.0));
    CHECK(s0["2d"]["pixels"] == 24);
    CHECK(s0["2d"]["objects"][0]["iou"].get<double>() == Approx(0.5));
    CHECK(s0["2d"]["objects"][0]["views"] == 3);
    CHECK(s0["2d"]["views"][3]["name"] == "view_d");
    CHECK(s0["2d"]["views"][3]["miou"].is_null());
    CHECK(s0["clicks"]["iou_at"]["1"].get<double>() == Approx(0.25));
    CHECK(s0["clicks"]["iou_at"]["10"].get<double>() == Approx(0.46));
    CHECK(s0["clicks"]["noc"]["90"].get<double>() == Approx(12.0));
    CHECK(s0["clicks"]["per_object"][1]["noc"]["80"] == 20);
    const json& s1 = j["scenes"][1];
    CHECK(s1["3d"].is_null());
    CHECK(s1["2d"]["miou"].get<double>() == 1.0);
    CHECK(s1["clicks"].is_null());
    CHECK(j["mean"]["3d"].get<double>() == Approx(5.0 / 18.0));
    CHECK(j["mean"]["2d"].get<double>() == Approx((25.0 / 36.0 + 1.0) / 2.0));
    CHECK(j["mean"]["oa"].get<double>() == Approx((5.0 / 6.0 + 1.0) / 2.0));
    CHECK(j["mean"]["clicks"]["objects"] == 2);

    const std::string md = pg::data::eval::report_markdown(result);
    INFO(md);
    CHECK(has(md, "| scene | 3D | 2D | OA |\n"));
    CHECK(has(md, "| desk_000 | 27.78 | 69.44 | 83.33 |\n"));
    CHECK(has(md, "| desk_001 | -- | 100.00 | 100.00 |\n"));
    CHECK(has(md, "| **mean** | 27.78 | 84.72 | 91.67 |\n"));
    CHECK(has(md, "| desk_000 | 2 | 25.00 | 42.50 | 46.00 | 46.00 | 11.50 | 11.50 | 12.00 |\n"));
    CHECK(has(md, "desk_003"));
    CHECK_FALSE(has(md, "desk_002"));
}

TEST_CASE("eval folders: a perfect prediction scores 1.0 everywhere", "[eval]") {
    const fs::path root = fresh("eval-perfect"), gt = root / "suite", pred = root / "pred";
    write_suite_json(gt, "desk", "instance", {}, {"desk_000", "desk_001"}, json::array());
    write_scene(gt, pred, "instance", perfect_scene("desk_000"));
    write_scene(gt, pred, "instance", perfect_scene("desk_001"));
    const json j = pg::data::eval::report_json(pg::data::eval::evaluate_suite(gt, pred, "all"));
    INFO(j.dump(1));
    REQUIRE(j["scenes"].size() == 2);
    for (const json& s : j["scenes"]) {
        for (const char* k : {"3d", "2d"}) {
            CHECK(s[k]["miou"].get<double>() == 1.0);
            CHECK(s[k]["oa"].get<double>() == 1.0);
            for (const json& o : s[k]["objects"]) CHECK(o["iou"].get<double>() == 1.0);
        }
        CHECK(s["3d"]["objects"].size() == 3);
    }
    for (const char* k : {"3d", "2d", "oa"}) CHECK(j["mean"][k].get<double>() == 1.0);
    for (auto& [k, v] : j["mean"]["clicks"]["iou_at"].items()) CHECK(v.get<double>() == 1.0);
    for (auto& [k, v] : j["mean"]["clicks"]["noc"].items()) CHECK(v.get<double>() == 1.0);
}

TEST_CASE("eval folders: a semantic suite reports per-class 3D and 2D IoU with mIoU and OA", "[eval]") {
    const fs::path root = fresh("eval-semantic"), gt = root / "suite", pred = root / "pred";
    write_suite_json(gt, "campus", "semantic", {}, {"campus_000"},
                     json::array({{{"id", 0}, {"name", "background"}}, {{"id", 1}, {"name", "building"}}}));
    SceneFiles s;
    s.name = "campus_000";
    s.gt = {0, 0, 0, 1, 1, 1, 1, 0};
    s.pred = {0, 0, 1, 1, 1, 0, 1, 2};
    s.width = s.height = 2;
    s.views = {{"v0", {1, 1, 0, 0}, {1, 0, 0, 0}}, {"v1", {1, 1, 1, 1}, {1, 1, 1, 1}}};
    write_scene(gt, pred, "class", s);

    const auto result = pg::data::eval::evaluate_suite(gt, pred, "test");
    const json j = pg::data::eval::report_json(result);
    INFO(j.dump(1));
    const json& s0 = j["scenes"][0];
    CHECK(s0["3d"]["classes"][0]["name"] == "background");
    CHECK(s0["3d"]["classes"][0]["iou"].get<double>() == Approx(0.4));
    CHECK(s0["3d"]["classes"][1]["iou"].get<double>() == Approx(0.6));
    CHECK(s0["3d"]["miou"].get<double>() == Approx(0.5));
    CHECK(s0["2d"]["classes"][0]["iou"].get<double>() == Approx(2.0 / 3.0));
    CHECK(s0["2d"]["miou"].get<double>() == Approx(0.75));
    CHECK(s0["2d"]["oa"].get<double>() == Approx(0.875));
    CHECK(j["mean"]["classes"][1]["3d"].get<double>() == Approx(0.6));

    const std::string md = pg::data::eval::report_markdown(result);
    INFO(md);
    CHECK(has(md, "| scene | background 3D | background 2D | building 3D | building 2D | 3D | 2D | OA |\n"));
    CHECK(has(md, "| campus_000 | 40.00 | 66.67 | 60.00 | 83.33 | 50.00 | 75.00 | 87.50 |\n"));
}

TEST_CASE("eval folders: the two-class view maps every other class to background in GT and prediction", "[eval]") {
    const fs::path root = fresh("eval-two-class"), gt = root / "suite", pred = root / "pred";
    write_suite_json(gt, "campus", "semantic", {}, {"campus_000"},
                     json::array({{{"id", 0}, {"name", "other"}}, {{"id", 1}, {"name", "building"}}, {{"id", 2}, {"name", "road"}}}));
    SceneFiles s;
    s.name = "campus_000";
    s.gt = {1, 1, 1, 1, 2, 2, 2, 0, 0, 0};
    s.pred = {1, 1, 1, 2, 2, 0, 2, 0, 1, 2};
    s.width = s.height = 2;
    s.views = {{"v0", {1, 2, 0, 2}, {1, 0, 2, 2}}};
    write_scene(gt, pred, "class", s);

    // Three classes. 3D: other 1/4, building 3/5, road 2/5, OA 6/10. 2D: 0, 1, 1/3, OA 2/4.
    const json multi = pg::data::eval::report_json(pg::data::eval::evaluate_suite(gt, pred, "test"));
    INFO(multi.dump(1));
    CHECK(multi["two_class"].is_null());
    CHECK(multi["scenes"][0]["3d"]["miou"].get<double>() == Approx((0.25 + 0.6 + 0.4) / 3.0));
    CHECK(multi["scenes"][0]["3d"]["oa"].get<double>() == Approx(0.6));
    CHECK(multi["scenes"][0]["2d"]["miou"].get<double>() == Approx(4.0 / 9.0));

    // Building vs background: road and other merge in both. 3D: background 5/7, building 3/5
    // (unchanged), OA 8/10. 2D: both views of the classes agree everywhere.
    for (const char* which : {"building", "1"}) {
        const auto result = pg::data::eval::evaluate_suite(gt, pred, "test", which);
        const json j = pg::data::eval::report_json(result);
        INFO(which << ": " << j.dump(1));
        CHECK(j["two_class"]["name"] == "building");
        const json& s0 = j["scenes"][0];
        REQUIRE(s0["3d"]["classes"].size() == 2);
        CHECK(s0["3d"]["classes"][0]["name"] == "background");
        CHECK(s0["3d"]["classes"][0]["iou"].get<double>() == Approx(5.0 / 7.0));
        CHECK(s0["3d"]["classes"][1]["iou"].get<double>() == Approx(0.6));
        CHECK(s0["3d"]["miou"].get<double>() == Approx((5.0 / 7.0 + 0.6) / 2.0));
        CHECK(s0["3d"]["oa"].get<double>() == Approx(0.8));
        CHECK(s0["2d"]["miou"].get<double>() == Approx(1.0));
        CHECK(s0["2d"]["oa"].get<double>() == Approx(1.0));
        const std::string md = pg::data::eval::report_markdown(result);
        INFO(md);
        CHECK(has(md, "two-class view: building vs background"));
        CHECK(has(md, "| scene | background 3D | background 2D | building 3D | building 2D | 3D | 2D | OA |\n"));
        CHECK(has(md, "| campus_000 | 71.43 | 100.00 | 60.00 | 100.00 | 65.71 | 100.00 | 100.00 |\n"));
    }

    // An unknown class, the background itself, an instance suite: errors naming the option.
    for (const char* bad : {"tree", "7", "other", "0"})
        CHECK_THROWS_WITH(pg::data::eval::evaluate_suite(gt, pred, "test", bad), Catch::Contains("--two-class"));
    const fs::path inst = root / "instance";
    write_suite_json(inst, "desk", "instance", {}, {"desk_000"}, json::array());
    write_scene(inst, root / "inst_pred", "instance", perfect_scene("desk_000"));
    CHECK_THROWS_WITH(pg::data::eval::evaluate_suite(inst, root / "inst_pred", "test", "1"), Catch::Contains("instance suite"));
}

TEST_CASE("eval folders: bad input is an InputError naming the file", "[eval]") {
    const fs::path root = fresh("eval-errors"), gt = root / "suite";
    write_suite_json(gt, "desk", "instance", {}, {"desk_000"}, json::array());
    write_scene(gt, "", "instance", perfect_scene("desk_000"));
    const fs::path gs = gt / "desk_000";

    struct Case {
        std::string what;
        std::function<void(const fs::path& pred_scene)> make;
        std::string must_name;  // relative to the prediction scene folder unless absolute
    };
    const std::vector<Case> cases = {
        {"Gaussian count", [](const fs::path& p) { write_labels(p / "scene.ply", "instance", {0, 1, 1}); }, "scene.ply"},
        {"no instance property", [](const fs::path& p) { write_labels(p / "scene.ply", "", {0, 1, 1, 2, 0, 3}); },
         "scene.ply"},
        {"class, not instance", [](const fs::path& p) { write_labels(p / "scene.ply", "class", {0, 1, 1, 2, 0, 3}); },
         "scene.ply"},
        {"mask size",
         [&](const fs::path& p) {
             fs::copy(gs / "masks", p / "masks");
             pg::data::write_png16(p / "masks" / "v1.png", 2, 3, Px(6, 0));
         },
         "v1.png"},
        {"missing mask",
         [&](const fs::path& p) {
             fs::copy(gs / "masks", p / "masks");
             fs::remove(p / "masks" / "v0.png");
         },
         "v0.png"},
        {"extra mask",
         [&](const fs::path& p) {
             fs::copy(gs / "masks", p / "masks");
             fs::copy(gs / "masks" / "v0.png", p / "masks" / "v9.png");
         },
         "v9.png"},
        {"colour mask",
         [&](const fs::path& p) {
             fs::copy(gs / "masks", p / "masks");
             pg::data::write_png8(p / "masks" / "v0.png", 3, 2, 3, std::vector<uint8_t>(18, 1));
         },
         "v0.png"},
        {"clicks IoU out of range",
         [](const fs::path& p) { write_text(p / "clicks.json", R"({"objects": [{"id": 1, "iou_per_click": [1.5]}]})"); },
         "clicks.json"},
        {"clicks not JSON", [](const fs::path& p) { write_text(p / "clicks.json", "{"); }, "clicks.json"},
        {"empty prediction folder", [](const fs::path&) {}, "desk_000"},
    };
    for (const auto& c : cases) {
        INFO(c.what);
        const fs::path pred = root / "pred";
        fs::remove_all(pred);
        fs::create_directories(pred / "desk_000");
        c.make(pred / "desk_000");
        try {
            pg::data::eval::evaluate_suite(gt, pred, "test");
            FAIL("no error");
        } catch (const pg::data::InputError& e) {
            INFO(e.what());
            CHECK(has(e.where(), c.must_name));
            CHECK(has(e.where(), (pred / "desk_000").string()));
        }
    }

    const fs::path pred = root / "pred";
    fs::remove_all(pred);
    fs::create_directories(pred / "other_scene");
    CHECK_THROWS_WITH(pg::data::eval::evaluate_suite(gt, pred, "test"), Catch::Contains(pred.string()));
    CHECK_THROWS_WITH(pg::data::eval::evaluate_suite(gt, root / "nowhere", "test"), Catch::Contains("nowhere"));
    CHECK_THROWS_WITH(pg::data::eval::evaluate_suite(root / "no_suite", pred, "test"), Catch::Contains("suite.json"));
    CHECK_THROWS_AS(pg::data::eval::evaluate_suite(gt, pred, "val"), pg::data::InputError);

    // A scene listed in suite.json without its GT folder.
    write_suite_json(gt, "desk", "instance", {}, {"desk_000", "desk_404"}, json::array());
    fs::create_directories(pred / "desk_404");
    CHECK_THROWS_WITH(pg::data::eval::evaluate_suite(gt, pred, "test"), Catch::Contains((gt / "desk_404").string()));
    // And names that would leave the suite folder.
    write_suite_json(gt, "desk", "instance", {}, {"../desk_000"}, json::array());
    CHECK_THROWS_WITH(pg::data::eval::evaluate_suite(gt, pred, "test"), Catch::Contains("suite.json"));
}

TEST_CASE("read_png16 keeps 16-bit values and widens 8-bit grey unchanged and refuses colour", "[eval][image_io]") {
    const fs::path dir = fresh("png16-read");
    pg::data::write_png16(dir / "m16.png", 3, 1, {0, 300, 65535});
    const auto m16 = pg::data::read_png16(dir / "m16.png");
    CHECK(m16.width == 3);
    CHECK(m16.height == 1);
    CHECK(m16.pixels == Px{0, 300, 65535});
    pg::data::write_png8(dir / "m8.png", 2, 2, 1, {0, 1, 7, 255});
    CHECK(pg::data::read_png16(dir / "m8.png").pixels == Px{0, 1, 7, 255});
    pg::data::write_png8(dir / "rgb.png", 1, 1, 3, {1, 2, 3});
    CHECK_THROWS_WITH(pg::data::read_png16(dir / "rgb.png"), Catch::Contains("rgb.png"));
    CHECK_THROWS_WITH(pg::data::read_png16(dir / "missing.png"), Catch::Contains("missing.png"));
    // A 1-bit grey header (stb would rescale 0/1 to 0/255): refused before decoding.
    std::string bytes;
    {
        std::ifstream in(dir / "m8.png", std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), {});
    }
    bytes[24] = 1;
    std::ofstream(dir / "bits1.png", std::ios::binary) << bytes;
    CHECK_THROWS_WITH(pg::data::read_png16(dir / "bits1.png"), Catch::Contains("1-bit"));
}
