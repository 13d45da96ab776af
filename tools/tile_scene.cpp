// tile_scene IN.ply OUT.ply --count N [--sh 3] [--up y]: a real-size benchmark scene from a
// small capture: copies of IN side by side on a ground grid (the two axes other than up) until N Gaussians,
// SH raised to the requested degree (the new coefficients are small and deterministic, so
// the colour stays IN's, yet every frame evaluates and every binding holds full SH).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>

#include <CLI/CLI.hpp>

#include "dataset/formats/scene_io.h"

using namespace pg;

namespace {
// Deterministic value in [-1, 1) from an index (splitmix64).
float hashed(uint64_t x) {
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    x ^= x >> 31;
    return float(x >> 40) / float(1ull << 23) - 1.0f;
}
}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Tile a scene into a real-size benchmark scene"};
    std::string in, out;
    size_t count = 0;
    int sh = 3;
    std::string up = "y";
    app.add_option("in", in, "Input scene")->required();
    app.add_option("out", out, "Output PLY (never the input)")->required();
    app.add_option("--count", count, "Gaussians in the output")->required()->check(CLI::Range(size_t(1), size_t(500000000)));
    app.add_option("--sh", sh, "SH degree of the output (0-3)")->check(CLI::Range(0, 3));
    app.add_option("--up", up, "The scene's up axis; copies are laid out over the other two")
        ->check(CLI::IsMember({"x", "y", "z"}));
    CLI11_PARSE(app, argc, argv);
    try {
        if (std::filesystem::weakly_canonical(in) == std::filesystem::weakly_canonical(out))
            throw std::runtime_error(out + ": would overwrite the input");
        const data::GaussianCloud src = data::load_scene(in);
        if (src.size() == 0) throw std::runtime_error(in + ": the scene is empty");
        glm::vec3 lo(1e30f), hi(-1e30f);
        for (auto& m : src.mean) lo = glm::min(lo, m), hi = glm::max(hi, m);
        const glm::vec3 extent = (hi - lo) * 1.05f;
        const int u = up[0] - 'x', a = (u + 1) % 3, b = (u + 2) % 3;
        const size_t copies = (count + src.size() - 1) / src.size();
        const size_t side = size_t(std::ceil(std::sqrt(double(copies))));

        data::GaussianCloud dst;
        dst.sh_degree = sh;
        dst.format = src.format;
        dst.flat = src.flat;
        dst.resize(count);
        const int src_coeffs = src.coeffs(), dst_coeffs = dst.coeffs();
        for (size_t i = 0; i < count; ++i) {
            const size_t c = i / src.size(), j = i % src.size();
            glm::vec3 offset(0.0f);
            offset[a] = float(c % side) * extent[a];
            offset[b] = float(c / side) * extent[b];
            dst.mean[i] = src.mean[j] + offset;
            dst.log_scale[i] = src.log_scale[j];
            dst.rotation[i] = src.rotation[j];
            dst.opacity_logit[i] = src.opacity_logit[j];
            for (int k = 0; k < dst_coeffs; ++k)
                for (int ch = 0; ch < 3; ++ch)
                    dst.sh[(i * dst_coeffs + k) * 3 + ch] =
                        k < src_coeffs ? src.sh[(j * src_coeffs + k) * 3 + ch] : 0.05f * hashed(i * 48 + k * 3 + ch);
        }
        data::write_ply(dst, out);
        std::printf("%s: %zu Gaussians (%zu copies of %s on a %zux%zu grid), SH degree %d\n", out.c_str(), count,
                    copies, in.c_str(), side, side, sh);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
    return 0;
}
