#include "dataset/clicks/view_choice.h"

#include <algorithm>

namespace pg::data::clicks {

size_t visible_area(std::span<const uint16_t> ids, uint16_t id) {
    return size_t(std::count(ids.begin(), ids.end(), id));
}

std::optional<size_t> choose_view_for_object(std::span<const std::vector<uint16_t>> views, uint16_t id) {
    std::optional<size_t> best;
    size_t best_area = 0;
    for (size_t v = 0; v < views.size(); ++v) {
        const size_t area = visible_area(views[v], id);
        if (area > best_area) {  // strict: the lower index keeps a tie
            best_area = area;
            best = v;
        }
    }
    return best;
}

}  // namespace pg::data::clicks
