// PLY reading: the header parser and body cursor (ply_header.h), the INRIA 3DGS / 2DGS
// vertex layout, and PlayCanvas's compressed layout (chunk + packed vertex + uchar SH).
#include <array>
#include <charconv>
#include <cmath>
#include <limits>

#include "dataset/atomic_file.h"
#include "dataset/error.h"
#include "dataset/formats/ply_header.h"
#include "dataset/mapped_file.h"
#include "dataset/formats/scene_io.h"

namespace pg::data {
namespace ply {

namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }

// A header or data snippet made safe for an error message.
std::string printable(std::string_view s) {
    constexpr size_t kMax = 60;
    std::string out;
    for (size_t i = 0; i < s.size() && i < kMax; ++i) {
        unsigned char c = static_cast<unsigned char>(s[i]);
        out += (c >= 32 && c < 127) ? static_cast<char>(c) : '?';
    }
    if (s.size() > kMax) out += "...";
    return out;
}

std::vector<std::string_view> split_words(std::string_view line) {
    std::vector<std::string_view> words;
    size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && is_space(line[i])) ++i;
        size_t start = i;
        while (i < line.size() && !is_space(line[i])) ++i;
        if (i > start) words.push_back(line.substr(start, i - start));
    }
    return words;
}

// "name_N" with N a plain decimal (no sign, no leading zeros) → N; -1 otherwise.
long indexed_name(std::string_view name, std::string_view prefix) {
    if (name.size() <= prefix.size() || name.substr(0, prefix.size()) != prefix) return -1;
    std::string_view digits = name.substr(prefix.size());
    if (digits.size() > 1 && digits[0] == '0') return -1;
    long v = 0;
    auto [ptr, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), v);
    if (ec != std::errc() || ptr != digits.data() + digits.size() || v < 0) return -1;
    return v;
}

bool is_integer_type(PlyType t) { return t != PlyType::Float32 && t != PlyType::Float64; }

// Range of each integer type, for ascii values and list counts.
bool fits_type(double v, PlyType t) {
    switch (t) {
        case PlyType::Int8: return v >= -128.0 && v <= 127.0;
        case PlyType::UInt8: return v >= 0.0 && v <= 255.0;
        case PlyType::Int16: return v >= -32768.0 && v <= 32767.0;
        case PlyType::UInt16: return v >= 0.0 && v <= 65535.0;
        case PlyType::Int32: return v >= -2147483648.0 && v <= 2147483647.0;
        case PlyType::UInt32: return v >= 0.0 && v <= 4294967295.0;
        default: return true;
    }
}

}  // namespace

bool parse_type(std::string_view w, PlyType& type) {
    struct Name {
        std::string_view a, b;
        PlyType t;
    };
    static constexpr Name kNames[] = {
        {"char", "int8", PlyType::Int8},       {"uchar", "uint8", PlyType::UInt8},
        {"short", "int16", PlyType::Int16},    {"ushort", "uint16", PlyType::UInt16},
        {"int", "int32", PlyType::Int32},      {"uint", "uint32", PlyType::UInt32},
        {"float", "float32", PlyType::Float32}, {"double", "float64", PlyType::Float64},
    };
    for (const auto& n : kNames) {
        if (w == n.a || w == n.b) {
            type = n.t;
            return true;
        }
    }
    return false;
}

bool Element::has_list() const {
    for (const auto& p : properties)
        if (p.is_list) return true;
    return false;
}

int Element::find(std::string_view property) const {
    for (size_t i = 0; i < properties.size(); ++i)
        if (properties[i].name == property) return static_cast<int>(i);
    return -1;
}

size_t Element::row_bytes() const {
    size_t n = 0;
    for (const auto& p : properties) n += ply_type_size(p.type);
    return n;
}

int Header::find(std::string_view element) const {
    for (size_t i = 0; i < elements.size(); ++i)
        if (elements[i].name == element) return static_cast<int>(i);
    return -1;
}

