// ZipReader and write_zip over libzip.
#include "dataset/formats/zip_archive.h"

#include <zip.h>


#include "dataset/atomic_file.h"
#include "dataset/error.h"

namespace pg::data {

namespace {

std::string zip_error_text(int code) {
    zip_error_t e;
    zip_error_init_with_code(&e, code);
    std::string text = zip_error_strerror(&e);
    zip_error_fini(&e);
    return text;
}

}  // namespace

bool is_safe_relative_name(const std::string& name) {
    if (name.empty() || name.front() == '/' || name.find('\\') != std::string::npos) return false;
    if (name.size() >= 2 && name[1] == ':') return false;  // a drive letter
    size_t start = 0;
    while (start <= name.size()) {
        size_t end = name.find('/', start);
        if (end == std::string::npos) end = name.size();
        const std::string part = name.substr(start, end - start);
        if (part == ".." || (part.empty() && end != name.size())) return false;
        start = end + 1;
    }
    return true;
}

ZipReader::ZipReader(const std::filesystem::path& path) : where_(path.string()) {
    int error = 0;
    archive_ = zip_open(where_.c_str(), ZIP_RDONLY | ZIP_CHECKCONS, &error);
    if (!archive_) throw InputError(where_, "not a readable zip archive (" + zip_error_text(error) + ")");
    const zip_int64_t n = zip_get_num_entries(archive_, 0);
    for (zip_int64_t i = 0; i < n; ++i) {
        const char* name = zip_get_name(archive_, zip_uint64_t(i), ZIP_FL_ENC_RAW);
        std::string s = name ? name : "";
        if (!s.empty() && s.back() == '/') continue;  // a folder entry
        if (!is_safe_relative_name(s)) {
            zip_discard(archive_);
            throw InputError(where_, "zip entry '" + s + "' has an absolute or '..' name (refused)");
        }
        names_.push_back(std::move(s));
    }
}

ZipReader::~ZipReader() {
    if (archive_) zip_discard(archive_);
}

bool ZipReader::contains(const std::string& name) const { return zip_name_locate(archive_, name.c_str(), 0) >= 0; }

std::vector<uint8_t> ZipReader::read(const std::string& name, uint64_t max_bytes) const {
    const std::string where = where_ + ": " + name;
    const zip_int64_t index = zip_name_locate(archive_, name.c_str(), 0);
    if (index < 0) throw InputError(where_, "zip archive has no entry '" + name + "'");
    zip_stat_t st;
    zip_stat_init(&st);
    if (zip_stat_index(archive_, zip_uint64_t(index), 0, &st) != 0 || !(st.valid & ZIP_STAT_SIZE))
        throw InputError(where, "zip entry's size is unreadable");
    if (st.size > max_bytes)
        throw InputError(where, "zip entry claims " + std::to_string(st.size) + " bytes, more than the " +
                                    std::to_string(max_bytes) + " allowed (refused before reading)");
    zip_file_t* file = zip_fopen_index(archive_, zip_uint64_t(index), 0);
    if (!file) throw InputError(where, std::string("cannot open zip entry (") + zip_strerror(archive_) + ")");
    std::vector<uint8_t> bytes(st.size);
    const zip_int64_t got = st.size ? zip_fread(file, bytes.data(), st.size) : 0;
    std::string problem;
    if (got < 0) problem = zip_file_strerror(file);
    else if (zip_uint64_t(got) != st.size)
        problem = "ends after " + std::to_string(got) + " of " + std::to_string(st.size) + " bytes";
    zip_fclose(file);
    if (!problem.empty()) throw InputError(where, "zip entry data is truncated or corrupt (" + problem + ")");
    return bytes;
}

void write_zip(const std::filesystem::path& path, const std::vector<ZipEntry>& entries) {
    // The archive is built in memory (SOG bundles are megabytes), then written like every other
    // output: a temporary sibling renamed at the end, removed on failure or on a signal.
    const std::string where = path.string();
    zip_error_t error;
    zip_error_init(&error);
    zip_source_t* memory = zip_source_buffer_create(nullptr, 0, 0, &error);
    zip_t* z = memory ? zip_open_from_source(memory, ZIP_TRUNCATE, &error) : nullptr;
    if (!z) {
        const std::string why = zip_error_strerror(&error);
        if (memory) zip_source_free(memory);
        zip_error_fini(&error);
        throw InputError(where, "zip: " + why);
    }
    zip_error_fini(&error);
    zip_source_keep(memory);  // outlives zip_close, which leaves the archive's bytes in it
    auto fail = [&](const std::string& why) {
        zip_discard(z);
        zip_source_free(memory);
        throw InputError(where, "zip: " + why);
    };
    for (const auto& e : entries) {
        zip_source_t* src = zip_source_buffer(z, e.bytes.data(), e.bytes.size(), 0);
        if (!src) fail(zip_strerror(z));
        const zip_int64_t i = zip_file_add(z, e.name.c_str(), src, ZIP_FL_ENC_UTF_8 | ZIP_FL_OVERWRITE);
        if (i < 0) {
            zip_source_free(src);
            fail(zip_strerror(z));
        }
        // A fixed time stamp (2024-01-01 UTC), so the same entries give the same archive bytes.
        if (zip_set_file_compression(z, zip_uint64_t(i), ZIP_CM_STORE, 0) != 0 ||
            zip_file_set_mtime(z, zip_uint64_t(i), time_t(1704067200), 0) != 0)
            fail(zip_strerror(z));
    }
    if (zip_close(z) != 0) fail(zip_strerror(z));
    std::vector<char> bytes;
    zip_stat_t st;
    zip_stat_init(&st);
    const bool ok = zip_source_stat(memory, &st) == 0 && zip_source_open(memory) == 0;
    if (ok) {
        bytes.resize(st.size);
        const zip_int64_t got = st.size ? zip_source_read(memory, bytes.data(), st.size) : 0;
        zip_source_close(memory);
        if (got != zip_int64_t(st.size)) bytes.clear();
    }
    zip_source_free(memory);
    if (!ok || bytes.size() != st.size) throw InputError(where, "zip: cannot read back the archive built in memory");
    write_atomically(path, [&](std::ostream& os) { os.write(bytes.data(), std::streamsize(bytes.size())); });
}

}  // namespace pg::data
