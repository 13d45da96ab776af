#include "dataset/eval/label_overlap.h"

#include <stdexcept>
#include <string>

namespace pg::data::eval {

namespace {

template <class T>
void accumulate(LabelOverlap& o, std::span<const T> g, std::span<const T> p) {
    if (g.size() != p.size())
        throw std::invalid_argument("LabelOverlap::add: " + std::to_string(g.size()) + " GT labels but " +
                                    std::to_string(p.size()) + " predicted");
    // Unsigned compare folds the negative ids into "out of range".
    const uint64_t n = o.ids();
    uint64_t agree = 0;
    for (size_t i = 0; i < g.size(); ++i) {
        const T a = g[i], b = p[i];
        const uint64_t ua = uint64_t(int64_t(a)), ub = uint64_t(int64_t(b));
        if (ua < n) ++o.gt[ua];
        if (ub < n) ++o.pred[ub];
        if (a == b) {
            ++agree;
            if (ua < n) ++o.both[ua];
        }
    }
    o.total += g.size();
    o.agree += agree;
}

}  // namespace

void LabelOverlap::add(std::span<const int32_t> g, std::span<const int32_t> p) { accumulate(*this, g, p); }
void LabelOverlap::add(std::span<const uint16_t> g, std::span<const uint16_t> p) { accumulate(*this, g, p); }

std::optional<double> LabelOverlap::iou(int32_t k) const {
    if (k < 0 || size_t(k) >= ids()) return std::nullopt;
    const uint64_t uni = gt[size_t(k)] + pred[size_t(k)] - both[size_t(k)];
    if (uni == 0) return std::nullopt;
    return double(both[size_t(k)]) / double(uni);
}

std::optional<double> LabelOverlap::accuracy() const {
    if (total == 0) return std::nullopt;
    return double(agree) / double(total);
}

}  // namespace pg::data::eval
