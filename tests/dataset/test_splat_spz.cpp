// .splat, .spz and PlayCanvas compressed PLY decoding, and load_scene's dispatch.
#include <catch2/catch.hpp>

#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "dataset/error.h"
#include "dataset/formats/scene_io.h"
#include "dataset/gaussian_cloud.h"
#include "tests/test_paths.h"

namespace fs = std::filesystem;
using namespace pg::data;

namespace {

fs::path write_file(const std::string& name, const std::string& bytes) {
    fs::path p = pg::test::scratch("splat_spz") / name;
    std::ofstream out(p, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    return p;
}

template <class T>
void put(std::string& out, T v) {
    out.append(reinterpret_cast<const char*>(&v), sizeof v);  // the test machines are little-endian
}

std::string gzip(const std::string& data) {
    z_stream zs{};
    REQUIRE(deflateInit2(&zs, 9, Z_DEFLATED, 16 + MAX_WBITS, 8, Z_DEFAULT_STRATEGY) == Z_OK);
    std::string out(deflateBound(&zs, static_cast<uLong>(data.size())) + 64, '\0');
    zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data()));
    zs.avail_in = static_cast<uInt>(data.size());
    zs.next_out = reinterpret_cast<Bytef*>(out.data());
    zs.avail_out = static_cast<uInt>(out.size());
    REQUIRE(deflate(&zs, Z_FINISH) == Z_STREAM_END);
    out.resize(zs.total_out);
    deflateEnd(&zs);
    return out;
}

float logit(float a) { return std::log(a / (1.0f - a)); }

glm::vec4 normalized(glm::vec4 q) { return q / std::sqrt(glm::dot(q, q)); }

// |cos| of the angle between two quaternions: 1 when they are the same rotation.
float same_rotation(glm::vec4 a, glm::vec4 b) { return std::abs(glm::dot(normalized(a), normalized(b))); }

// spz v3 "smallest three" packing, after nianticlabs/spz packQuaternionSmallestThree:
// components in (x, y, z, w) order, the largest dropped and made positive.
uint32_t spz_pack_rotation(glm::vec4 wxyz) {
    glm::vec4 n = normalized(wxyz);
    float q[4] = {n.y, n.z, n.w, n.x};
    int largest = 0;
    for (int i = 1; i < 4; ++i)
        if (std::abs(q[i]) > std::abs(q[largest])) largest = i;
    const bool negate = q[largest] < 0;
    uint32_t comp = static_cast<uint32_t>(largest);
    for (int i = 0; i < 4; ++i) {
        if (i == largest) continue;
        uint32_t negbit = (q[i] < 0) ^ negate;
        uint32_t mag = static_cast<uint32_t>(511.0f * (std::abs(q[i]) / 0.70710678f) + 0.5f);
        comp = (comp << 10) | (negbit << 9) | mag;
    }
    return comp;
}

// PlayCanvas 2-10-10-10 packing, after splat-transform's CompressedChunk.packRot:
// components in (rot_0..rot_3) order, the largest dropped and made positive.
uint32_t pc_pack_rotation(glm::vec4 wxyz) {
    glm::vec4 n = normalized(wxyz);
    float a[4] = {n.x, n.y, n.z, n.w};  // glm's x..w hold rot_0..rot_3
    int largest = 0;
    for (int i = 1; i < 4; ++i)
        if (std::abs(a[i]) > std::abs(a[largest])) largest = i;
    if (a[largest] < 0)
        for (float& v : a) v = -v;
    uint32_t result = static_cast<uint32_t>(largest);
    for (int i = 0; i < 4; ++i) {
        if (i == largest) continue;
        float u = a[i] * 0.70710678f + 0.5f;
        result = (result << 10) | static_cast<uint32_t>(std::clamp(std::floor(u * 1023.0f + 0.5f), 0.0f, 1023.0f));
    }
    return result;
}

uint32_t pack_unorm(float v, int bits) {
    const float t = static_cast<float>((1u << bits) - 1);
    return static_cast<uint32_t>(std::clamp(std::floor(v * t + 0.5f), 0.0f, t));
}

uint32_t pack_111011(glm::vec3 t) { return pack_unorm(t.x, 11) << 21 | pack_unorm(t.y, 10) << 11 | pack_unorm(t.z, 11); }

float unorm(uint32_t v, int bits) { return static_cast<float>(v) / static_cast<float>((1u << bits) - 1); }

}  // namespace

