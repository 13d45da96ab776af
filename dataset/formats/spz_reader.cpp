// Niantic .spz, versions 2 and 3 (as written by nianticlabs/spz saveSpz): a gzip stream
// holding a 16-byte header
//   uint32 magic 0x5053474e ("NGSP"), uint32 version, uint32 numPoints,
//   uint8 shDegree, uint8 fractionalBits, uint8 flags (1 = antialiased), uint8 reserved,
// then attribute arrays, one after another:
//   positions  3 x 24-bit signed fixed point (value / 2^fractionalBits), little-endian
//   alphas     uint8, sigmoid(opacity) * 255
//   colours    3 x uint8, f_dc * 0.15 * 255 + 127.5 (spz's own scale, not kShC0)
//   scales     3 x uint8, (log_scale + 10) * 16
//   rotations  v2: 3 x uint8 (x, y, z) * 127.5 + 127.5 with w >= 0 derived;
//              v3: uint32 "smallest three": 2 bits index of the largest of (x, y, z, w),
//              then per other component, from the last, 9 bits magnitude / sqrt2 and a sign bit
//   sh         per point, per coefficient (degree 1 first), r g b as uint8 (v - 128) / 128.
// Coordinates are kept as stored. spz's ply_to_spz converts nothing (its coordinate
// systems default to UNSPECIFIED), so a file made from an INRIA PLY holds the PLY's frame.
// Version 1 (float16 positions), version 4 (ZSTD container) and files with extensions
// (flag 2) are rejected with a clear message.
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "dataset/atomic_file.h"
#include "dataset/error.h"
#include "dataset/formats/scene_io.h"

namespace pg::data {

namespace {

constexpr uint32_t kSpzMagic = 0x5053474e;
constexpr size_t kSpzHeaderBytes = 16;
constexpr uint8_t kFlagHasExtensions = 0x2;
constexpr float kSpzColorScale = 0.15f;
// Bytes of decompressed data tolerated after the arrays the header accounts for.
constexpr size_t kTrailingSlack = 64 * 1024;

struct SpzHeader {
    uint32_t magic = 0, version = 0, num_points = 0;
    uint8_t sh_degree = 0, fractional_bits = 0, flags = 0, reserved = 0;
};

uint32_t read_u32(const uint8_t* p) {
    return static_cast<uint32_t>(p[0]) | static_cast<uint32_t>(p[1]) << 8 | static_cast<uint32_t>(p[2]) << 16 |
           static_cast<uint32_t>(p[3]) << 24;
}

SpzHeader parse_header(const uint8_t* p) {
    SpzHeader h;
    h.magic = read_u32(p);
    h.version = read_u32(p + 4);
    h.num_points = read_u32(p + 8);
    h.sh_degree = p[12];
    h.fractional_bits = p[13];
    h.flags = p[14];
    h.reserved = p[15];
    return h;
}

void check_header(const SpzHeader& h, const std::string& where) {
    if (h.magic != kSpzMagic) throw InputError(where, "not an .spz file (bad magic in the decompressed header)");
    if (h.version == 1) throw InputError(where, "spz version 1 (float16 positions) is not supported");
    if (h.version != 2 && h.version != 3)
        throw InputError(where, "unsupported spz version " + std::to_string(h.version) + " (expected 2 or 3)");
    if (h.sh_degree > kMaxShDegree)
        throw InputError(where, "spz SH degree " + std::to_string(h.sh_degree) + " is not supported (at most 3)");
    if (h.flags & kFlagHasExtensions) throw InputError(where, "spz extensions (flag 2) are not supported");
}

uint64_t payload_bytes(const SpzHeader& h) {
    const uint64_t rest = 3u * static_cast<uint64_t>(sh_coeffs(h.sh_degree) - 1);
    const uint64_t per_point = 9 + 1 + 3 + 3 + (h.version >= 3 ? 4 : 3) + rest;
    return per_point * h.num_points;
}

// Inflates a gzip stream, but never more than the header's point count accounts for (plus
// a little slack): a forged count or a zip bomb ends in an error, not in a huge buffer.
std::vector<uint8_t> inflate_spz(const std::vector<char>& in, const std::string& where, SpzHeader& header) {
    z_stream zs{};
    if (inflateInit2(&zs, 16 + MAX_WBITS) != Z_OK) throw InputError(where, "cannot initialise zlib");
    struct End {
        z_stream* z;
        ~End() { inflateEnd(z); }
    } end{&zs};
    if (in.size() > 0x7fffffff) throw InputError(where, "file larger than 2 GiB");
    zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(in.data()));
    zs.avail_in = static_cast<uInt>(in.size());

