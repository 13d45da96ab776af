#include "dataset/atomic_file.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <random>

#include "dataset/error.h"

namespace pg::data {

namespace fs = std::filesystem;

void write_atomically(const fs::path& path, const std::function<void(std::ostream&)>& write) {
    std::random_device rd;
    fs::path tmp = path;
    tmp += ".tmp" + std::to_string(rd() % 1000000);
    try {
        {
            std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
            if (!out) throw InputError(path.string(), std::string("cannot write: ") + std::strerror(errno));
            write(out);
            out.flush();
            if (!out) throw InputError(path.string(), "write failed (disk full?)");
        }
        fs::rename(tmp, path);
    } catch (...) {
        std::error_code ec;
        fs::remove(tmp, ec);
        throw;
    }
}

std::vector<char> read_file(const fs::path& path) {
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    if (!in) throw InputError(path.string(), fs::exists(path) ? "cannot open for reading" : "no such file");
    std::streamsize n = in.tellg();
    if (n < 0) throw InputError(path.string(), "cannot determine file size");
    std::vector<char> data(static_cast<size_t>(n));
    in.seekg(0);
    if (n > 0 && !in.read(data.data(), n)) throw InputError(path.string(), "read failed");
    return data;
}

std::string read_text_file(const fs::path& path) {
    auto bytes = read_file(path);
    return std::string(bytes.begin(), bytes.end());
}

}  // namespace pg::data
