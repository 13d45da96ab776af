#pragma once
// A file's bytes for a parser that reads it front to back: mapped read-only where the system
// allows it (else read into memory), and `release(upto)` hands the pages before `upto` back to
// the kernel, so parsing a large file into a cloud does not hold the file and the cloud at once.
#include <cstddef>
#include <filesystem>
#include <vector>

namespace pg::data {

class MappedFile {
public:
    // InputError naming the path when it cannot be opened or read.
    explicit MappedFile(const std::filesystem::path& path);
    ~MappedFile();
    MappedFile(const MappedFile&) = delete;
    MappedFile& operator=(const MappedFile&) = delete;

    const char* data() const { return data_; }
    size_t size() const { return size_; }
    // The bytes before `upto` will not be read again (reading them still works: the pages come
    // back from the file).
    void release(size_t upto);

private:
    const char* data_ = nullptr;
    size_t size_ = 0;
    void* map_ = nullptr;       // the mapping, or null when the bytes were read into `copy_`
    size_t released_ = 0;
    std::vector<char> copy_;
};

}  // namespace pg::data