Header parse_header(const char* data, size_t size, const std::string& where) {
    if (size == 0) throw InputError(where, "empty file");
    size_t pos = 0;
    int line_no = 0;
    auto next_line = [&](std::string_view& line) {
        if (pos >= size) return false;
        const void* nl = std::memchr(data + pos, '\n', size - pos);
        size_t end = nl ? static_cast<size_t>(static_cast<const char*>(nl) - data) : size;
        line = std::string_view(data + pos, end - pos);
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        pos = nl ? end + 1 : size;
        ++line_no;
        return true;
    };
    auto fail = [&](const std::string& reason) -> void {
        throw InputError(where, "PLY header line " + std::to_string(line_no) + ": " + reason);
    };

    std::string_view line;
    next_line(line);
    if (line != "ply") throw InputError(where, "not a PLY file (the first line is not 'ply')");

    Header h;
    bool have_format = false, ended = false;
    while (next_line(line)) {
        auto words = split_words(line);
        if (words.empty()) continue;
        std::string_view kw = words[0];
        if (kw == "end_header") {
            ended = true;
            break;
        } else if (kw == "comment") {
            size_t at = line.find("comment") + 7;
            if (at < line.size()) ++at;  // the one separator after the keyword
            h.comments.emplace_back(line.substr(std::min(at, line.size())));
        } else if (kw == "obj_info") {
            continue;
        } else if (kw == "format") {
            if (have_format) fail("second format line");
            if (words.size() != 3) fail("expected 'format <encoding> 1.0', found '" + printable(line) + "'");
            if (words[1] == "ascii") h.encoding = Encoding::Ascii;
            else if (words[1] == "binary_little_endian") h.encoding = Encoding::BinaryLittleEndian;
            else if (words[1] == "binary_big_endian") h.encoding = Encoding::BinaryBigEndian;
            else fail("unknown format '" + printable(words[1]) + "'");
            if (words[2] != "1.0") fail("unsupported PLY version '" + printable(words[2]) + "'");
            have_format = true;
        } else if (kw == "element") {
            if (words.size() != 3) fail("expected 'element <name> <count>', found '" + printable(line) + "'");
            Element e;
            e.name = std::string(words[1]);
            if (h.find(e.name) >= 0) fail("element '" + printable(e.name) + "' declared twice");
            auto [ptr, ec] = std::from_chars(words[2].data(), words[2].data() + words[2].size(), e.count);
            if (ec == std::errc::result_out_of_range)
                fail("element '" + printable(e.name) + "' count " + printable(words[2]) + " is too large");
            if (ec != std::errc() || ptr != words[2].data() + words[2].size())
                fail("element '" + printable(e.name) + "' count '" + printable(words[2]) +
                     "' is not a non-negative integer");
            h.elements.push_back(std::move(e));
        } else if (kw == "property") {
            if (h.elements.empty()) fail("property before any element");
            Element& e = h.elements.back();
            Property p;
            if (words.size() == 3) {
                if (!parse_type(words[1], p.type)) fail("unknown property type '" + printable(words[1]) + "'");
                p.name = std::string(words[2]);
            } else if (words.size() == 5 && words[1] == "list") {
                if (!parse_type(words[2], p.count_type) || !is_integer_type(p.count_type))
                    fail("list count type '" + printable(words[2]) + "' is not an integer type");
                if (!parse_type(words[3], p.type)) fail("unknown property type '" + printable(words[3]) + "'");
                p.is_list = true;
                p.name = std::string(words[4]);
            } else {
                fail("expected 'property <type> <name>', found '" + printable(line) + "'");
            }
            if (e.find(p.name) >= 0)
                fail("property '" + printable(p.name) + "' declared twice in element '" + printable(e.name) + "'");
            e.properties.push_back(std::move(p));
        } else {
            fail("unknown keyword '" + printable(kw) + "'");
        }
    }
    if (!ended) throw InputError(where, "PLY header has no end_header line");
    if (!have_format) throw InputError(where, "PLY header has no format line");
    h.body_offset = pos;
    return h;
}

BodyReader::BodyReader(const char* data, size_t size, const Header& header, std::string where)
    : data_(data), size_(size), pos_(header.body_offset), encoding_(header.encoding), where_(std::move(where)) {}

void BodyReader::fail(const std::string& reason) const { throw InputError(where_, reason); }