    std::vector<uint8_t> out;
    uint64_t limit = kSpzHeaderBytes;  // until the header is known
    bool have_header = false, done = false;
    auto read_header = [&]() {
        if (have_header || out.size() < kSpzHeaderBytes) return;
        header = parse_header(out.data());
        check_header(header, where);
        const uint64_t expected = kSpzHeaderBytes + payload_bytes(header);
        // Deflate cannot expand data more than ~1032:1.
        if (expected > static_cast<uint64_t>(in.size()) * 1032 + 4096)
            throw InputError(where, "header claims " + std::to_string(header.num_points) + " points, more than " +
                                        std::to_string(in.size()) + " compressed bytes can hold");
        limit = expected + kTrailingSlack;
        have_header = true;
    };
    while (!done) {
        read_header();
        const size_t have = out.size();
        if (have > limit)
            throw InputError(where, "decompressed data is larger than the " + std::to_string(header.num_points) +
                                        " points of the header account for");
        const size_t room = static_cast<size_t>(std::min<uint64_t>(limit - have + 1, 1u << 20));
        out.resize(have + room);
        zs.next_out = out.data() + have;
        zs.avail_out = static_cast<uInt>(room);
        const int rc = inflate(&zs, Z_NO_FLUSH);
        out.resize(have + (room - zs.avail_out));
        if (rc == Z_STREAM_END) {
            done = true;
        } else if (rc == Z_BUF_ERROR || (rc == Z_OK && zs.avail_in == 0 && zs.avail_out != 0)) {
            throw InputError(where, "truncated gzip stream (the data ends before the end of the compressed stream)");
        } else if (rc != Z_OK) {
            throw InputError(where, std::string("corrupt gzip data: ") + (zs.msg ? zs.msg : "inflate failed"));
        }
    }
    read_header();
    if (have_header && out.size() > limit)
        throw InputError(where, "decompressed data is larger than the " + std::to_string(header.num_points) +
                                    " points of the header account for");
    if (!have_header) throw InputError(where, "decompressed data is shorter than the 16-byte spz header");
    const uint64_t expected = kSpzHeaderBytes + payload_bytes(header);
    if (out.size() < expected)
        throw InputError(where, "decompressed data holds " + std::to_string(out.size()) + " bytes but " +
                                    std::to_string(header.num_points) + " points need " + std::to_string(expected) +
                                    " (truncated?)");
    return out;
}

}  // namespace

GaussianCloud read_spz(const std::filesystem::path& path) {
    const std::string where = path.string();
    const std::vector<char> bytes = read_file(path);
    if (bytes.empty()) throw InputError(where, "empty file");
    const auto* raw = reinterpret_cast<const uint8_t*>(bytes.data());
    if (bytes.size() >= 8 && read_u32(raw) == kSpzMagic)
        throw InputError(where, "uncompressed spz container version " + std::to_string(read_u32(raw + 4)) +
                                    " is not supported (only gzip-compressed versions 2 and 3)");
    if (bytes.size() < 2 || raw[0] != 0x1f || raw[1] != 0x8b)
        throw InputError(where, "not a gzip-compressed .spz file (bad magic)");

    SpzHeader h;
    const std::vector<uint8_t> data = inflate_spz(bytes, where, h);
    const size_t n = h.num_points;

    GaussianCloud cloud;
    cloud.sh_degree = h.sh_degree;
    cloud.resize(n);
    cloud.format = SceneFormat::Spz;
    const size_t coeffs = static_cast<size_t>(cloud.coeffs());
    const uint8_t* positions = data.data() + kSpzHeaderBytes;
    const uint8_t* alphas = positions + n * 9;
    const uint8_t* colors = alphas + n;
    const uint8_t* scales = colors + n * 3;
    const uint8_t* rotations = scales + n * 3;
    const size_t rotation_bytes = h.version >= 3 ? 4 : 3;
    const uint8_t* sh = rotations + n * rotation_bytes;
    const size_t rest = 3 * (coeffs - 1);

    for (size_t i = 0; i < n; ++i) {
        for (int k = 0; k < 3; ++k) {
            const uint8_t* p = positions + i * 9 + k * 3;
            int32_t fixed = static_cast<int32_t>(p[0] | p[1] << 8 | p[2] << 16);
            if (fixed & 0x800000) fixed -= 0x1000000;  // sign-extend 24 bits
            cloud.mean[i][k] = std::ldexp(static_cast<float>(fixed), -static_cast<int>(h.fractional_bits));
            cloud.log_scale[i][k] = scales[i * 3 + k] / 16.0f - 10.0f;
            cloud.sh[i * coeffs * 3 + k] = (colors[i * 3 + k] / 255.0f - 0.5f) / kSpzColorScale;
        }
        cloud.opacity_logit[i] = logit_from_opacity(alphas[i] / 255.0f);

        float xyzw[4];
        if (h.version >= 3) {
            uint32_t comp = read_u32(rotations + i * 4);
            const uint32_t largest = comp >> 30;
            constexpr uint32_t kMask = (1u << 9) - 1;
            float sum = 0.0f;
            for (int k = 3; k >= 0; --k) {
                if (static_cast<uint32_t>(k) == largest) continue;
                const uint32_t mag = comp & kMask, negative = (comp >> 9) & 1u;
                comp >>= 10;
                float v = 0.70710678f * static_cast<float>(mag) / static_cast<float>(kMask);
                xyzw[k] = negative ? -v : v;
                sum += v * v;
            }
            xyzw[largest] = std::sqrt(std::max(0.0f, 1.0f - sum));
        } else {
            const uint8_t* r = rotations + i * 3;
            float sum = 0.0f;
            for (int k = 0; k < 3; ++k) {
                xyzw[k] = r[k] / 127.5f - 1.0f;
                sum += xyzw[k] * xyzw[k];
            }
            xyzw[3] = std::sqrt(std::max(0.0f, 1.0f - sum));
        }
        cloud.rotation[i] = glm::vec4(xyzw[3], xyzw[0], xyzw[1], xyzw[2]);  // (w, x, y, z)

        // spz: coefficient-major, then channel — the same as GaussianCloud::sh after the DC.
        const uint8_t* s = sh + i * rest;
        float* dst = &cloud.sh[(i * coeffs + 1) * 3];
        for (size_t j = 0; j < rest; ++j) dst[j] = (static_cast<float>(s[j]) - 128.0f) / 128.0f;
    }
    if (h.flags & 0x1) cloud.ply_comments.push_back("spz: antialiased");
    validate_cloud(cloud, where);
    return cloud;
}

}  // namespace pg::data
