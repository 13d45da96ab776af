#include "nn/ptv3/config.h"

#include <stdexcept>

#include <nlohmann/json.hpp>

namespace pg::nn {

Ptv3Config Ptv3Config::paper() {
    Ptv3Config c;
    c.enc_depths = {2, 2, 2, 6, 2};
    c.enc_channels = {32, 64, 128, 256, 512};
    c.enc_num_head = {2, 4, 8, 16, 32};
    c.enc_patch_size = {1024, 1024, 1024, 1024, 1024};
    c.dec_depths = {2, 2, 2, 2};
    c.dec_channels = {64, 64, 128, 256};
    c.dec_num_head = {4, 4, 8, 16};
    c.dec_patch_size = {1024, 1024, 1024, 1024};
    return c;
}

Ptv3Config Ptv3Config::small() {
    Ptv3Config c;
    c.enc_depths = {1, 1, 1, 2, 1};
    c.enc_channels = {16, 32, 64, 128, 256};
    c.enc_num_head = {1, 2, 4, 8, 16};
    c.enc_patch_size = {128, 128, 128, 128, 128};
    c.dec_depths = {1, 1, 1, 1};
    c.dec_channels = {32, 32, 64, 128};
    c.dec_num_head = {2, 2, 4, 8};
    c.dec_patch_size = {128, 128, 128, 128};
    return c;
}

Ptv3Config Ptv3Config::tiny() {
    Ptv3Config c;
    c.enc_depths = {1, 1, 1, 2, 1};
    c.enc_channels = {8, 16, 16, 32, 32};
    c.enc_num_head = {1, 2, 2, 4, 4};
    c.enc_patch_size = {48, 48, 48, 48, 48};
    c.dec_depths = {2, 1, 1, 1};
    c.dec_channels = {16, 16, 16, 32};
    c.dec_num_head = {2, 2, 2, 4};
    c.dec_patch_size = {48, 48, 48, 48};
    return c;
}

Ptv3Config Ptv3Config::named(const std::string& name) {
    if (name == "paper") return paper();
    if (name == "small") return small();
    if (name == "tiny") return tiny();
    throw std::invalid_argument("PTv3 config: no config named '" + name + "' (paper, small, tiny)");
}

namespace {
template <class T> void read(const nlohmann::json& j, const char* key, T& out, bool required) {
    if (!j.contains(key)) {
        if (required) throw std::invalid_argument(std::string("PTv3 config: missing '") + key + "'");
        return;
    }
    try {
        if (!j[key].is_null()) out = j[key].get<T>();
    } catch (const std::exception&) {
        throw std::invalid_argument(std::string("PTv3 config: '") + key + "' has the wrong type");
    }
}
void require_value(const nlohmann::json& j, const char* key, bool expected) {
    if (j.contains(key) && j[key].is_boolean() && j[key].get<bool>() != expected)
        throw std::invalid_argument(std::string("PTv3 config: ") + key + "=" + (expected ? "false" : "true") +
                                    " is not supported");
}
}  // namespace

Ptv3Config Ptv3Config::from_json(const nlohmann::json& j) {
    if (!j.is_object()) throw std::invalid_argument("PTv3 config: not a JSON object");
    Ptv3Config c;
    read(j, "in_channels", c.in_channels, true);
    read(j, "num_classes", c.num_classes, true);
    read(j, "order", c.order, false);
    read(j, "stride", c.stride, false);
    read(j, "enc_depths", c.enc_depths, true);
    read(j, "enc_channels", c.enc_channels, true);
    read(j, "enc_num_head", c.enc_num_head, true);
    read(j, "enc_patch_size", c.enc_patch_size, true);
    read(j, "dec_depths", c.dec_depths, true);
    read(j, "dec_channels", c.dec_channels, true);
    read(j, "dec_num_head", c.dec_num_head, true);
    read(j, "dec_patch_size", c.dec_patch_size, true);
    read(j, "mlp_ratio", c.mlp_ratio, false);
    read(j, "qkv_bias", c.qkv_bias, false);
    read(j, "qk_scale", c.qk_scale, false);
    read(j, "grid_size", c.grid_size, false);
    read(j, "input_frame", c.input_frame, false);
    read(j, "tile_size", c.tile_size, false);
    read(j, "features", c.features, false);
    read(j, "scale_spacing", c.scale_spacing, false);
    read(j, "class_names", c.class_names, false);
    require_value(j, "cls_mode", false);
    require_value(j, "enable_rpe", false);
    require_value(j, "pre_norm", true);
    require_value(j, "pdnorm_bn", false);
    require_value(j, "pdnorm_ln", false);
    c.validate();
    return c;
}

nlohmann::json Ptv3Config::to_json() const {
    nlohmann::json j = {{"in_channels", in_channels},       {"num_classes", num_classes},   {"order", order},
            {"stride", stride},                 {"enc_depths", enc_depths},     {"enc_channels", enc_channels},
            {"enc_num_head", enc_num_head},     {"enc_patch_size", enc_patch_size},
            {"dec_depths", dec_depths},         {"dec_channels", dec_channels}, {"dec_num_head", dec_num_head},
            {"dec_patch_size", dec_patch_size}, {"mlp_ratio", mlp_ratio},       {"qkv_bias", qkv_bias},
            {"qk_scale", qk_scale == 0 ? nlohmann::json(nullptr) : nlohmann::json(qk_scale)},
            {"grid_size", grid_size},           {"cls_mode", false},            {"enable_rpe", false},
            {"pre_norm", true},                 {"input_frame", input_frame}};
    if (tile_size > 0) j["tile_size"] = tile_size;
    if (!features.empty()) j["features"] = features;
    if (scale_spacing != 0) j["scale_spacing"] = scale_spacing;
    if (!class_names.empty()) j["class_names"] = class_names;
    return j;
}

void Ptv3Config::validate() const {
    auto fail = [](const std::string& m) { throw std::invalid_argument("PTv3 config: " + m); };
    const size_t s = enc_channels.size();
    if (s < 1) fail("enc_channels is empty");
    if (enc_depths.size() != s || enc_num_head.size() != s || enc_patch_size.size() != s)
        fail("enc_depths, enc_channels, enc_num_head and enc_patch_size differ in length");
    if (stride.size() != s - 1) fail("stride needs one entry per pooling (" + std::to_string(s - 1) + ")");
    if (dec_depths.size() != s - 1 || dec_channels.size() != s - 1 || dec_num_head.size() != s - 1 ||
        dec_patch_size.size() != s - 1)
        fail("decoder lists need " + std::to_string(s - 1) + " entries");
    if (input_frame != "world" && input_frame != "roi" && input_frame != "tile")
        fail("input_frame must be 'world', 'roi' or 'tile'");
    if (semantic() && !(tile_size > 0)) fail("a 'tile' frame needs tile_size > 0");
    if (semantic() && features.empty()) fail("a 'tile' frame needs its feature groups");
    if (!class_names.empty() && int(class_names.size()) != num_classes)
        fail("class_names has " + std::to_string(class_names.size()) + " names for " + std::to_string(num_classes) +
             " classes");
    if (order.empty() || order.size() > 4) fail("order needs 1 to 4 entries");
    for (auto& o : order)
        if (o != "z" && o != "z-trans" && o != "hilbert" && o != "hilbert-trans") fail("unknown order '" + o + "'");
    for (int st : stride)
        if (st != 2 && st != 4 && st != 8) fail("stride must be 2, 4 or 8");
    auto heads_ok = [&](const std::vector<int>& ch, const std::vector<int>& h, const char* what) {
        for (size_t i = 0; i < ch.size(); ++i)
            if (ch[i] <= 0 || h[i] <= 0 || ch[i] % h[i]) fail(std::string(what) + ": channels not divisible by heads");
    };
    heads_ok(enc_channels, enc_num_head, "encoder");
    heads_ok(dec_channels, dec_num_head, "decoder");
    for (int p : enc_patch_size)
        if (p <= 0) fail("patch sizes must be positive");
    for (int p : dec_patch_size)
        if (p <= 0) fail("patch sizes must be positive");
    if (in_channels <= 0 || num_classes <= 0 || mlp_ratio <= 0) fail("in_channels, num_classes, mlp_ratio must be > 0");
    if (!(grid_size > 0)) fail("grid_size must be > 0");
}

long long Ptv3Config::parameter_count() const {
    auto block = [&](long long c) {
        long long hidden = c * mlp_ratio;
        return (27 * c * c + c) + (c * c + c) + 2 * c  // cpe: conv, linear, LN
               + 2 * c + (3 * c * c + (qkv_bias ? 3 * c : 0)) + (c * c + c)  // norm1, qkv, proj
               + 2 * c + (hidden * c + hidden) + (c * hidden + c);  // norm2, mlp
    };
    long long n = 125LL * in_channels * enc_channels[0] + 2 * enc_channels[0];  // stem conv + BN affine
    for (int s = 0; s < stages(); ++s) {
        if (s > 0) n += (long long)enc_channels[s - 1] * enc_channels[s] + enc_channels[s] + 2 * enc_channels[s];
        n += enc_depths[s] * block(enc_channels[s]);
    }
    for (int s = stages() - 2; s >= 0; --s) {
        long long in = s + 1 == stages() - 1 ? enc_channels.back() : dec_channels[s + 1];
        long long out = dec_channels[s];
        n += in * out + out + 2 * out + (long long)enc_channels[s] * out + out + 2 * out;
        n += dec_depths[s] * block(out);
    }
    n += (long long)dec_channels[0] * num_classes + num_classes;
    return n;
}

}  // namespace pg::nn
