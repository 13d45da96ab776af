#include "app/common/up_arg.h"

#include <cstdio>
#include <utility>

#include "dataset/error.h"
#include "dataset/up_axis.h"

namespace pg::app {

glm::dvec3 parse_up(const std::string& s) {
    static const std::pair<const char*, glm::dvec3> named[] = {
        {"x", {1, 0, 0}}, {"-x", {-1, 0, 0}}, {"y", {0, 1, 0}}, {"-y", {0, -1, 0}}, {"z", {0, 0, 1}}, {"-z", {0, 0, -1}}};
    for (auto& [n, v] : named)
        if (s == n) return v;
    glm::dvec3 v;
    char extra;
    if (std::sscanf(s.c_str(), "%lf,%lf,%lf%c", &v.x, &v.y, &v.z, &extra) != 3 || !(glm::length(v) > 0))
        throw data::InputError("--up", "expected x,y,z or one of x -x y -y z -z, got '" + s + "'");
    return glm::normalize(v);
}

glm::dvec3 resolve_up(const std::string& spec, const std::vector<data::Camera>& cameras,
                      const data::GaussianCloud& cloud) {
    if (spec == "cameras") return data::up_from_cameras(cameras);
    if (spec == "ground") return data::up_from_ground_plane(cloud);
    return parse_up(spec);
}

}  // namespace pg::app
