// pointgauss infer: PTv3 logits for a point cloud file, as the release's model computes them.
// IN.bin is coord f32 [N,3] then feat f32 [N,C] (C = the model's in_channels); LOGITS.bin is
// f32 [N, classes] in input order.
#include <cstdio>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "app/cli/commands.h"
#include "app/cli/point_file.h"
#include "dataset/atomic_file.h"
#include "dataset/error.h"
#include "engine/vk/context.h"
#include "nn/ptv3/model.h"
#include "nn/safetensors.h"

namespace pg::app {

namespace {

struct InferArgs {
    std::string model, input, out, perm, offsets;
    DeviceOptions device;
};

// "0,1,2,3/1,0,3,2/..." -> one permutation per level.
std::vector<std::vector<int>> parse_perms(const std::string& s) {
    std::vector<std::vector<int>> perms;
    if (s.empty()) return perms;
    std::stringstream levels(s);
    std::string level;
    while (std::getline(levels, level, '/')) {
        std::vector<int> p;
        std::stringstream items(level);
        std::string item;
        while (std::getline(items, item, ',')) {
            try {
                size_t used = 0;
                p.push_back(std::stoi(item, &used));
                if (used != item.size()) throw std::invalid_argument(item);
            } catch (const std::exception&) {
                throw data::InputError("--perm", "'" + item + "' is not an integer (expected e.g. 0,1,2,3/1,0,3,2/...)");
            }
        }
        perms.push_back(p);
    }
    return perms;
}

std::vector<int64_t> parse_offsets(const std::string& s) {
    std::vector<int64_t> v;
    std::stringstream items(s);
    std::string item;
    while (std::getline(items, item, ',')) {
        try {
            size_t used = 0;
            v.push_back(std::stoll(item, &used));
            if (used != item.size()) throw std::invalid_argument(item);
        } catch (const std::exception&) {
            throw data::InputError("--offsets", "'" + item + "' is not an integer");
        }
    }
    return v;
}

void run_infer(const InferArgs& a) {
    if (std::filesystem::exists(a.out) && std::filesystem::equivalent(a.out, a.input))
        throw data::InputError("--out", "would overwrite the input file");
    // Everything that can be wrong with the input is checked before the device starts.
    nn::Ptv3Config c;
    std::map<std::string, std::vector<float>> values;
    try {
        const auto file = nn::SafeTensors::load(a.model);
        c = nn::Ptv3Weights::config_of(file);
        values = nn::Ptv3Weights::host_values(file);
    } catch (const nn::FormatError& e) {
        throw data::InputError("--model", e.what());
    }
    nn::Ptv3Input in = read_point_file(a.input, c.in_channels);
    const size_t n = in.size();
    in.offsets = parse_offsets(a.offsets);
    in.perms = parse_perms(a.perm);
    try {
        nn::Ptv3::validate(c, in);
    } catch (const std::invalid_argument& e) {
        throw data::InputError(!a.perm.empty() && std::string(e.what()).find("permutation") != std::string::npos
                                   ? "--perm"
                                   : !a.offsets.empty() && std::string(e.what()).find("offset") != std::string::npos
                                         ? "--offsets"
                                         : a.input,
                               e.what());
    }

    vk::ContextOptions co;
    co.device = a.device.device;
    vk::Context ctx(co);
    auto pool = nn::Pool::create(ctx);
    nn::Ptv3 model(*pool, nn::Ptv3Weights::from_host(*pool, c, values, a.model));
    const nn::Ptv3Output out = model.forward(in);
    data::write_atomically(a.out, [&](std::ostream& os) {
        os.write(reinterpret_cast<const char*>(out.logits.data()), std::streamsize(out.logits.size() * sizeof(float)));
    });
    double gpu_ms = 0;
    for (const auto& p : out.passes) gpu_ms += p.ms;
    std::printf("%zu points (%lld voxels), %d classes -> %s (GPU %.1f ms)\n", n, (long long)out.voxels, c.num_classes,
                a.out.c_str(), gpu_ms);
}

}  // namespace

void register_infer(CLI::App& app, std::function<void()>& run) {
    auto a = std::make_shared<InferArgs>();
    auto* cmd = app.add_subcommand("infer", "PTv3 logits for a point cloud (IN.bin: coord f32 [N,3], feat f32 [N,C])");
    cmd->add_option("--model", a->model, "Model file (.safetensors with the config in __metadata__)")->required();
    cmd->add_option("--input", a->input, "Input points: coord f32 [N,3] then feat f32 [N,C], little-endian")->required();
    cmd->add_option("--out", a->out, "Output logits f32 [N, classes] in input order")->required();
    cmd->add_option("--perm", a->perm,
                    "Serialization order permutation per level, as the release's shuffle drew them: "
                    "0,1,2,3/1,0,3,2/... (input, then one per pooling)");
    cmd->add_option("--offsets", a->offsets, "Cloud ends (cumulative counts, Pointcept's offset), e.g. 700,1000");
    add_device_option(*cmd, a->device);
    cmd->callback([a, &run] { run = [a] { run_infer(*a); }; });
}

}  // namespace pg::app