void BodyReader::check_fits(const Element& e) const {
    for (const auto& p : e.properties)
        if (p.is_list)
            fail("list property '" + printable(p.name) + "' in element '" + printable(e.name) + "' is not supported");
    const size_t remaining = size_ - pos_;
    if (encoding_ == Encoding::Ascii) {
        // Each value takes at least one character and one separator.
        const uint64_t per_row = 2 * static_cast<uint64_t>(e.properties.size());
        if (per_row > 0 && e.count > (static_cast<uint64_t>(remaining) + 1) / per_row)
            fail("element '" + printable(e.name) + "' declares " + std::to_string(e.count) + " rows but only " +
                 std::to_string(remaining) + " bytes of data remain (truncated file?)");
        return;
    }
    const uint64_t stride = e.row_bytes();
    if (stride == 0) return;
    uint64_t bytes = 0;
    if (__builtin_mul_overflow(e.count, stride, &bytes))
        fail("element '" + printable(e.name) + "': " + std::to_string(e.count) + " rows of " + std::to_string(stride) +
             " bytes overflow a 64-bit size");
    if (bytes > remaining)
        fail("element '" + printable(e.name) + "' needs " + std::to_string(e.count) + " x " + std::to_string(stride) +
             " = " + std::to_string(bytes) + " bytes but only " + std::to_string(remaining) +
             " remain (truncated file?)");
}

bool BodyReader::next_line(std::string_view& line) {
    while (pos_ < size_) {
        const void* nl = std::memchr(data_ + pos_, '\n', size_ - pos_);
        size_t end = nl ? static_cast<size_t>(static_cast<const char*>(nl) - data_) : size_;
        line = std::string_view(data_ + pos_, end - pos_);
        pos_ = nl ? end + 1 : size_;
        for (char c : line)
            if (!is_space(c)) return true;
    }
    return false;
}

void BodyReader::parse_ascii_row(const Element& e, uint64_t row, std::string_view line, double* values) {
    const char* p = line.data();
    const char* end = p + line.size();
    auto where_row = [&]() { return "element '" + printable(e.name) + "' row " + std::to_string(row); };
    for (size_t k = 0; k < e.properties.size(); ++k) {
        while (p < end && is_space(*p)) ++p;
        if (p == end)
            fail(where_row() + ": expected " + std::to_string(e.properties.size()) + " values, found " +
                 std::to_string(k));
        const char* start = p;
        while (p < end && !is_space(*p)) ++p;
        const char* first = (*start == '+') ? start + 1 : start;
        const PlyType t = e.properties[k].type;
        bool ok = false;
        if (t == PlyType::Float32) {
            float v = 0.0f;
            auto r = std::from_chars(first, p, v);
            ok = r.ec == std::errc() && r.ptr == p;
            values[k] = v;
        } else if (t == PlyType::Float64) {
            double v = 0.0;
            auto r = std::from_chars(first, p, v);
            ok = r.ec == std::errc() && r.ptr == p;
            values[k] = v;
        } else {
            int64_t v = 0;
            auto r = std::from_chars(first, p, v);
            ok = r.ec == std::errc() && r.ptr == p && fits_type(static_cast<double>(v), t);
            values[k] = static_cast<double>(v);
            if (!ok) {  // some writers print integers as "3.0"
                double d = 0.0;
                auto rd = std::from_chars(first, p, d);
                ok = rd.ec == std::errc() && rd.ptr == p && d == std::floor(d) && fits_type(d, t);
                values[k] = d;
            }
        }
        if (!ok)
            fail(where_row() + ": property '" + printable(e.properties[k].name) + "' value '" +
                 printable(std::string_view(start, p - start)) + "' is not a valid " + ply_type_name(t));
    }
    while (p < end && is_space(*p)) ++p;
    if (p != end)
        fail(where_row() + ": more than " + std::to_string(e.properties.size()) + " values on the line");
}

