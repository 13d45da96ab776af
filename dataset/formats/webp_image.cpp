// decode_webp / encode_webp_lossless over libwebp's simple API.
#include "dataset/formats/webp_image.h"

#include <stdexcept>

#include <webp/decode.h>
#include <webp/encode.h>

#include "dataset/error.h"

namespace pg::data {

RgbaImage decode_webp(const std::vector<uint8_t>& bytes, size_t max_pixels, const std::string& where) {
    int w = 0, h = 0;
    if (bytes.empty() || !WebPGetInfo(bytes.data(), bytes.size(), &w, &h))
        throw InputError(where, "not a WebP image (header unreadable)");
    if (w <= 0 || h <= 0) throw InputError(where, "WebP image has an empty canvas");
    const size_t pixels = size_t(w) * size_t(h);
    if (pixels > max_pixels)
        throw InputError(where, "WebP canvas " + std::to_string(w) + "x" + std::to_string(h) + " holds " +
                                    std::to_string(pixels) + " pixels, more than the " + std::to_string(max_pixels) +
                                    " this image needs (refused before decoding)");
    RgbaImage img;
    img.width = w, img.height = h;
    img.rgba.resize(pixels * 4);
    if (!WebPDecodeRGBAInto(bytes.data(), bytes.size(), img.rgba.data(), img.rgba.size(), w * 4))
        throw InputError(where, "WebP image data is truncated or corrupt");
    return img;
}

size_t webp_pixels(const std::vector<uint8_t>& bytes, const std::string& where) {
    int w = 0, h = 0;
    if (bytes.empty() || !WebPGetInfo(bytes.data(), bytes.size(), &w, &h) || w <= 0 || h <= 0)
        throw InputError(where, "not a WebP image (header unreadable)");
    return size_t(w) * size_t(h);
}

std::vector<uint8_t> encode_webp_lossless(const RgbaImage& image) {
    WebPConfig config;
    WebPPicture pic;
    if (!WebPConfigInit(&config) || !WebPPictureInit(&pic)) throw std::runtime_error("libwebp: version mismatch");
    config.lossless = 1;
    config.exact = 1;
    config.quality = 75;  // lossless effort, libwebp's default
    config.method = 4;
    pic.use_argb = 1;
    pic.width = image.width, pic.height = image.height;
    WebPMemoryWriter writer;
    WebPMemoryWriterInit(&writer);
    pic.writer = WebPMemoryWrite;
    pic.custom_ptr = &writer;
    const bool ok = WebPPictureImportRGBA(&pic, image.rgba.data(), image.width * 4) && WebPEncode(&config, &pic);
    const int error = pic.error_code;
    WebPPictureFree(&pic);
    std::vector<uint8_t> out(writer.mem, writer.mem + (ok ? writer.size : 0));
    WebPMemoryWriterClear(&writer);
    if (!ok) throw std::runtime_error("libwebp: encoding failed (error " + std::to_string(error) + ")");
    return out;
}

}  // namespace pg::data
