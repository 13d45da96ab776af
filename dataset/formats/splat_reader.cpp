// antimatter15 .splat: no header, 32 bytes per Gaussian, little-endian:
//   float position[3], float scale[3] (linear, not log),
//   uint8 rgba[4] (rgb = 0.5 + kShC0 * f_dc, a = sigmoid(opacity)),
//   uint8 rotation[4] (w, x, y, z, each round(q * 128 + 128) clamped to 0..255).
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "dataset/atomic_file.h"
#include "dataset/error.h"
#include "dataset/formats/scene_io.h"

namespace pg::data {

namespace {

constexpr size_t kSplatBytes = 32;

float read_f32(const unsigned char* p) {
    uint32_t bits = static_cast<uint32_t>(p[0]) | static_cast<uint32_t>(p[1]) << 8 |
                    static_cast<uint32_t>(p[2]) << 16 | static_cast<uint32_t>(p[3]) << 24;
    return std::bit_cast<float>(bits);
}

}  // namespace

GaussianCloud read_splat(const std::filesystem::path& path) {
    const std::string where = path.string();
    const std::vector<char> bytes = read_file(path);
    if (bytes.empty()) throw InputError(where, "empty file");
    if (bytes.size() % kSplatBytes != 0)
        throw InputError(where, ".splat size " + std::to_string(bytes.size()) + " bytes is not a multiple of " +
                                    std::to_string(kSplatBytes) + " (32 bytes per Gaussian)");
    const size_t n = bytes.size() / kSplatBytes;

    GaussianCloud cloud;
    cloud.resize(n);
    cloud.format = SceneFormat::Splat;
    const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
    for (size_t i = 0; i < n; ++i) {
        const unsigned char* s = data + i * kSplatBytes;
        for (int k = 0; k < 3; ++k) cloud.mean[i][k] = read_f32(s + 4 * k);
        for (int k = 0; k < 3; ++k) {
            const float scale = read_f32(s + 12 + 4 * k);
            if (!(scale >= 0.0f) || !std::isfinite(scale)) {
                char value[32];
                std::snprintf(value, sizeof value, "%g", scale);
                throw InputError(where, "vertex " + std::to_string(i) + ": property 'scale_" + std::to_string(k) +
                                            "' is " + value + " (a .splat scale must be finite and not negative)");
            }
            // A zero scale (a flat splat) gets the 2DGS flat log-scale rather than -inf.
            cloud.log_scale[i][k] = scale > 0.0f ? std::log(scale) : kFlatLogScale;
        }
        for (int k = 0; k < 3; ++k) cloud.sh[i * 3 + k] = (s[24 + k] / 255.0f - 0.5f) / kShC0;
        cloud.opacity_logit[i] = logit_from_opacity(s[27] / 255.0f);
        for (int k = 0; k < 4; ++k) cloud.rotation[i][k] = (static_cast<float>(s[28 + k]) - 128.0f) / 128.0f;
    }
    validate_cloud(cloud, where);
    return cloud;
}

}  // namespace pg::data
