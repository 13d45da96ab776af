#pragma once
// Shared by the SOG readers: where a meta.json's files come from, and checked access to the
// JSON's fields (every error names the file and the field).
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "dataset/gaussian_cloud.h"

namespace pg::data {

// The files a meta.json names: a zip archive's entries or a folder's files.
struct SogFiles {
    // Bytes of a file named in the meta (already checked to be a safe relative name).
    std::function<std::vector<uint8_t>(const std::string& name, uint64_t max_bytes)> read;
    // How errors name that file: "scene.sog: quats.webp", "scene/quats.webp".
    std::function<std::string(const std::string& name)> where;
};

// Reads meta.json (a folder's or a zip entry's) through `files`.
SogFiles sog_folder(const std::filesystem::path& folder);

// Checked reads of `meta` fields; `where` names the meta file. `field` is a dotted path
// ("means.mins") used both to find the value and to name it in errors.
class MetaFields {
public:
    MetaFields(const nlohmann::json& meta, std::string where) : meta_(meta), where_(std::move(where)) {}
    const nlohmann::json* find(const std::string& field) const;  // null if absent
    const nlohmann::json& object(const std::string& field) const;
    uint64_t count(const std::string& field, uint64_t max) const;   // a non-negative integer <= max
    double number(const std::string& field) const;
    std::vector<double> numbers(const std::string& field, size_t size) const;  // exactly `size` finite numbers
    std::vector<std::string> files(const std::string& field, size_t size) const;  // safe relative names
    std::string text(const std::string& field) const;
    [[noreturn]] void fail(const std::string& field, const std::string& reason) const;

private:
    const nlohmann::json& meta_;
    std::string where_;
};

nlohmann::json parse_sog_json(const std::vector<uint8_t>& bytes, const std::string& where);

// Decodes one meta.json (v1 or v2) and the images it names.
GaussianCloud decode_sog(const nlohmann::json& meta, const SogFiles& files, const std::string& meta_where,
                         const std::function<void(double)>& progress = {});
// A v1 palette image's width -> its SH bands (0 for a width no v1 palette has).
int v1_bands_from_width(int width);
// The Gaussian count and SH degree a meta.json declares, without decoding images.
void sog_meta_shape(const nlohmann::json& meta, const std::string& meta_where, int& version, uint64_t& count,
                    int& sh_degree);

}  // namespace pg::data
