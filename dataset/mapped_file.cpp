#include "dataset/mapped_file.h"

#include <algorithm>

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "dataset/atomic_file.h"
#include "dataset/error.h"

namespace pg::data {

MappedFile::MappedFile(const std::filesystem::path& path) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    struct stat st {};
    if (fd >= 0 && ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && st.st_size > 0) {
        void* m = ::mmap(nullptr, size_t(st.st_size), PROT_READ, MAP_PRIVATE, fd, 0);
        if (m != MAP_FAILED) {
            map_ = m;
            data_ = static_cast<const char*>(m);
            size_ = size_t(st.st_size);
            ::madvise(m, size_, MADV_SEQUENTIAL);
        }
    }
    if (fd >= 0) ::close(fd);
    if (!map_) {  // empty, special or unmappable files: read them (read_file names the failure)
        copy_ = read_file(path);
        data_ = copy_.data();
        size_ = copy_.size();
    }
}

MappedFile::~MappedFile() {
    if (map_) ::munmap(map_, size_);
}

void MappedFile::release(size_t upto) {
    if (!map_) return;
    const size_t page = size_t(::sysconf(_SC_PAGESIZE));
    const size_t end = std::min(upto, size_) / page * page;
    if (end <= released_) return;
    ::madvise(static_cast<char*>(map_) + released_, end - released_, MADV_DONTNEED);
    released_ = end;
}

}  // namespace pg::data
