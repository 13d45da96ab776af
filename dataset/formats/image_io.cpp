// PNG writer (our own, on zlib: 8- and 16-bit through one path) and reader (stb_image).
#include "dataset/formats/image_io.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <ostream>
#include <string>

#include <stb_image.h>
#include <zlib.h>

#include "dataset/atomic_file.h"
#include "dataset/error.h"

namespace pg::data {

namespace fs = std::filesystem;

namespace {

void put_be32(std::vector<uint8_t>& out, uint32_t v) {
    for (int shift = 24; shift >= 0; shift -= 8) out.push_back(uint8_t(v >> shift));
}

void put_chunk(std::ostream& out, const char type[4], const std::vector<uint8_t>& data) {
    std::vector<uint8_t> chunk;
    chunk.reserve(data.size() + 12);
    put_be32(chunk, uint32_t(data.size()));
    chunk.insert(chunk.end(), type, type + 4);
    chunk.insert(chunk.end(), data.begin(), data.end());
    // The CRC covers the type and the data, not the length.
    uLong crc = crc32(0L, Z_NULL, 0);
    crc = crc32(crc, chunk.data() + 4, uInt(chunk.size() - 4));
    put_be32(chunk, uint32_t(crc));
    out.write(reinterpret_cast<const char*>(chunk.data()), std::streamsize(chunk.size()));
}

// Per row, the filter (None, Sub or Up) with the smallest sum of |signed bytes|, the usual
// PNG heuristic. `raw` holds height rows of `stride` bytes; bpp is bytes per pixel.
std::vector<uint8_t> filter_rows(const std::vector<uint8_t>& raw, size_t stride, size_t height, size_t bpp) {
    std::vector<uint8_t> out;
    out.reserve((stride + 1) * height);
    std::vector<uint8_t> candidate[3];
    for (auto& c : candidate) c.resize(stride);
    for (size_t y = 0; y < height; ++y) {
        const uint8_t* row = raw.data() + y * stride;
        const uint8_t* up = y > 0 ? row - stride : nullptr;
        uint64_t best_cost = UINT64_MAX;
        int best = 0;
        for (int f = 0; f < 3; ++f) {
            if (f == 2 && !up) break;
            uint64_t cost = 0;
            for (size_t x = 0; x < stride; ++x) {
                uint8_t pred = 0;
                if (f == 1 && x >= bpp) pred = row[x - bpp];
                if (f == 2) pred = up[x];
                const uint8_t v = uint8_t(row[x] - pred);
                candidate[f][x] = v;
                cost += uint64_t(std::abs(int(int8_t(v))));
            }
            if (cost < best_cost) {
                best_cost = cost;
                best = f;
            }
        }
        out.push_back(uint8_t(best));
        out.insert(out.end(), candidate[best].begin(), candidate[best].end());
    }
    return out;
}

// bit_depth 8 or 16; `raw` rows are already in PNG byte order (16-bit big-endian).
void write_png(const fs::path& path, int width, int height, int channels, int bit_depth,
               const std::vector<uint8_t>& raw) {
    const size_t bpp = size_t(channels) * size_t(bit_depth / 8);
    const size_t stride = size_t(width) * bpp;
    const std::vector<uint8_t> filtered = filter_rows(raw, stride, size_t(height), bpp);

    uLongf packed_size = compressBound(uLong(filtered.size()));
    std::vector<uint8_t> packed(packed_size);
    if (compress2(packed.data(), &packed_size, filtered.data(), uLong(filtered.size()), Z_DEFAULT_COMPRESSION) != Z_OK)
        throw InputError(path.string(), "zlib compression failed");
    packed.resize(packed_size);

    std::vector<uint8_t> ihdr;
    put_be32(ihdr, uint32_t(width));
    put_be32(ihdr, uint32_t(height));
    const uint8_t colour_type = channels == 1 ? 0 : channels == 3 ? 2 : 6;  // grey, RGB, RGBA
    ihdr.insert(ihdr.end(), {uint8_t(bit_depth), colour_type, 0, 0, 0});      // deflate, adaptive, no interlace

    write_atomically(path, [&](std::ostream& out) {
        static const unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
        out.write(reinterpret_cast<const char*>(signature), 8);
        put_chunk(out, "IHDR", ihdr);
        put_chunk(out, "IDAT", packed);
        put_chunk(out, "IEND", {});
    });
}

void check_size(const fs::path& path, int width, int height, int channels, size_t bytes_per_sample,
                size_t given) {
    if (width <= 0 || height <= 0)
        throw InputError(path.string(), "cannot write a " + std::to_string(width) + "x" + std::to_string(height) +
                                            " image: the size must be positive");
    // Whole image in one zlib call (uLong) and PNG's 31-bit dimensions.
    const uint64_t bytes = uint64_t(width) * uint64_t(height) * uint64_t(channels) * bytes_per_sample;
    if (bytes + uint64_t(height) > uint64_t(UINT32_MAX) / 2)
        throw InputError(path.string(), "image too large for the PNG writer");
    if (uint64_t(given) != uint64_t(width) * uint64_t(height) * uint64_t(channels))
        throw InputError(path.string(), "pixel buffer holds " + std::to_string(given) + " values, a " +
                                            std::to_string(width) + "x" + std::to_string(height) + "x" +
                                            std::to_string(channels) + " image needs " +
                                            std::to_string(uint64_t(width) * uint64_t(height) * uint64_t(channels)));
}

}  // namespace

void write_png8(const fs::path& path, int width, int height, int channels, const std::vector<uint8_t>& pixels) {
    if (channels != 1 && channels != 3 && channels != 4)
        throw InputError(path.string(), "cannot write " + std::to_string(channels) + " channels (1, 3 or 4)");
    check_size(path, width, height, channels, 1, pixels.size());
    write_png(path, width, height, channels, 8, pixels);
}

void write_png16(const fs::path& path, int width, int height, const std::vector<uint16_t>& pixels) {
    check_size(path, width, height, 1, 2, pixels.size());
    std::vector<uint8_t> raw(pixels.size() * 2);
    for (size_t i = 0; i < pixels.size(); ++i) {
        raw[2 * i] = uint8_t(pixels[i] >> 8);
        raw[2 * i + 1] = uint8_t(pixels[i] & 0xff);
    }
    write_png(path, width, height, 1, 16, raw);
}

Image8 read_png8(const fs::path& path) {
    const auto data = read_file(path);
    if (data.size() > size_t(INT_MAX)) throw InputError(path.string(), "file too large to decode");
    int w = 0, h = 0, comp = 0;
    stbi_uc* pixels = stbi_load_from_memory(reinterpret_cast<const stbi_uc*>(data.data()), int(data.size()), &w, &h,
                                            &comp, 0);
    if (!pixels) {
        const char* why = stbi_failure_reason();
        throw InputError(path.string(), std::string("cannot decode image: ") + (why ? why : "unknown error"));
    }
    Image8 img;
    img.width = w;
    img.height = h;
    img.channels = comp;
    img.pixels.assign(pixels, pixels + size_t(w) * size_t(h) * size_t(comp));
    stbi_image_free(pixels);
    return img;
}

Image16 read_png16(const fs::path& path) {
    const auto data = read_file(path);
    if (data.size() > size_t(INT_MAX)) throw InputError(path.string(), "file too large to decode");
    const auto* bytes = reinterpret_cast<const stbi_uc*>(data.data());
    const int size = int(data.size());
    const bool wide = stbi_is_16_bit_from_memory(bytes, size);
    // stb rescales 1-, 2- and 4-bit grey to 0..255, which would change ids: refuse them.
    // The bit depth is the first byte after the IHDR chunk's width and height.
    if (data.size() > 24 && std::string(data.data() + 12, 4) == "IHDR" && uint8_t(data[24]) < 8)
        throw InputError(path.string(),
                         "a " + std::to_string(int(data[24])) + "-bit PNG cannot hold mask ids (8 or 16 bits)");
    int w = 0, h = 0, comp = 0;
    void* pixels = wide ? static_cast<void*>(stbi_load_16_from_memory(bytes, size, &w, &h, &comp, 0))
                        : static_cast<void*>(stbi_load_from_memory(bytes, size, &w, &h, &comp, 0));
    if (!pixels) {
        const char* why = stbi_failure_reason();
        throw InputError(path.string(), std::string("cannot decode image: ") + (why ? why : "unknown error"));
    }
    Image16 img;
    img.width = w;
    img.height = h;
    const size_t n = size_t(w) * size_t(h);
    if (comp == 1) {
        if (wide) img.pixels.assign(static_cast<const uint16_t*>(pixels), static_cast<const uint16_t*>(pixels) + n);
        else img.pixels.assign(static_cast<const uint8_t*>(pixels), static_cast<const uint8_t*>(pixels) + n);
    }
    stbi_image_free(pixels);
    if (comp != 1)
        throw InputError(path.string(), "expected a single-channel grey image, found " + std::to_string(comp) +
                                            " channels");
    return img;
}

std::vector<uint8_t> to_8bit(const std::vector<float>& values) {
    std::vector<uint8_t> out(values.size());
    for (size_t i = 0; i < values.size(); ++i) {
        const float v = values[i];
        const float c = std::isnan(v) ? 0.0f : std::clamp(v, 0.0f, 1.0f);
        out[i] = uint8_t(std::lround(c * 255.0f));
    }
    return out;
}

}  // namespace pg::data
