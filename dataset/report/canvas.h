#pragma once
// Drawing into an RGB8 image for the pictures the tools write (charts, legends): filled
// rectangles, thick lines and text in stb's easy font (printable ASCII, doubled to read).
#include <array>
#include <cstdint>
#include <string>

#include "dataset/formats/image_io.h"

namespace pg::data::report {

struct Canvas {
    using Rgb = std::array<uint8_t, 3>;
    Image8& img;
    void fill(int x0, int y0, int x1, int y1, Rgb c);
    // A line `thick` px wide (a square brush stepped along the longer axis).
    void line(double x0, double y0, double x1, double y1, Rgb c, int thick);
    static int text_width(const std::string& s);
    static int text_height();
    void text(int x, int y, const std::string& text, Rgb c);
};

}  // namespace pg::data::report
