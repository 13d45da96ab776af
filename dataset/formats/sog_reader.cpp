// read_sog / describe_sog: finds the layout, then decodes through sog_decode.cpp.
//   bundled    a zip holding meta.json and the images it names
//   unbundled  meta.json beside its images
//   streamed   lod-meta.json: `filenames` lists chunk metas (unbundled folders "0_0/meta.json",
//              ...); `tree` is a hierarchy whose leaves map a LOD level to a range
//              {file, offset, count} of one chunk; `environment` names a meta drawn at every level.
//              A level is gathered leaf by leaf in tree order, each chunk decoded once.
#include <algorithm>
#include <cstring>
#include <fstream>
#include <map>

#include "dataset/error.h"
#include "dataset/formats/scene_io.h"
#include "dataset/formats/sog.h"
#include "dataset/formats/sog_meta.h"
#include "dataset/formats/webp_image.h"
#include "dataset/formats/zip_archive.h"

namespace pg::data {

namespace fs = std::filesystem;

namespace {

constexpr uint64_t kMaxMetaBytes = uint64_t(64) << 20;
constexpr int kMaxTreeDepth = 64;

bool starts_with_zip_magic(const fs::path& path) {
    char magic[4] = {0, 0, 0, 0};
    std::ifstream in(path, std::ios::binary);
    in.read(magic, 4);
    return in.gcount() == 4 && std::memcmp(magic, "PK\x03\x04", 4) == 0;
}

std::vector<uint8_t> read_meta_file(const fs::path& path) {
    SogFiles folder = sog_folder(path.parent_path());
    return folder.read(path.filename().string(), kMaxMetaBytes);
}

bool is_lod_meta(const nlohmann::json& j) { return j.contains("tree") || j.contains("filenames") || j.contains("lodLevels"); }

// One chunk or a whole non-streamed scene, with its meta for describe_sog.
struct SogUnit {
    nlohmann::json meta;
    std::string where;
    SogFiles files;
    std::shared_ptr<ZipReader> zip;
    SogLayout layout = SogLayout::Unbundled;
};

SogUnit open_unit(const fs::path& path) {
    SogUnit u;
    if (starts_with_zip_magic(path)) {
        u.layout = SogLayout::Bundled;
        u.zip = std::make_shared<ZipReader>(path);
        const std::string zip_where = path.string();
        if (!u.zip->contains("meta.json")) throw InputError(zip_where, "SOG bundle holds no meta.json");
        u.where = zip_where + ": meta.json";
        u.meta = parse_sog_json(u.zip->read("meta.json", kMaxMetaBytes), u.where);
        auto zip = u.zip;
        u.files.read = [zip](const std::string& name, uint64_t max) { return zip->read(name, max); };
        u.files.where = [zip_where](const std::string& name) { return zip_where + ": " + name; };
        return u;
    }
    u.where = path.string();
    u.meta = parse_sog_json(read_meta_file(path), u.where);
    if (!u.meta.contains("means")) throw InputError(u.where, "is JSON but not a SOG meta (it has no 'means' field)");
    u.files = sog_folder(path.parent_path());
    return u;
}

struct LodRange {
    size_t file;
    uint64_t offset, count;
};

struct LodMeta {
    fs::path dir;
    std::string where;
    nlohmann::json json;
    std::vector<std::string> filenames;
    int levels = 1;
};

LodMeta open_lod_meta(const fs::path& path, nlohmann::json json) {
    LodMeta m{path.parent_path(), path.string(), std::move(json), {}, 1};
    const MetaFields f(m.json, m.where);
    const auto* names = f.find("filenames");
    if (!names || !names->is_array() || names->empty()) f.fail("filenames", "must be a non-empty array of chunk metas");
    m.filenames = f.files("filenames", names->size());
    m.levels = int(f.count("lodLevels", 64));
    if (m.levels < 1) f.fail("lodLevels", "is 0; a streamed scene has at least one level");
    f.object("tree");
    return m;
}

// Walks the tree in order, adding each leaf's range at `lod` (and every level's total to `totals`).
void collect_ranges(const LodMeta& m, const MetaFields& f, const std::string& field, int depth, int lod,
                    std::vector<LodRange>& out, std::vector<uint64_t>& totals) {
    if (depth > kMaxTreeDepth) f.fail(field, "nests deeper than " + std::to_string(kMaxTreeDepth) + " levels");
    const auto& node = f.object(field);
    if (const auto* children = f.find(field + ".children")) {
        if (!children->is_array()) f.fail(field + ".children", "must be an array");
        for (size_t i = 0; i < children->size(); ++i)
            collect_ranges(m, f, field + ".children." + std::to_string(i), depth + 1, lod, out, totals);
        return;
    }
    if (!node.contains("lods")) f.fail(field, "has neither 'children' nor 'lods'");
    const auto& lods = f.object(field + ".lods");
    for (auto it = lods.begin(); it != lods.end(); ++it) {
        const std::string key = field + ".lods." + it.key();
        const std::string& level_text = it.key();
        if (level_text.empty() || level_text.size() > 2 || level_text.find_first_not_of("0123456789") != std::string::npos ||
            std::stoi(level_text) >= m.levels)
            f.fail(key, "is not a level below lodLevels (" + std::to_string(m.levels) + ")");
        const int level = std::stoi(level_text);
        LodRange r{size_t(f.count(key + ".file", m.filenames.size() ? m.filenames.size() - 1 : 0)),
                   f.count(key + ".offset", uint64_t(1) << 40), f.count(key + ".count", uint64_t(1) << 40)};
        totals[size_t(level)] += r.count;
        if (level == lod) out.push_back(r);
    }
}

// Copies Gaussians [begin, begin + n) of `src` to `dst` from `at`; SH beyond src's degree stays zero.
void copy_gaussians(const GaussianCloud& src, uint64_t begin, uint64_t n, GaussianCloud& dst, size_t at) {
    const size_t sc = size_t(src.coeffs()) * 3, dc = size_t(dst.coeffs()) * 3;
    for (uint64_t k = 0; k < n; ++k) {
        const size_t i = size_t(begin + k), o = at + size_t(k);
        dst.mean[o] = src.mean[i];
        dst.log_scale[o] = src.log_scale[i];
        dst.rotation[o] = src.rotation[i];
        dst.opacity_logit[o] = src.opacity_logit[i];
        std::copy_n(&src.sh[i * sc], std::min(sc, dc), &dst.sh[o * dc]);
    }
}

GaussianCloud read_streamed(const LodMeta& m, int lod, const LoadProgress& progress) {
    const MetaFields f(m.json, m.where);
    if (lod >= m.levels)
        throw InputError(m.where, "LOD level " + std::to_string(lod) + " asked for; the scene has " +
                                      std::to_string(m.levels) + " (0 to " + std::to_string(m.levels - 1) + ")");
    std::vector<LodRange> ranges;
    std::vector<uint64_t> totals(size_t(m.levels), 0);
    collect_ranges(m, f, "tree", 0, lod, ranges, totals);

    std::map<size_t, std::vector<size_t>> by_file;  // chunk -> its ranges, in tree order
    std::vector<size_t> at(ranges.size());
    size_t total = 0;
    for (size_t r = 0; r < ranges.size(); ++r) {
        at[r] = total;
        total += size_t(ranges[r].count);
        by_file[ranges[r].file].push_back(r);
    }
    std::vector<GaussianCloud> env;
    if (const auto* e = f.find("environment")) {
        if (!e->is_string() || !is_safe_relative_name(e->get<std::string>()))
            f.fail("environment", "must name a meta file by a relative path without '..'");
        const SogUnit u = open_unit(m.dir / e->get<std::string>());
        env.push_back(decode_sog(u.meta, u.files, u.where));
    }

    GaussianCloud out;
    out.format = SceneFormat::Sog;
    out.sh_degree = env.empty() ? 0 : env[0].sh_degree;
    size_t done = 0;
    bool sized = false;
    // Every range against its chunk's declared count before anything is allocated; ranges that
    // overlap could claim more Gaussians than the chunks hold.
    uint64_t held = 0;
    std::map<size_t, SogUnit> units;
    for (const auto& [file, members] : by_file) {
        const SogUnit& u = units[file] = open_unit(m.dir / m.filenames[file]);
        int version = 0, degree = 0;
        uint64_t count = 0;
        sog_meta_shape(u.meta, u.where, version, count, degree);
        for (size_t r : members)
            if (ranges[r].offset + ranges[r].count > count)
                throw InputError(m.where, "a tree leaf's level-" + std::to_string(lod) + " range [" +
                                              std::to_string(ranges[r].offset) + ", " +
                                              std::to_string(ranges[r].offset + ranges[r].count) + ") runs past " +
                                              m.filenames[file] + ", which holds " + std::to_string(count) +
                                              " Gaussians");
        held += count;
    }
    if (total > held)
        throw InputError(m.where, "level " + std::to_string(lod) + "'s ranges overlap: they cover " +
                                      std::to_string(total) + " Gaussians of chunks holding " + std::to_string(held));
    for (const auto& [file, members] : by_file) {
        const SogUnit& u = units[file];
        const GaussianCloud c = decode_sog(u.meta, u.files, u.where);  // holds the count checked above
        if (!sized || c.sh_degree > out.sh_degree) {
            // (Re)size on the first chunk or a higher SH degree; copies so far are redone below.
            GaussianCloud grown;
            grown.format = SceneFormat::Sog;
            grown.sh_degree = std::max(out.sh_degree, c.sh_degree);
            grown.resize(total + (env.empty() ? 0 : env[0].size()));
            if (sized) copy_gaussians(out, 0, out.size(), grown, 0);
            out = std::move(grown);
            sized = true;
        }
        for (size_t r : members) copy_gaussians(c, ranges[r].offset, ranges[r].count, out, at[r]);
        if (progress) progress(double(++done) / double(by_file.size()));
    }
    if (!sized) {
        out.resize(env.empty() ? 0 : env[0].size());
    }
    if (!env.empty()) copy_gaussians(env[0], 0, env[0].size(), out, total);
    if (out.size() == 0) throw InputError(m.where, "LOD level " + std::to_string(lod) + " holds no Gaussians");
    return out;
}

fs::path resolve_entry(const fs::path& path) {
    std::error_code ec;
    if (!fs::is_directory(path, ec)) return path;
    if (auto entry = sog_folder_entry(path)) return *entry;
    throw InputError(path.string(), "is a folder without lod-meta.json, meta.json or scene.sog");
}

}  // namespace

const char* sog_layout_name(SogLayout layout) {
    switch (layout) {
        case SogLayout::Bundled: return "bundled";
        case SogLayout::Unbundled: return "unbundled";
        case SogLayout::Streamed: return "streamed";
    }
    return "?";
}

std::optional<fs::path> sog_folder_entry(const fs::path& folder) {
    std::error_code ec;
    for (const char* name : {"lod-meta.json", "meta.json", "scene.sog"})
        if (fs::is_regular_file(folder / name, ec)) return folder / name;
    return std::nullopt;
}

GaussianCloud read_sog(const fs::path& path, int lod, const LoadProgress& progress) {
    const fs::path entry = resolve_entry(path);
    if (lod < 0) throw InputError(entry.string(), "LOD level " + std::to_string(lod) + " is negative");
    if (!starts_with_zip_magic(entry)) {
        auto json = parse_sog_json(read_meta_file(entry), entry.string());
        if (is_lod_meta(json)) {
            GaussianCloud c = read_streamed(open_lod_meta(entry, std::move(json)), lod, progress);
            validate_cloud(c, entry.string());
            return c;
        }
    }
    if (lod > 0)
        throw InputError(entry.string(), "LOD level " + std::to_string(lod) +
                                             " asked for, but only a streamed SOG (lod-meta.json) has levels");
    const SogUnit u = open_unit(entry);
    GaussianCloud c = decode_sog(u.meta, u.files, u.where, progress);
    validate_cloud(c, entry.string());
    return c;
}

SogSummary describe_sog(const fs::path& path) {
    const fs::path entry = resolve_entry(path);
    SogSummary s;
    auto shape = [&](const SogUnit& u, int& version, uint64_t& count, int& degree) {
        sog_meta_shape(u.meta, u.where, version, count, degree);
        if (degree < 0) {  // v1: the palette image's width tells the degree
            degree = 0;
            const auto* shn = u.meta.contains("shN") ? &u.meta["shN"] : nullptr;
            if (shn && shn->contains("files") && (*shn)["files"].is_array() && !(*shn)["files"].empty() &&
                (*shn)["files"][0].is_string()) {
                const std::string name = (*shn)["files"][0].get<std::string>();
                if (is_safe_relative_name(name)) {
                    const RgbaImage img = decode_webp(u.files.read(name, uint64_t(1) << 31), 65536 * 15, u.files.where(name));
                    degree = v1_bands_from_width(img.width);
                }
            }
        }
    };
    if (!starts_with_zip_magic(entry)) {
        auto json = parse_sog_json(read_meta_file(entry), entry.string());
        if (is_lod_meta(json)) {
            const LodMeta m = open_lod_meta(entry, std::move(json));
            const MetaFields f(m.json, m.where);
            s.layout = SogLayout::Streamed;
            s.lod_levels = m.levels;
            std::vector<LodRange> ranges;
            s.lod_counts.assign(size_t(m.levels), 0);
            collect_ranges(m, f, "tree", 0, 0, ranges, s.lod_counts);
            uint64_t count = 0;
            shape(open_unit(m.dir / m.filenames[0]), s.version, count, s.sh_degree);
            if (const auto* e = f.find("environment"); e && e->is_string() && is_safe_relative_name(e->get<std::string>())) {
                int v = 0, d = 0;
                shape(open_unit(m.dir / e->get<std::string>()), v, s.environment, d);
            }
            s.count = s.lod_counts[0] + s.environment;
            return s;
        }
    }
    const SogUnit u = open_unit(entry);
    s.layout = u.layout;
    shape(u, s.version, s.count, s.sh_degree);
    return s;
}

}  // namespace pg::data
