#include "dataset/gaussian_cloud.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pg::data {

size_t ply_type_size(PlyType t) {
    switch (t) {
        case PlyType::Int8:
        case PlyType::UInt8: return 1;
        case PlyType::Int16:
        case PlyType::UInt16: return 2;
        case PlyType::Int32:
        case PlyType::UInt32:
        case PlyType::Float32: return 4;
        case PlyType::Float64: return 8;
    }
    return 0;
}

const char* ply_type_name(PlyType t) {
    switch (t) {
        case PlyType::Int8: return "char";
        case PlyType::UInt8: return "uchar";
        case PlyType::Int16: return "short";
        case PlyType::UInt16: return "ushort";
        case PlyType::Int32: return "int";
        case PlyType::UInt32: return "uint";
        case PlyType::Float32: return "float";
        case PlyType::Float64: return "double";
    }
    return "?";
}

const char* scene_format_name(SceneFormat f) {
    switch (f) {
        case SceneFormat::InriaPly: return "3DGS PLY (binary)";
        case SceneFormat::InriaPlyAscii: return "3DGS PLY (ascii)";
        case SceneFormat::TwoDgsPly: return "2DGS PLY";
        case SceneFormat::CompressedPly: return "PlayCanvas compressed PLY";
        case SceneFormat::Splat: return "antimatter15 .splat";
        case SceneFormat::Spz: return "Niantic .spz";
        case SceneFormat::Sog: return "PlayCanvas SOG";
        case SceneFormat::Synthetic: return "synthetic";
    }
    return "?";
}

bool is_gaussian_property_name(std::string_view name) {
    static constexpr std::string_view kFixed[] = {"x", "y", "z", "opacity"};
    for (auto f : kFixed)
        if (name == f) return true;
    static constexpr std::string_view kPrefixes[] = {"f_dc_", "f_rest_", "scale_", "rot_"};
    for (auto p : kPrefixes) {
        if (name.size() > p.size() && name.substr(0, p.size()) == p &&
            std::all_of(name.begin() + p.size(), name.end(), [](char c) { return c >= '0' && c <= '9'; }))
            return true;
    }
    return false;
}

void GaussianCloud::resize(size_t n) {
    mean.resize(n, glm::vec3(0.0f));
    log_scale.resize(n, glm::vec3(0.0f, 0.0f, flat ? kFlatLogScale : 0.0f));
    rotation.resize(n, glm::vec4(1.0f, 0.0f, 0.0f, 0.0f));
    opacity_logit.resize(n, 0.0f);
    sh.resize(n * static_cast<size_t>(coeffs()) * 3, 0.0f);
    for (auto& e : extras) e.values.resize(n, 0.0);
}

const ExtraProperty* GaussianCloud::find_extra(const std::string& name) const {
    for (const auto& e : extras)
        if (e.name == name) return &e;
    return nullptr;
}

void GaussianCloud::set_int_property(const std::string& name, const std::vector<int32_t>& values, PlyType type) {
    if (values.size() != size())
        throw std::invalid_argument("set_int_property '" + name + "': " + std::to_string(values.size()) +
                                    " values for " + std::to_string(size()) + " Gaussians");
    if (is_gaussian_property_name(name))
        throw std::invalid_argument("set_int_property '" + name + "': name of a Gaussian attribute");
    if (type == PlyType::Float32 || type == PlyType::Float64)
        throw std::invalid_argument("set_int_property '" + name + "': type must be an integer type");
    ExtraProperty* slot = nullptr;
    for (auto& e : extras)
        if (e.name == name) slot = &e;
    if (!slot) {
        extras.push_back(ExtraProperty{name, type, {}});
        slot = &extras.back();
    }
    slot->type = type;
    slot->values.assign(values.begin(), values.end());
}

std::optional<std::vector<int32_t>> GaussianCloud::int_property(const std::string& name) const {
    const ExtraProperty* e = find_extra(name);
    if (!e) return std::nullopt;
    std::vector<int32_t> out(e->values.size());
    for (size_t i = 0; i < out.size(); ++i) {
        double v = e->values[i];
        // Not an integer column (or out of range, or NaN): no integer view of it.
        if (!(v >= -2147483648.0 && v <= 2147483647.0) || v != std::floor(v)) return std::nullopt;
        out[i] = static_cast<int32_t>(v);
    }
    return out;
}

float opacity_from_logit(float logit) { return 1.0f / (1.0f + std::exp(-logit)); }

float logit_from_opacity(float opacity) {
    constexpr float kMinOpacity = 1e-4f;
    float a = std::clamp(opacity, kMinOpacity, 1.0f - kMinOpacity);
    if (std::isnan(opacity)) a = 0.5f;
    return std::log(a / (1.0f - a));
}

}  // namespace pg::data