TEST_CASE("splat: decodes the antimatter15 32-byte layout") {
    std::string bytes;
    put(bytes, 1.0f), put(bytes, -2.0f), put(bytes, 3.5f);
    put(bytes, 0.5f), put(bytes, 0.25f), put(bytes, 2.0f);
    for (uint8_t b : {255, 0, 128, 191}) bytes.push_back(static_cast<char>(b));
    for (uint8_t b : {228, 128, 28, 128}) bytes.push_back(static_cast<char>(b));
    // A second, flat splat with a zero scale and full alpha.
    put(bytes, 0.0f), put(bytes, 0.0f), put(bytes, 0.0f);
    put(bytes, 0.1f), put(bytes, 0.0f), put(bytes, 0.1f);
    for (uint8_t b : {0, 0, 0, 255}) bytes.push_back(static_cast<char>(b));
    for (uint8_t b : {128, 255, 128, 128}) bytes.push_back(static_cast<char>(b));

    GaussianCloud c = load_scene(write_file("two.splat", bytes));
    REQUIRE(c.size() == 2);
    CHECK(c.format == SceneFormat::Splat);
    CHECK(c.sh_degree == 0);
    CHECK(c.mean[0] == glm::vec3(1.0f, -2.0f, 3.5f));
    CHECK(c.log_scale[0].x == Approx(std::log(0.5f)));
    CHECK(c.log_scale[0].y == Approx(std::log(0.25f)));
    CHECK(c.log_scale[0].z == Approx(std::log(2.0f)));
    CHECK(c.sh[0] == Approx((1.0f - 0.5f) / kShC0));
    CHECK(c.sh[1] == Approx((0.0f - 0.5f) / kShC0));
    CHECK(c.sh[2] == Approx((128.0f / 255.0f - 0.5f) / kShC0));
    CHECK(c.opacity_logit[0] == Approx(logit(191.0f / 255.0f)));
    CHECK(c.rotation[0] == glm::vec4(100.0f / 128, 0.0f, -100.0f / 128, 0.0f));
    CHECK(c.log_scale[1].y == kFlatLogScale);
    CHECK(opacity_from_logit(c.opacity_logit[1]) > 0.999f);
    CHECK(c.rotation[1] == glm::vec4(0.0f, 127.0f / 128, 0.0f, 0.0f));
}

TEST_CASE("spz: decodes version 2 (first-three rotations) with SH degree 1") {
    const int n = 2;
    std::string raw;
    put(raw, uint32_t(0x5053474e)), put(raw, uint32_t(2)), put(raw, uint32_t(n));
    raw.push_back(1), raw.push_back(12), raw.push_back(1), raw.push_back(0);  // degree, fractional bits, flags
    const int32_t fixed[n][3] = {{6144, -9216, 1}, {-1, 8388607, -8388608}};
    for (const auto& p : fixed)
        for (int32_t v : p)
            for (int b = 0; b < 3; ++b) raw.push_back(static_cast<char>((v >> (8 * b)) & 0xff));
    raw.push_back(static_cast<char>(128)), raw.push_back(static_cast<char>(255));        // alphas
    for (uint8_t b : {200, 128, 50, 0, 255, 127}) raw.push_back(static_cast<char>(b));    // colours
    for (uint8_t b : {96, 160, 0, 255, 16, 32}) raw.push_back(static_cast<char>(b));      // scales
    for (uint8_t b : {191, 127, 64, 128, 128, 128}) raw.push_back(static_cast<char>(b));  // rotations xyz
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < 9; ++j) raw.push_back(static_cast<char>(10 * j + 100 * i + 5));  // SH

    GaussianCloud c = load_scene(write_file("v2.spz", gzip(raw)));
    REQUIRE(c.size() == 2);
    CHECK(c.format == SceneFormat::Spz);
    REQUIRE(c.sh_degree == 1);
    CHECK(c.mean[0] == glm::vec3(1.5f, -2.25f, 1.0f / 4096));
    CHECK(c.mean[1] == glm::vec3(-1.0f / 4096, 8388607.0f / 4096, -2048.0f));
    CHECK(c.opacity_logit[0] == Approx(logit(128.0f / 255.0f)));
    CHECK(opacity_from_logit(c.opacity_logit[1]) > 0.999f);
    CHECK(c.sh[0] == Approx((200.0f / 255.0f - 0.5f) / 0.15f));
    CHECK(c.sh[2] == Approx((50.0f / 255.0f - 0.5f) / 0.15f));
    CHECK(c.log_scale[0] == glm::vec3(-4.0f, 0.0f, -10.0f));
    CHECK(c.log_scale[1] == glm::vec3(255.0f / 16 - 10, -9.0f, -8.0f));
    const float x = 191 / 127.5f - 1, y = 127 / 127.5f - 1, z = 64 / 127.5f - 1;
    CHECK(c.rotation[0].x == Approx(std::sqrt(1 - x * x - y * y - z * z)));
    CHECK(c.rotation[0].y == Approx(x));
    CHECK(c.rotation[0].z == Approx(y));
    CHECK(c.rotation[0].w == Approx(z));
    CHECK(c.rotation[1].x == Approx(1.0f).margin(1e-4));
    // spz stores SH coefficient-major with rgb inner: the same order as GaussianCloud::sh.
    for (int i = 0; i < n; ++i)
        for (int k = 1; k < 4; ++k)
            for (int ch = 0; ch < 3; ++ch) {
                const int j = (k - 1) * 3 + ch;
                CHECK(c.sh[(i * 4 + k) * 3 + ch] == Approx((10 * j + 100 * i + 5 - 128) / 128.0f));
            }
    CHECK(c.ply_comments == std::vector<std::string>{"spz: antialiased"});
}

