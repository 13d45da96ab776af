#pragma once
// Interactive segmentation scores from the IoU an object reached after each click.
//   IoU@k  = mean over objects of the IoU after click k. A run that stopped before k
//            clicks (it reached its target) keeps its last IoU: clicks.json cannot say
//            why a run stopped, so every short run is clamped to its last click.
//   NoC@t  = mean over objects of the first click count c (1-based) whose IoU >= t, or
//            kMaxClicks (20) if no click up to the 20th reaches t.
// An object with no clicks at all scores IoU 0 and NoC 20.
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace pg::data::eval {

constexpr std::array<int, 4> kIouAtClicks = {1, 3, 5, 10};
constexpr std::array<double, 3> kNocThresholds = {0.80, 0.85, 0.90};
constexpr int kMaxClicks = 20;

struct ObjectClicks {
    int32_t id = 0;
    std::vector<double> iou_per_click;  // IoU after click 1, 2, ...
};

double iou_after_clicks(const ObjectClicks& o, int k);     // k >= 1, clamped to the last click
int clicks_to_reach(const ObjectClicks& o, double threshold);  // in [1, kMaxClicks]

struct ClickScores {
    std::array<double, kIouAtClicks.size()> iou_at{};   // IoU@1, @3, @5, @10
    std::array<double, kNocThresholds.size()> noc{};    // NoC@80, @85, @90
    size_t objects = 0;
};

// nullopt when there is no object.
std::optional<ClickScores> click_scores(std::span<const ObjectClicks> objects);

}  // namespace pg::data::eval
