#include "dataset/atomic_file.h"

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <fstream>
#include <random>

#include <unistd.h>

#include "dataset/error.h"

namespace pg::data {

namespace fs = std::filesystem;

namespace {

// The temporaries being written, for the signal handler: fixed storage, claimed with an atomic
// flag, read by the handler with nothing but unlink (async-signal-safe).
constexpr size_t kSlots = 32, kPathBytes = 4096;
char g_pending[kSlots][kPathBytes];
std::atomic<bool> g_claimed[kSlots];
std::atomic<bool> g_ready[kSlots];

// Registers a temporary for the handler while it exists; a path too long or too many writes at
// once only go without the handler's cleanup.
class PendingFile {
public:
    explicit PendingFile(const fs::path& tmp) {
        const std::string s = tmp.string();
        if (s.size() >= kPathBytes) return;
        for (size_t i = 0; i < kSlots; ++i) {
            bool expected = false;
            if (g_claimed[i].compare_exchange_strong(expected, true)) {
                std::memcpy(g_pending[i], s.c_str(), s.size() + 1);
                g_ready[i].store(true);
                slot_ = int(i);
                return;
            }
        }
    }
    ~PendingFile() {
        if (slot_ < 0) return;
        g_ready[size_t(slot_)].store(false);
        g_claimed[size_t(slot_)].store(false);
    }
    PendingFile(const PendingFile&) = delete;
    PendingFile& operator=(const PendingFile&) = delete;

private:
    int slot_ = -1;
};

extern "C" void remove_pending_and_die(int sig) {
    for (size_t i = 0; i < kSlots; ++i)
        if (g_ready[i].load()) ::unlink(g_pending[i]);
    std::signal(sig, SIG_DFL);
    std::raise(sig);
}

}  // namespace

void remove_partial_files_on_signals() {
    std::signal(SIGINT, remove_pending_and_die);
    std::signal(SIGTERM, remove_pending_and_die);
    std::signal(SIGXFSZ, SIG_IGN);
}

void write_atomically(const fs::path& path, const std::function<void(std::ostream&)>& write) {
    std::random_device rd;
    fs::path tmp = path;
    tmp += ".tmp" + std::to_string(rd() % 1000000);
    const PendingFile pending(tmp);
    try {
        {
            std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
            if (!out) throw InputError(path.string(), std::string("cannot write: ") + std::strerror(errno));
            errno = 0;
            write(out);
            out.flush();
            if (!out) throw InputError(path.string(), std::string("write failed: ") + (errno ? std::strerror(errno) : "disk full?"));
            out.close();
            if (!out) throw InputError(path.string(), std::string("write failed: ") + (errno ? std::strerror(errno) : "disk full?"));
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
