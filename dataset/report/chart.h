#pragma once
// Line charts as pictures (training curves, IoU against clicks): panels stacked top to bottom,
// each with its axes, ticks at round values, a legend, drawn into an RGB image with stb's easy
// font. Host-side only; written with write_png8.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "dataset/formats/image_io.h"

namespace pg::data::report {

struct ChartSeries {
    std::string name;
    std::array<uint8_t, 3> colour{0, 0, 0};
    std::vector<std::pair<double, double>> points;  // (x, y); non-finite points are skipped
    bool markers = false;                           // a dot at every point (sparse series)
};

struct ChartPanel {
    std::string title, x_label;
    std::vector<ChartSeries> series;
    std::optional<double> y_min, y_max;  // fixed range (else the data's, padded)
};

// An RGB image `width` wide, `panel_height` per panel. Panels without a finite point show
// their title and empty axes.
Image8 draw_chart(const std::vector<ChartPanel>& panels, int width = 900, int panel_height = 320);

}  // namespace pg::data::report
