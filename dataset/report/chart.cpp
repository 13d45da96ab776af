#include "dataset/report/chart.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "dataset/report/canvas.h"

namespace pg::data::report {

namespace {

using Rgb = std::array<uint8_t, 3>;
constexpr Rgb kInk{40, 40, 40}, kGrid{225, 225, 225}, kFrame{120, 120, 120};

// Round tick spacing giving about `target` intervals over [lo, hi].
double tick_step(double lo, double hi, int target) {
    const double raw = (hi - lo) / target, mag = std::pow(10.0, std::floor(std::log10(raw)));
    for (double m : {1.0, 2.0, 5.0, 10.0})
        if (raw <= m * mag) return m * mag;
    return 10 * mag;
}

std::string tick_label(double v, double step) {
    char buf[32];
    const int decimals = step >= 1 ? 0 : std::min(6, int(std::ceil(-std::log10(step) - 1e-9)));
    std::snprintf(buf, sizeof buf, "%.*f", decimals, std::fabs(v) < step * 1e-6 ? 0.0 : v);
    return buf;
}

void draw_panel(Canvas& cv, const ChartPanel& p, int top, int width, int height) {
    const int th = Canvas::text_height();
    const int left = 14 + 6 * Canvas::text_height(), right = width - 16;
    cv.text(left, top + 8, p.title, kInk);
    // Legend right-aligned on the title's line, or on a line of its own when they would meet.
    int legend_width = 0;
    for (const auto& s : p.series)
        if (!s.name.empty()) legend_width += cv.text_width(s.name) + 50;
    const bool own_line = right - legend_width < left + cv.text_width(p.title) + 20;
    const int legend_y = own_line ? top + 8 + th + 8 : top + 8;
    const int plot_top = legend_y + th + 12, bottom = top + height - (p.x_label.empty() ? th + 20 : 2 * th + 26);

    double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
    for (const auto& s : p.series)
        for (const auto& [x, y] : s.points)
            if (std::isfinite(x) && std::isfinite(y)) x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    if (!(x0 <= x1)) x0 = 0, x1 = 1, y0 = 0, y1 = 1;
    if (x1 - x0 < 1e-12) x0 -= 0.5, x1 += 0.5;
    if (p.y_min) y0 = *p.y_min;
    if (p.y_max) y1 = *p.y_max;
    if (!p.y_min && !p.y_max) {
        const double pad = std::max(y1 - y0, 1e-9) * 0.05;
        y0 -= pad, y1 += pad;
    }
    if (y1 - y0 < 1e-12) y0 -= 0.5, y1 += 0.5;
    auto px = [&](double x) { return left + (x - x0) / (x1 - x0) * (right - left); };
    auto py = [&](double y) { return bottom - (y - y0) / (y1 - y0) * (bottom - plot_top); };

    const double ys = tick_step(y0, y1, 5), xs = tick_step(x0, x1, 8);
    for (double v = std::ceil(y0 / ys) * ys; v <= y1 + ys * 1e-9; v += ys) {
        const int y = int(std::lround(py(v)));
        cv.fill(left, y, right, y + 1, kGrid);
        const std::string s = tick_label(v, ys);
        cv.text(left - 8 - cv.text_width(s), y - th / 2, s, kInk);
    }
    for (double v = std::ceil(x0 / xs) * xs; v <= x1 + xs * 1e-9; v += xs) {
        const int x = int(std::lround(px(v)));
        cv.fill(x, plot_top, x + 1, bottom, kGrid);
        const std::string s = tick_label(v, xs);
        cv.text(x - cv.text_width(s) / 2, bottom + 6, s, kInk);
    }
    cv.fill(left, plot_top, right, plot_top + 1, kFrame);
    cv.fill(left, bottom, right, bottom + 1, kFrame);
    cv.fill(left, plot_top, left + 1, bottom, kFrame);
    cv.fill(right - 1, plot_top, right, bottom, kFrame);
    if (!p.x_label.empty()) cv.text((left + right - cv.text_width(p.x_label)) / 2, bottom + th + 14, p.x_label, kInk);

    for (const auto& s : p.series) {
        bool have = false;
        double lx = 0, ly = 0;
        for (const auto& [x, y] : s.points) {
            if (!std::isfinite(x) || !std::isfinite(y)) {
                have = false;
                continue;
            }
            const double X = px(x), Y = std::clamp(py(std::clamp(y, y0, y1)), double(plot_top), double(bottom));
            if (have) cv.line(lx, ly, X, Y, s.colour, 2);
            if (s.markers) cv.fill(int(X) - 3, int(Y) - 3, int(X) + 4, int(Y) + 4, s.colour);
            lx = X, ly = Y, have = true;
        }
    }
    int x = right;
    for (auto it = p.series.rbegin(); it != p.series.rend(); ++it) {
        if (it->name.empty()) continue;
        x -= cv.text_width(it->name);
        cv.text(x, legend_y, it->name, kInk);
        cv.fill(x - 26, legend_y + th / 2 - 2, x - 6, legend_y + th / 2 + 2, it->colour);
        x -= 26 + 24;
    }
}

}  // namespace

Image8 draw_chart(const std::vector<ChartPanel>& panels, int width, int panel_height) {
    if (width < 200 || panel_height < 120) throw std::invalid_argument("draw_chart: the picture must be at least 200 x 120 per panel");
    Image8 img;
    img.width = width;
    img.height = panel_height * int(std::max<size_t>(panels.size(), 1));
    img.channels = 3;
    img.pixels.assign(size_t(img.width) * img.height * 3, 255);
    Canvas cv{img};
    for (size_t i = 0; i < panels.size(); ++i) draw_panel(cv, panels[i], int(i) * panel_height, width, panel_height);
    return img;
}

}  // namespace pg::data::report
