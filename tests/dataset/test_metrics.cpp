// Evaluation metrics (pg::data::eval) on tiny hand-computed cases: 3D IoU, 2D mIoU per
// view, OA, semantic per-class IoU, IoU@k and NoC.
#include <catch2/catch.hpp>

#include <stdexcept>
#include <vector>

#include "dataset/eval/click_metrics.h"
#include "dataset/eval/instance_metrics.h"
#include "dataset/eval/semantic_metrics.h"

using namespace pg::data::eval;

namespace {

using Ids = std::vector<int32_t>;
using Px = std::vector<uint16_t>;

const ObjectIou2d& object2d(const InstanceScores2d& s, int32_t id) {
    for (const auto& o : s.objects)
        if (o.id == id) return o;
    FAIL("object " << id << " missing");
    return s.objects.front();
}

}  // namespace

TEST_CASE("metrics: 3D IoU per object over Gaussian indices with known overlaps", "[metrics]") {
    //                 0  1  2  3  4  5  6   7  8  9
    const Ids gt   = {0, 1, 1, 1, 2, 2, 0, 0, 0, 3};
    const Ids pred = {0, 1, 1, 0, 2, 1, 2, -1, 9, 0};
    const auto s = instance_scores_3d(gt, pred);
    // 1: G={1,2,3} P={1,2,5} -> 2/4. 2: G={4,5} P={4,6} -> 1/3. 3: G={9} P={} -> 0.
    // 9 is no GT object (only OA); -1 is "unlabelled".
    REQUIRE(s.objects.size() == 3);
    CHECK(s.objects[0].id == 1);
    CHECK(s.objects[0].iou == Approx(0.5));
    CHECK(s.objects[1].id == 2);
    CHECK(s.objects[1].iou == Approx(1.0 / 3.0));
    CHECK(s.objects[2].id == 3);
    CHECK(s.objects[2].iou == 0.0);
    CHECK(*s.miou == Approx((0.5 + 1.0 / 3.0 + 0.0) / 3.0));
    CHECK(*s.oa == Approx(4.0 / 10.0));  // indices 0, 1, 2, 4 agree
    CHECK(s.gaussians == 10);
}

TEST_CASE("metrics: 3D perfect prediction is 1.0 and a GT without objects has no mIoU", "[metrics]") {
    const Ids gt = {0, 4, 4, 7, 0, 7};
    const auto s = instance_scores_3d(gt, gt);
    CHECK(s.objects.size() == 2);
    CHECK(*s.miou == 1.0);
    CHECK(*s.oa == 1.0);

    const auto empty = instance_scores_3d(Ids{0, 0}, Ids{1, 0});
    CHECK(empty.objects.empty());
    CHECK_FALSE(empty.miou.has_value());
    CHECK(*empty.oa == 0.5);

    CHECK_THROWS_AS(instance_scores_3d(Ids{0, 1}, Ids{0}), std::invalid_argument);
    CHECK_THROWS_AS(instance_scores_3d(Ids{70000}, Ids{0}), std::invalid_argument);
}

TEST_CASE("metrics: 2D mIoU averages per view without absent objects or empty views and OA pools pixels", "[metrics]") {
    // Scene objects {1, 2}; four 6-pixel views.
    const Px gt_a = {0, 1, 1, 2, 2, 0}, pred_a = {0, 1, 0, 2, 2, 2};  // 1: 1/2, 2: 2/3; OA 4/6
    const Px gt_b = {0, 0, 1, 1, 1, 0}, pred_b = gt_b;                // 2 absent: 1 only, IoU 1; OA 6/6
    const Px gt_c = {0, 0, 0, 2, 2, 2}, pred_c = {1, 0, 0, 2, 2, 2};  // 1 predicted, not in GT: 0; 2: 1; OA 5/6
    const Px gt_d = {0, 0, 0, 0, 0, 0}, pred_d = {7, 0, 0, 0, 0, 0};  // no object (7 is none); OA 5/6
    const double view_a = (0.5 + 2.0 / 3.0) / 2.0, view_b = 1.0, view_c = 0.5;

    for (const bool listed : {true, false}) {
        INFO("scene objects given up front: " << listed);
        InstanceMaskScorer scorer(listed ? Ids{1, 2} : Ids{});
        // Without the list, object 1 is only known from later views: the result must not care.
        scorer.add_view("c", gt_c, pred_c);
        scorer.add_view("a", gt_a, pred_a);
        scorer.add_view("d", gt_d, pred_d);
        scorer.add_view("b", gt_b, pred_b);
        const auto s = scorer.result();

        REQUIRE(s.views.size() == 4);
        CHECK(s.views[0].name == "c");
        CHECK(*s.views[0].miou == Approx(view_c));
        CHECK(*s.views[1].miou == Approx(view_a));
        CHECK_FALSE(s.views[2].miou.has_value());
        CHECK(s.views[2].objects.empty());
        CHECK(*s.views[3].miou == Approx(view_b));
        REQUIRE(s.views[3].objects.size() == 1);

        CHECK(*s.miou == Approx((view_a + view_b + view_c) / 3.0));  // 25/36
        CHECK(*s.oa == Approx(20.0 / 24.0));
        CHECK(s.pixels == 24);

        REQUIRE(s.objects.size() == 2);
        CHECK(object2d(s, 1).iou == Approx((0.5 + 1.0 + 0.0) / 3.0));
        CHECK(object2d(s, 1).views == 3);
        CHECK(object2d(s, 2).iou == Approx((2.0 / 3.0 + 1.0) / 2.0));
        CHECK(object2d(s, 2).views == 2);
    }
}

