// Click simulation (dataset/clicks): hand-built 2D and 3D cases with known answers, brute
// force references for the distance transforms, components and interior-point search,
// the session driver, the view choice, and a 300k-point run.
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include "dataset/clicks/click2d.h"
#include "dataset/clicks/click3d.h"
#include "dataset/clicks/components.h"
#include "dataset/clicks/distance_transform.h"
#include "dataset/clicks/interior_point.h"
#include "dataset/clicks/kd_tree.h"
#include "dataset/clicks/mask.h"
#include "dataset/clicks/session.h"
#include "dataset/clicks/view_choice.h"
#include "dataset/error.h"
#include "dataset/synth/synth.h"

using namespace pg::data::clicks;
using pg::data::InputError;

namespace {

// splitmix64: the same stream on every platform.
struct Rng {
    uint64_t s;
    uint64_t next() {
        uint64_t z = (s += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    float uniform() { return float(next() >> 40) * (1.0f / 16777216.0f); }
};

struct Image {
    int w, h;
    Mask m;
    Image(int w_, int h_) : w(w_), h(h_), m(size_t(w_) * h_, 0) {}
    void fill(int x0, int y0, int x1, int y1, uint8_t v = 1) {  // inclusive
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) m[size_t(y) * w + x] = v;
    }
    bool at(int x, int y) const { return m[size_t(y) * w + x] != 0; }
};

// Squared distance to the nearest outside pixel, the border ring counting as outside.
double brute_distance_to_outside(const Image& img, int x, int y) {
    double best = 1e300;
    for (int yy = -1; yy <= img.h; ++yy)
        for (int xx = -1; xx <= img.w; ++xx) {
            const bool outside = xx < 0 || yy < 0 || xx >= img.w || yy >= img.h || !img.at(xx, yy);
            if (outside) best = std::min(best, double(xx - x) * (xx - x) + double(yy - y) * (yy - y));
        }
    return best;
}

// The most interior pixel of a mask by brute force, lowest row-major index on ties.
std::pair<int, int> brute_most_interior(const Image& img) {
    double best = -1;
    std::pair<int, int> at{-1, -1};
    for (int y = 0; y < img.h; ++y)
        for (int x = 0; x < img.w; ++x)
            if (img.at(x, y)) {
                const double d = brute_distance_to_outside(img, x, y);
                if (d > best) best = d, at = {x, y};
            }
    return at;
}

// A regular grid of points with spacing 1, index = x + nx * (y + ny * z).
struct Lattice {
    int nx, ny, nz;
    std::vector<glm::vec3> p;
    Lattice(int nx_, int ny_, int nz_) : nx(nx_), ny(ny_), nz(nz_) {
        for (int z = 0; z < nz; ++z)
            for (int y = 0; y < ny; ++y)
                for (int x = 0; x < nx; ++x) p.emplace_back(float(x), float(y), float(z));
    }
    size_t index(int x, int y, int z) const { return size_t(x) + size_t(nx) * (size_t(y) + size_t(ny) * z); }
    Mask box(glm::ivec3 lo, glm::ivec3 hi) const {  // inclusive
        Mask m(p.size(), 0);
        for (int z = lo.z; z <= hi.z; ++z)
            for (int y = lo.y; y <= hi.y; ++y)
                for (int x = lo.x; x <= hi.x; ++x) m[index(x, y, z)] = 1;
        return m;
    }
};

Mask unite(const Mask& a, const Mask& b) {
    Mask m(a.size());
    for (size_t i = 0; i < a.size(); ++i) m[i] = a[i] || b[i];
    return m;
}
Mask subtract(const Mask& a, const Mask& b) {
    Mask m(a.size());
    for (size_t i = 0; i < a.size(); ++i) m[i] = a[i] && !b[i];
    return m;
}

// The documented interior rule by brute force: distance to the nearest non-member capped
// at max(half the largest side, min_cap); at the cap, nearest to the capped members'
// centroid; lowest index on ties.
uint32_t brute_most_interior_point(const std::vector<glm::vec3>& p, const Mask& in, float min_cap) {
    std::vector<uint32_t> members;
    glm::dvec3 lo(1e300), hi(-1e300);
    for (size_t i = 0; i < p.size(); ++i)
        if (in[i]) {
            members.push_back(uint32_t(i));
            lo = glm::min(lo, glm::dvec3(p[i]));
            hi = glm::max(hi, glm::dvec3(p[i]));
        }
    if (members.size() == 1) return members[0];
    const glm::dvec3 side = hi - lo;
    const double cap = std::max(0.5 * std::max({side.x, side.y, side.z}), double(min_cap)), cap2 = cap * cap;
    double best2 = -1;
    uint32_t best = 0;
    std::vector<uint32_t> at_cap;
    for (uint32_t i : members) {
        double d2 = cap2;
        for (size_t j = 0; j < p.size(); ++j)
            if (!in[j]) {
                const glm::dvec3 d = glm::dvec3(p[j]) - glm::dvec3(p[i]);
                d2 = std::min(d2, glm::dot(d, d));
            }
        if (d2 > best2) best2 = d2, best = i;
        if (d2 >= cap2) at_cap.push_back(i);
    }
    if (best2 < cap2 || at_cap.size() < 2) return best;
    glm::dvec3 c(0);
    for (uint32_t i : at_cap) c += glm::dvec3(p[i]);
    c /= double(at_cap.size());
    double near2 = 1e300;
    for (uint32_t i : at_cap) {
        const glm::dvec3 d = glm::dvec3(p[i]) - c;
        if (glm::dot(d, d) < near2) near2 = glm::dot(d, d), best = i;
    }
    return best;
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Distance transforms and components against brute force

TEST_CASE("clicks: 2D distance transform is exact and treats the border as outside", "[clicks]") {
    Rng rng{7};
    for (int trial = 0; trial < 20; ++trial) {
        Image img(1 + int(rng.next() % 23), 1 + int(rng.next() % 17));
        const float density = 0.5f + 0.5f * rng.uniform();
        for (auto& v : img.m) v = rng.uniform() < density;
        const std::vector<double> d = squared_distance_to_outside(img.w, img.h, img.m);
        for (int y = 0; y < img.h; ++y)
            for (int x = 0; x < img.w; ++x)
                REQUIRE(d[size_t(y) * img.w + x] == (img.at(x, y) ? brute_distance_to_outside(img, x, y) : 0.0));
    }
    Image full(5, 3);
    full.fill(0, 0, 4, 2);
    const std::vector<double> d = squared_distance_to_outside(5, 3, full.m);
    CHECK(d[0] == 1);           // corner pixel: the padding is one pixel away
    CHECK(d[1 * 5 + 2] == 4);   // middle of a 5x3 image: two pixels from the top/bottom padding
}

TEST_CASE("clicks: 3D grid distance transform is exact", "[clicks]") {
    Rng rng{11};
    const int nx = 9, ny = 7, nz = 6;
    std::vector<double> grid(size_t(nx) * ny * nz, kFar);
    std::vector<glm::ivec3> sites;
    for (int k = 0; k < 5; ++k) {
        glm::ivec3 s(int(rng.next() % nx), int(rng.next() % ny), int(rng.next() % nz));
        sites.push_back(s);
        grid[(size_t(s.z) * ny + s.y) * nx + s.x] = 0;
    }
    squared_edt_3d(grid, nx, ny, nz);
    for (int z = 0; z < nz; ++z)
        for (int y = 0; y < ny; ++y)
            for (int x = 0; x < nx; ++x) {
                double best = kFar;
                for (glm::ivec3 s : sites) {
                    const glm::ivec3 d = s - glm::ivec3(x, y, z);
                    best = std::min(best, double(d.x * d.x + d.y * d.y + d.z * d.z));
                }
                REQUIRE(grid[(size_t(z) * ny + y) * nx + x] == best);
            }
    std::vector<double> empty(8, kFar);
    squared_edt_3d(empty, 2, 2, 2);
    CHECK(empty[5] == kFar);
}

TEST_CASE("clicks: pixel components are 8-connected and numbered by first pixel", "[clicks]") {
    Image img(8, 6);
    img.fill(0, 0, 1, 1);  // a 2x2 block
    img.fill(2, 2, 2, 2);  // touching it by a corner only: same component
    img.fill(5, 0, 7, 4);  // a separate 3x5 block
    const Components c = pixel_components(img.w, img.h, img.m);
    REQUIRE(c.size.size() == 2);
    CHECK(c.size[0] == 5);
    CHECK(c.first[0] == 0);
    CHECK(c.size[1] == 15);
    CHECK(c.first[1] == 5);
    CHECK(c.largest() == 1);
    CHECK(c.label[size_t(2) * 8 + 2] == 0);
}

TEST_CASE("clicks: point components link points closer than the radius", "[clicks]") {
    Rng rng{3};
    std::vector<glm::vec3> p(1500);
    for (auto& q : p) q = glm::vec3(rng.uniform(), rng.uniform(), rng.uniform()) * 4.0f;
    Mask in(p.size());
    for (auto& v : in) v = rng.uniform() < 0.6f;
    const float r = 0.3f;
    const Components c = point_components(p, in, r);
    // Brute force: flood fill over all pairs.
    std::vector<int> label(p.size(), -1);
    int n = 0;
    for (size_t s = 0; s < p.size(); ++s) {
        if (!in[s] || label[s] >= 0) continue;
        std::vector<size_t> stack{s};
        label[s] = n;
        while (!stack.empty()) {
            const size_t i = stack.back();
            stack.pop_back();
            for (size_t j = 0; j < p.size(); ++j) {
                const glm::dvec3 d = glm::dvec3(p[j]) - glm::dvec3(p[i]);
                if (in[j] && label[j] < 0 && glm::dot(d, d) < double(r) * r) {
                    label[j] = n;
                    stack.push_back(j);
                }
            }
        }
        ++n;
    }
    REQUIRE(int(c.size.size()) == n);
    // Both number components by their lowest index, so the labels agree exactly.
    for (size_t i = 0; i < p.size(); ++i) REQUIRE(c.label[i] == label[i]);
}

TEST_CASE("clicks: k-d tree nearest distances are exact", "[clicks]") {
    // A lattice (many equal coordinates on every split axis) plus random points.
    Lattice grid(12, 9, 7);
    std::vector<glm::vec3> p = grid.p;
    Rng rng{5};
    for (int k = 0; k < 500; ++k) p.emplace_back(rng.uniform() * 12, rng.uniform() * 9, rng.uniform() * 7);
    std::vector<uint32_t> subset;
    for (size_t i = 0; i < p.size(); ++i)
        if (rng.uniform() < 0.3f) subset.push_back(uint32_t(i));
    const KdTree tree(p, subset);
    for (size_t i = 0; i < p.size(); ++i)
        for (double bound2 : {1e30, 2.0}) {
            double brute = bound2;
            for (uint32_t j : subset) {
                const glm::dvec3 d = glm::dvec3(p[j]) - glm::dvec3(p[i]);
                brute = std::min(brute, glm::dot(d, d));
            }
            REQUIRE(tree.nearest2(glm::dvec3(p[i]), bound2) == brute);
        }
    CHECK(KdTree(p, {}).nearest2(glm::dvec3(0), 7.0) == 7.0);
}

TEST_CASE("clicks: most interior point matches brute force", "[clicks]") {
    Rng rng{21};
    for (int trial = 0; trial < 12; ++trial) {
        // Clustered points (blobs of varying density) so that distances vary a lot.
        std::vector<glm::vec3> p;
        for (int b = 0; b < 6; ++b) {
            const glm::vec3 c(rng.uniform() * 10, rng.uniform() * 10, rng.uniform() * 3);
            const float rad = 0.5f + 2 * rng.uniform();
            const int count = 200 + int(rng.next() % 400);
            for (int k = 0; k < count; ++k)
                p.push_back(c + rad * (glm::vec3(rng.uniform(), rng.uniform(), rng.uniform()) - 0.5f));
        }
        const glm::vec3 centre = p[rng.next() % p.size()];
        const float radius = 1.0f + 3 * rng.uniform();
        Mask in(p.size());
        std::vector<uint32_t> members;
        for (size_t i = 0; i < p.size(); ++i)
            if (glm::distance(p[i], centre) < radius || (trial % 3 == 0 && rng.uniform() < 0.05f)) {
                in[i] = 1;
                members.push_back(uint32_t(i));
            }
        const float min_cap = trial % 2 ? 0.2f : 4.0f;  // the second saturates everything
        INFO("trial " << trial << ", " << members.size() << " members of " << p.size());
        CHECK(most_interior_point(p, in, members, min_cap, 0.05f) == brute_most_interior_point(p, in, min_cap));
    }
}

// ---------------------------------------------------------------------------------------
// 2D clicks

TEST_CASE("clicks: 2D first click at the centre of a square", "[clicks]") {
    Image gt(20, 20);
    gt.fill(5, 4, 13, 12);  // 9x9, centre (9, 8)
    const auto click = first_click_2d(gt.w, gt.h, gt.m);
    REQUIRE(click);
    CHECK(click->u == 9);
    CHECK(click->v == 8);
    CHECK(click->positive);
    const auto same = next_click_2d(gt.w, gt.h, gt.m, Mask(gt.m.size(), 0));  // empty prediction
    REQUIRE(same);
    CHECK((same->u == 9 && same->v == 8 && same->positive));

    Image edge(12, 12);  // a square cut by the image border: pushed away from the border
    edge.fill(0, 0, 6, 6);
    const auto e = first_click_2d(edge.w, edge.h, edge.m);
    REQUIRE(e);
    CHECK(e->u == 3);
    CHECK(e->v == 3);
}

TEST_CASE("clicks: 2D first click on an L-shape is its most interior pixel", "[clicks]") {
    Image gt(30, 26);
    gt.fill(2, 2, 8, 23);    // vertical bar, 7 wide
    gt.fill(2, 17, 27, 23);  // horizontal bar, 7 tall, sharing the corner
    const auto click = first_click_2d(gt.w, gt.h, gt.m);
    REQUIRE(click);
    const auto [bx, by] = brute_most_interior(gt);
    CHECK(click->u == bx);
    CHECK(click->v == by);
    // Deepest in the corner square, where both bars meet (not the centroid, which is outside).
    CHECK((click->u >= 2 && click->u <= 8 && click->v >= 17 && click->v <= 23));

    // A second, smaller but thicker part elsewhere: the first click stays in the larger part.
    gt.fill(19, 3, 27, 11);  // 81 pixels, deeper than the bars, fewer than their 273
    const auto still = first_click_2d(gt.w, gt.h, gt.m);
    REQUIRE(still);
    CHECK(still->u == bx);
    CHECK(still->v == by);
}

TEST_CASE("clicks: 2D negative click inside a larger false positive blob", "[clicks]") {
    Image gt(40, 30), pred(40, 30);
    gt.fill(2, 2, 16, 16);
    pred.fill(2, 2, 16, 16);
    pred.fill(4, 4, 6, 6, 0);  // a 3x3 miss: 9 false negatives
    pred.fill(24, 10, 32, 18); // a 9x9 false positive blob, centre (28, 14)
    const auto click = next_click_2d(gt.w, gt.h, gt.m, pred.m);
    REQUIRE(click);
    CHECK_FALSE(click->positive);
    CHECK(click->u == 28);
    CHECK(click->v == 14);

    pred.fill(24, 10, 32, 18, 0);  // blob gone: the miss is left, a positive click in it
    const auto fix = next_click_2d(gt.w, gt.h, gt.m, pred.m);
    REQUIRE(fix);
    CHECK(fix->positive);
    CHECK(fix->u == 5);
    CHECK(fix->v == 5);

    CHECK_FALSE(next_click_2d(gt.w, gt.h, gt.m, gt.m));  // nothing to fix
    CHECK_FALSE(first_click_2d(gt.w, gt.h, Mask(gt.m.size(), 0)));
    CHECK_THROWS_AS(next_click_2d(gt.w, gt.h, gt.m, Mask(5, 0)), InputError);
}

TEST_CASE("clicks: 2D ties go to the lowest index", "[clicks]") {
    // Two equal 4x4 regions, a false negative and a false positive: the one starting on
    // the earlier row wins; inside it, of the four equally deep centre pixels, the top-left.
    for (int flip = 0; flip < 2; ++flip) {
        Image gt(30, 30), pred(30, 30);
        const int a = flip ? 15 : 3, b = flip ? 3 : 15;
        gt.fill(3, a, 6, a + 3);     // missed
        pred.fill(20, b, 23, b + 3);  // wrong
        const auto click = next_click_2d(gt.w, gt.h, gt.m, pred.m);
        REQUIRE(click);
        CHECK(click->positive == (flip == 0));
        CHECK(click->u == (flip ? 21 : 4));
        CHECK(click->v == 4);
        const auto again = next_click_2d(gt.w, gt.h, gt.m, pred.m);
        CHECK((again->u == click->u && again->v == click->v && again->positive == click->positive));
    }
}

// ---------------------------------------------------------------------------------------
// 3D clicks

TEST_CASE("clicks: 3D first click at the centre of a box inside a larger box", "[clicks]") {
    const Lattice grid(21, 21, 21);
    const Clicker3D clicker(grid.p);
    CHECK(clicker.link_radius() == Approx(3.0f));  // 3 x spacing 1
    const Mask gt = grid.box({5, 5, 5}, {15, 15, 15});
    const auto click = clicker.first_click(gt);
    REQUIRE(click);
    CHECK(click->index == grid.index(10, 10, 10));
    CHECK(click->position == glm::vec3(10, 10, 10));
    CHECK(click->positive);
    const auto same = clicker.next_click(gt, Mask(gt.size(), 0));
    REQUIRE(same);
    CHECK(same->index == click->index);
    // With that Gaussian clicked already, the next click moves off it, still inside the box,
    // as deep as it can be while keeping away from the earlier click.
    const std::vector<size_t> clicked{click->index};
    const auto moved = clicker.next_click(gt, Mask(gt.size(), 0), clicked);
    REQUIRE(moved);
    CHECK(moved->index != click->index);
    CHECK(gt[moved->index]);
    CHECK(glm::distance(moved->position, click->position) >= 2.0f);
    // A region made of clicked Gaussians alone is passed over for the next largest.
    Mask two_specks(gt.size(), 0);
    two_specks[grid.index(0, 0, 0)] = two_specks[grid.index(1, 0, 0)] = 1;
    two_specks[grid.index(20, 20, 20)] = 1;
    const std::vector<size_t> both{grid.index(0, 0, 0), grid.index(1, 0, 0)};
    const auto other = clicker.next_click(two_specks, Mask(gt.size(), 0), both);
    REQUIRE(other);
    CHECK(other->index == grid.index(20, 20, 20));
    const std::vector<size_t> all{grid.index(0, 0, 0), grid.index(1, 0, 0), grid.index(20, 20, 20)};
    CHECK_FALSE(clicker.next_click(two_specks, Mask(gt.size(), 0), all));

    // A stray Gaussian of the object far from everything would be the farthest from all
    // non-object points; the click stays in the object's largest part.
    std::vector<glm::vec3> with_floater = grid.p;
    with_floater.emplace_back(100, 100, 100);
    Mask gt_floater = gt;
    gt_floater.push_back(1);
    const auto f = Clicker3D(with_floater).first_click(gt_floater);
    REQUIRE(f);
    CHECK(f->index == grid.index(10, 10, 10));

    // A slab three points thick: every middle-layer point at least 2 from the slab's faces
    // is equally deep, and the lowest index wins the tie.
    const Mask slab = grid.box({2, 8, 2}, {18, 10, 18});
    const auto s = clicker.first_click(slab);
    REQUIRE(s);
    CHECK(s->position == glm::vec3(3, 9, 3));
}

TEST_CASE("clicks: 3D next click goes to the largest error region", "[clicks]") {
    const Lattice grid(32, 12, 12);
    const Clicker3D clicker(grid.p);
    const Mask gt = grid.box({2, 2, 2}, {13, 9, 9});
    const Mask missed = grid.box({3, 3, 3}, {5, 5, 5});                  // 27 points
    const Mask wrong = grid.box({19, 2, 2}, {27, 8, 8});                 // 9x7x7 = 441 points
    const Mask small_wrong = grid.box({19, 2, 2}, {20, 3, 3});           // 8 points
    {
        const Mask pred = unite(subtract(gt, missed), wrong);
        const auto click = clicker.next_click(gt, pred);
        REQUIRE(click);
        CHECK_FALSE(click->positive);
        CHECK(wrong[click->index]);
        CHECK(click->index == brute_most_interior_point(grid.p, wrong, clicker.link_radius()));
        CHECK(click->position == glm::vec3(23, 5, 5));  // the slab's centre
    }
    {
        const Mask pred = unite(subtract(gt, missed), small_wrong);
        const auto click = clicker.next_click(gt, pred);
        REQUIRE(click);
        CHECK(click->positive);
        CHECK(click->position == glm::vec3(4, 4, 4));  // centre of the 3x3x3 miss
    }
    {
        // Two false positive regions more than a link radius apart: the larger one.
        const Mask two = unite(grid.box({18, 1, 1}, {20, 3, 3}), grid.box({25, 1, 1}, {30, 10, 10}));
        const auto click = clicker.next_click(gt, unite(gt, two));
        REQUIRE(click);
        CHECK_FALSE(click->positive);
        CHECK(click->position.x >= 25);
    }
    CHECK_FALSE(clicker.next_click(gt, gt));
    CHECK_FALSE(clicker.first_click(Mask(gt.size(), 0)));
    CHECK_THROWS_AS(clicker.next_click(gt, Mask(3, 0)), InputError);
}

TEST_CASE("clicks: 3D clicks are deterministic and the first click lands on each sample object",
          "[clicks]") {
    pg::data::synth::SynthOptions options;
    options.density = 0.1;
    options.masks = false;
    const auto scene = pg::data::synth::make_suite_scene(pg::data::synth::SuiteKind::Desk, 0, 1, options);
    const std::vector<int32_t> instance = *scene.cloud.int_property("instance");
    const Clicker3D a(scene.cloud.mean), b(scene.cloud.mean);
    CHECK(a.link_radius() == b.link_radius());
    REQUIRE_FALSE(scene.instances.empty());
    for (const auto& object : scene.instances) {
        const int id = object.id;
        const Mask gt = mask_of(instance, id);
        const auto ca = a.first_click(gt), cb = b.first_click(gt);
        REQUIRE(ca);
        REQUIRE(cb);
        CHECK(ca->index == cb->index);
        CHECK(instance[ca->index] == id);
    }
}

// ---------------------------------------------------------------------------------------
// Sessions

TEST_CASE("clicks: a session stops at 20 clicks when nothing improves", "[clicks]") {
    const Lattice grid(10, 10, 10);
    const Clicker3D clicker(grid.p);
    const Mask gt = grid.box({2, 2, 2}, {6, 6, 6});
    int calls = 0;
    const SessionResult<Click3D> r = make_session_3d(clicker, gt).run([&](const std::vector<Click3D>& clicks) {
        ++calls;
        return Mask(gt.size(), 0);  // a model that never finds anything
    });
    CHECK(calls == 20);
    CHECK(r.clicks.size() == 20);
    REQUIRE(r.iou_per_click.size() == 20);
    CHECK(r.iou_per_click.back() == 0.0);
    // A person clicks elsewhere on a part that ignored a click: never the same Gaussian twice,
    // and each click keeps at least a spacing from the earlier ones, all inside the object.
    for (size_t k = 0; k < r.clicks.size(); ++k) {
        CHECK(gt[r.clicks[k].index]);
        for (size_t j = 0; j < k; ++j) CHECK(glm::distance(r.clicks[k].position, r.clicks[j].position) >= 1.0f);
    }

    SessionOptions five;
    five.max_clicks = 5;
    CHECK(make_session_3d(clicker, gt, five).run([&](const auto&) { return Mask(gt.size(), 0); }).clicks.size() == 5);
    CHECK_THROWS_AS(make_session_3d(clicker, gt).run([](const auto&) { return Mask(1, 0); }), InputError);
}

TEST_CASE("clicks: a session with a growing prediction reaches IoU 1", "[clicks]") {
    const Lattice grid(24, 24, 24);
    const Clicker3D clicker(grid.p);
    const Mask gt = grid.box({4, 4, 4}, {19, 19, 19});
    // A fake model: the ground truth within a radius of the first click that grows by 2
    // per click, minus nothing, so only positive clicks in the shrinking misses follow.
    auto grow = [&](const std::vector<Click3D>& clicks) {
        Mask m(gt.size(), 0);
        const float radius = 2.0f * float(clicks.size());
        for (size_t i = 0; i < gt.size(); ++i)
            m[i] = gt[i] && glm::distance(grid.p[i], clicks.front().position) <= radius;
        return m;
    };
    const SessionResult<Click3D> r = make_session_3d(clicker, gt).run(grow);
    REQUIRE(!r.iou_per_click.empty());
    CHECK(r.iou_per_click.size() == r.clicks.size());
    CHECK(r.iou_per_click.back() == 1.0);
    CHECK(r.clicks.size() < 20);
    CHECK(r.clicks.front().position == glm::vec3(11, 11, 11));  // the 16^3 box's lowest centre point
    for (size_t k = 0; k < r.clicks.size(); ++k) {
        CHECK(r.clicks[k].positive);
        CHECK(gt[r.clicks[k].index]);
        if (k > 0) CHECK(r.iou_per_click[k] > r.iou_per_click[k - 1]);
    }
    // Deterministic: the same session again gives the same clicks and IoUs.
    const SessionResult<Click3D> again = make_session_3d(clicker, gt).run(grow);
    REQUIRE(again.clicks.size() == r.clicks.size());
    for (size_t k = 0; k < r.clicks.size(); ++k) CHECK(again.clicks[k].index == r.clicks[k].index);
    CHECK(again.iou_per_click == r.iou_per_click);

    SessionOptions target;
    target.target_iou = 0.5;
    const SessionResult<Click3D> early = make_session_3d(clicker, gt, target).run(grow);
    CHECK(early.iou_per_click.back() >= 0.5);
    CHECK(early.iou_per_click.size() < r.iou_per_click.size());
    for (size_t k = 0; k + 1 < early.iou_per_click.size(); ++k) CHECK(early.iou_per_click[k] < 0.5);
}

TEST_CASE("clicks: a 2D session fixes a prediction that overshoots", "[clicks]") {
    Image gt(40, 40);
    gt.fill(8, 8, 27, 27);
    // A fake model: a disc around each positive click, minus a disc around each negative one.
    auto discs = [&](const std::vector<Click2D>& clicks) {
        Mask m(gt.m.size(), 0);
        for (int y = 0; y < gt.h; ++y)
            for (int x = 0; x < gt.w; ++x) {
                bool on = false;
                for (const Click2D& c : clicks) {
                    const int d2 = (x - c.u) * (x - c.u) + (y - c.v) * (y - c.v);
                    if (c.positive && d2 <= 14 * 14) on = true;
                    if (!c.positive && d2 <= 4 * 4) on = false;
                }
                m[size_t(y) * gt.w + x] = on;
            }
        return m;
    };
    const SessionResult<Click2D> r = make_session_2d(gt.w, gt.h, gt.m).run(discs);
    REQUIRE(r.clicks.size() >= 2);
    CHECK(r.clicks[0].positive);
    CHECK(r.clicks[0].u == 17);  // centre of the 20x20 square (lowest of the four)
    CHECK(r.clicks[0].v == 17);
    CHECK_FALSE(r.clicks[1].positive);  // the disc spills over the square: a negative click outside it
    CHECK_FALSE(gt.at(r.clicks[1].u, r.clicks[1].v));
    CHECK(r.clicks.size() <= 20);
    CHECK(r.iou_per_click.size() == r.clicks.size());
}

// ---------------------------------------------------------------------------------------
// View choice and scale

TEST_CASE("clicks: the view where the object is largest is chosen", "[clicks]") {
    std::vector<std::vector<uint16_t>> views = {
        {0, 3, 3, 0, 0, 0}, {3, 3, 3, 7, 7, 0}, {7, 3, 3, 3, 0}, {3, 3, 3, 0, 7, 7, 7, 7}};
    CHECK(visible_area(views[1], 3) == 3);
    CHECK(choose_view_for_object(views, 3) == std::optional<size_t>(1));  // 3 pixels in views 1, 2 and 3
    CHECK(choose_view_for_object(views, 7) == std::optional<size_t>(3));
    CHECK_FALSE(choose_view_for_object(views, 9));
    CHECK_FALSE(choose_view_for_object({}, 3));
}

TEST_CASE("clicks: 300k random points run", "[clicks]") {
    Rng rng{99};
    std::vector<glm::vec3> p(300000);
    for (auto& q : p) q = glm::vec3(rng.uniform(), rng.uniform(), rng.uniform()) * 10.0f;
    const auto t0 = std::chrono::steady_clock::now();
    const Clicker3D clicker(p);
    Mask gt(p.size()), pred(p.size());
    for (size_t i = 0; i < p.size(); ++i) {
        gt[i] = glm::distance(p[i], glm::vec3(4, 5, 5)) < 2.5f;
        pred[i] = glm::distance(p[i], glm::vec3(5, 5, 5)) < 2.5f;
    }
    const auto t1 = std::chrono::steady_clock::now();
    const auto first = clicker.first_click(gt);
    const auto t2 = std::chrono::steady_clock::now();
    const auto next = clicker.next_click(gt, pred);
    const auto t3 = std::chrono::steady_clock::now();
    REQUIRE(first);
    REQUIRE(next);
    CHECK(gt[first->index]);
    CHECK(glm::distance(first->position, glm::vec3(4, 5, 5)) < 1.0f);
    CHECK(gt[next->index] == next->positive);
    CHECK(gt[next->index] != bool(pred[next->index]));
    auto ms = [](auto a, auto b) { return std::chrono::duration<double, std::milli>(b - a).count(); };
    WARN("300k points: setup " << ms(t0, t1) << " ms, first click " << ms(t1, t2) << " ms, next click "
                                << ms(t2, t3) << " ms (link radius " << clicker.link_radius() << ")");
}
