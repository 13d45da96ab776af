#include "dataset/report/chart.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include <stb_easy_font.h>

namespace pg::data::report {

namespace {

using Rgb = std::array<uint8_t, 3>;
constexpr Rgb kInk{40, 40, 40}, kGrid{225, 225, 225}, kFrame{120, 120, 120};
constexpr int kTextScale = 2;  // easy-font glyphs are ~6 px tall: doubled to read

// The font has printable ASCII only.
std::string printable(std::string s) {
    for (char& ch : s)
        if (ch < 32 || ch > 126) ch = '?';
    return s;
}

struct Canvas {
    Image8& img;
    void fill(int x0, int y0, int x1, int y1, Rgb c) {
        x0 = std::max(x0, 0), y0 = std::max(y0, 0), x1 = std::min(x1, img.width), y1 = std::min(y1, img.height);
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) std::copy(c.begin(), c.end(), &img.pixels[(size_t(y) * img.width + x) * 3]);
    }
    // A line `thick` px wide (a square brush stepped along the longer axis).
    void line(double x0, double y0, double x1, double y1, Rgb c, int thick) {
        const int steps = int(std::ceil(std::max(std::fabs(x1 - x0), std::fabs(y1 - y0)))) + 1;
        for (int i = 0; i <= steps; ++i) {
            const double t = double(i) / steps;
            const int x = int(std::lround(x0 + t * (x1 - x0))) - thick / 2, y = int(std::lround(y0 + t * (y1 - y0))) - thick / 2;
            fill(x, y, x + thick, y + thick, c);
        }
    }
    static int text_width(const std::string& s) {
        std::string p = printable(s);
        return stb_easy_font_width(p.data()) * kTextScale;
    }
    static int text_height() { return 7 * kTextScale; }
    void text(int x, int y, const std::string& text, Rgb c) {
        std::string s = printable(text);
        std::vector<float> quads(s.size() * 64 * 16 + 16);  // up to 64 quads of 16 floats per glyph
        const int n = stb_easy_font_print(0, 0, s.data(), nullptr, quads.data(), int(quads.size() * sizeof(float)));
        for (int q = 0; q < n; ++q) {
            const float* v = &quads[size_t(q) * 16];  // 4 vertices of (x, y, z, colour)
            fill(x + int(v[0]) * kTextScale, y + int(v[1]) * kTextScale, x + int(v[8]) * kTextScale,
                 y + int(v[9]) * kTextScale, c);
        }
    }
};

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
    const int left = 14 + 6 * 7 * kTextScale, right = width - 16;
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
