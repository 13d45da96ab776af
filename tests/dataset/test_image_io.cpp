// PNG writer (own encoder on zlib) checked by decoding with stb_image; reader errors; to_8bit.
#include <cmath>
#include <fstream>
#include <limits>

#include <catch2/catch.hpp>
#include <stb/stb_image.h>  // the test target has no stb include path; the library links libstb

#include "dataset/error.h"
#include "dataset/formats/image_io.h"
#include "tests/test_paths.h"

namespace fs = std::filesystem;

namespace {

fs::path fresh_scratch(const char* name) {
    fs::remove_all(pg::test::binary_dir() / "test-scratch" / name);
    return pg::test::scratch(name);
}

std::string read_bytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

// Smooth gradients, flat areas and noise, so every row filter gets used.
std::vector<uint8_t> pattern8(int w, int h, int c) {
    std::vector<uint8_t> px(size_t(w) * h * c);
    uint32_t rng = 12345;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int k = 0; k < c; ++k) {
                rng = rng * 1664525u + 1013904223u;
                uint8_t v = y < h / 3 ? uint8_t(x * 7 + k * 50) : y < 2 * h / 3 ? uint8_t(y * 3 + k) : uint8_t(rng >> 24);
                px[(size_t(y) * w + x) * c + k] = v;
            }
    return px;
}

}  // namespace

TEST_CASE("PNG 8-bit: grey, RGB and RGBA decode exactly with stb_image", "[image_io]") {
    const fs::path dir = fresh_scratch("png8");
    for (const int c : {1, 3, 4})
        for (const auto& [w, h] : {std::pair{1, 1}, std::pair{37, 23}, std::pair{64, 3}}) {
            INFO(c << " channels, " << w << "x" << h);
            const auto px = pattern8(w, h, c);
            const fs::path file = dir / ("img_" + std::to_string(c) + "_" + std::to_string(w) + ".png");
            pg::data::write_png8(file, w, h, c, px);

            const std::string bytes = read_bytes(file);
            int rw = 0, rh = 0, rc = 0;
            stbi_uc* data = stbi_load_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()), int(bytes.size()),
                                                  &rw, &rh, &rc, 0);
            REQUIRE(data != nullptr);
            REQUIRE(rw == w);
            REQUIRE(rh == h);
            REQUIRE(rc == c);
            const bool same = std::equal(px.begin(), px.end(), data);
            stbi_image_free(data);
            REQUIRE(same);

            const pg::data::Image8 img = pg::data::read_png8(file);
            REQUIRE(img.width == w);
            REQUIRE(img.height == h);
            REQUIRE(img.channels == c);
            REQUIRE(img.pixels == px);
        }
}

TEST_CASE("PNG 16-bit grey decodes exactly with stbi_load_16", "[image_io]") {
    const fs::path dir = fresh_scratch("png16");
    const int w = 41, h = 19;
    std::vector<uint16_t> px(size_t(w) * h);
    for (size_t i = 0; i < px.size(); ++i) px[i] = uint16_t(i * 2654435761u >> 7);
    px[0] = 0;
    px[1] = 65535;
    px[2] = 0x0100;  // byte order matters
    px[3] = 0x0001;
    const fs::path file = dir / "mask16.png";
    pg::data::write_png16(file, w, h, px);

    const std::string bytes = read_bytes(file);
    REQUIRE(bytes.substr(1, 3) == "PNG");
    REQUIRE(uint8_t(bytes[24]) == 16);  // IHDR bit depth
    REQUIRE(uint8_t(bytes[25]) == 0);   // grey
    int rw = 0, rh = 0, rc = 0;
    REQUIRE(stbi_is_16_bit_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()), int(bytes.size())));
    stbi_us* data = stbi_load_16_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()), int(bytes.size()), &rw,
                                             &rh, &rc, 0);
    REQUIRE(data != nullptr);
    REQUIRE(rw == w);
    REQUIRE(rh == h);
    REQUIRE(rc == 1);
    const bool same = std::equal(px.begin(), px.end(), data);
    stbi_image_free(data);
    REQUIRE(same);
}

