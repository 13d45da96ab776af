// MetaFields: checked access to a SOG meta's fields; SogFiles over a folder.
#include "dataset/formats/sog_meta.h"

#include <cmath>
#include <fstream>

#include "dataset/error.h"
#include "dataset/formats/zip_archive.h"

namespace pg::data {

nlohmann::json parse_sog_json(const std::vector<uint8_t>& bytes, const std::string& where) {
    nlohmann::json j = nlohmann::json::parse(bytes.begin(), bytes.end(), nullptr, false);
    if (j.is_discarded()) throw InputError(where, "invalid JSON");
    if (!j.is_object()) throw InputError(where, "must be a JSON object");
    return j;
}

SogFiles sog_folder(const std::filesystem::path& folder) {
    SogFiles f;
    f.where = [folder](const std::string& name) { return (folder / name).string(); };
    f.read = [folder](const std::string& name, uint64_t max_bytes) {
        const std::filesystem::path p = folder / name;
        std::error_code ec;
        if (!std::filesystem::is_regular_file(p, ec)) throw InputError(p.string(), "no such file (named in the SOG meta)");
        const uint64_t size = std::filesystem::file_size(p, ec);
        if (ec) throw InputError(p.string(), "cannot read its size");
        if (size > max_bytes)
            throw InputError(p.string(), "is " + std::to_string(size) + " bytes, more than the " +
                                             std::to_string(max_bytes) + " allowed");
        std::vector<uint8_t> bytes(size);
        std::ifstream in(p, std::ios::binary);
        if (!in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(size)))
            throw InputError(p.string(), "cannot read");
        return bytes;
    };
    return f;
}

const nlohmann::json* MetaFields::find(const std::string& field) const {
    const nlohmann::json* node = &meta_;
    size_t start = 0;
    while (start <= field.size()) {
        size_t end = field.find('.', start);
        if (end == std::string::npos) end = field.size();
        const std::string part = field.substr(start, end - start);
        if (node->is_object()) {
            auto it = node->find(part);
            if (it == node->end()) return nullptr;
            node = &*it;
        } else if (node->is_array() && !part.empty() && part.find_first_not_of("0123456789") == std::string::npos &&
                   part.size() < 9) {
            const size_t i = std::stoul(part);
            if (i >= node->size()) return nullptr;
            node = &(*node)[i];
        } else {
            return nullptr;
        }
        start = end + 1;
    }
    return node;
}

void MetaFields::fail(const std::string& field, const std::string& reason) const {
    throw InputError(where_, "field '" + field + "' " + reason);
}

const nlohmann::json& MetaFields::object(const std::string& field) const {
    const auto* v = find(field);
    if (!v) fail(field, "is missing");
    if (!v->is_object()) fail(field, "must be an object");
    return *v;
}

uint64_t MetaFields::count(const std::string& field, uint64_t max) const {
    const auto* v = find(field);
    if (!v) fail(field, "is missing");
    if (v->is_number_float()) {
        const double d = v->get<double>();
        if (!(d >= 0.0) || d != std::floor(d) || d > double(max))
            fail(field, "must be an integer from 0 to " + std::to_string(max));
        return uint64_t(d);
    }
    if (v->is_number_unsigned()) {
        const uint64_t n = v->get<uint64_t>();
        if (n > max) fail(field, "is " + std::to_string(n) + ", more than " + std::to_string(max));
        return n;
    }
    if (v->is_number_integer()) fail(field, "is negative");
    fail(field, "must be a number");
}

double MetaFields::number(const std::string& field) const {
    const auto* v = find(field);
    if (!v) fail(field, "is missing");
    if (!v->is_number()) fail(field, "must be a number");
    const double d = v->get<double>();
    if (!std::isfinite(d)) fail(field, "must be finite");
    return d;
}

std::vector<double> MetaFields::numbers(const std::string& field, size_t size) const {
    const auto* v = find(field);
    if (!v) fail(field, "is missing");
    if (!v->is_array()) fail(field, "must be an array of " + std::to_string(size) + " numbers");
    if (v->size() != size)
        fail(field, "has " + std::to_string(v->size()) + " entries; it must have " + std::to_string(size));
    std::vector<double> out;
    out.reserve(size);
    for (size_t i = 0; i < size; ++i) {
        const auto& e = (*v)[i];
        if (!e.is_number() || !std::isfinite(e.get<double>()))
            fail(field, "entry " + std::to_string(i) + " is not a finite number");
        out.push_back(e.get<double>());
    }
    return out;
}

std::string MetaFields::text(const std::string& field) const {
    const auto* v = find(field);
    if (!v) fail(field, "is missing");
    if (!v->is_string()) fail(field, "must be a string");
    return v->get<std::string>();
}

std::vector<std::string> MetaFields::files(const std::string& field, size_t size) const {
    const auto* v = find(field);
    if (!v) fail(field, "is missing");
    if (!v->is_array() || v->size() < size)
        fail(field, "must be an array of " + std::to_string(size) + " file name" + (size > 1 ? "s" : ""));
    std::vector<std::string> out;
    for (size_t i = 0; i < size; ++i) {
        const auto& e = (*v)[i];
        if (!e.is_string()) fail(field, "entry " + std::to_string(i) + " is not a string");
        const std::string name = e.get<std::string>();
        if (!is_safe_relative_name(name)) fail(field, "names '" + name + "', an absolute or '..' path (refused)");
        out.push_back(name);
    }
    return out;
}

}  // namespace pg::data
