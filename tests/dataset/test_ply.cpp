// INRIA / 2DGS PLY reading and writing, the GaussianCloud helpers and compute_stats.
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "dataset/error.h"
#include "dataset/formats/scene_io.h"
#include "dataset/gaussian_cloud.h"
#include "dataset/scene_stats.h"
#include "tests/test_paths.h"

namespace fs = std::filesystem;
using namespace pg::data;

namespace {

struct Prop {
    std::string type;  // PLY spelling
    std::string name;
};

void append_value(std::string& out, const std::string& type, double v, bool big_endian) {
    char b[8];
    size_t n = 0;
    auto put = [&](auto x) {
        n = sizeof x;
        std::memcpy(b, &x, n);
    };
    if (type == "char" || type == "int8") put(static_cast<int8_t>(v));
    else if (type == "uchar" || type == "uint8") put(static_cast<uint8_t>(v));
    else if (type == "short" || type == "int16") put(static_cast<int16_t>(v));
    else if (type == "ushort" || type == "uint16") put(static_cast<uint16_t>(v));
    else if (type == "int" || type == "int32") put(static_cast<int32_t>(v));
    else if (type == "uint" || type == "uint32") put(static_cast<uint32_t>(v));
    else if (type == "float" || type == "float32") put(static_cast<float>(v));
    else put(v);
    if (big_endian) std::reverse(b, b + n);
    out.append(b, n);
}

// A PLY file in memory: header (comments, one vertex element) and body in `format`.
std::string make_ply(const std::string& format, const std::vector<Prop>& props,
                     const std::vector<std::vector<double>>& rows, const std::vector<std::string>& comments = {},
                     const std::string& extra_header = "", const std::string& extra_body = "") {
    std::ostringstream h;
    h << "ply\nformat " << format << " 1.0\n";
    for (const auto& c : comments) h << "comment " << c << "\n";
    h << "element vertex " << rows.size() << "\n";
    for (const auto& p : props) h << "property " << p.type << " " << p.name << "\n";
    h << extra_header << "end_header\n";
    std::string out = h.str();
    const bool ascii = format == "ascii";
    for (const auto& row : rows) {
        for (size_t k = 0; k < props.size(); ++k) {
            if (ascii) {
                char buf[64];
                if (props[k].type == "float") std::snprintf(buf, sizeof buf, "%.9g", static_cast<float>(row[k]));
                else std::snprintf(buf, sizeof buf, "%.17g", row[k]);
                out += buf;
                out += k + 1 < props.size() ? " " : "\n";
            } else {
                append_value(out, props[k].type, row[k], format == "binary_big_endian");
            }
        }
    }
    return out + extra_body;
}

fs::path write_file(const std::string& name, const std::string& bytes) {
    fs::path p = pg::test::scratch("ply") / name;
    std::ofstream out(p, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    return p;
}

std::string read_bytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

// Deterministic pseudo-random floats in [lo, hi).
struct Lcg {
    uint64_t s = 12345;
    float next(float lo = -1.0f, float hi = 1.0f) {
        s = s * 6364136223846793005ull + 1442695040888963407ull;
        return lo + (hi - lo) * static_cast<float>((s >> 40) & 0xffffff) / 16777216.0f;
    }
};

std::vector<Prop> inria_props(int degree, bool normals) {
    std::vector<Prop> p = {{"float", "x"}, {"float", "y"}, {"float", "z"}};
    if (normals)
        for (const char* n : {"nx", "ny", "nz"}) p.push_back({"float", n});
    for (int c = 0; c < 3; ++c) p.push_back({"float", "f_dc_" + std::to_string(c)});
    for (int j = 0; j < 3 * (sh_coeffs(degree) - 1); ++j) p.push_back({"float", "f_rest_" + std::to_string(j)});
    p.push_back({"float", "opacity"});
    for (int k = 0; k < 3; ++k) p.push_back({"float", "scale_" + std::to_string(k)});
    for (int k = 0; k < 4; ++k) p.push_back({"float", "rot_" + std::to_string(k)});
    return p;
}

std::vector<std::vector<double>> random_rows(const std::vector<Prop>& props, size_t n, Lcg& rng) {
    std::vector<std::vector<double>> rows(n, std::vector<double>(props.size()));
    for (size_t i = 0; i < n; ++i) {
        for (size_t k = 0; k < props.size(); ++k) {
            const auto& t = props[k].type;
            if (t == "float" || t == "double") rows[i][k] = rng.next(-3.0f, 3.0f);
            else if (t == "uchar") rows[i][k] = static_cast<int>(rng.next(0, 255));
            else if (t == "char") rows[i][k] = static_cast<int>(rng.next(-128, 127));
            else if (t == "ushort") rows[i][k] = static_cast<int>(rng.next(0, 65535));
            else if (t == "short") rows[i][k] = static_cast<int>(rng.next(-32768, 32767));
            else if (t == "uint") rows[i][k] = std::floor(rng.next(0, 4.0e9f));
            else rows[i][k] = static_cast<int>(rng.next(-2.0e9f, 2.0e9f));
        }
    }
    return rows;
}

void require_same_cloud(const GaussianCloud& a, const GaussianCloud& b) {
    REQUIRE(a.size() == b.size());
    REQUIRE(a.sh_degree == b.sh_degree);
    REQUIRE(a.flat == b.flat);
    CHECK(a.mean == b.mean);
    CHECK(a.log_scale == b.log_scale);
    CHECK(a.rotation == b.rotation);
    CHECK(a.opacity_logit == b.opacity_logit);
    CHECK(a.sh == b.sh);
    REQUIRE(a.extras.size() == b.extras.size());
    for (size_t e = 0; e < a.extras.size(); ++e) {
        CHECK(a.extras[e].name == b.extras[e].name);
        CHECK(a.extras[e].type == b.extras[e].type);
        CHECK(a.extras[e].values == b.extras[e].values);
    }
}

}  // namespace

TEST_CASE("ply: INRIA binary read-write round trip is byte-exact") {
    Lcg rng;
    SECTION("plain INRIA layout with normals, SH degree 1") {
        auto props = inria_props(1, true);
        auto rows = random_rows(props, 50, rng);
        fs::path in = write_file("inria.ply", make_ply("binary_little_endian", props, rows));
        GaussianCloud cloud = read_ply(in);
        CHECK(cloud.format == SceneFormat::InriaPly);
        fs::path out = pg::test::scratch("ply") / "inria_out.ply";
        write_ply(cloud, out);
        CHECK(read_bytes(out) == read_bytes(in));
    }
    SECTION("comments and extra integer properties in the middle and at the end") {
        auto props = inria_props(3, true);
        props.insert(props.begin() + 6, Prop{"uchar", "label"});
        props.push_back({"int", "instance"});
        props.push_back({"short", "segment"});
        props.push_back({"double", "confidence"});
        props.push_back({"uint", "id"});
        props.push_back({"char", "flag"});
        props.push_back({"ushort", "group"});
        auto rows = random_rows(props, 37, rng);
        std::vector<std::string> comments = {"Generated by a trainer", "  spaced   comment  ", ""};
        fs::path in = write_file("extras.ply", make_ply("binary_little_endian", props, rows, comments));
        GaussianCloud cloud = read_ply(in);
        CHECK(cloud.sh_degree == 3);
        CHECK(cloud.ply_comments == comments);
        REQUIRE(cloud.extras.size() == 10);
        fs::path out = pg::test::scratch("ply") / "extras_out.ply";
        write_ply(cloud, out);
        CHECK(read_bytes(out) == read_bytes(in));
    }
}

TEST_CASE("ply: ascii and binary files give the same cloud") {
    Lcg rng;
    auto props = inria_props(2, true);
    props.push_back({"int", "label"});
    auto rows = random_rows(props, 20, rng);
    GaussianCloud bin = read_ply(write_file("same_bin.ply", make_ply("binary_little_endian", props, rows)));
    GaussianCloud asc = read_ply(write_file("same_ascii.ply", make_ply("ascii", props, rows)));
    GaussianCloud big = read_ply(write_file("same_big.ply", make_ply("binary_big_endian", props, rows)));
    CHECK(bin.format == SceneFormat::InriaPly);
    CHECK(asc.format == SceneFormat::InriaPlyAscii);
    require_same_cloud(bin, asc);
    require_same_cloud(bin, big);
    CHECK(asc.ply_property_order == bin.ply_property_order);

    // Integers printed as "7.0" by some writers are accepted when integral.
    std::vector<Prop> small = inria_props(0, false);
    small.push_back({"int", "label"});
    std::string text = make_ply("ascii", small, {std::vector<double>(small.size(), 1.0)});
    text.replace(text.rfind(" 1\n"), 3, " 7.0\n");
    GaussianCloud seven = read_ply(write_file("int_as_float.ply", text));
    CHECK(seven.int_property("label") == std::vector<int32_t>{7});
}

TEST_CASE("ply: SH degrees 0 to 3 place f_dc and f_rest at the documented sh index") {
    for (int degree = 0; degree <= 3; ++degree) {
        INFO("degree " << degree);
        const int coeffs = sh_coeffs(degree), rest = 3 * (coeffs - 1);
        auto props = inria_props(degree, false);
        std::vector<std::vector<double>> rows;
        for (int i = 0; i < 3; ++i) {
            std::vector<double> row;
            for (const auto& p : props) {
                double v = 0.5;
                if (p.name.rfind("f_dc_", 0) == 0) v = 100 + std::stoi(p.name.substr(5));
                if (p.name.rfind("f_rest_", 0) == 0) v = 1000 + std::stoi(p.name.substr(7));
                if (p.name == "rot_0") v = 1.0;
                if (p.name.rfind("f_", 0) == 0) v += 10000.0 * i;  // tells the Gaussians apart
                row.push_back(v);
            }
            rows.push_back(row);
        }
        GaussianCloud c = read_ply(write_file("deg" + std::to_string(degree) + ".ply",
                                              make_ply("binary_little_endian", props, rows)));
        REQUIRE(c.sh_degree == degree);
        REQUIRE(c.sh.size() == 3u * coeffs * 3);
        for (int i = 0; i < 3; ++i) {
            for (int ch = 0; ch < 3; ++ch) {
                CHECK(c.sh[(i * coeffs + 0) * 3 + ch] == 100 + ch + 10000 * i);
                for (int k = 1; k < coeffs; ++k) {
                    const int j = ch * (coeffs - 1) + (k - 1);
                    CHECK(c.sh[(i * coeffs + k) * 3 + ch] == 1000 + j + 10000 * i);
                }
            }
        }
        if (degree == 3) {
            // Spot checks written out: f_rest_0 is (k=1, red), f_rest_15 is (k=1, green),
            // f_rest_44 is (k=15, blue).
            CHECK(c.sh[(0 * 16 + 1) * 3 + 0] == 1000);
            CHECK(c.sh[(0 * 16 + 1) * 3 + 1] == 1015);
            CHECK(c.sh[(0 * 16 + 15) * 3 + 2] == 1044);
        }
        CHECK(rest == static_cast<int>(std::count_if(c.ply_property_order.begin(), c.ply_property_order.end(),
                                                     [](const std::string& n) { return n.rfind("f_rest_", 0) == 0; })));
    }
}

TEST_CASE("ply: a permutation of the properties gives the same cloud") {
    Lcg rng;
    auto props = inria_props(1, true);
    props.push_back({"ushort", "label"});
    auto rows = random_rows(props, 16, rng);
    GaussianCloud a = read_ply(write_file("perm_a.ply", make_ply("binary_little_endian", props, rows)));

    std::vector<size_t> perm(props.size());
    for (size_t k = 0; k < perm.size(); ++k) perm[k] = (k * 7 + 3) % perm.size();  // 7 is coprime to 27
    std::vector<Prop> props_b;
    for (size_t k : perm) props_b.push_back(props[k]);
    std::vector<std::vector<double>> rows_b;
    for (const auto& r : rows) {
        std::vector<double> rb;
        for (size_t k : perm) rb.push_back(r[k]);
        rows_b.push_back(rb);
    }
    GaussianCloud b = read_ply(write_file("perm_b.ply", make_ply("binary_little_endian", props_b, rows_b)));
    // Extras keep their own file order; here the normals and the label appear in a new order.
    std::sort(a.extras.begin(), a.extras.end(), [](auto& x, auto& y) { return x.name < y.name; });
    std::sort(b.extras.begin(), b.extras.end(), [](auto& x, auto& y) { return x.name < y.name; });
    require_same_cloud(a, b);
    CHECK(a.ply_property_order != b.ply_property_order);

    // The writer keeps the permuted order.
    fs::path out = pg::test::scratch("ply") / "perm_out.ply";
    write_ply(read_ply(pg::test::scratch("ply") / "perm_b.ply"), out);
    CHECK(read_bytes(out) == read_bytes(pg::test::scratch("ply") / "perm_b.ply"));
}

TEST_CASE("ply: unknown properties are kept as extras in file order with their type") {
    std::vector<Prop> props = inria_props(0, false);
    props.insert(props.begin() + 3, Prop{"float", "nx"});
    props.insert(props.begin() + 5, Prop{"uchar", "red"});
    props.push_back({"int", "class"});
    props.push_back({"double", "weight"});
    std::vector<std::vector<double>> rows;
    for (int i = 0; i < 4; ++i) {
        std::vector<double> r(props.size(), 0.25);
        for (size_t k = 0; k < props.size(); ++k) {
            if (props[k].name == "rot_0") r[k] = 1.0;
            if (props[k].name == "nx") r[k] = 0.5 * i;
            if (props[k].name == "red") r[k] = 200 + i;
            if (props[k].name == "class") r[k] = -7 * i;
            if (props[k].name == "weight") r[k] = 0.1 * i;
        }
        rows.push_back(r);
    }
    GaussianCloud c = read_ply(write_file("extras_kept.ply", make_ply("binary_little_endian", props, rows)));
    REQUIRE(c.extras.size() == 4);
    CHECK(c.extras[0].name == "nx");
    CHECK(c.extras[0].type == PlyType::Float32);
    CHECK(c.extras[1].name == "red");
    CHECK(c.extras[1].type == PlyType::UInt8);
    CHECK(c.extras[2].name == "class");
    CHECK(c.extras[2].type == PlyType::Int32);
    CHECK(c.extras[3].name == "weight");
    CHECK(c.extras[3].type == PlyType::Float64);
    CHECK(c.extras[1].values == std::vector<double>{200, 201, 202, 203});
    CHECK(c.extras[2].values == std::vector<double>{0, -7, -14, -21});
    CHECK(c.extras[3].values[3] == 0.1 * 3);  // double kept exactly
    REQUIRE(c.find_extra("class") != nullptr);
    CHECK(c.find_extra("missing") == nullptr);
    auto cls = c.int_property("class");
    REQUIRE(cls);
    CHECK(*cls == std::vector<int32_t>{0, -7, -14, -21});
    CHECK_FALSE(c.int_property("weight"));  // not integers
    CHECK(c.ply_property_order.size() == props.size());
    CHECK(c.ply_property_order[3] == "nx");
}

TEST_CASE("ply: set_int_property survives write and read") {
    Lcg rng;
    auto props = inria_props(0, false);
    auto rows = random_rows(props, 10, rng);
    GaussianCloud c = read_ply(write_file("labels_in.ply", make_ply("binary_little_endian", props, rows)));
    std::vector<int32_t> instance(10), cls(10);
    for (int i = 0; i < 10; ++i) {
        instance[i] = i % 3 - 1;
        cls[i] = 200 + i;
    }
    c.set_int_property("instance", instance);
    c.set_int_property("class", cls, PlyType::UInt8);
    c.set_int_property("instance", instance);  // replacing keeps one column
    CHECK(c.extras.size() == 2);
    CHECK_THROWS_AS(c.set_int_property("short", std::vector<int32_t>(3)), std::invalid_argument);
    CHECK_THROWS_AS(c.set_int_property("opacity", instance), std::invalid_argument);

    fs::path out = pg::test::scratch("ply") / "labels_out.ply";
    write_ply(c, out);
    const std::string bytes = read_bytes(out);
    CHECK(bytes.find("property int instance\nproperty uchar class\nend_header\n") != std::string::npos);
    GaussianCloud back = read_ply(out);
    require_same_cloud(c, back);
    CHECK(back.int_property("instance") == instance);
    CHECK(back.int_property("class") == cls);
    CHECK(back.find_extra("class")->type == PlyType::UInt8);
    CHECK_FALSE(back.int_property("nothing"));
}

TEST_CASE("ply: 2DGS files with two scales load as flat surfels") {
    std::vector<Prop> props;
    for (const char* n : {"x", "y", "z", "f_dc_0", "f_dc_1", "f_dc_2", "opacity", "scale_0", "scale_1", "rot_0",
                          "rot_1", "rot_2", "rot_3"})
        props.push_back({"float", n});
    std::vector<std::vector<double>> rows = {{1, 2, 3, 0.1, 0.2, 0.3, 0.5, -2, -3, 1, 0, 0, 0},
                                             {4, 5, 6, 0.4, 0.5, 0.6, -0.5, -4, -5, 0, 1, 0, 0}};
    fs::path in = write_file("surfels.ply", make_ply("binary_little_endian", props, rows));
    GaussianCloud c = load_scene(in);
    CHECK(c.flat);
    CHECK(c.format == SceneFormat::TwoDgsPly);
    REQUIRE(c.size() == 2);
    CHECK(c.log_scale[0] == glm::vec3(-2, -3, kFlatLogScale));
    CHECK(c.log_scale[1] == glm::vec3(-4, -5, kFlatLogScale));
    fs::path out = pg::test::scratch("ply") / "surfels_out.ply";
    write_ply(c, out);
    CHECK(read_bytes(out) == read_bytes(in));
    CHECK(read_bytes(out).find("scale_2") == std::string::npos);
}

TEST_CASE("ply: any scalar type is accepted for the required properties") {
    std::vector<Prop> props = {{"double", "x"},  {"short", "y"},      {"uchar", "z"},      {"int8", "f_dc_0"},
                               {"int16", "f_dc_1"}, {"uint16", "f_dc_2"}, {"float64", "opacity"}, {"int", "scale_0"},
                               {"uint", "scale_1"}, {"int32", "scale_2"}, {"uint8", "rot_0"},   {"char", "rot_1"},
                               {"float32", "rot_2"}, {"uint32", "rot_3"}};
    std::vector<std::vector<double>> rows = {{0.125, -300, 200, -5, -1000, 60000, 2.5, -3, 4, -5, 1, -2, 0.5, 7}};
    for (const char* format : {"binary_little_endian", "binary_big_endian", "ascii"}) {
        INFO(format);
        GaussianCloud c = read_ply(write_file("types.ply", make_ply(format, props, rows)));
        REQUIRE(c.size() == 1);
        CHECK(c.mean[0] == glm::vec3(0.125f, -300, 200));
        CHECK(c.sh[0] == -5);
        CHECK(c.sh[1] == -1000);
        CHECK(c.sh[2] == 60000);
        CHECK(c.opacity_logit[0] == 2.5f);
        CHECK(c.log_scale[0] == glm::vec3(-3, 4, -5));
        CHECK(c.rotation[0] == glm::vec4(1, -2, 0.5f, 7));
        CHECK(c.extras.empty());
    }
}

TEST_CASE("ply: elements before and after the vertex element are skipped") {
    Lcg rng;
    auto props = inria_props(0, false);
    auto rows = random_rows(props, 5, rng);
    // A face element with lists after the vertices, as meshes exported with splats have.
    std::string face_header = "element face 2\nproperty list uchar int vertex_indices\nproperty uchar flags\n";
    std::string faces;
    faces.push_back(3);
    for (int32_t v : {0, 1, 2}) faces.append(reinterpret_cast<const char*>(&v), 4);
    faces.push_back(9);
    faces.push_back(4);
    for (int32_t v : {1, 2, 3, 4}) faces.append(reinterpret_cast<const char*>(&v), 4);
    faces.push_back(8);
    GaussianCloud a = read_ply(write_file("plain.ply", make_ply("binary_little_endian", props, rows)));
    GaussianCloud b =
        read_ply(write_file("faces.ply", make_ply("binary_little_endian", props, rows, {}, face_header, faces)));
    require_same_cloud(a, b);
    GaussianCloud c = read_ply(write_file(
        "faces_ascii.ply", make_ply("ascii", props, rows, {}, face_header, "3 0 1 2 9\n4 1 2 3 4 8\n")));
    CHECK(c.size() == 5);

    // An element before the vertices (a camera block, say) is skipped by its stride.
    std::string bytes = make_ply("binary_little_endian", props, rows);
    const std::string cam_header = "element camera 2\nproperty float fx\nproperty double fy\n";
    std::string cams;
    for (int i = 0; i < 2; ++i) {
        append_value(cams, "float", 500.0, false);
        append_value(cams, "double", 501.0, false);
    }
    size_t at = bytes.find("element vertex");
    bytes.insert(at, cam_header);
    size_t body = bytes.find("end_header\n") + 11;
    bytes.insert(body, cams);
    GaussianCloud d = read_ply(write_file("camera_first.ply", bytes));
    require_same_cloud(a, d);
}

TEST_CASE("ply: writer uses the canonical INRIA order for clouds not read from a PLY") {
    GaussianCloud c;
    c.sh_degree = 1;
    c.resize(2);
    c.extras.push_back({"label", PlyType::Int32, {1, 2}});
    c.extras.push_back({"nz", PlyType::Float32, {0, 0}});
    c.extras.push_back({"nx", PlyType::Float32, {0, 0}});
    c.extras.push_back({"ny", PlyType::Float32, {0, 0}});
    c.ply_comments = {"made by a test"};
    fs::path out = pg::test::scratch("ply") / "canonical.ply";
    write_ply(c, out);
    std::string expected = "ply\nformat binary_little_endian 1.0\ncomment made by a test\nelement vertex 2\n"
                           "property float x\nproperty float y\nproperty float z\n"
                           "property float nx\nproperty float ny\nproperty float nz\n"
                           "property float f_dc_0\nproperty float f_dc_1\nproperty float f_dc_2\n";
    for (int j = 0; j < 9; ++j) expected += "property float f_rest_" + std::to_string(j) + "\n";
    expected += "property float opacity\nproperty float scale_0\nproperty float scale_1\nproperty float scale_2\n"
                "property float rot_0\nproperty float rot_1\nproperty float rot_2\nproperty float rot_3\n"
                "property int label\nend_header\n";
    const std::string bytes = read_bytes(out);
    REQUIRE(bytes.size() == expected.size() + 2 * (4 * 26 + 4));
    CHECK(bytes.substr(0, expected.size()) == expected);
    GaussianCloud back = read_ply(out);
    CHECK(back.rotation[1] == glm::vec4(1, 0, 0, 0));  // resize gives identity rotations
    CHECK(back.int_property("label") == std::vector<int32_t>{1, 2});
}

TEST_CASE("ply: writer leaves no file behind when it fails") {
    GaussianCloud c;
    c.resize(1);
    fs::path dir = pg::test::scratch("ply") / "no_such_dir";
    fs::remove_all(dir);
    CHECK_THROWS_AS(write_ply(c, dir / "out.ply"), InputError);
    CHECK_FALSE(fs::exists(dir));

    fs::path out = pg::test::scratch("ply") / "bad_name.ply";
    fs::remove(out);
    c.extras.push_back({"two words", PlyType::Int32, {0}});
    CHECK_THROWS_AS(write_ply(c, out), InputError);
    CHECK_FALSE(fs::exists(out));
}

TEST_CASE("gaussian_cloud: resize, type names and format names") {
    GaussianCloud c;
    c.sh_degree = 2;
    c.extras.push_back({"label", PlyType::UInt8, {}});
    c.resize(3);
    CHECK(c.size() == 3);
    CHECK(c.sh.size() == 3u * 9 * 3);
    CHECK(c.extras[0].values.size() == 3);
    CHECK(c.rotation[2] == glm::vec4(1, 0, 0, 0));
    c.flat = true;
    c.resize(4);
    CHECK(c.log_scale[3].z == kFlatLogScale);
    c.resize(1);
    CHECK(c.opacity_logit.size() == 1);
    CHECK(c.extras[0].values.size() == 1);

    CHECK(ply_type_size(PlyType::Int8) == 1);
    CHECK(ply_type_size(PlyType::UInt16) == 2);
    CHECK(ply_type_size(PlyType::Float32) == 4);
    CHECK(ply_type_size(PlyType::Float64) == 8);
    CHECK(std::string(ply_type_name(PlyType::UInt8)) == "uchar");
    CHECK(std::string(ply_type_name(PlyType::Int32)) == "int");
    CHECK(std::string(ply_type_name(PlyType::Float64)) == "double");
    CHECK(std::string(scene_format_name(SceneFormat::Spz)).find("spz") != std::string::npos);
    CHECK(is_gaussian_property_name("f_rest_44"));
    CHECK_FALSE(is_gaussian_property_name("label"));
    CHECK(opacity_from_logit(0.0f) == 0.5f);
    CHECK(logit_from_opacity(1.0f) == Approx(std::log(9999.0f)).epsilon(1e-4));
    CHECK(std::isfinite(logit_from_opacity(0.0f)));
}

TEST_CASE("scene stats: counts, bounds and percentiles") {
    GaussianCloud c;
    c.resize(101);
    for (int i = 0; i <= 100; ++i) {
        c.mean[i] = glm::vec3(i, -i, 0.5f * i);
        c.log_scale[i] = glm::vec3(std::log(0.01f * (i + 1)), -10.0f, -10.0f);
        c.opacity_logit[i] = logit_from_opacity(0.001f + 0.0099f * i);
    }
    c.sh[5] = std::nanf("");
    SceneStats s = compute_stats(c);
    CHECK(s.count == 101);
    CHECK(s.sh_degree == 0);
    CHECK(s.bounds_min == glm::vec3(0, -100, 0));
    CHECK(s.bounds_max == glm::vec3(100, 0, 50));
    CHECK(s.non_finite == 1);
    CHECK(s.max_scale.p(50) == Approx(0.51f).epsilon(1e-4));
    CHECK(s.max_scale.p(1) == Approx(0.02f).epsilon(1e-4));
    CHECK(s.max_scale.p(99) == Approx(1.0f).epsilon(1e-4));
    CHECK(s.opacity.p(50) == Approx(0.001f + 0.0099f * 50).epsilon(1e-3));
    CHECK(s.opacity.value[0] <= s.opacity.value[6]);
    CHECK(std::isnan(s.opacity.p(42)));

    SceneStats empty = compute_stats(GaussianCloud{});
    CHECK(empty.count == 0);
    CHECK(empty.opacity.p(50) == 0.0f);
}

TEST_CASE("ply: the real guitar scene loads and writes back byte-exact") {
    const fs::path guitar = pg::test::shared_dir() / "data" / "real" / "guitar.ply";
    if (!fs::exists(guitar)) {
        WARN("skipped: " << guitar.string() << " is absent (../shared is not in a user's clone)");
        return;
    }
    const auto t0 = std::chrono::steady_clock::now();
    GaussianCloud c = load_scene(guitar);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    INFO("loaded in " << ms << " ms");
    CHECK(c.size() == 90854);
    CHECK(c.sh_degree == 0);
    CHECK(c.extras.size() == 3);  // nx ny nz
    SceneStats s = compute_stats(c);
    CHECK(s.non_finite == 0);
    CHECK(s.bounds_min.y == Approx(-4.29).margin(0.01));
    CHECK(s.bounds_max.x == Approx(0.82).margin(0.01));
    fs::path out = pg::test::scratch("ply") / "guitar_out.ply";
    write_ply(c, out);
    CHECK(read_bytes(out) == read_bytes(guitar));
}

TEST_CASE("ply: loading reports its progress from 0 to 1, every 2^20 Gaussians") {
    const auto path = pg::test::source_dir() / "assets/sample/desk_000/scene.ply";
    std::vector<double> seen;
    const auto cloud = pg::data::load_scene(path, [&](double f) { seen.push_back(f); });
    REQUIRE(cloud.size() > 0);
    REQUIRE(seen.size() == (cloud.size() + (1u << 20) - 1) / (1u << 20) + 1);
    CHECK(seen.front() == 0.0);
    CHECK(seen.back() == 1.0);
    CHECK(std::is_sorted(seen.begin(), seen.end()));
    CHECK(pg::data::load_scene(path).mean == cloud.mean);  // the same scene without a callback
}