TEST_CASE("spz: decodes version 3 smallest-three rotations") {
    const std::vector<glm::vec4> rotations = {
        {1, 0, 0, 0}, {0, -1, 0, 0}, {0.3f, -0.5f, 0.7f, 0.2f}, {-0.1f, 0.2f, -0.3f, 0.9f}, {0.5f, 0.5f, -0.5f, -0.5f},
        {0.05f, 0.9f, 0.1f, -0.4f}};
    const uint32_t n = static_cast<uint32_t>(rotations.size());
    std::string raw;
    put(raw, uint32_t(0x5053474e)), put(raw, uint32_t(3)), put(raw, n);
    raw.push_back(0), raw.push_back(8), raw.push_back(0), raw.push_back(0);
    raw.append(9 * n, '\0');                      // positions
    raw.append(n, static_cast<char>(200));        // alphas
    raw.append(3 * n, static_cast<char>(128));    // colours
    raw.append(3 * n, static_cast<char>(80));     // scales
    for (const auto& q : rotations) put(raw, spz_pack_rotation(q));
    CHECK(spz_pack_rotation({1, 0, 0, 0}) == 3u << 30);  // identity: w is the largest, nothing else set

    GaussianCloud c = read_spz(write_file("v3.spz", gzip(raw)));
    REQUIRE(c.size() == n);
    CHECK(c.rotation[0] == glm::vec4(1, 0, 0, 0));
    CHECK(c.rotation[1] == glm::vec4(0, 1, 0, 0));
    for (uint32_t i = 0; i < n; ++i) {
        INFO("rotation " << i);
        CHECK(same_rotation(c.rotation[i], rotations[i]) > 0.9999f);
        CHECK(glm::dot(c.rotation[i], c.rotation[i]) == Approx(1.0f).margin(1e-3));
    }
    CHECK(c.mean[3] == glm::vec3(0.0f));
    CHECK(c.log_scale[2] == glm::vec3(-5.0f));
}

namespace {

// A PlayCanvas compressed PLY of n Gaussians, all with the same packed words; chunk c's
// bounds are shifted by 10 * c so the test can tell chunks apart.
std::string compressed_ply(uint32_t n, bool chunk_colour, int sh_degree, const uint32_t packed[4],
                           const std::vector<uint8_t>& sh_bytes) {
    const uint32_t chunks = (n + 255) / 256;
    std::ostringstream h;
    h << "ply\nformat binary_little_endian 1.0\ncomment Generated by a test\nelement chunk " << chunks << "\n";
    for (const char* p : {"min_x", "min_y", "min_z", "max_x", "max_y", "max_z", "min_scale_x", "min_scale_y",
                          "min_scale_z", "max_scale_x", "max_scale_y", "max_scale_z"})
        h << "property float " << p << "\n";
    if (chunk_colour)
        for (const char* p : {"min_r", "min_g", "min_b", "max_r", "max_g", "max_b"}) h << "property float " << p << "\n";
    h << "element vertex " << n << "\n";
    for (const char* p : {"packed_position", "packed_rotation", "packed_scale", "packed_color"})
        h << "property uint " << p << "\n";
    const int rest = 3 * (sh_coeffs(sh_degree) - 1);
    if (sh_degree > 0) {
        h << "element sh " << n << "\n";
        for (int j = 0; j < rest; ++j) h << "property uchar f_rest_" << j << "\n";
    }
    h << "end_header\n";
    std::string out = h.str();
    for (uint32_t c = 0; c < chunks; ++c) {
        const float o = 10.0f * c;
        for (float v : {o - 1, o - 2, o - 3, o + 1, o + 2, o + 5, -6.f, -5.f, -4.f, -2.f, -1.f, 0.f}) put(out, v);
        if (chunk_colour)
            for (float v : {0.2f, 0.1f, -0.5f, 0.8f, 0.9f, 1.5f}) put(out, v);
    }
    for (uint32_t i = 0; i < n; ++i)
        for (int k = 0; k < 4; ++k) put(out, packed[k]);
    for (uint32_t i = 0; i < n && sh_degree > 0; ++i)
        for (int j = 0; j < rest; ++j) out.push_back(static_cast<char>(sh_bytes[j]));
    return out;
}

}  // namespace

