// Line charts (dataset/report/chart.h): series land where their values say, in their colours; text,
// legends and empty or non-finite data draw without failing.
#include <catch2/catch.hpp>

#include <cmath>
#include <stdexcept>

#include "dataset/report/chart.h"

using namespace pg::data;
using namespace pg::data::report;

namespace {

bool has_colour(const Image8& img, int x0, int y0, int x1, int y1, std::array<uint8_t, 3> c) {
    for (int y = std::max(y0, 0); y < std::min(y1, img.height); ++y)
        for (int x = std::max(x0, 0); x < std::min(x1, img.width); ++x) {
            const uint8_t* p = &img.pixels[(size_t(y) * img.width + x) * 3];
            if (p[0] == c[0] && p[1] == c[1] && p[2] == c[2]) return true;
        }
    return false;
}

// Rows of column x holding colour c.
std::vector<int> rows_with(const Image8& img, int x, std::array<uint8_t, 3> c) {
    std::vector<int> rows;
    for (int y = 0; y < img.height; ++y)
        if (has_colour(img, x, y, x + 1, y + 1, c)) rows.push_back(y);
    return rows;
}

}  // namespace

TEST_CASE("draw_chart puts each series where its values are, in its colour") {
    const std::array<uint8_t, 3> red{200, 30, 30}, blue{30, 30, 200};
    ChartPanel p{"two lines", "step", {{"high", red, {{0, 0.8}, {100, 0.8}}}, {"rising", blue, {{0, 0.0}, {100, 1.0}}}}, 0.0, 1.0};
    const Image8 img = draw_chart({p}, 600, 300);
    REQUIRE(img.width == 600);
    REQUIRE(img.height == 300);
    REQUIRE(img.channels == 3);
    REQUIRE(img.pixels.size() == size_t(600 * 300 * 3));

    // At the middle column the flat line sits above the rising one (y grows downwards), and the
    // rising line there is about halfway between the flat line's row and the bottom (value 0.5 vs 0.8).
    const std::vector<int> high = rows_with(img, 300, red), rising = rows_with(img, 300, blue);
    REQUIRE_FALSE(high.empty());
    REQUIRE_FALSE(rising.empty());
    CHECK(high.back() < rising.front());
    // The rising line climbs: further right it is higher up.
    const std::vector<int> rising_right = rows_with(img, 450, blue);
    REQUIRE_FALSE(rising_right.empty());
    CHECK(rising_right.front() < rising.front());
    // The legend names the series in their colours on the title's line (top 30 px).
    CHECK(has_colour(img, 0, 0, 600, 30, red));
    CHECK(has_colour(img, 0, 0, 600, 30, blue));
    // Text is drawn: dark pixels in the title's corner.
    CHECK(has_colour(img, 0, 0, 200, 30, {40, 40, 40}));
}

TEST_CASE("draw_chart stacks panels and survives empty, constant and non-finite data") {
    const std::array<uint8_t, 3> green{20, 160, 20};
    ChartPanel empty{"nothing yet", "", {}, {}, {}};
    ChartPanel constant{"flat", "", {{"c", green, {{5, 2.0}, {5, 2.0}}}}, {}, {}};
    ChartPanel gaps{"gaps", "x", {{"g", green, {{0, 1}, {1, NAN}, {2, INFINITY}, {3, 2}}, true}}, {}, {}};
    const Image8 img = draw_chart({empty, constant, gaps}, 400, 200);
    CHECK(img.height == 600);
    CHECK_FALSE(has_colour(img, 0, 30, 400, 200, green));  // the empty panel has no series pixels
    CHECK(has_colour(img, 0, 200, 400, 400, green));
    CHECK(has_colour(img, 0, 400, 400, 600, green));
    CHECK_THROWS_AS(draw_chart({empty}, 50, 50), std::invalid_argument);
}
