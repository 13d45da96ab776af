#include "dataset/clicks/click3d.h"

#include <cmath>
#include <string>

#include "dataset/clicks/components.h"
#include "dataset/clicks/interior_point.h"
#include "dataset/clicks/mask.h"
#include "dataset/clicks/point_grid.h"
#include "dataset/error.h"

namespace pg::data::clicks {
namespace {

void check_size(std::span<const uint8_t> mask, size_t n, const char* what) {
    if (mask.size() != n)
        throw InputError("click simulation", std::string(what) + " has " + std::to_string(mask.size()) +
                                                 " entries for " + std::to_string(n) + " Gaussians");
}

}  // namespace

Clicker3D::Clicker3D(std::span<const glm::vec3> positions, Clicker3DOptions options)
    : positions_(positions.begin(), positions.end()) {
    for (size_t i = 0; i < positions_.size(); ++i)
        if (!std::isfinite(positions_[i].x) || !std::isfinite(positions_[i].y) || !std::isfinite(positions_[i].z))
            throw InputError("click simulation", "Gaussian " + std::to_string(i) + " has a non-finite mean");
    link_radius_ = options.link_radius > 0 ? options.link_radius : kLinkSpacings * median_spacing(positions_);
    // A cloud of coincident points has no spacing: link coincident points only.
    if (!(link_radius_ > 0)) link_radius_ = 1e-6f;
}

std::optional<Click3D> Clicker3D::first_click(std::span<const uint8_t> gt) const {
    return next_click(gt, Mask(gt.size(), 0));
}

std::optional<Click3D> Clicker3D::next_click(std::span<const uint8_t> gt, std::span<const uint8_t> prediction,
                                             std::span<const size_t> clicked) const {
    check_size(gt, size(), "ground truth mask");
    check_size(prediction, size(), "prediction mask");
    Mask is_clicked(size(), 0);
    for (size_t c : clicked)
        if (c < size()) is_clicked[c] = 1;
    Mask missed(size()), wrong(size());
    for (size_t i = 0; i < size(); ++i) {
        missed[i] = gt[i] && !prediction[i];
        wrong[i] = prediction[i] && !gt[i];
    }
    // A region made only of clicked Gaussians leaves the race, and the next largest is taken.
    for (;;) {
        const Components fn = point_components(positions_, missed, link_radius_);
        const Components fp = point_components(positions_, wrong, link_radius_);
        const std::optional<ErrorRegion> error = largest_error_region(fn, fp);
        if (!error) return std::nullopt;
        const Components& chosen = error->positive ? fn : fp;
        const int32_t id = error->id;

        // Clicked Gaussians count as outside the region, so the most interior point keeps away
        // from them as from the region's boundary.
        Mask region(size());
        std::vector<uint32_t> members;
        members.reserve(chosen.size[id]);
        for (size_t i = 0; i < size(); ++i)
            if (chosen.label[i] == id && !is_clicked[i]) {
                region[i] = 1;
                members.push_back(uint32_t(i));
            }
        if (members.empty()) {
            Mask& from = error->positive ? missed : wrong;
            for (size_t i = 0; i < size(); ++i)
                if (chosen.label[i] == id) from[i] = 0;
            continue;
        }
        const uint32_t i = most_interior_point(positions_, region, members, link_radius_, link_radius_ / kLinkSpacings);
        return Click3D{i, positions_[i], error->positive};
    }
}

}  // namespace pg::data::clicks
