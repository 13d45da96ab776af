// load_scene: picks the reader from the file's first bytes, then its extension.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>

#include "dataset/error.h"
#include "dataset/formats/scene_io.h"
#include "dataset/formats/sog.h"

namespace pg::data {

namespace fs = std::filesystem;

void validate_cloud(const GaussianCloud& cloud, const std::string& where) {
    auto fail = [&](size_t i, const std::string& property, float v) {
        throw InputError(where, "vertex " + std::to_string(i) + ": property '" + property + "' is " +
                                    (std::isnan(v) ? "nan" : v > 0 ? "+inf" : "-inf") + " (must be finite)");
    };
    static const char* kMean[3] = {"x", "y", "z"};
    static const char* kScale[3] = {"scale_0", "scale_1", "scale_2"};
    static const char* kRot[4] = {"rot_0", "rot_1", "rot_2", "rot_3"};
    for (size_t i = 0; i < cloud.size(); ++i) {
        for (int k = 0; k < 3; ++k)
            if (!std::isfinite(cloud.mean[i][k])) fail(i, kMean[k], cloud.mean[i][k]);
        for (int k = 0; k < 3; ++k)
            if (!std::isfinite(cloud.log_scale[i][k])) fail(i, kScale[k], cloud.log_scale[i][k]);
        for (int k = 0; k < 4; ++k)
            if (!std::isfinite(cloud.rotation[i][k])) fail(i, kRot[k], cloud.rotation[i][k]);
        if (!std::isfinite(cloud.opacity_logit[i])) fail(i, "opacity", cloud.opacity_logit[i]);
        const glm::vec4& q = cloud.rotation[i];
        if (q.x == 0.0f && q.y == 0.0f && q.z == 0.0f && q.w == 0.0f)
            throw InputError(where, "vertex " + std::to_string(i) + ": rotation quaternion (rot_0..rot_3) has zero length");
    }
}

namespace {

GaussianCloud load_single_level(const fs::path& path, const LoadProgress& progress);

bool ends_with(const std::string& s, const std::string& tail) {
    return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

}  // namespace

GaussianCloud load_scene(const fs::path& path, const LoadProgress& progress, int lod) {
    const std::string where = path.string();
    std::error_code ec;
    if (fs::is_directory(path, ec)) {
        if (sog_folder_entry(path)) return read_sog(path, lod, progress);
        throw InputError(where, "is a directory, expected a scene file (or a SOG folder holding meta.json)");
    }
    if (!fs::exists(path, ec)) throw InputError(where, "no such file");
    std::string name = path.filename().string();
    std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return std::tolower(c); });
    unsigned char zip[4] = {0, 0, 0, 0};
    {
        std::ifstream in(path, std::ios::binary);
        in.read(reinterpret_cast<char*>(zip), sizeof zip);
    }
    const bool is_zip = zip[0] == 'P' && zip[1] == 'K' && zip[2] == 3 && zip[3] == 4;
    const bool other_format = ends_with(name, ".ply") || ends_with(name, ".splat") || ends_with(name, ".spz");
    if ((is_zip && !other_format) || ends_with(name, ".sog") || ends_with(name, ".json"))
        return read_sog(path, lod, progress);
    if (lod != 0)
        throw InputError(where, "LOD level " + std::to_string(lod) +
                                    " asked for, but only a streamed SOG (lod-meta.json) has levels");
    return load_single_level(path, progress);
}

namespace {

GaussianCloud load_single_level(const fs::path& path, const LoadProgress& progress) {
    const std::string where = path.string();

    unsigned char magic[4] = {0, 0, 0, 0};
    std::streamsize got = 0;
    {
        std::ifstream in(path, std::ios::binary);
        if (!in) throw InputError(where, "cannot open for reading");
        in.read(reinterpret_cast<char*>(magic), sizeof magic);
        got = in.gcount();
    }
    if (got == 0) throw InputError(where, "empty file");
    if (got >= 4 && magic[0] == 'p' && magic[1] == 'l' && magic[2] == 'y' && (magic[3] == '\n' || magic[3] == '\r'))
        return read_ply(path, progress);
    if (got >= 2 && magic[0] == 0x1f && magic[1] == 0x8b) return read_spz(path);
    if (got >= 4 && magic[0] == 'N' && magic[1] == 'G' && magic[2] == 'S' && magic[3] == 'P') return read_spz(path);

    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    if (ext == ".ply") return read_ply(path, progress);  // reports what is wrong with the header
    if (ext == ".splat") return read_splat(path);
    if (ext == ".spz") return read_spz(path);
    throw InputError(where, "unknown scene format" + (ext.empty() ? std::string() : " '" + ext + "'") +
                                ": expected a PLY (.ply), .splat, .spz or SOG (.sog, meta.json, lod-meta.json) file");
}

}  // namespace

}  // namespace pg::data
