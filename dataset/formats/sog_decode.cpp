// One SOG meta.json and its WebP images into a GaussianCloud, as PlayCanvas's splat-transform
// decodes them (its read-sog / read-sog-v1), in the PLY's own frame:
//   means    means_l / means_u: 16-bit lerp between mins and maxs of sign(x)·ln(|x|+1), per axis
//   quats    RGB: the three smaller components of the unit quaternion (w, x, y, z), each
//            (c·√2 + 1)/2 · 255; alpha 252 + index of the largest, which is positive
//   scales   v2: each byte indexes a 256-entry codebook of log-scales; v1: per-axis min/max lerp
//   sh0      v2: RGB index a codebook of f_dc, alpha is sigmoid(opacity)·255;
//            v1: per-channel min/max lerp, alpha a lerp of the opacity logit
//   shN      labels (16-bit, R + G·256) pick a palette entry; the palette image has 64 entries a
//            row, each `coeffs` pixels wide, whose bytes index a codebook (v1: a scalar min/max)
// Only the first `count` pixels of each image are Gaussians; the rest is padding.
#include <algorithm>
#include <cmath>

#include "dataset/error.h"
#include "dataset/formats/sog_meta.h"
#include "dataset/formats/webp_image.h"

namespace pg::data {

namespace {

// A lossless WebP of a canvas is at most about its raw RGBA bytes; more is refused before it
// is read (a deflated zip entry can claim gigabytes in a few kilobytes).
uint64_t max_image_bytes(size_t max_pixels) { return uint64_t(max_pixels) * 4 + (uint64_t(1) << 20); }
constexpr uint64_t kMaxCount = uint64_t(16383) * 16383;  // WebP's largest canvas
constexpr size_t kPaletteRow = 64;

// Pixels a Gaussian texture may hold beyond `count` (padding) before its canvas counts as a bomb.
size_t max_pixels_for(uint64_t count) { return size_t(std::min<uint64_t>(2 * count + 65536, kMaxCount)); }

int coeffs_of_bands(int bands) { return sh_coeffs(bands) - 1; }

float inv_log_transform(double v) {
    const double e = std::exp(std::abs(v)) - 1.0;
    return float(v < 0 ? -e : e);
}

struct Decoder {
    const MetaFields& meta;
    const SogFiles& files;
    uint64_t count;

