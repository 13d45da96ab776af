// pointgauss bench gemm: GPU ms and GFLOP/s of the dense GEMMs (nn.Linear) and sparse convolutions a
// PTv3 forward is made of, one shape at a time, as medians over repeated runs. Where the kernels
// stand against the machine's peak is what issue 17 asks; a whole forward (bench ptv3) mixes
// them with everything else.
#include <algorithm>
#include <cstdio>
#include <random>
#include <sstream>

#include <nlohmann/json.hpp>

#include "app/cli/commands.h"
#include "app/common/progress.h"
#include "dataset/error.h"
#include "engine/vk/context.h"
#include "nn/ops/linear.h"
#include "nn/ops/sparse_conv.h"

namespace pg::app {

namespace {

struct Shape {
    int64_t M, K, N, taps;  // taps 1: a dense linear; else a sparse conv of K input channels per tap
};

// The paper config's linears and convs at the levels of an 8192-point crop (levels 8192, 3880,
// 1089, 266, 61; channels 32 ... 512): attention's qkv, the MLP's two, and the blocks' convs.
const char* kDefaultShapes = "8192x32x96,8192x32x128,8192x128x32,3880x64x256,3880x256x64,1089x128x512,1089x512x128,"
                             "266x256x1024,8192x32x32x27,3880x64x64x27,1089x128x128x27";

std::vector<Shape> parse_shapes(const std::string& text) {
    std::vector<Shape> shapes;
    std::stringstream list(text);
    std::string item;
    while (std::getline(list, item, ',')) {
        std::vector<int64_t> v;
        std::stringstream parts(item);
        std::string p;
        while (std::getline(parts, p, 'x')) {
            size_t used = 0;
            long long n = 0;
            try {
                n = std::stoll(p, &used);
            } catch (const std::exception&) {
                used = 0;
            }
            if (used == 0 || used != p.size() || n < 1)
                throw data::InputError("--shapes", "'" + item + "': sizes must be positive integers");
            v.push_back(n);
        }
        if (v.size() != 3 && v.size() != 4)
            throw data::InputError("--shapes", "'" + item + "' must be MxKxN or MxKxNxTAPS");
        const Shape s{v[0], v[1], v[2], v.size() == 4 ? v[3] : 1};
        if (s.M * s.K * s.taps > (int64_t(1) << 31) || s.N * s.K * s.taps > (int64_t(1) << 31) || s.M * s.N > (int64_t(1) << 31))
            throw data::InputError("--shapes", "'" + item + "' is too large");
        shapes.push_back(s);
    }
    if (shapes.empty()) throw data::InputError("--shapes", "no shape given");
    return shapes;
}

struct BenchGemmArgs {
    std::string shapes = kDefaultShapes;
    int repeats = 5, warmup = 1;
    bool json = false;
    DeviceOptions device;
};

void run_bench_gemm(const BenchGemmArgs& a) {
    if (a.repeats < 1) throw data::InputError("--repeats", "must be at least 1");
    if (a.warmup < 0) throw data::InputError("--warmup", "must not be negative");
    const auto shapes = parse_shapes(a.shapes);
    vk::ContextOptions co;
    co.device = a.device.device;
    co.quiet = a.json;
    vk::Context ctx(co);
    auto pool = nn::Pool::create(ctx);
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> uni(-1.0f, 1.0f);
    auto random = [&](size_t n) {
        std::vector<float> v(n);
        for (float& f : v) f = uni(rng);
        return v;
    };

    nlohmann::json rows = nlohmann::json::array();
    if (!a.json)
        std::printf("device: %s, medians of %d runs\n\n| shape | kind | GPU ms | GFLOP/s |\n|---|---|---:|---:|\n",
                    ctx.info().name.c_str(), a.repeats);
    Progress progress("bench gemm", shapes.size() * size_t(a.warmup + a.repeats));
    for (const Shape& s : shapes) {
        const bool conv = s.taps > 1;
        nn::Tensor x = nn::upload_tensor(*pool, random(size_t(s.M * s.K)), {s.M, s.K}, nn::DType::F32);
        nn::Tensor w = nn::upload_tensor(*pool, random(size_t(s.N * s.K * s.taps)), {s.N, s.K * s.taps}, nn::DType::F32);
        nn::Tensor b = nn::upload_tensor(*pool, random(size_t(s.N)), {s.N}, nn::DType::F32);
        // A conv's neighbour table: every row has all its taps but one in three (a surface's
        // fill), neighbours drawn from the rows near it as serialized points are.
        nn::Tensor nbr;
        nn::ops::Rulebook rules;
        double pairs = double(s.M);
        if (conv) {
            std::vector<int32_t> table(size_t(s.M * s.taps));
            std::uniform_int_distribution<int64_t> near(-64, 64);
            pairs = 0;
            for (int64_t m = 0; m < s.M; ++m)
                for (int64_t t = 0; t < s.taps; ++t) {
                    const bool centre = t == s.taps / 2;
                    const bool present = centre || (m * 7 + t * 13) % 3 != 0;
                    table[size_t(m * s.taps + t)] =
                        centre ? int32_t(m) : present ? int32_t(std::clamp<int64_t>(m + near(rng), 0, s.M - 1)) : -1;
                    pairs += present ? 1 : 0;
                }
            nbr = nn::upload_tensor(*pool, table, {s.M, s.taps}, nn::DType::I32);
            vk::CommandList cmd(ctx);
            rules = nn::ops::build_rulebook(cmd, *pool, nbr);
            cmd.submit_and_wait();
        }
        std::vector<double> ms;
        for (int r = 0; r < a.warmup + a.repeats; ++r) {
            vk::CommandList cmd(ctx);
            cmd.begin_pass("gemm");
            nn::Tensor y = conv ? nn::ops::sparse_conv(cmd, *pool, x, rules, w, b)
                                : nn::ops::linear(cmd, *pool, x, w, b, nn::Tensor{}, nn::ops::Activation::None);
            cmd.end_pass();
            cmd.submit_and_wait();
            progress.step();
            if (r >= a.warmup) ms.push_back(cmd.total_ms());
        }
        // A conv's work is what its present neighbours multiply, as bench ptv3 counts it.
        const double flop = 2.0 * pairs * double(s.K) * double(s.N);
        const double med = median(ms), gflops = flop * 1e-6 / std::max(med, 1e-9);
        const std::string name = std::to_string(s.M) + "x" + std::to_string(s.K) + "x" + std::to_string(s.N) +
                                 (conv ? "x" + std::to_string(s.taps) : "");
        if (a.json) {
            rows.push_back({{"shape", name}, {"kind", conv ? "sparse_conv" : "linear"}, {"gpu_ms", med},
                            {"gflop", flop * 1e-9}, {"gflops_per_s", gflops}});
        } else {
            std::printf("| %s | %s | %.3f | %.1f |\n", name.c_str(), conv ? "sparse_conv" : "linear", med, gflops);
        }
    }
    progress.finish();
    if (a.json) {
        nlohmann::json j;
        j["device"] = ctx.info().name;
        j["repeats"] = a.repeats;
        j["shapes"] = rows;
        std::printf("%s\n", j.dump(2).c_str());
    }
}

}  // namespace

void register_bench_gemm(CLI::App& bench, std::function<void()>& run) {
    auto a = std::make_shared<BenchGemmArgs>();
    auto* cmd = bench.add_subcommand("gemm", "GPU ms and GFLOP/s of PTv3's linears and sparse convs, shape by shape");
    cmd->add_option("--shapes", a->shapes,
                    "Comma-separated MxKxN (a linear: M rows, K in, N out) or MxKxNxTAPS (a sparse conv of K input "
                    "channels per tap)")
        ->capture_default_str();
    cmd->add_option("--repeats", a->repeats, "Timed runs (medians are reported)")->capture_default_str();
    cmd->add_option("--warmup", a->warmup, "Untimed runs first")->capture_default_str();
    cmd->add_flag("--json", a->json, "Print JSON instead of a table");
    add_device_option(*cmd, a->device);
    cmd->callback([a, &run] { run = [a] { run_bench_gemm(*a); }; });
}

}  // namespace pg::app
