#pragma once
// One self-rewriting progress line on a terminal; silent when stderr is not a terminal or
// when CI is set, so logs stay clean.
#include <cstdio>
#include <cstdlib>
#include <string>

#include <unistd.h>

namespace pg::app {

class Progress {
public:
    Progress(std::string label, size_t total)
        : label_(std::move(label)), total_(total), enabled_(isatty(2) && !std::getenv("CI") && total > 1) {}
    ~Progress() { finish(); }
    void step(const std::string& item = {}) {
        ++done_;
        if (!enabled_) return;
        std::fprintf(stderr, "\r%s %zu/%zu %s\x1b[K", label_.c_str(), done_, total_, item.c_str());
        std::fflush(stderr);
    }
    void finish() {
        if (enabled_ && done_) std::fprintf(stderr, "\n");
        enabled_ = false;
    }

private:
    std::string label_;
    size_t total_, done_ = 0;
    bool enabled_;
};

}  // namespace pg::app
