#pragma once
// Private to dataset/: the parsed header of a PLY file and a cursor over its body. The
// 3DGS readers (INRIA/2DGS and PlayCanvas compressed) are built on these.
#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "dataset/gaussian_cloud.h"

namespace pg::data::ply {

enum class Encoding { Ascii, BinaryLittleEndian, BinaryBigEndian };

struct Property {
    std::string name;
    PlyType type = PlyType::Float32;  // the value type (of the items, for a list)
    bool is_list = false;
    PlyType count_type = PlyType::UInt8;  // lists only
};

struct Element {
    std::string name;
    uint64_t count = 0;
    std::vector<Property> properties;

    bool has_list() const;
    int find(std::string_view property) const;  // index or -1
    size_t row_bytes() const;                   // binary size of one row; only without lists
};

struct Header {
    Encoding encoding = Encoding::BinaryLittleEndian;
    std::vector<std::string> comments;
    std::vector<Element> elements;
    size_t body_offset = 0;  // first byte after the end_header line

    int find(std::string_view element) const;  // index or -1
};

// Parses "char".."double" and "int8".."float64"; false if unknown.
bool parse_type(std::string_view word, PlyType& type);

// Parses the header of a whole PLY file held in memory; throws InputError(where, ...).
Header parse_header(const char* data, size_t size, const std::string& where);

// Reads the body element by element, in header order. Every read is bounds-checked
// against the data and throws InputError(where, ...) naming the element and row.
class BodyReader {
public:
    BodyReader(const char* data, size_t size, const Header& header, std::string where);

    // Skips the next element (binary: by stride, or by walking its lists; ascii: by lines).
    void skip(const Element& e);
    // Decodes the next element, which must have no list properties: calls
    // fn(row, values) with one double per property, in header order. Every PLY scalar
    // converts to double exactly.
    template <class Fn>
    void read_rows(const Element& e, Fn&& fn);
    // Throws unless the next element is list-free and its rows can fit in the remaining
    // data; call it before allocating for the element's count.
    void check_fits(const Element& e) const;
    // Called now and then with the offset below which the reader is done with the data (a
    // mapped file gives those pages back).
    void on_consumed(std::function<void(size_t)> fn) { consumed_ = std::move(fn); }

private:
    bool next_line(std::string_view& line);
    void parse_ascii_row(const Element& e, uint64_t row, std::string_view line, double* values);
    [[noreturn]] void fail(const std::string& reason) const;

    const char* data_;
    size_t size_;
    size_t pos_;
    Encoding encoding_;
    std::string where_;
    std::function<void(size_t)> consumed_;
    static constexpr uint64_t kConsumedEvery = 1u << 16;  // rows between two on_consumed calls
};

// One binary scalar at p as double; Swap reverses its bytes (file and host endianness differ).
template <bool Swap>
inline double decode_scalar(const char* p, PlyType type) {
    auto load = [p](auto v) {
        std::memcpy(&v, p, sizeof v);
        if constexpr (Swap) {
            unsigned char b[sizeof v];
            std::memcpy(b, &v, sizeof v);
            std::reverse(b, b + sizeof v);
            std::memcpy(&v, b, sizeof v);
        }
        return static_cast<double>(v);
    };
    switch (type) {
        case PlyType::Int8: return load(int8_t{});
        case PlyType::UInt8: return load(uint8_t{});
        case PlyType::Int16: return load(int16_t{});
        case PlyType::UInt16: return load(uint16_t{});
        case PlyType::Int32: return load(int32_t{});
        case PlyType::UInt32: return load(uint32_t{});
        case PlyType::Float32: return load(float{});
        case PlyType::Float64: return load(double{});
    }
    return 0.0;
}

inline double decode_scalar(const char* p, PlyType type, bool swap) {
    return swap ? decode_scalar<true>(p, type) : decode_scalar<false>(p, type);
}

template <class Fn>
void BodyReader::read_rows(const Element& e, Fn&& fn) {
    check_fits(e);
    const size_t n_props = e.properties.size();
    std::vector<double> values(n_props);
    if (encoding_ == Encoding::Ascii) {
        for (uint64_t row = 0; row < e.count; ++row) {
            std::string_view line;
            if (!next_line(line))
                fail("element '" + e.name + "' ends after " + std::to_string(row) + " of " +
                     std::to_string(e.count) + " rows");
            parse_ascii_row(e, row, line, values.data());
            fn(row, static_cast<const double*>(values.data()));
            if (consumed_ && (row + 1) % kConsumedEvery == 0) consumed_(pos_);
        }
        return;
    }
    struct Column {
        uint32_t offset;
        PlyType type;
    };
    std::vector<Column> columns(n_props);
    uint32_t offset = 0;
    for (size_t p = 0; p < n_props; ++p) {
        columns[p] = {offset, e.properties[p].type};
        offset += static_cast<uint32_t>(ply_type_size(e.properties[p].type));
    }
    const size_t stride = offset;
    const bool swap = (encoding_ == Encoding::BinaryBigEndian) != (std::endian::native == std::endian::big);
    auto decode_all = [&]<bool Swap>() {
        const char* base = data_ + pos_;
        for (uint64_t row = 0; row < e.count; ++row, base += stride) {
            for (size_t p = 0; p < n_props; ++p)
                values[p] = decode_scalar<Swap>(base + columns[p].offset, columns[p].type);
            fn(row, static_cast<const double*>(values.data()));
            if (consumed_ && (row + 1) % kConsumedEvery == 0) consumed_(size_t(base + stride - data_));
        }
    };
    if (swap) decode_all.template operator()<true>();
    else decode_all.template operator()<false>();
    pos_ += static_cast<size_t>(e.count) * stride;
}

}  // namespace pg::data::ply