TEST_CASE("metrics: 2D listed object predicted outside its GT views scores 0 and perfect masks score 1", "[metrics]") {
    const Px gt = {0, 1, 1, 0}, ghost = {5, 1, 1, 0};
    InstanceMaskScorer listed({1, 5});
    listed.add_view("v", gt, ghost);
    CHECK(*listed.result().miou == Approx(0.5));  // object 1: 1, object 5: 0
    InstanceMaskScorer unlisted;
    unlisted.add_view("v", gt, ghost);
    CHECK(*unlisted.result().miou == 1.0);  // 5 is no object: only OA sees it
    CHECK(*unlisted.result().oa == 0.75);

    InstanceMaskScorer perfect;
    perfect.add_view("v", gt, gt);
    perfect.add_view("w", Px{3, 3, 0, 1}, Px{3, 3, 0, 1});
    CHECK(*perfect.result().miou == 1.0);
    CHECK(*perfect.result().oa == 1.0);
}

TEST_CASE("metrics: semantic per-class IoU pooled over elements with mIoU over GT classes and OA", "[metrics]") {
    //                 0  1  2  3  4  5  6  7
    const Ids gt   = {0, 0, 0, 1, 1, 1, 1, 0};
    const Ids pred = {0, 0, 1, 1, 1, 0, 1, 2};
    const Ids classes = {0, 1, 2};
    const auto s = semantic_scores_3d(gt, pred, classes);
    // 0: G={0,1,2,7} P={0,1,5} -> 2/5. 1: G={3,4,5,6} P={2,3,4,6} -> 3/5. 2: not in GT -> 0, no mIoU.
    REQUIRE(s.classes.size() == 3);
    CHECK(*s.classes[0].iou == Approx(0.4));
    CHECK(*s.classes[1].iou == Approx(0.6));
    CHECK(*s.classes[2].iou == 0.0);
    CHECK_FALSE(s.classes[2].in_gt);
    CHECK(*s.miou == Approx(0.5));
    CHECK(*s.oa == Approx(5.0 / 8.0));

    // 2D: two views pooled (per-view averaging would give 19/24, not 3/4).
    LabelOverlap px(kMaxLabel + 1);
    px.add(Px{1, 1, 0, 0}, Px{1, 0, 0, 0});
    px.add(Px{1, 1, 1, 1}, Px{1, 1, 1, 1});
    const auto p = semantic_scores(px, classes);
    CHECK(*p.classes[0].iou == Approx(2.0 / 3.0));
    CHECK(*p.classes[1].iou == Approx(5.0 / 6.0));
    CHECK_FALSE(p.classes[2].iou.has_value());  // neither GT nor prediction has class 2
    CHECK(*p.miou == Approx(0.75));
    CHECK(*p.oa == Approx(7.0 / 8.0));

    // A GT class missing from the list is still scored; perfect is 1.0.
    const auto extra = semantic_scores_3d(Ids{0, 3, 3}, Ids{0, 3, 3}, Ids{0});
    REQUIRE(extra.classes.size() == 2);
    CHECK(extra.classes[1].id == 3);
    CHECK(*extra.miou == 1.0);
    CHECK(*extra.oa == 1.0);
}

TEST_CASE("metrics: IoU@k clamps early-stopped runs to the last click and NoC is 20 when never reached", "[metrics]") {
    std::vector<ObjectClicks> objects(4);
    objects[0] = {1, {0.5, 0.7, 0.85, 0.92}};  // stopped at click 4: reached 0.9
    objects[1] = {2, {0.2, 0.4, 0.6}};
    objects[1].iou_per_click.resize(20, 0.79);  // 20 clicks, never 0.8
    objects[2] = {3, std::vector<double>(20, 0.5)};
    objects[2].iou_per_click.push_back(0.95);   // reaches it at click 21: past the cap
    objects[3] = {4, {}};                        // no click at all

    CHECK(iou_after_clicks(objects[0], 5) == 0.92);
    CHECK(iou_after_clicks(objects[0], 10) == 0.92);
    CHECK(clicks_to_reach(objects[0], 0.85) == 3);  // exactly the threshold counts
    CHECK(clicks_to_reach(objects[0], 0.90) == 4);
    CHECK(clicks_to_reach(objects[1], 0.80) == 20);
    CHECK(clicks_to_reach(objects[2], 0.80) == 20);
    CHECK(clicks_to_reach(objects[3], 0.80) == 20);
    CHECK(iou_after_clicks(objects[3], 1) == 0.0);

    const auto s = click_scores(objects);
    REQUIRE(s);
    CHECK(s->objects == 4);
    CHECK(s->iou_at[0] == Approx((0.5 + 0.2 + 0.5 + 0.0) / 4));    // @1
    CHECK(s->iou_at[1] == Approx((0.85 + 0.6 + 0.5 + 0.0) / 4));   // @3
    CHECK(s->iou_at[2] == Approx((0.92 + 0.79 + 0.5 + 0.0) / 4));  // @5
    CHECK(s->iou_at[3] == Approx((0.92 + 0.79 + 0.5 + 0.0) / 4));  // @10
    CHECK(s->noc[0] == Approx((3 + 20 + 20 + 20) / 4.0));          // @80
    CHECK(s->noc[1] == Approx((3 + 20 + 20 + 20) / 4.0));          // @85
    CHECK(s->noc[2] == Approx((4 + 20 + 20 + 20) / 4.0));          // @90

    const std::vector<ObjectClicks> perfect = {{1, {1.0}}, {2, {1.0}}};
    const auto p = click_scores(perfect);
    for (double v : p->iou_at) CHECK(v == 1.0);
    for (double v : p->noc) CHECK(v == 1.0);
    CHECK_FALSE(click_scores(std::vector<ObjectClicks>{}).has_value());
}
