// Ground-truth masks by ray casting the shapes at every pixel centre.
#include <algorithm>
#include <atomic>
#include <thread>

#include "dataset/synth/synth.h"

namespace pg::data::synth {

Ray camera_ray(const Camera& cam, double u, double v) {
    const glm::dvec3 d_cam((u - cam.cx) / cam.fx, (v - cam.cy) / cam.fy, 1.0);
    return Ray{cam.position(), glm::normalize(glm::transpose(cam.R) * d_cam)};
}

namespace {

void cast_row(const ShapeSet& shapes, const Camera& cam, bool semantic, int v, uint16_t* row) {
    for (int u = 0; u < cam.width; ++u) {
        Hit hit;
        uint16_t id = 0;
        const Ray ray = camera_ray(cam, u + 0.5, v + 0.5);
        if (shapes.first_hit(ray, 0.0, kInf, hit)) {
            const Shape& s = shapes.shapes()[size_t(hit.shape)];
            const int label = semantic ? s.class_of(s.frame.to_local(ray.origin + hit.t * ray.dir)) : s.instance;
            id = uint16_t(std::clamp(label, 0, 65535));
        }
        row[u] = id;
    }
}

}  // namespace

std::vector<uint16_t> cast_mask(const ShapeSet& shapes, const Camera& cam, bool semantic) {
    std::vector<uint16_t> mask(size_t(cam.width) * size_t(cam.height));
    for (int v = 0; v < cam.height; ++v) cast_row(shapes, cam, semantic, v, mask.data() + size_t(v) * cam.width);
    return mask;
}

std::vector<std::vector<uint16_t>> cast_masks(const ShapeSet& shapes, const std::vector<Camera>& cams, bool semantic,
                                              int threads) {
    std::vector<std::vector<uint16_t>> masks(cams.size());
    std::vector<std::pair<int, int>> rows;  // (camera, row), the unit of work
    for (size_t c = 0; c < cams.size(); ++c) {
        masks[c].resize(size_t(cams[c].width) * size_t(cams[c].height));
        for (int v = 0; v < cams[c].height; ++v) rows.emplace_back(int(c), v);
    }
    std::atomic<size_t> next{0};
    auto work = [&] {
        for (size_t i = next++; i < rows.size(); i = next++) {
            const auto [c, v] = rows[i];
            cast_row(shapes, cams[size_t(c)], semantic, v, masks[size_t(c)].data() + size_t(v) * cams[size_t(c)].width);
        }
    };
    if (threads <= 0) threads = int(std::max(1u, std::thread::hardware_concurrency()));
    std::vector<std::thread> pool;
    for (int t = 1; t < threads; ++t) pool.emplace_back(work);
    work();
    for (auto& t : pool) t.join();
    return masks;
}

}  // namespace pg::data::synth
