#pragma once
// The in-memory 3DGS scene: a structure of arrays, one entry per Gaussian, in the units
// the optimiser trains (log-scale, opacity logit, SH coefficients with DC first).
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

namespace pg::data {

// PLY scalar types, in the spelling of the PLY spec.
enum class PlyType : uint8_t { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };
size_t ply_type_size(PlyType t);
const char* ply_type_name(PlyType t);  // "char", "uchar", ... "float", "double"

// A per-Gaussian property the loader does not interpret (normals, labels, anything a tool
// added). Values are held as double, which represents every PLY scalar type exactly, so
// writing them back in their own type is lossless.
struct ExtraProperty {
    std::string name;
    PlyType type = PlyType::Float32;
    std::vector<double> values;  // size == GaussianCloud::size()
};

// True for the names the loader interprets (x, y, z, f_dc_N, f_rest_N, opacity, scale_N,
// rot_N); set_int_property refuses them.
bool is_gaussian_property_name(std::string_view name);

enum class SceneFormat { InriaPly, InriaPlyAscii, TwoDgsPly, CompressedPly, Splat, Spz, Sog, Synthetic };
const char* scene_format_name(SceneFormat f);

constexpr int kMaxShDegree = 3;
constexpr int sh_coeffs(int degree) { return (degree + 1) * (degree + 1); }
// log-scale given to the missing third axis of a 2DGS surfel: flat, yet finite for the GPU.
constexpr float kFlatLogScale = -20.0f;

struct GaussianCloud {
    std::vector<glm::vec3> mean;
    std::vector<glm::vec3> log_scale;      // natural log of the standard deviations
    std::vector<glm::vec4> rotation;       // quaternion (w, x, y, z) as rot_0..rot_3, not normalised
    std::vector<float> opacity_logit;      // sigmoid gives opacity
    // SH coefficients, Gaussian-major then coefficient then channel:
    // sh[(i * sh_coeffs(sh_degree) + k) * 3 + c]. k = 0 is the DC term (f_dc_c);
    // k >= 1 is f_rest_{c * (sh_coeffs - 1) + k - 1} in the INRIA layout.
    std::vector<float> sh;
    int sh_degree = 0;
    bool flat = false;                     // 2DGS surfels: two scales, the third is kFlatLogScale
    std::vector<ExtraProperty> extras;     // kept and written back in their original order

    // Where the cloud came from; the writer reproduces an INRIA file's property order.
    SceneFormat format = SceneFormat::Synthetic;
    std::vector<std::string> ply_property_order;  // names as read, empty if not from a PLY
    std::vector<std::string> ply_comments;

    size_t size() const { return mean.size(); }
    int coeffs() const { return sh_coeffs(sh_degree); }
    void resize(size_t n);  // resizes every array (extras too), new entries zero / identity

    const ExtraProperty* find_extra(const std::string& name) const;
    // Adds or replaces an integer per-Gaussian property (e.g. "instance", "class").
    void set_int_property(const std::string& name, const std::vector<int32_t>& values,
                          PlyType type = PlyType::Int32);
    // The values of an extra as integers; nullopt if it is missing or holds a non-integer.
    std::optional<std::vector<int32_t>> int_property(const std::string& name) const;
};

// SH band 0 constant: colour = 0.5 + kShC0 * f_dc.
constexpr float kShC0 = 0.28209479177387814f;

// Opacity from its logit (the sigmoid), and back. The inverse clamps the opacity to
// [1e-4, 1 - 1e-4] (logits within +-9.21), so 8-bit alphas of 0 and 255 in the packed
// formats stay finite.
float opacity_from_logit(float logit);
float logit_from_opacity(float opacity);

}  // namespace pg::data
