#pragma once
// This process's host memory from /proc/self/status, in bytes (0 where it is not available).
#include <cstdint>

namespace pg::app {

uint64_t resident_host_bytes();  // VmRSS: now
uint64_t peak_host_bytes();      // VmHWM: the most so far

}  // namespace pg::app
