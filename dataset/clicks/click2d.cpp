#include "dataset/clicks/click2d.h"

#include <algorithm>
#include <string>
#include <vector>

#include "dataset/clicks/components.h"
#include "dataset/clicks/distance_transform.h"
#include "dataset/clicks/mask.h"
#include "dataset/error.h"

namespace pg::data::clicks {
namespace {

void check_size(int width, int height, std::span<const uint8_t> mask, const char* what) {
    if (width <= 0 || height <= 0 || mask.size() != size_t(width) * size_t(height))
        throw InputError("click simulation", std::string(what) + " has " + std::to_string(mask.size()) +
                                                 " pixels for a " + std::to_string(width) + "x" +
                                                 std::to_string(height) + " view");
}

// The most interior pixel of the pixels where region(x, y) holds, searched within the box
// [x0, x1] x [y0, y1] that contains them all. Distances are computed on the box alone:
// its one-pixel surround is outside the region (other pixels or beyond the image), and
// no outside pixel farther away can be nearer than the surround straight across.
template <class InRegion>
Click2D most_interior(int width, int x0, int y0, int x1, int y1, InRegion region, bool positive) {
    const int bw = x1 - x0 + 1, bh = y1 - y0 + 1;
    std::vector<uint8_t> box(size_t(bw) * bh);
    for (int y = 0; y < bh; ++y)
        for (int x = 0; x < bw; ++x) box[size_t(y) * bw + x] = region(size_t(y0 + y) * width + x0 + x);
    const std::vector<double> d = squared_distance_to_outside(bw, bh, box);
    size_t best = 0;
    double best_d = -1;
    for (size_t i = 0; i < d.size(); ++i)  // row-major within the box = row-major in the image
        if (box[i] && d[i] > best_d) {
            best_d = d[i];
            best = i;
        }
    return Click2D{x0 + int(best % bw), y0 + int(best / bw), positive};
}

}  // namespace

std::optional<Click2D> first_click_2d(int width, int height, std::span<const uint8_t> gt) {
    return next_click_2d(width, height, gt, Mask(gt.size(), 0));
}

std::optional<Click2D> next_click_2d(int width, int height, std::span<const uint8_t> gt,
                                     std::span<const uint8_t> prediction) {
    check_size(width, height, gt, "ground truth mask");
    check_size(width, height, prediction, "prediction mask");
    const size_t n = gt.size();
    Mask missed(n), wrong(n);
    for (size_t i = 0; i < n; ++i) {
        missed[i] = gt[i] && !prediction[i];
        wrong[i] = prediction[i] && !gt[i];
    }
    const Components fn = pixel_components(width, height, missed);
    const Components fp = pixel_components(width, height, wrong);
    const std::optional<ErrorRegion> region = largest_error_region(fn, fp);
    if (!region) return std::nullopt;
    const Components& chosen = region->positive ? fn : fp;
    const int32_t id = region->id;

    int x0 = width, y0 = height, x1 = -1, y1 = -1;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            if (chosen.label[size_t(y) * width + x] == id) {
                x0 = std::min(x0, x), x1 = std::max(x1, x);
                y0 = std::min(y0, y), y1 = std::max(y1, y);
            }
    return most_interior(width, x0, y0, x1, y1, [&](size_t i) { return chosen.label[i] == id; }, region->positive);
}

}  // namespace pg::data::clicks
