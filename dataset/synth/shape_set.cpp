// Bounding volume hierarchy over the shapes, built by the surface area heuristic (scenes mix
// room-sized boxes with millimetre parts, which median splits handle badly); traversal
// visits the nearer child first and prunes by the best hit so far.
#include <algorithm>
#include <numeric>

#include "dataset/synth/shape.h"

namespace pg::data::synth {
namespace {

double half_area(const Aabb& b) {
    if (b.empty()) return 0.0;
    const glm::dvec3 s = b.size();
    return s.x * s.y + s.y * s.z + s.z * s.x;
}

// Entry distance into a box, or +inf if the ray misses it within (t_min, t_max).
inline double enter_box(const Ray& ray, const glm::dvec3& inv, const Aabb& b, double t_min, double t_max) {
    double lo = t_min, hi = t_max;
    for (int a = 0; a < 3; ++a) {
        const double t1 = (b.lo[a] - ray.origin[a]) * inv[a], t2 = (b.hi[a] - ray.origin[a]) * inv[a];
        lo = std::max(lo, std::min(t1, t2));
        hi = std::min(hi, std::max(t1, t2));
    }
    return lo <= hi ? lo : kInf;
}

}  // namespace

ShapeSet::ShapeSet(std::vector<Shape> shapes) : shapes_(std::move(shapes)) {
    for (const Shape& s : shapes_) {
        boxes_.push_back(transform_box(s.frame, s.prim->bounds()));
        bounds_.grow(boxes_.back());
    }
    order_.resize(shapes_.size());
    std::iota(order_.begin(), order_.end(), 0);
    if (!shapes_.empty()) build(0, int(shapes_.size()), 0);
}

int ShapeSet::build(int first, int count, int depth) {
    const int index = int(nodes_.size());
    nodes_.push_back({});
    Aabb box;
    for (int k = first; k < first + count; ++k) box.grow(boxes_[order_[k]]);
    nodes_[index].box = box;
    // Best split over the three axes by centroid order: cost = area(L) n(L) + area(R) n(R).
    double best_cost = half_area(box) * count;
    int best_axis = -1, best_split = 0;
    std::vector<double> right_area(size_t(count) + 1);
    for (int axis = 0; axis < 3 && count > 1 && depth < 60; ++axis) {  // depth bounds the stacks
        std::sort(order_.begin() + first, order_.begin() + first + count, [&](int a, int b) {
            const double ca = boxes_[a].centre()[axis], cb = boxes_[b].centre()[axis];
            return ca < cb || (ca == cb && a < b);
        });
        Aabb acc;
        for (int k = count - 1; k >= 1; --k) {
            acc.grow(boxes_[order_[first + k]]);
            right_area[size_t(k)] = half_area(acc);
        }
        acc = Aabb{};
        for (int k = 1; k < count; ++k) {
            acc.grow(boxes_[order_[first + k - 1]]);
            const double cost = half_area(acc) * k + right_area[size_t(k)] * (count - k) + 0.5 * half_area(box);
            if (cost < best_cost) {
                best_cost = cost;
                best_axis = axis;
                best_split = k;
            }
        }
    }
    if (best_axis < 0 || count <= 1) {
        nodes_[index].first = first;
        nodes_[index].count = count;
        return index;
    }
    std::sort(order_.begin() + first, order_.begin() + first + count, [&](int a, int b) {
        const double ca = boxes_[a].centre()[best_axis], cb = boxes_[b].centre()[best_axis];
        return ca < cb || (ca == cb && a < b);
    });
    const int left = build(first, best_split, depth + 1);
    const int right = build(first + best_split, count - best_split, depth + 1);
    nodes_[index].left = left;
    nodes_[index].right = right;
    return index;
}

bool ShapeSet::first_hit(const Ray& ray, double t_min, double t_max, Hit& hit) const {
    return nearest(ray, t_min, t_max, hit, false);
}

bool ShapeSet::shadow_hit(const Ray& ray, double t_min, double t_max, Hit& hit) const {
    return nearest(ray, t_min, t_max, hit, true);
}

bool ShapeSet::nearest(const Ray& ray, double t_min, double t_max, Hit& hit, bool shadow_only) const {
    if (nodes_.empty()) return false;
    const glm::dvec3 inv = 1.0 / ray.dir;
    double best = t_max;
    int best_shape = -1;
    struct Entry {
        int node;
        double t;
    };
    Entry stack[128];
    int top = 0;
    const double t_root = enter_box(ray, inv, nodes_[0].box, t_min, best);
    if (t_root < kInf) stack[top++] = {0, t_root};
    while (top > 0) {
        const Entry e = stack[--top];
        if (e.t >= best) continue;
        const Node& node = nodes_[size_t(e.node)];
        if (node.left < 0) {
            for (int k = node.first; k < node.first + node.count; ++k) {
                const Shape& s = shapes_[size_t(order_[k])];
                if (shadow_only && !s.casts_shadow) continue;
                double t;
                if (s.prim->intersect(s.frame.to_local(ray), t_min, best, t)) {
                    best = t;
                    best_shape = order_[k];
                }
            }
            continue;
        }
        const double tl = enter_box(ray, inv, nodes_[size_t(node.left)].box, t_min, best);
        const double tr = enter_box(ray, inv, nodes_[size_t(node.right)].box, t_min, best);
        // Push the farther child first so the nearer one is visited next.
        if (tl <= tr) {
            if (tr < kInf) stack[top++] = {node.right, tr};
            if (tl < kInf) stack[top++] = {node.left, tl};
        } else {
            if (tl < kInf) stack[top++] = {node.left, tl};
            if (tr < kInf) stack[top++] = {node.right, tr};
        }
    }
    if (best_shape < 0) return false;
    hit.t = best;
    hit.shape = best_shape;
    return true;
}

bool ShapeSet::inside(const glm::dvec3& p, int skip) const {
    if (nodes_.empty()) return false;
    int stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const Node& node = nodes_[size_t(stack[--top])];
        if (!node.box.contains(p)) continue;
        if (node.left < 0) {
            for (int k = node.first; k < node.first + node.count; ++k) {
                const int s = order_[k];
                if (s != skip && boxes_[size_t(s)].contains(p) && shapes_[size_t(s)].prim->contains(shapes_[size_t(s)].frame.to_local(p)))
                    return true;
            }
            continue;
        }
        stack[top++] = node.left;
        stack[top++] = node.right;
    }
    return false;
}

}  // namespace pg::data::synth
