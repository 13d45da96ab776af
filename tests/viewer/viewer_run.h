#pragma once
// Runs pointgauss-viewer (PG_VIEWER) under Xvfb with a script, and reads what it saved.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "dataset/formats/image_io.h"
#include "tests/app/cli_run.h"

namespace pg::test {

// `env`: assignments put before the command (NAME=value ...).
inline Run run_viewer(const std::string& args, const std::string& env = "") {
    REQUIRE(std::system("command -v xvfb-run >/dev/null 2>&1") == 0);  // tools/setup.sh installs xvfb
    const std::string command =
        env + (env.empty() ? "" : " ") + "xvfb-run -a -s '-screen 0 1280x1024x24' " + std::string(PG_VIEWER) + " " + args;
    // Under parallel tests xvfb-run can fail around the viewer: it exits 5 when removing its own
    // temporary folder fails (the viewer's exit status is lost), and `-a` can hand two servers
    // the same display number, so one viewer finds no display. Such a run is repeated.
    auto xvfb_failed = [](const Run& r) {
        return (r.code == 5 && r.out.find("problem while cleaning up temporary directory") != std::string::npos) ||
               (r.code == 1 && r.out.find("X11: Failed to open display") != std::string::npos);
    };
    Run r = run_command(command);
    for (int again = 0; again < 2 && xvfb_failed(r); ++again) r = run_command(command);
    return r;
}

inline std::filesystem::path write_script(const std::filesystem::path& dir, const nlohmann::json& actions) {
    auto p = dir / "script.json";
    std::ofstream(p) << nlohmann::json{{"actions", actions}}.dump(1);
    return p;
}

// A binary mask at `w` x `h` of the pixels where two same-sized RGB pictures differ by more
// than `threshold` in some channel, sampled at the centres of the smaller grid's pixels.
inline std::vector<bool> changed(const data::Image8& a, const data::Image8& b, int w, int h, int threshold = 24) {
    REQUIRE(a.width == b.width);
    REQUIRE(a.height == b.height);
    std::vector<bool> m(size_t(w) * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const int px = int((x + 0.5) * a.width / w), py = int((y + 0.5) * a.height / h);
            const size_t i = (size_t(py) * a.width + px) * a.channels;
            int d = 0;
            for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(int(a.pixels[i + c]) - int(b.pixels[i + c])));
            m[size_t(y) * w + x] = d > threshold;
        }
    return m;
}

inline double iou(const std::vector<bool>& a, const std::vector<bool>& b) {
    size_t i = 0, u = 0;
    for (size_t k = 0; k < a.size(); ++k) i += a[k] && b[k], u += a[k] || b[k];
    return u ? double(i) / double(u) : 1.0;
}

}  // namespace pg::test