void BodyReader::skip(const Element& e) {
    if (encoding_ == Encoding::Ascii) {
        if (e.properties.empty()) return;
        std::string_view line;
        for (uint64_t row = 0; row < e.count; ++row)
            if (!next_line(line))
                fail("element '" + printable(e.name) + "' ends after " + std::to_string(row) + " of " +
                     std::to_string(e.count) + " rows (truncated file?)");
        return;
    }
    if (!e.has_list()) {
        check_fits(e);
        pos_ += static_cast<size_t>(e.count * e.row_bytes());
        return;
    }
    // Lists: walk the rows. Every row holds at least one count byte, so this is bounded
    // by the data size however large the declared count.
    const bool swap = (encoding_ == Encoding::BinaryBigEndian) != (std::endian::native == std::endian::big);
    auto truncated = [&](uint64_t row) {
        fail("element '" + printable(e.name) + "' is truncated at row " + std::to_string(row) + " of " +
             std::to_string(e.count));
    };
    for (uint64_t row = 0; row < e.count; ++row) {
        for (const auto& p : e.properties) {
            if (!p.is_list) {
                size_t n = ply_type_size(p.type);
                if (size_ - pos_ < n) truncated(row);
                pos_ += n;
                continue;
            }
            size_t cn = ply_type_size(p.count_type);
            if (size_ - pos_ < cn) truncated(row);
            double items = decode_scalar(data_ + pos_, p.count_type, swap);
            pos_ += cn;
            if (items < 0)
                fail("element '" + printable(e.name) + "' row " + std::to_string(row) + ": negative list length");
            uint64_t bytes = static_cast<uint64_t>(items) * ply_type_size(p.type);
            if (size_ - pos_ < bytes) truncated(row);
            pos_ += static_cast<size_t>(bytes);
        }
    }
}

}  // namespace ply

