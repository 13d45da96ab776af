#include "dataset/report/legend.h"

#include <algorithm>
#include <cmath>

#include "dataset/report/canvas.h"

namespace pg::data::report {

void draw_legend(Image8& img, const std::vector<LegendEntry>& entries) {
    if (entries.empty() || img.channels != 3) return;
    Canvas cv{img};
    const int line = Canvas::text_height() + 6, pad = 6, swatch = Canvas::text_height();
    int width = 0;
    for (const auto& e : entries) width = std::max(width, Canvas::text_width(e.name));
    cv.fill(0, 0, 3 * pad + swatch + width, 2 * pad + line * int(entries.size()) - 6, {255, 255, 255});
    for (size_t i = 0; i < entries.size(); ++i) {
        const int y = pad + line * int(i);
        Canvas::Rgb c;
        for (int k = 0; k < 3; ++k) c[size_t(k)] = uint8_t(std::lround(std::clamp(entries[i].colour[k], 0.0f, 1.0f) * 255.0f));
        cv.fill(pad, y, pad + swatch, y + swatch, c);
        cv.text(2 * pad + swatch, y + 1, entries[i].name, {40, 40, 40});
    }
}

}  // namespace pg::data::report
