#pragma once
// One simulated interactive session on one object: click, let the model predict, measure,
// click again where the error is largest, up to max_clicks (20 in the InterObject3D /
// AGILE3D protocol). Works on Gaussians (Click3D) and on the pixels of a view (Click2D).
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "dataset/clicks/click2d.h"
#include "dataset/clicks/click3d.h"
#include "dataset/clicks/mask.h"
#include "dataset/error.h"

namespace pg::data::clicks {

struct SessionOptions {
    int max_clicks = 20;
    // > 0: stop as soon as the IoU reaches this (e.g. 0.9 when only NoC@90 is wanted).
    double target_iou = 0;
};

template <class Click>
struct SessionResult {
    std::vector<Click> clicks;
    // IoU after click 1, 2, ... (the eval's `iou_per_click`). Shorter than max_clicks when
    // the target was reached or no error was left (IoU 1): later clicks would change nothing.
    std::vector<double> iou_per_click;
};

template <class Click>
class ClickSession {
public:
    // The click rule: where to click given the ground truth, the current prediction and the
    // clicks so far; nullopt when there is nothing left to click.
    using NextClick =
        std::function<std::optional<Click>(const Mask& gt, const Mask& prediction, const std::vector<Click>& clicks)>;
    // The model under test: all clicks so far (in order) -> a prediction mask.
    using Predictor = std::function<Mask(const std::vector<Click>& clicks)>;

    ClickSession(Mask gt, NextClick next_click, SessionOptions options = {})
        : gt_(std::move(gt)), next_click_(std::move(next_click)), options_(options) {}

    SessionResult<Click> run(const Predictor& predict) const {
        SessionResult<Click> result;
        Mask prediction(gt_.size(), 0);
        for (int k = 0; k < options_.max_clicks; ++k) {
            std::optional<Click> click = next_click_(gt_, prediction, result.clicks);
            if (!click) break;
            result.clicks.push_back(*click);
            prediction = predict(result.clicks);
            if (prediction.size() != gt_.size())
                throw InputError("click session", "the predictor returned " + std::to_string(prediction.size()) +
                                                      " labels for " + std::to_string(gt_.size()));
            result.iou_per_click.push_back(iou(gt_, prediction));
            if (options_.target_iou > 0 && result.iou_per_click.back() >= options_.target_iou) break;
        }
        return result;
    }

private:
    Mask gt_;
    NextClick next_click_;
    SessionOptions options_;
};

using ClickSession3D = ClickSession<Click3D>;
using ClickSession2D = ClickSession<Click2D>;

// Sessions with the standard click rules. The clicker must outlive the session.
inline ClickSession3D make_session_3d(const Clicker3D& clicker, Mask gt, SessionOptions options = {}) {
    return ClickSession3D(
        std::move(gt),
        [&clicker](const Mask& g, const Mask& p, const std::vector<Click3D>& clicks) {
            std::vector<size_t> clicked;
            for (const Click3D& c : clicks) clicked.push_back(c.index);
            return clicker.next_click(g, p, clicked);
        },
        options);
}

inline ClickSession2D make_session_2d(int width, int height, Mask gt, SessionOptions options = {}) {
    return ClickSession2D(
        std::move(gt),
        [width, height](const Mask& g, const Mask& p, const std::vector<Click2D>&) {
            return next_click_2d(width, height, g, p);
        },
        options);
}

}  // namespace pg::data::clicks