TEST_CASE("compressed ply: decodes hand-packed chunks, colours and SH") {
    const glm::vec4 q = normalized({0.3f, -0.5f, 0.7f, 0.2f});
    const uint32_t packed[4] = {pack_111011({0.5f, 0.25f, 1.0f}), pc_pack_rotation(q),
                                pack_111011({0.0f, 0.5f, 0.75f}), 255u << 24 | 0u << 16 | 128u << 8 | 64u};
    std::vector<uint8_t> sh_bytes(9);
    for (int j = 0; j < 9; ++j) sh_bytes[j] = static_cast<uint8_t>(j == 0 ? 0 : j == 1 ? 255 : 20 * j);

    for (bool chunk_colour : {true, false}) {
        INFO("chunk colour: " << chunk_colour);
        GaussianCloud c =
            load_scene(write_file("packed.ply", compressed_ply(257, chunk_colour, 1, packed, sh_bytes)));
        REQUIRE(c.size() == 257);
        CHECK(c.format == SceneFormat::CompressedPly);
        REQUIRE(c.sh_degree == 1);
        CHECK(c.ply_property_order.empty());
        for (size_t i : {size_t(0), size_t(255), size_t(256)}) {
            INFO("Gaussian " << i);
            const float o = i < 256 ? 0.0f : 10.0f;
            const float tx = unorm(1024, 11), ty = unorm(256, 10);
            CHECK(c.mean[i].x == Approx((o - 1) * (1 - tx) + (o + 1) * tx).margin(1e-5));
            CHECK(c.mean[i].y == Approx((o - 2) * (1 - ty) + (o + 2) * ty).margin(1e-5));
            CHECK(c.mean[i].z == Approx(o + 5).margin(1e-5));
            CHECK(c.log_scale[i].x == Approx(-6.0f));
            CHECK(c.log_scale[i].y == Approx(-5.0f * (1 - unorm(512, 10)) + -1.0f * unorm(512, 10)));
            CHECK(c.log_scale[i].z == Approx(-4.0f * (1 - unorm(1535, 11))).margin(1e-5));
            CHECK(same_rotation(c.rotation[i], q) > 0.9999f);
            const float r = chunk_colour ? 0.8f : 1.0f, g = chunk_colour ? 0.1f : 0.0f;
            const float b = chunk_colour ? -0.5f + 2.0f * (128.0f / 255.0f) : 128.0f / 255.0f;
            CHECK(c.sh[i * 12 + 0] == Approx((r - 0.5f) / kShC0));
            CHECK(c.sh[i * 12 + 1] == Approx((g - 0.5f) / kShC0));
            CHECK(c.sh[i * 12 + 2] == Approx((b - 0.5f) / kShC0).margin(1e-5));
            CHECK(c.opacity_logit[i] == Approx(logit(64.0f / 255.0f)));
            // f_rest_j in the INRIA order: j = channel * 3 + (k - 1).
            CHECK(c.sh[(i * 4 + 1) * 3 + 0] == Approx(-4.0f));  // f_rest_0 = 0
            CHECK(c.sh[(i * 4 + 2) * 3 + 0] == Approx(4.0f));   // f_rest_1 = 255
            CHECK(c.sh[(i * 4 + 3) * 3 + 2] == Approx(((160 + 0.5f) / 256 - 0.5f) * 8));  // f_rest_8 = 160
            CHECK(c.sh[(i * 4 + 1) * 3 + 1] == Approx(((60 + 0.5f) / 256 - 0.5f) * 8));   // f_rest_3 = 60
        }
    }
}

