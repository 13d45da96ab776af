#pragma once
// Work a newer request has made pointless (the viewer's next click while a solve runs): long
// loops look at a flag between GPU submissions and stop by throwing Cancelled. Nothing is left
// half-updated: caches hold only what was finished before the throw.
#include <atomic>
#include <stdexcept>

namespace pg::seg {

struct Cancelled : std::runtime_error {
    Cancelled() : std::runtime_error("cancelled") {}
};

inline void stop_if_cancelled(const std::atomic<bool>* flag) {
    if (flag && flag->load(std::memory_order_relaxed)) throw Cancelled();
}

}  // namespace pg::seg
