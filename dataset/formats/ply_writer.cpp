// write_ply: binary little-endian INRIA PLY. A cloud read from a PLY keeps its property
// order, its comments and its extras' types, so reading and writing an INRIA file gives
// back the same bytes.
#include <cerrno>
#include <cstring>
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <ostream>
#include <stdexcept>

#include "dataset/atomic_file.h"
#include "dataset/error.h"
#include "dataset/formats/scene_io.h"

namespace pg::data {

namespace {

enum class Kind : uint8_t { Mean, Sh, Opacity, Scale, Rot, Extra };

struct Column {
    std::string name;
    PlyType type = PlyType::Float32;
    Kind kind = Kind::Mean;
    uint32_t index = 0;  // component; Sh: offset k * 3 + c in a Gaussian's SH; Extra: extras index
};

long indexed(std::string_view name, std::string_view prefix) {
    if (name.size() <= prefix.size() || name.substr(0, prefix.size()) != prefix) return -1;
    std::string_view d = name.substr(prefix.size());
    if (d.size() > 1 && d[0] == '0') return -1;
    long v = 0;
    for (char c : d) {
        if (c < '0' || c > '9' || v > 100000) return -1;
        v = v * 10 + (c - '0');
    }
    return v;
}

// The column of a property the cloud holds natively, if `name` is one.
std::optional<Column> known_column(const GaussianCloud& cloud, std::string_view name) {
    const long rest = 3L * (cloud.coeffs() - 1);
    long k;
    if (name == "x" || name == "y" || name == "z")
        return Column{std::string(name), PlyType::Float32, Kind::Mean, static_cast<uint32_t>(name[0] - 'x')};
    if ((k = indexed(name, "f_dc_")) >= 0 && k < 3)
        return Column{std::string(name), PlyType::Float32, Kind::Sh, static_cast<uint32_t>(k)};
    if ((k = indexed(name, "f_rest_")) >= 0 && k < rest) {
        const long per_channel = cloud.coeffs() - 1;
        const long c = k / per_channel, coeff = k % per_channel + 1;
        return Column{std::string(name), PlyType::Float32, Kind::Sh, static_cast<uint32_t>(coeff * 3 + c)};
    }
    if (name == "opacity") return Column{std::string(name), PlyType::Float32, Kind::Opacity, 0};
    if ((k = indexed(name, "scale_")) >= 0 && k < (cloud.flat ? 2 : 3))
        return Column{std::string(name), PlyType::Float32, Kind::Scale, static_cast<uint32_t>(k)};
    if ((k = indexed(name, "rot_")) >= 0 && k < 4)
        return Column{std::string(name), PlyType::Float32, Kind::Rot, static_cast<uint32_t>(k)};
    return std::nullopt;
}

// The native properties in the INRIA order (normals, which are extras, go in between).
std::vector<std::string> canonical_names(const GaussianCloud& cloud) {
    std::vector<std::string> names = {"x", "y", "z", "f_dc_0", "f_dc_1", "f_dc_2"};
    for (int j = 0; j < 3 * (cloud.coeffs() - 1); ++j) names.push_back("f_rest_" + std::to_string(j));
    names.push_back("opacity");
    for (int k = 0; k < (cloud.flat ? 2 : 3); ++k) names.push_back("scale_" + std::to_string(k));
    for (int k = 0; k < 4; ++k) names.push_back("rot_" + std::to_string(k));
    return names;
}

std::vector<Column> plan_columns(const GaussianCloud& cloud) {
    std::vector<Column> cols;
    std::vector<bool> extra_used(cloud.extras.size(), false);
    auto has = [&](const std::string& name) {
        return std::any_of(cols.begin(), cols.end(), [&](const Column& c) { return c.name == name; });
    };
    auto add_extra = [&](size_t e) {
        const ExtraProperty& x = cloud.extras[e];
        // An extra that shadows a native property, or repeats a name, would make an
        // unreadable file: the native value wins.
        if (!extra_used[e] && !known_column(cloud, x.name) && !has(x.name))
            cols.push_back(Column{x.name, x.type, Kind::Extra, static_cast<uint32_t>(e)});
        extra_used[e] = true;
    };
    auto find_extra = [&](const std::string& name) -> long {
        for (size_t e = 0; e < cloud.extras.size(); ++e)
            if (cloud.extras[e].name == name) return static_cast<long>(e);
        return -1;
    };
    auto add_named = [&](const std::string& name) {
        if (has(name)) return;
        if (auto k = known_column(cloud, name)) cols.push_back(*k);
        else if (long e = find_extra(name); e >= 0) add_extra(static_cast<size_t>(e));
        // else: a property the cloud no longer has (e.g. f_rest_* after an SH change)
    };

    if (!cloud.ply_property_order.empty()) {
        for (const auto& name : cloud.ply_property_order) add_named(name);
        for (const auto& name : canonical_names(cloud)) add_named(name);  // in case the order lacks one
    } else {
        for (const auto& name : canonical_names(cloud)) {
            if (name == "f_dc_0")
                for (const char* normal : {"nx", "ny", "nz"}) add_named(normal);
            add_named(name);
        }
    }
    for (size_t e = 0; e < cloud.extras.size(); ++e) add_extra(e);
    return cols;
}

template <class T>
void put(char*& out, T v) {
    if constexpr (std::endian::native == std::endian::big && sizeof(T) > 1) {
        unsigned char b[sizeof(T)];
        std::memcpy(b, &v, sizeof(T));
        std::reverse(b, b + sizeof(T));
        std::memcpy(out, b, sizeof(T));
    } else {
        std::memcpy(out, &v, sizeof(T));
    }
    out += sizeof(T);
}

template <class T>
T to_int(double v) {
    double lo = static_cast<double>(std::numeric_limits<T>::min());
    double hi = static_cast<double>(std::numeric_limits<T>::max());
    if (std::isnan(v)) return T(0);
    return static_cast<T>(std::llround(std::clamp(v, lo, hi)));
}

void put_value(char*& out, PlyType t, double v) {
    switch (t) {
        case PlyType::Int8: put(out, to_int<int8_t>(v)); break;
        case PlyType::UInt8: put(out, to_int<uint8_t>(v)); break;
        case PlyType::Int16: put(out, to_int<int16_t>(v)); break;
        case PlyType::UInt16: put(out, to_int<uint16_t>(v)); break;
        case PlyType::Int32: put(out, to_int<int32_t>(v)); break;
        case PlyType::UInt32: put(out, to_int<uint32_t>(v)); break;
        case PlyType::Float32: put(out, static_cast<float>(v)); break;
        case PlyType::Float64: put(out, v); break;
    }
}

void check_consistent(const GaussianCloud& cloud, const std::string& where) {
    const size_t n = cloud.size();
    bool ok = cloud.log_scale.size() == n && cloud.rotation.size() == n && cloud.opacity_logit.size() == n &&
              cloud.sh.size() == n * static_cast<size_t>(cloud.coeffs()) * 3 && cloud.sh_degree >= 0 &&
              cloud.sh_degree <= kMaxShDegree;
    for (const auto& e : cloud.extras) ok = ok && e.values.size() == n;
    if (!ok) throw std::logic_error("write_ply " + where + ": the cloud's arrays have inconsistent sizes");
    for (const auto& e : cloud.extras) {
        bool bad_name = e.name.empty() || std::any_of(e.name.begin(), e.name.end(), [](unsigned char c) {
                            return c <= ' ' || c >= 127;
                        });
        if (bad_name) throw InputError(where, "cannot write property name '" + e.name + "' into a PLY header");
    }
}

}  // namespace

void write_ply(const GaussianCloud& cloud, const std::filesystem::path& path) {
    const std::string where = path.string();
    check_consistent(cloud, where);
    const std::vector<Column> cols = plan_columns(cloud);

    std::string header = "ply\nformat binary_little_endian 1.0\n";
    for (std::string c : cloud.ply_comments) {
        std::replace(c.begin(), c.end(), '\n', ' ');
        std::replace(c.begin(), c.end(), '\r', ' ');
        header += "comment " + c + "\n";
    }
    header += "element vertex " + std::to_string(cloud.size()) + "\n";
    size_t row_bytes = 0;
    for (const auto& c : cols) {
        header += std::string("property ") + ply_type_name(c.type) + " " + c.name + "\n";
        row_bytes += ply_type_size(c.type);
    }
    header += "end_header\n";

    write_atomically(path, [&](std::ostream& os) {
        os.write(header.data(), static_cast<std::streamsize>(header.size()));
        const size_t n = cloud.size();
        const size_t coeffs3 = static_cast<size_t>(cloud.coeffs()) * 3;
        constexpr size_t kRowsPerBlock = 4096;
        std::vector<char> block(kRowsPerBlock * row_bytes);
        for (size_t first = 0; first < n; first += kRowsPerBlock) {
            const size_t last = std::min(n, first + kRowsPerBlock);
            char* out = block.data();
            for (size_t i = first; i < last; ++i) {
                for (const auto& c : cols) {
                    switch (c.kind) {
                        case Kind::Mean: put(out, cloud.mean[i][c.index]); break;
                        case Kind::Sh: put(out, cloud.sh[i * coeffs3 + c.index]); break;
                        case Kind::Opacity: put(out, cloud.opacity_logit[i]); break;
                        case Kind::Scale: put(out, cloud.log_scale[i][c.index]); break;
                        case Kind::Rot: put(out, cloud.rotation[i][c.index]); break;
                        case Kind::Extra: put_value(out, c.type, cloud.extras[c.index].values[i]); break;
                    }
                }
            }
            os.write(block.data(), out - block.data());
            if (!os) throw InputError(where, std::string("write failed: ") + (errno ? std::strerror(errno) : "disk full?"));
        }
    });
}

}  // namespace pg::data
