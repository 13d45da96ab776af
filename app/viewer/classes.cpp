// Label by class in the viewer: the semantic model's job on the job thread (progress and
// Cancel like an export), its result as class tints and a legend, and objects made from a
// class (whole, or the connected region under a point) that clicks then correct.
#include <chrono>

#include "app/viewer/viewer.h"
#include "dataset/error.h"
#include "engine/segment/cancel.h"

namespace pg::viewer {

namespace {
using Clock = std::chrono::steady_clock;
}  // namespace

void Viewer::label_by_class(const std::string& model) {
    if (class_job_ && class_job_->running) {
        status("label by class is already running", true);
        return;
    }
    const std::string path = model.empty() ? scene_.semantic_model : model;
    class_job_ = std::make_shared<ClassJob>();
    class_job_->running = true;
    auto job = class_job_;
    status("labelling by class...");
    jobs_->post([this, path, job] {
        std::shared_ptr<const ClassLabels> labels;
        std::map<std::string, double> ms;
        std::string error;
        bool cancelled = false;
        const auto t0 = Clock::now();
        try {
            labels = std::make_shared<const ClassLabels>(job_engine_->label_by_class(
                path, &job->cancel,
                [job](size_t done, size_t total) {
                    job->total = total;
                    job->done = done;
                },
                ms));
        } catch (const seg::Cancelled&) {
            cancelled = true;
        } catch (const std::exception& e) {
            error = e.what();
        }
        const double wall = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
        job->running = false;
        inbox_.post([this, labels, ms, wall, error, cancelled] {
            if (cancelled) return status("label by class cancelled");
            if (!error.empty()) return status("label by class failed: " + error, true);
            classes_ = labels;
            ++classes_version_;
            class_ms_ = ms;
            class_wall_ms_ = wall;
            class_chosen_ = -1;
            size_t present = 0;
            for (size_t n : labels->counts) present += n > 0;
            status("labelled by class: " + std::to_string(present) + " classes present");
        });
    });
}

void Viewer::cancel_label_by_class() {
    if (class_job_) class_job_->cancel = true;
}

bool Viewer::object_from_class(int cls) {
    if (!classes_ || cls < 0 || cls >= int(classes_->counts.size())) return false;
    if (classes_->counts[size_t(cls)] == 0) {
        status("class " + classes_->name(cls) + " holds no Gaussians", true);
        return false;
    }
    // A pass over every Gaussian: fast enough for the UI thread (no spacing or flood fill).
    doc_.add_region_object(classes_->name(cls), class_region(scene_.cloud.mean, *classes_, cls));
    status("object made from class " + classes_->name(cls) + ": click to correct it");
    return true;
}

void Viewer::object_from_class_at(double x, double y) {
    if (!classes_) return status("label by class first", true);
    if (!picture_valid_ || x < 0 || y < 0 || x >= 1 || y >= 1) return;
    const data::Camera cam = picture_.camera;
    const double u = x * cam.width, v = y * cam.height;
    auto classes = classes_;
    // The lift and the flood fill run on the job thread; the object lands in the document after.
    jobs_->post([this, cam, u, v, classes] {
        try {
            const seg::Anchor a = job_engine_->lift(cam, u, v, true);
            if (a.gaussian < 0) throw data::InputError("click", "hit no Gaussian");
            const int cls = classes->classes[size_t(a.gaussian)];
            auto region = class_region(scene_.cloud.mean, *classes, cls, a.gaussian);
            inbox_.post([this, classes, cls, region] {
                doc_.add_region_object(classes->name(cls), region);
                status("object made from a region of class " + classes->name(cls) + " (" +
                       std::to_string(region->gaussians.size()) + " Gaussians): click to correct it");
            });
        } catch (const std::exception& e) {
            std::string what = e.what();
            inbox_.post([this, what] { status("no class region there: " + what, true); });
        }
    });
}

}  // namespace pg::viewer
