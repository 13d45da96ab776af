#pragma once
// WebP images as SOG stores them: RGBA8, lossless. A thin layer over libwebp.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace pg::data {

struct RgbaImage {
    int width = 0, height = 0;
    std::vector<uint8_t> rgba;  // row-major, 4 bytes a pixel
    size_t pixels() const { return size_t(width) * size_t(height); }
};

// Decodes a WebP held in memory. The canvas size is read from the header first and refused if
// it holds more than `max_pixels`, so a small file claiming a huge canvas allocates nothing.
// Errors are InputError(where, ...).
RgbaImage decode_webp(const std::vector<uint8_t>& bytes, size_t max_pixels, const std::string& where);

// The canvas a WebP's header claims, without decoding; InputError(where, ...) if unreadable.
size_t webp_pixels(const std::vector<uint8_t>& bytes, const std::string& where);

// Lossless, exact (RGB kept under zero alpha). Throws std::runtime_error if libwebp fails.
std::vector<uint8_t> encode_webp_lossless(const RgbaImage& image);

}  // namespace pg::data
