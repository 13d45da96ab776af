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
// Semantic class at a point of the shape, in its local coordinates: for shapes that span
// several classes (the campus terrain: roads, lawns, fields painted on one heightfield).
using ClassAt = std::function<int(const glm::dvec3& local_p)>;

// Distance from a point of the shape (local coordinates) to the nearest edge the images show
// on it: a painted border (a road meeting a lawn), the foot of a wall standing on it.
using PatternEdge = std::function<double(const glm::dvec3& local_p)>;

struct Material {
    Albedo albedo;
    // Empty: none. Otherwise each region between such edges is fitted like a solid's outline:
    // Gaussians shrink towards the edge and none lies within the silhouette inset of it.
    PatternEdge edge;
    float gloss = 0.02f;         // strength of the view-dependent SH terms
    float colour_noise = 0.04f;  // per-Gaussian brightness/hue noise
    float fuzz = 0.0f;           // 0: a hard surface; 1: foliage (loose, tilted, translucent splats)
    float aligned = 0.0f;        // 1: long axes follow the surface tangent (grain); 0: any angle
    // Centres sink below the surface by the silhouette inset (splats.cpp), which fits curved
    // outlines. false: they stay on it, for terrain, whose outline is a far horizon but whose
    // painted edges must not shift in oblique views.
    bool sink = true;
    // Parts thinner than the silhouette inset (lamp posts, cars seen from far away): false,
    // no Gaussians; true, a few at their core, as an optimiser fits what it can of them.
    bool keep_thin = false;
};

struct Shape {
    PrimitivePtr prim;
    Frame frame;                 // local to world
    int instance = 0;            // 0: background
    int cls = 0;
    ClassAt class_at;            // empty: `cls` everywhere
    Material material;
    double sigma = 0.01;         // Gaussian in-plane sd on large flat areas, scene units
    bool casts_shadow = true;    // false for rooms around the light

    // The class at a local point; the Gaussians' labels and the masks both ask this.
    int class_of(const glm::dvec3& local_p) const { return class_at ? class_at(local_p) : cls; }
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
