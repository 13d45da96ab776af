#pragma once
// One self-rewriting progress line on a terminal; silent when stderr is not a terminal or
// when CI is set, so logs stay clean.
#include <cstdio>
#include <cstdlib>
#include <string>

#include "dataset/formats/scene_io.h"

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
    // Jumps to `done` of total (a percentage, bytes...); only forward moves are shown.
    void set(size_t done, const std::string& item = {}) {
        if (done <= done_) return;
        done_ = done - 1;
        step(item);
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

// load_scene with a percentage line on a terminal (a 6 M-Gaussian PLY takes ~15 s on 2 cores).
// `lod` picks a level of a streamed SOG (--lod).
inline data::GaussianCloud load_scene_shown(const std::string& path, int lod = 0) {
    Progress progress("loading " + path, 100);
    return data::load_scene(path, [&](double f) { progress.set(size_t(f * 100.0), "%"); }, lod);
}

}  // namespace pg::app
