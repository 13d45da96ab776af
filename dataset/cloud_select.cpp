#include "dataset/cloud_select.h"

#include <algorithm>
#include <stdexcept>

namespace pg::data {

GaussianCloud select_gaussians(const GaussianCloud& cloud, const std::vector<uint32_t>& indices) {
    GaussianCloud out;
    out.sh_degree = cloud.sh_degree;
    out.flat = cloud.flat;
    out.format = cloud.format;
    out.ply_property_order = cloud.ply_property_order;
    out.ply_comments = cloud.ply_comments;
    for (const auto& e : cloud.extras) out.extras.push_back({e.name, e.type, {}});
    out.resize(indices.size());
    const size_t k = size_t(cloud.coeffs()) * 3;
    for (size_t j = 0; j < indices.size(); ++j) {
        const size_t i = indices[j];
        if (i >= cloud.size()) throw std::out_of_range("select_gaussians: index past the cloud");
        out.mean[j] = cloud.mean[i];
        out.log_scale[j] = cloud.log_scale[i];
        out.rotation[j] = cloud.rotation[i];
        out.opacity_logit[j] = cloud.opacity_logit[i];
        std::copy_n(cloud.sh.begin() + long(i * k), k, out.sh.begin() + long(j * k));
        for (size_t e = 0; e < cloud.extras.size(); ++e) out.extras[e].values[j] = cloud.extras[e].values[i];
    }
    return out;
}

}  // namespace pg::data
