#pragma once
// A placed, labelled solid of a synthetic scene, and the set of them with a bounding volume
// hierarchy for exact first-hit queries (ground-truth masks, shadows) and inside tests
// (hiding the surfaces where solids touch).
#include <functional>
#include <vector>

#include "dataset/synth/primitives.h"

namespace pg::data::synth {

// Colour before lighting at a point of the shape, in the shape's local coordinates.
using Albedo = std::function<glm::vec3(const glm::dvec3& local_p, const glm::dvec3& local_n)>;

struct Material {
    Albedo albedo;
    float gloss = 0.02f;         // strength of the view-dependent SH terms
    float colour_noise = 0.04f;  // per-Gaussian brightness/hue noise
    float fuzz = 0.0f;           // 0: a hard surface; 1: foliage (loose, tilted, translucent splats)
    float aligned = 0.0f;        // 1: long axes follow the surface tangent (grain); 0: any angle
};

struct Shape {
    PrimitivePtr prim;
    Frame frame;                 // local to world
    int instance = 0;            // 0: background
    int cls = 0;
    Material material;
    double sigma = 0.01;         // Gaussian in-plane sd on large flat areas, scene units
    bool casts_shadow = true;    // false for rooms around the light
};

struct Hit {
    double t = kInf;
    int shape = -1;
};

class ShapeSet {
public:
    ShapeSet() = default;
    explicit ShapeSet(std::vector<Shape> shapes);

    const std::vector<Shape>& shapes() const { return shapes_; }
    size_t size() const { return shapes_.size(); }
    const Aabb& bounds() const { return bounds_; }

    // Nearest surface crossing with t in (t_min, t_max) over every shape.
    bool first_hit(const Ray& ray, double t_min, double t_max, Hit& hit) const;
    // The same over the shapes that cast shadows.
    bool shadow_hit(const Ray& ray, double t_min, double t_max, Hit& hit) const;
    // Whether p lies inside some shape other than `skip` (-1: none skipped).
    bool inside(const glm::dvec3& p, int skip = -1) const;

private:
    struct Node {
        Aabb box;
        int left = -1, right = -1;  // children, or -1 for a leaf
        int first = 0, count = 0;   // leaf range in order_
    };
    int build(int first, int count, int depth);
    bool nearest(const Ray& ray, double t_min, double t_max, Hit& hit, bool shadow_only) const;

    std::vector<Shape> shapes_;
    std::vector<Aabb> boxes_;       // world bounds per shape
    std::vector<int> order_;        // shape indices, grouped by leaf
    std::vector<Node> nodes_;
    Aabb bounds_;
};

}  // namespace pg::data::synth
