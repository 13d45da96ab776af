#pragma once
// Reading and writing 3DGS scenes. Every reader throws InputError naming the file and the
// problem on malformed input; none crashes or reads past the data.
#include <filesystem>
#include <functional>
#include <string>

#include "dataset/gaussian_cloud.h"

namespace pg::data {

// Called with the fraction of the Gaussians read so far, for a progress line (readers that
// report: binary and ASCII INRIA / 2DGS PLY, every 2^20 Gaussians).
using LoadProgress = std::function<void(double fraction)>;

// Picks the reader from the file's content (PLY header, gzip or zip magic) and extension; a
// folder holding a SOG meta is read as SOG. `lod` picks a level of a streamed SOG (0, the
// finest); any other scene has only level 0.
GaussianCloud load_scene(const std::filesystem::path& path, const LoadProgress& progress = {}, int lod = 0);

GaussianCloud read_ply(const std::filesystem::path& path,         // INRIA, 2DGS, PlayCanvas compressed
                       const LoadProgress& progress = {});
GaussianCloud read_splat(const std::filesystem::path& path);      // antimatter15 .splat
GaussianCloud read_spz(const std::filesystem::path& path);        // Niantic .spz (gzip)
// PlayCanvas SOG (formats/sog.h): a bundled .sog, an unbundled meta.json (or its folder), or a
// streamed lod-meta.json, v1 or v2. A streamed scene's environment Gaussians follow level `lod`'s.
GaussianCloud read_sog(const std::filesystem::path& path, int lod = 0, const LoadProgress& progress = {});

// Throws InputError(where, ...) naming the Gaussian and the property if a mean, scale,
// rotation or opacity logit is not finite, or a rotation quaternion has zero length.
// Every reader runs it on what it loaded.
void validate_cloud(const GaussianCloud& cloud, const std::string& where);

// Writes a binary little-endian INRIA PLY. Properties the cloud was read with keep their
// order and type; extras not in that order follow. Written to a temporary file and renamed,
// so a failure leaves no partial output. Known properties are written as float.
void write_ply(const GaussianCloud& cloud, const std::filesystem::path& path);

}  // namespace pg::data