TEST_CASE("compressed ply: the guitar scene matches its uncompressed version") {
    const fs::path dir = pg::test::shared_dir() / "data" / "real";
    if (!fs::exists(dir / "guitar.compressed.ply") || !fs::exists(dir / "guitar.ply")) {
        WARN("skipped: " << dir.string() << " is absent (../shared is not in a user's clone)");
        return;
    }
    GaussianCloud packed = load_scene(dir / "guitar.compressed.ply");
    GaussianCloud plain = load_scene(dir / "guitar.ply");
    REQUIRE(packed.format == SceneFormat::CompressedPly);
    REQUIRE(packed.size() == 90854);
    REQUIRE(plain.size() == packed.size());
    REQUIRE(packed.sh_degree == 0);

    // Tolerances per chunk of 256, from the extent of the uncompressed values in it: one
    // step of the 11-bit position and scale quantization, of the 8-bit colour.
    size_t worst_rotation = 0, failures = 0;
    float min_cos = 1.0f;
    for (size_t first = 0; first < plain.size(); first += 256) {
        const size_t last = std::min(plain.size(), first + 256);
        glm::vec3 lo(1e30f), hi(-1e30f), slo(1e30f), shi(-1e30f), clo(1e30f), chi(-1e30f);
        for (size_t i = first; i < last; ++i) {
            lo = glm::min(lo, plain.mean[i]);
            hi = glm::max(hi, plain.mean[i]);
            slo = glm::min(slo, plain.log_scale[i]);
            shi = glm::max(shi, plain.log_scale[i]);
            glm::vec3 dc(plain.sh[i * 3], plain.sh[i * 3 + 1], plain.sh[i * 3 + 2]);
            clo = glm::min(clo, dc);
            chi = glm::max(chi, dc);
        }
        const glm::vec3 pos_tol = (hi - lo) / 2047.0f + 1e-6f;
        const glm::vec3 scale_tol = (shi - slo) / 2047.0f + 1e-5f;
        const glm::vec3 dc_tol = (chi - clo) / 255.0f + 1e-5f;
        for (size_t i = first; i < last; ++i) {
            bool ok = true;
            for (int k = 0; k < 3; ++k) {
                ok = ok && std::abs(packed.mean[i][k] - plain.mean[i][k]) <= pos_tol[k];
                ok = ok && std::abs(packed.log_scale[i][k] - plain.log_scale[i][k]) <= scale_tol[k];
                ok = ok && std::abs(packed.sh[i * 3 + k] - plain.sh[i * 3 + k]) <= dc_tol[k];
            }
            ok = ok && std::abs(opacity_from_logit(packed.opacity_logit[i]) -
                                opacity_from_logit(plain.opacity_logit[i])) <= 0.5f / 255.0f + 1e-4f;
            const float cos = same_rotation(packed.rotation[i], plain.rotation[i]);
            if (cos < min_cos) {
                min_cos = cos;
                worst_rotation = i;
            }
            failures += !ok;
        }
    }
    INFO("worst rotation at Gaussian " << worst_rotation << ": |cos| " << min_cos);
    CHECK(failures == 0);
    CHECK(min_cos > 0.999f);
}

TEST_CASE("load_scene: picks the reader by content first, then by extension") {
    std::string ply = "ply\nformat ascii 1.0\nelement vertex 1\n";
    for (const char* p : {"x", "y", "z", "f_dc_0", "f_dc_1", "f_dc_2", "opacity", "scale_0", "scale_1", "scale_2",
                          "rot_0", "rot_1", "rot_2", "rot_3"})
        ply += std::string("property float ") + p + "\n";
    ply += "end_header\n1 2 3 0 0 0 0 -1 -1 -1 1 0 0 0\n";
    CHECK(load_scene(write_file("scene.data", ply)).format == SceneFormat::InriaPlyAscii);
    CHECK(load_scene(write_file("crlf.ply", "ply\r\nformat ascii 1.0\r\n" + ply.substr(21))).size() == 1);

    std::string raw;
    put(raw, uint32_t(0x5053474e)), put(raw, uint32_t(2)), put(raw, uint32_t(1));
    raw.append(4, '\0');
    raw.append(9 + 1 + 3 + 3 + 3, '\0');
    CHECK(load_scene(write_file("scene.bin", gzip(raw))).format == SceneFormat::Spz);

    std::string splat(32, '\0');
    splat[28] = static_cast<char>(255);  // rotation w
    CHECK(load_scene(write_file("scene.SPLAT", splat)).format == SceneFormat::Splat);
    CHECK_THROWS_AS(load_scene(write_file("scene.obj", splat)), InputError);
}
