#include "dataset/clicks/mask.h"

#include <string>

#include "dataset/error.h"

namespace pg::data::clicks {

double iou(std::span<const uint8_t> gt, std::span<const uint8_t> prediction) {
    if (gt.size() != prediction.size())
        throw InputError("click simulation", "prediction has " + std::to_string(prediction.size()) +
                                                 " entries, ground truth " + std::to_string(gt.size()));
    size_t both = 0, either = 0;
    for (size_t i = 0; i < gt.size(); ++i) {
        const bool g = gt[i] != 0, p = prediction[i] != 0;
        both += g && p;
        either += g || p;
    }
    return either == 0 ? 1.0 : double(both) / double(either);
}

template <class T>
static Mask mask_of_impl(std::span<const T> labels, T id) {
    Mask m(labels.size());
    for (size_t i = 0; i < labels.size(); ++i) m[i] = labels[i] == id;
    return m;
}

Mask mask_of(std::span<const int32_t> labels, int32_t id) { return mask_of_impl(labels, id); }
Mask mask_of(std::span<const uint16_t> labels, uint16_t id) { return mask_of_impl(labels, id); }

size_t count(std::span<const uint8_t> mask) {
    size_t n = 0;
    for (uint8_t v : mask) n += v != 0;
    return n;
}

}  // namespace pg::data::clicks