TEST_CASE("PNG writer rejects bad sizes and channel counts without leaving a file", "[image_io]") {
    const fs::path dir = fresh_scratch("png_bad");
    using pg::data::InputError;
    REQUIRE_THROWS_AS(pg::data::write_png8(dir / "a.png", 0, 4, 1, {}), InputError);
    REQUIRE_THROWS_AS(pg::data::write_png8(dir / "a.png", 4, -1, 1, {}), InputError);
    REQUIRE_THROWS_AS(pg::data::write_png8(dir / "a.png", 2, 2, 2, std::vector<uint8_t>(8)), InputError);
    REQUIRE_THROWS_AS(pg::data::write_png8(dir / "a.png", 2, 2, 3, std::vector<uint8_t>(11)), InputError);
    REQUIRE_THROWS_AS(pg::data::write_png8(dir / "a.png", 2, 2, 4, std::vector<uint8_t>(12)), InputError);
    REQUIRE_THROWS_AS(pg::data::write_png8(dir / "a.png", 1 << 20, 1 << 20, 4, std::vector<uint8_t>(4)), InputError);
    REQUIRE_THROWS_AS(pg::data::write_png16(dir / "a.png", 3, 3, std::vector<uint16_t>(8)), InputError);
    REQUIRE_THROWS_AS(pg::data::write_png16(dir / "a.png", 3, 0, {}), InputError);
    REQUIRE_THROWS_AS(pg::data::write_png8(dir / "no_such_folder" / "a.png", 1, 1, 1, {7}), InputError);
    REQUIRE(fs::is_empty(dir));
    try {
        pg::data::write_png8(dir / "named.png", 2, 2, 3, std::vector<uint8_t>(5));
        FAIL("no error");
    } catch (const InputError& e) {
        REQUIRE(std::string(e.what()).find("named.png") != std::string::npos);
    }
}

TEST_CASE("read_png8: missing and corrupt files are InputErrors naming the file", "[image_io]") {
    const fs::path dir = fresh_scratch("png_read_bad");
    using pg::data::InputError;
    REQUIRE_THROWS_AS(pg::data::read_png8(dir / "missing.png"), InputError);
    pg::data::write_png8(dir / "good.png", 8, 8, 3, pattern8(8, 8, 3));
    const std::string good = read_bytes(dir / "good.png");
    std::ofstream(dir / "cut.png", std::ios::binary) << good.substr(0, good.size() / 2);
    std::ofstream(dir / "text.png", std::ios::binary) << "not a png";
    for (const char* name : {"cut.png", "text.png", "missing.png"}) {
        try {
            pg::data::read_png8(dir / name);
            FAIL("no error for " << name);
        } catch (const InputError& e) {
            REQUIRE(std::string(e.what()).find(name) != std::string::npos);
        }
    }
}

TEST_CASE("read_png8 reads 16-bit files as 8-bit", "[image_io]") {
    const fs::path file = fresh_scratch("png16_as_8") / "m.png";
    pg::data::write_png16(file, 2, 1, {0, 65535});
    const auto img = pg::data::read_png8(file);
    REQUIRE(img.channels == 1);
    REQUIRE(img.pixels == std::vector<uint8_t>{0, 255});
}

TEST_CASE("to_8bit clamps and rounds", "[image_io]") {
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    const auto out = pg::data::to_8bit({0.0f, 1.0f, -0.5f, 2.0f, 0.5f, 1.0f / 255 * 0.49f, 1.0f / 255 * 0.51f,
                                        254.6f / 255, nan, inf, -inf});
    REQUIRE(out == std::vector<uint8_t>{0, 255, 0, 255, 128, 0, 1, 255, 0, 255, 0});
}
