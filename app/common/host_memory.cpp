#include "app/common/host_memory.h"

#include <fstream>
#include <string>

namespace pg::app {

namespace {
uint64_t status_bytes(const char* field) {
    std::ifstream status("/proc/self/status");
    const std::string key = std::string(field) + ":";
    std::string line;
    while (std::getline(status, line))
        if (line.rfind(key, 0) == 0) return std::stoull(line.substr(key.size())) * 1024;  // kB
    return 0;
}
}  // namespace

uint64_t resident_host_bytes() { return status_bytes("VmRSS"); }
uint64_t peak_host_bytes() { return status_bytes("VmHWM"); }

}  // namespace pg::app