    RgbaImage image(const std::string& name, size_t max_pixels, uint64_t min_pixels) const {
        const std::string where = files.where(name);
        RgbaImage img = decode_webp(files.read(name, max_image_bytes(max_pixels)), max_pixels, where);
        if (img.pixels() < min_pixels)
            throw InputError(where, "image is " + std::to_string(img.width) + "x" + std::to_string(img.height) + " (" +
                                        std::to_string(img.pixels()) + " pixels), too small for the meta's count of " +
                                        std::to_string(min_pixels));
        return img;
    }
    RgbaImage gaussian_image(const std::string& name) const { return image(name, max_pixels_for(count), count); }
};

void decode_means(const Decoder& d, GaussianCloud& cloud) {
    const auto files = d.meta.files("means.files", 2);
    const auto mins = d.meta.numbers("means.mins", 3), maxs = d.meta.numbers("means.maxs", 3);
    const RgbaImage lo = d.gaussian_image(files[0]), hi = d.gaussian_image(files[1]);
    if (lo.width != hi.width || lo.height != hi.height)
        throw InputError(d.files.where(files[1]), "is " + std::to_string(hi.width) + "x" + std::to_string(hi.height) +
                                                      ", but " + files[0] + " is " + std::to_string(lo.width) + "x" +
                                                      std::to_string(lo.height));
    for (size_t i = 0; i < d.count; ++i)
        for (int a = 0; a < 3; ++a) {
            const double range = maxs[a] - mins[a] != 0.0 ? maxs[a] - mins[a] : 1.0;
            const unsigned q = unsigned(lo.rgba[i * 4 + a]) | (unsigned(hi.rgba[i * 4 + a]) << 8);
            cloud.mean[i][a] = inv_log_transform(mins[a] + range * (q / 65535.0));
        }
}

void decode_quats(const Decoder& d, GaussianCloud& cloud) {
    const auto file = d.meta.files("quats.files", 1)[0];
    const RgbaImage img = d.gaussian_image(file);
    static constexpr int kOthers[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
    for (size_t i = 0; i < d.count; ++i) {
        const uint8_t* p = &img.rgba[i * 4];
        if (p[3] < 252)
            throw InputError(d.files.where(file), "Gaussian " + std::to_string(i) + ": largest-component mode " +
                                                      std::to_string(p[3]) + " in alpha (must be 252..255)");
        const int largest = p[3] - 252;
        double q[4] = {0, 0, 0, 0}, sum = 0.0;
        for (int k = 0; k < 3; ++k) {
            q[kOthers[largest][k]] = (p[k] / 255.0 * 2.0 - 1.0) / std::sqrt(2.0);
            sum += q[kOthers[largest][k]] * q[kOthers[largest][k]];
        }
        q[largest] = std::sqrt(std::max(0.0, 1.0 - sum));
        for (int k = 0; k < 4; ++k) cloud.rotation[i][k] = float(q[k]);
    }
}

std::vector<double> codebook(const Decoder& d, const std::string& field) { return d.meta.numbers(field, 256); }

void decode_scales(const Decoder& d, int version, GaussianCloud& cloud) {
    const RgbaImage img = d.gaussian_image(d.meta.files("scales.files", 1)[0]);
    if (version == 2) {
        const auto book = codebook(d, "scales.codebook");
        for (size_t i = 0; i < d.count; ++i)
            for (int a = 0; a < 3; ++a) cloud.log_scale[i][a] = float(book[img.rgba[i * 4 + a]]);
        return;
    }
    const auto mins = d.meta.numbers("scales.mins", 3), maxs = d.meta.numbers("scales.maxs", 3);
    for (size_t i = 0; i < d.count; ++i)
        for (int a = 0; a < 3; ++a)
            cloud.log_scale[i][a] = float(mins[a] + (maxs[a] - mins[a]) * (img.rgba[i * 4 + a] / 255.0));
}

void decode_sh0(const Decoder& d, int version, GaussianCloud& cloud) {
    const RgbaImage img = d.gaussian_image(d.meta.files("sh0.files", 1)[0]);
    const size_t stride = size_t(cloud.coeffs()) * 3;
    if (version == 2) {
        const auto book = codebook(d, "sh0.codebook");
        for (size_t i = 0; i < d.count; ++i) {
            for (int c = 0; c < 3; ++c) cloud.sh[i * stride + c] = float(book[img.rgba[i * 4 + c]]);
            const double a = std::clamp(img.rgba[i * 4 + 3] / 255.0, 1e-6, 1.0 - 1e-6);
            cloud.opacity_logit[i] = float(std::log(a / (1.0 - a)));
        }
        return;
    }
    const auto mins = d.meta.numbers("sh0.mins", 4), maxs = d.meta.numbers("sh0.maxs", 4);
    for (size_t i = 0; i < d.count; ++i) {
        for (int c = 0; c < 3; ++c)
            cloud.sh[i * stride + c] = float(mins[c] + (maxs[c] - mins[c]) * (img.rgba[i * 4 + c] / 255.0));
        cloud.opacity_logit[i] = float(mins[3] + (maxs[3] - mins[3]) * (img.rgba[i * 4 + 3] / 255.0));
    }
}

}  // namespace

// The SH degree a meta declares: v2 says `shN.bands`; v1 has no field, so its palette image's
// width (64 entries of 3, 8 or 15 pixels) tells, which needs the image header.
int v1_bands_from_width(int width) {
    switch (width) {
        case 64 * 3: return 1;
        case 64 * 8: return 2;
        case 64 * 15: return 3;
        default: return 0;
    }
}

namespace {

void decode_shn(const Decoder& d, int version, const RgbaImage& palette, GaussianCloud& cloud) {
    const auto files = d.meta.files("shN.files", 2);
    const int coeffs = coeffs_of_bands(cloud.sh_degree);
    const uint64_t entries = version == 2 ? d.meta.count("shN.count", 65536) : uint64_t(palette.height) * kPaletteRow;
    if (palette.width != int(kPaletteRow) * coeffs)
        throw InputError(d.files.where(files[0]), "palette image is " + std::to_string(palette.width) +
                                                      " pixels wide; " + std::to_string(cloud.sh_degree) +
                                                      " SH bands need " + std::to_string(kPaletteRow * coeffs));
    if (uint64_t(palette.height) * kPaletteRow < entries)
        throw InputError(d.files.where(files[0]), "palette image has " + std::to_string(palette.height) +
                                                      " rows, too few for shN.count " + std::to_string(entries));
    std::vector<double> book(256);
    if (version == 2) {
        book = codebook(d, "shN.codebook");
    } else {
        const double lo = d.meta.number("shN.mins"), hi = d.meta.number("shN.maxs");
        for (int b = 0; b < 256; ++b) book[b] = lo + (hi - lo) * (b / 255.0);
    }
    const RgbaImage labels = d.gaussian_image(files[1]);
    const size_t stride = size_t(cloud.coeffs()) * 3;
    for (size_t i = 0; i < d.count; ++i) {
        const unsigned label = unsigned(labels.rgba[i * 4]) | (unsigned(labels.rgba[i * 4 + 1]) << 8);
        if (label >= entries)
            throw InputError(d.files.where(files[1]), "Gaussian " + std::to_string(i) + ": SH label " +
                                                          std::to_string(label) + " is past the palette's " +
                                                          std::to_string(entries) + " entries");
        const size_t row = label / kPaletteRow, col = (label % kPaletteRow) * size_t(coeffs);
        for (int j = 0; j < coeffs; ++j) {
            const uint8_t* px = &palette.rgba[(row * size_t(palette.width) + col + size_t(j)) * 4];
            for (int c = 0; c < 3; ++c) cloud.sh[i * stride + size_t(1 + j) * 3 + c] = float(book[px[c]]);
        }
    }
}

int meta_version(const MetaFields& meta) {
    if (!meta.find("version")) return 1;
    const uint64_t v = meta.count("version", 1000);
    if (v != 2) meta.fail("version", "is " + std::to_string(v) + "; this reader knows SOG v1 (no version) and v2");
    return 2;
}

}  // namespace

void sog_meta_shape(const nlohmann::json& json, const std::string& where, int& version, uint64_t& count,
                    int& sh_degree) {
    const MetaFields meta(json, where);
    version = meta_version(meta);
    if (version == 2) {
        count = meta.count("count", kMaxCount);
        sh_degree = 0;
        if (meta.find("shN")) {
            sh_degree = int(meta.count("shN.bands", 3));
        }
        return;
    }
    const auto* shape = meta.find("means.shape");
    if (!shape || !shape->is_array() || shape->empty())
        meta.fail("means.shape", shape ? "must be an array [count, 3]" : "is missing (a v1 meta needs it)");
    count = meta.count("means.shape.0", kMaxCount);
    sh_degree = -1;  // v1: known once the palette image's header is read
}

GaussianCloud decode_sog(const nlohmann::json& json, const SogFiles& files, const std::string& where,
                         const std::function<void(double)>& progress) {
    const MetaFields meta(json, where);
    int version = 0, sh_degree = 0;
    uint64_t count = 0;
    sog_meta_shape(json, where, version, count, sh_degree);
    if (count == 0) meta.fail(version == 2 ? "count" : "means.shape", "is 0: the scene holds no Gaussians");
    const Decoder d{meta, files, count};
    // Every named file is checked before any is read, so an unsafe name is the error reported.
    for (const auto& [group, n] : {std::pair<const char*, size_t>{"means", 2}, {"quats", 1}, {"scales", 1}, {"sh0", 1}})
        meta.files(std::string(group) + ".files", n);
    if (meta.find("shN")) meta.files("shN.files", 2);

    RgbaImage palette;
    if (meta.find("shN") && (version == 1 || sh_degree > 0)) {
        const auto shn = meta.files("shN.files", 2);
        // 65536 entries of at most 15 pixels: the palette's largest legitimate size.
        palette = d.image(shn[0], 65536 * 15, 1);
        if (version == 1) {
            sh_degree = v1_bands_from_width(palette.width);
            if (sh_degree == 0)
                throw InputError(files.where(shn[0]), "palette image is " + std::to_string(palette.width) +
                                                          " pixels wide; a v1 palette is 192, 512 or 960 (1-3 SH bands)");
        }
    }
    if (sh_degree < 0) sh_degree = 0;

    // The count sizes the cloud: before allocating, an image's header must hold it (a tiny file
    // claiming 2^28 Gaussians is refused here, not by running out of memory).
    {
        const std::string first = meta.files("means.files", 2)[0];
        const size_t pixels = webp_pixels(files.read(first, max_image_bytes(max_pixels_for(count))), files.where(first));
        if (pixels < count)
            throw InputError(files.where(first), "image holds " + std::to_string(pixels) +
                                                     " pixels, too small for the meta's count of " + std::to_string(count));
    }
    GaussianCloud cloud;
    cloud.sh_degree = sh_degree;
    cloud.resize(count);
    cloud.format = SceneFormat::Sog;
    const int passes = 4 + (sh_degree > 0 ? 1 : 0);
    int done = 0;
    auto step = [&] {
        if (progress) progress(double(++done) / passes);
    };
    decode_means(d, cloud), step();
    decode_quats(d, cloud), step();
    decode_scales(d, version, cloud), step();
    decode_sh0(d, version, cloud), step();
    if (sh_degree > 0) decode_shn(d, version, palette, cloud), step();
    return cloud;
}

}  // namespace pg::data