namespace {

using ply::BodyReader;
using ply::Element;
using ply::Header;

// Where one vertex property of an INRIA file lands in the cloud.
enum class Slot : uint8_t { Mean, Dc, Rest, Opacity, Scale, Rot, Extra };
struct Target {
    Slot slot = Slot::Extra;
    uint32_t index = 0;  // component; for Rest the offset (k * 3 + c) inside a Gaussian's SH
};

int sh_degree_for_rest_count(size_t n) {
    for (int d = 0; d <= kMaxShDegree; ++d)
        if (static_cast<size_t>(3 * (sh_coeffs(d) - 1)) == n) return d;
    return -1;
}

GaussianCloud read_inria(const Header& h, BodyReader& body, const Element& vertex, const std::string& where,
                         const LoadProgress& progress) {
    auto fail = [&](const std::string& reason) -> void { throw InputError(where, reason); };
    const size_t n_props = vertex.properties.size();
    std::vector<Target> targets(n_props);
    std::array<int, 3> mean_at{-1, -1, -1}, dc_at{-1, -1, -1}, scale_at{-1, -1, -1};
    std::array<int, 4> rot_at{-1, -1, -1, -1};
    int opacity_at = -1;
    std::vector<int> rest_at;  // property index of f_rest_j
    GaussianCloud cloud;

    for (size_t p = 0; p < n_props; ++p) {
        const auto& prop = vertex.properties[p];
        if (prop.is_list)
            fail("list property '" + prop.name + "' in element 'vertex' is not supported");
        const std::string& name = prop.name;
        long k;
        Target t;
        if (name.size() == 1 && name[0] >= 'x' && name[0] <= 'z') {
            t = {Slot::Mean, static_cast<uint32_t>(name[0] - 'x')};
            mean_at[t.index] = static_cast<int>(p);
        } else if ((k = ply::indexed_name(name, "f_dc_")) >= 0 && k < 3) {
            t = {Slot::Dc, static_cast<uint32_t>(k)};
            dc_at[k] = static_cast<int>(p);
        } else if ((k = ply::indexed_name(name, "f_rest_")) >= 0 && k < 1000) {
            t = {Slot::Rest, static_cast<uint32_t>(k)};
            if (rest_at.size() <= static_cast<size_t>(k)) rest_at.resize(k + 1, -1);
            rest_at[k] = static_cast<int>(p);
        } else if (name == "opacity") {
            t = {Slot::Opacity, 0};
            opacity_at = static_cast<int>(p);
        } else if ((k = ply::indexed_name(name, "scale_")) >= 0 && k < 3) {
            t = {Slot::Scale, static_cast<uint32_t>(k)};
            scale_at[k] = static_cast<int>(p);
        } else if ((k = ply::indexed_name(name, "rot_")) >= 0 && k < 4) {
            t = {Slot::Rot, static_cast<uint32_t>(k)};
            rot_at[k] = static_cast<int>(p);
        } else {
            t = {Slot::Extra, static_cast<uint32_t>(cloud.extras.size())};
            cloud.extras.push_back(ExtraProperty{name, prop.type, {}});
        }
        targets[p] = t;
    }

    auto require = [&](int at, const std::string& name) {
        if (at < 0) fail("missing required vertex property '" + name + "'");
    };
    for (int c = 0; c < 3; ++c) require(mean_at[c], std::string(1, static_cast<char>('x' + c)));
    for (int c = 0; c < 3; ++c) require(dc_at[c], "f_dc_" + std::to_string(c));
    require(opacity_at, "opacity");
    require(scale_at[0], "scale_0");
    require(scale_at[1], "scale_1");
    for (int c = 0; c < 4; ++c) require(rot_at[c], "rot_" + std::to_string(c));

    size_t rest_count = 0;
    for (int at : rest_at) rest_count += at >= 0;
    const int degree = sh_degree_for_rest_count(rest_count);
    if (degree < 0)
        fail("vertex has " + std::to_string(rest_count) +
             " f_rest_* properties; expected 0, 9, 24 or 45 (SH degree 0 to 3)");
    if (rest_at.size() != rest_count)
        fail("f_rest_* properties are not numbered 0.." + std::to_string(rest_count - 1) + " (f_rest_" +
             std::to_string(rest_at.size() - 1) + " present)");

    cloud.sh_degree = degree;
    cloud.flat = scale_at[2] < 0;
    const uint32_t coeffs = static_cast<uint32_t>(cloud.coeffs());
    const uint32_t rest_per_channel = coeffs - 1;
    for (auto& t : targets) {
        if (t.slot != Slot::Rest) continue;
        uint32_t c = t.index / rest_per_channel, k = t.index % rest_per_channel + 1;
        t.index = k * 3 + c;
    }

    body.check_fits(vertex);  // before allocating for the declared count
    cloud.resize(static_cast<size_t>(vertex.count));
    float* sh = cloud.sh.data();
    body.read_rows(vertex, [&](uint64_t i, const double* v) {
        if (progress && (i & 0xFFFFF) == 0) progress(double(i) / double(vertex.count));
        for (size_t p = 0; p < n_props; ++p) {
            const Target t = targets[p];
            switch (t.slot) {
                case Slot::Mean: cloud.mean[i][t.index] = static_cast<float>(v[p]); break;
                case Slot::Dc: sh[i * coeffs * 3 + t.index] = static_cast<float>(v[p]); break;
                case Slot::Rest: sh[i * coeffs * 3 + t.index] = static_cast<float>(v[p]); break;
                case Slot::Opacity: cloud.opacity_logit[i] = static_cast<float>(v[p]); break;
                case Slot::Scale: cloud.log_scale[i][t.index] = static_cast<float>(v[p]); break;
                case Slot::Rot: cloud.rotation[i][t.index] = static_cast<float>(v[p]); break;
                case Slot::Extra: cloud.extras[t.index].values[i] = v[p]; break;
            }
        }
    });
    // Elements after the vertex data must still be consistent with the file size.
    for (size_t e = static_cast<size_t>(h.find("vertex")) + 1; e < h.elements.size(); ++e) body.skip(h.elements[e]);

    if (cloud.flat) cloud.format = SceneFormat::TwoDgsPly;
    else if (h.encoding == ply::Encoding::Ascii) cloud.format = SceneFormat::InriaPlyAscii;
    else cloud.format = SceneFormat::InriaPly;
    for (const auto& p : vertex.properties) cloud.ply_property_order.push_back(p.name);
    cloud.ply_comments = h.comments;
    return cloud;
}

// PlayCanvas compressed PLY (SuperSplat, splat-transform): per 256 Gaussians a chunk of
// float bounds; per Gaussian four uints — position 11-10-11 bits lerped in the chunk box,
// rotation as 2 bits (index of the largest of rot_0..3) + 3 x 10 bits (the others, in
// order, in [-1/sqrt2, 1/sqrt2]), log-scale 11-10-11 lerped in the chunk's scale box,
// colour RGBA 8-8-8-8 (RGB lerped in the chunk's colour box when it has one);
// optionally an 'sh' element of uchar f_rest_* in the INRIA order.
constexpr uint64_t kChunkSplats = 256;

GaussianCloud read_compressed(const Header& h, BodyReader& body, const std::string& where) {
    auto fail = [&](const std::string& reason) -> void { throw InputError(where, "compressed PLY: " + reason); };
    static const char* kChunkNames[18] = {"min_x",       "min_y",       "min_z",       "max_x",       "max_y",
                                          "max_z",       "min_scale_x", "min_scale_y", "min_scale_z", "max_scale_x",
                                          "max_scale_y", "max_scale_z", "min_r",       "min_g",       "min_b",
                                          "max_r",       "max_g",       "max_b"};
    static const char* kPackedNames[4] = {"packed_position", "packed_rotation", "packed_scale", "packed_color"};

    const Element& chunk = h.elements[h.find("chunk")];
    const Element& vertex = h.elements[h.find("vertex")];
    const uint64_t n = vertex.count;
    const uint64_t expected_chunks = n / kChunkSplats + (n % kChunkSplats != 0);
    if (chunk.count != expected_chunks)
        fail(std::to_string(n) + " vertices need " + std::to_string(expected_chunks) + " chunks of 256, the file has " +
             std::to_string(chunk.count));

    std::array<int, 18> chunk_at{};
    for (int k = 0; k < 18; ++k) {
        chunk_at[k] = chunk.find(kChunkNames[k]);
        if (k < 12 && chunk_at[k] < 0) fail(std::string("chunk element lacks '") + kChunkNames[k] + "'");
    }
    const bool chunk_colour = chunk_at[12] >= 0;
    for (int k = 12; k < 18; ++k)
        if ((chunk_at[k] >= 0) != chunk_colour) fail("chunk element has only some of min_r..max_b");
    std::array<int, 4> packed_at{};
    for (int k = 0; k < 4; ++k) {
        packed_at[k] = vertex.find(kPackedNames[k]);
        if (packed_at[k] < 0) fail(std::string("vertex element lacks '") + kPackedNames[k] + "'");
        PlyType t = vertex.properties[packed_at[k]].type;
        if (t != PlyType::UInt32 && t != PlyType::Int32)
            fail(std::string("'") + kPackedNames[k] + "' must be a 32-bit integer, not " + ply_type_name(t));
    }

    const int sh_index = h.find("sh");
    std::vector<int> rest_at;  // property index in 'sh' of f_rest_j
    int degree = 0;
    if (sh_index >= 0) {
        const Element& she = h.elements[sh_index];
        if (she.count != n)
            fail("'sh' element has " + std::to_string(she.count) + " rows for " + std::to_string(n) + " vertices");
        degree = sh_degree_for_rest_count(she.properties.size());
        if (degree < 1)
            fail("'sh' element has " + std::to_string(she.properties.size()) +
                 " properties; expected 9, 24 or 45 (SH degree 1 to 3)");
        for (size_t j = 0; j < she.properties.size(); ++j) {
            int at = she.find("f_rest_" + std::to_string(j));
            if (at < 0) fail("'sh' element lacks 'f_rest_" + std::to_string(j) + "'");
            if (she.properties[at].type != PlyType::UInt8) fail("'sh' properties must be uchar");
            rest_at.push_back(at);
        }
    }

    std::vector<float> chunks;
    std::vector<uint32_t> packed;
    std::vector<uint8_t> rest;
    for (const Element& e : h.elements) {
        if (&e == &chunk) {
            body.check_fits(e);
            chunks.assign(static_cast<size_t>(e.count) * 18, 0.0f);
            body.read_rows(e, [&](uint64_t c, const double* v) {
                float* out = &chunks[c * 18];
                for (int k = 0; k < 18; ++k) out[k] = chunk_at[k] >= 0 ? static_cast<float>(v[chunk_at[k]]) : 0.0f;
                if (!chunk_colour) out[15] = out[16] = out[17] = 1.0f;
            });
        } else if (&e == &vertex) {
            body.check_fits(e);
            packed.assign(static_cast<size_t>(n) * 4, 0u);
            body.read_rows(e, [&](uint64_t i, const double* v) {
                for (int k = 0; k < 4; ++k)
                    packed[i * 4 + k] = static_cast<uint32_t>(static_cast<int64_t>(v[packed_at[k]]));
            });
        } else if (sh_index >= 0 && &e == &h.elements[sh_index]) {
            body.check_fits(e);
            const size_t m = rest_at.size();
            rest.assign(static_cast<size_t>(n) * m, 0);
            body.read_rows(e, [&](uint64_t i, const double* v) {
                for (size_t j = 0; j < m; ++j) rest[i * m + j] = static_cast<uint8_t>(v[rest_at[j]]);
            });
        } else {
            body.skip(e);
        }
    }

    GaussianCloud cloud;
    cloud.sh_degree = degree;
    cloud.resize(static_cast<size_t>(n));
    cloud.format = SceneFormat::CompressedPly;
    cloud.ply_comments = h.comments;
    const uint32_t coeffs = static_cast<uint32_t>(cloud.coeffs());
    const uint32_t rest_per_channel = coeffs - 1;
    const double sqrt2 = std::sqrt(2.0);
    auto lerp = [](double a, double b, double t) { return a * (1.0 - t) + b * t; };
    auto unorm = [](uint32_t v, int bits) { return static_cast<double>(v & ((1u << bits) - 1u)) / ((1u << bits) - 1u); };
    for (size_t i = 0; i < n; ++i) {
        const float* c = &chunks[(i / kChunkSplats) * 18];
        const uint32_t* p = &packed[i * 4];
        const double t3[3] = {unorm(p[0] >> 21, 11), unorm(p[0] >> 11, 10), unorm(p[0], 11)};
        const double s3[3] = {unorm(p[2] >> 21, 11), unorm(p[2] >> 11, 10), unorm(p[2], 11)};
        for (int k = 0; k < 3; ++k) {
            cloud.mean[i][k] = static_cast<float>(lerp(c[k], c[3 + k], t3[k]));
            cloud.log_scale[i][k] = static_cast<float>(lerp(c[6 + k], c[9 + k], s3[k]));
        }
        const double small[3] = {(unorm(p[1] >> 20, 10) - 0.5) * sqrt2, (unorm(p[1] >> 10, 10) - 0.5) * sqrt2,
                                 (unorm(p[1], 10) - 0.5) * sqrt2};
        const uint32_t largest = p[1] >> 30;
        const double m = std::sqrt(std::max(0.0, 1.0 - (small[0] * small[0] + small[1] * small[1] + small[2] * small[2])));
        for (uint32_t k = 0, s = 0; k < 4; ++k)
            cloud.rotation[i][k] = static_cast<float>(k == largest ? m : small[s++]);
        const uint32_t col = p[3];
        for (int k = 0; k < 3; ++k) {
            double v = unorm(col >> (24 - 8 * k), 8);
            if (chunk_colour) v = lerp(c[12 + k], c[15 + k], v);
            cloud.sh[i * coeffs * 3 + k] = static_cast<float>((v - 0.5) / kShC0);
        }
        cloud.opacity_logit[i] = logit_from_opacity(static_cast<float>(unorm(col, 8)));
        if (!rest.empty()) {
            const uint8_t* r = &rest[i * rest_at.size()];
            for (uint32_t j = 0; j < rest_at.size(); ++j) {
                // splat-transform's dequantisation: bucket centres, with 0 and 255 the ends.
                double u = r[j] == 0 ? 0.0 : r[j] == 255 ? 1.0 : (r[j] + 0.5) / 256.0;
                uint32_t ch = j / rest_per_channel, k = j % rest_per_channel + 1;
                cloud.sh[(i * coeffs + k) * 3 + ch] = static_cast<float>((u - 0.5) * 8.0);
            }
        }
    }
    return cloud;
}

}  // namespace

GaussianCloud read_ply(const std::filesystem::path& path, const LoadProgress& progress) {
    const std::string where = path.string();
    MappedFile file(path);
    const Header h = ply::parse_header(file.data(), file.size(), where);
    const int vi = h.find("vertex");
    if (vi < 0) throw InputError(where, "PLY has no 'vertex' element");
    const Element& vertex = h.elements[vi];
    BodyReader body(file.data(), file.size(), h, where);
    body.on_consumed([&file](size_t upto) { file.release(upto); });

    GaussianCloud cloud;
    if (h.find("chunk") >= 0 && vertex.find("packed_position") >= 0) {
        cloud = read_compressed(h, body, where);
    } else {
        for (int e = 0; e < vi; ++e) body.skip(h.elements[e]);
        cloud = read_inria(h, body, vertex, where, progress);
    }
    validate_cloud(cloud, where);
    if (progress) progress(1.0);
    return cloud;
}

}  // namespace pg::data
