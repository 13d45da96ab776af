#pragma once
// PNG output for renders and masks (stb), written atomically.
#include <cstdint>
#include <filesystem>
#include <vector>

namespace pg::data {

// 8-bit image with 1 (grey), 3 (RGB) or 4 (RGBA) channels, row-major, top row first.
void write_png8(const std::filesystem::path& path, int width, int height, int channels,
                const std::vector<uint8_t>& pixels);
// 16-bit single-channel image (index masks, depth), stored big-endian as PNG requires.
void write_png16(const std::filesystem::path& path, int width, int height, const std::vector<uint16_t>& pixels);

struct Image8 {
    int width = 0, height = 0, channels = 0;
    std::vector<uint8_t> pixels;
};
Image8 read_png8(const std::filesystem::path& path);

struct Image16 {
    int width = 0, height = 0;
    std::vector<uint16_t> pixels;  // one channel, row-major, top row first
};
// Reads a grey PNG (index masks). 16-bit samples come back as stored; 8-bit samples are
// widened unchanged (0..255, not rescaled to 0..65535), since a mask's values are ids.
// Colour or grey+alpha images are refused with an InputError naming the file.
Image16 read_png16(const std::filesystem::path& path);

// Float [0,1] RGB(A) to 8-bit with rounding and clamping.
std::vector<uint8_t> to_8bit(const std::vector<float>& values);

}  // namespace pg::data
