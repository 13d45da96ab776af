#pragma once
// Reading zip archives (a bundled .sog) through libzip. Every entry name is checked when the
// archive opens: an absolute name or one with a ".." part is refused, whether or not it is read.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

struct zip;

namespace pg::data {

class ZipReader {
public:
    // InputError naming the file if it is not a readable zip or holds an unsafe entry name.
    explicit ZipReader(const std::filesystem::path& path);
    ~ZipReader();
    ZipReader(const ZipReader&) = delete;
    ZipReader& operator=(const ZipReader&) = delete;

    bool contains(const std::string& name) const;
    // The entry's bytes; InputError if it is missing, larger than `max_bytes`, or its data is
    // truncated or fails its CRC.
    std::vector<uint8_t> read(const std::string& name, uint64_t max_bytes) const;
    const std::vector<std::string>& names() const { return names_; }

private:
    std::string where_;
    zip* archive_ = nullptr;
    std::vector<std::string> names_;
};

// Stored (uncompressed) entries, as SOG's WebP images gain nothing from deflate.
struct ZipEntry {
    std::string name;
    std::vector<uint8_t> bytes;
};
// Writes `entries` as a zip through write_atomically: InputError naming `path` on failure, with
// no file left behind.
void write_zip(const std::filesystem::path& path, const std::vector<ZipEntry>& entries);

// True for a relative name without ".." parts, empty parts or backslashes: safe to look up in
// an archive or under a folder.
bool is_safe_relative_name(const std::string& name);

}  // namespace pg::data
