#include "dataset/report/canvas.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <stb_easy_font.h>

namespace pg::data::report {

namespace {

constexpr int kTextScale = 2;  // easy-font glyphs are ~6 px tall: doubled to read

// The font has printable ASCII only.
std::string printable(std::string s) {
    for (char& ch : s)
        if (ch < 32 || ch > 126) ch = '?';
    return s;
}

}  // namespace

void Canvas::fill(int x0, int y0, int x1, int y1, Rgb c) {
    x0 = std::max(x0, 0), y0 = std::max(y0, 0), x1 = std::min(x1, img.width), y1 = std::min(y1, img.height);
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) std::copy(c.begin(), c.end(), &img.pixels[(size_t(y) * size_t(img.width) + size_t(x)) * 3]);
}

void Canvas::line(double x0, double y0, double x1, double y1, Rgb c, int thick) {
    const int steps = int(std::ceil(std::max(std::fabs(x1 - x0), std::fabs(y1 - y0)))) + 1;
    for (int i = 0; i <= steps; ++i) {
        const double t = double(i) / steps;
        const int x = int(std::lround(x0 + t * (x1 - x0))) - thick / 2, y = int(std::lround(y0 + t * (y1 - y0))) - thick / 2;
        fill(x, y, x + thick, y + thick, c);
    }
}

int Canvas::text_width(const std::string& s) {
    std::string p = printable(s);
    return stb_easy_font_width(p.data()) * kTextScale;
}

int Canvas::text_height() { return 7 * kTextScale; }

void Canvas::text(int x, int y, const std::string& text, Rgb c) {
    std::string s = printable(text);
    std::vector<float> quads(s.size() * 64 * 16 + 16);  // up to 64 quads of 16 floats per glyph
    const int n = stb_easy_font_print(0, 0, s.data(), nullptr, quads.data(), int(quads.size() * sizeof(float)));
    for (int q = 0; q < n; ++q) {
        const float* v = &quads[size_t(q) * 16];  // 4 vertices of (x, y, z, colour)
        fill(x + int(v[0]) * kTextScale, y + int(v[1]) * kTextScale, x + int(v[8]) * kTextScale,
             y + int(v[9]) * kTextScale, c);
    }
}

}  // namespace pg::data::report
