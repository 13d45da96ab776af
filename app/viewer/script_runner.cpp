#include "app/viewer/script_runner.h"

#include <algorithm>

#include "app/common/host_memory.h"
#include "app/viewer/viewer.h"
#include "dataset/error.h"
#include "engine/vk/buffer.h"

namespace pg::viewer {

ScriptRunner::ScriptRunner(std::vector<Action> actions, std::string final_screenshot, const std::string& log)
    : actions_(std::move(actions)), final_screenshot_(std::move(final_screenshot)) {
    if (log.empty()) return;
    log_.open(log, std::ios::trunc);
    if (!log_) throw data::InputError(log, "cannot write the script log");
}


void ScriptRunner::log_settled() {
    if (!log_.is_open() || next_ == 0) return;
    const Action& a = actions_[next_ - 1];
    log_ << nlohmann::json{{"action", next_ - 1}, {"kind", a.kind}, {"host_rss", app::resident_host_bytes()},
                           {"device_live", vk::memory_stats().live}}
                .dump()
         << '\n' << std::flush;
}

void ScriptRunner::step(Viewer& viewer, bool idle) {
    if (finished_) return;
    idle_frames_ = idle && viewer.errors() == 0 ? idle_frames_ + 1 : 0;
    if (viewer.errors() > 0) return viewer.quit();
    // Three idle frames: the picture of the last change has been drawn, not just received.
    if (idle_frames_ < 3) return;
    log_settled();
    if (next_ < actions_.size()) {
        run(viewer, actions_[next_++]);
        idle_frames_ = 0;
        return;
    }
    finished_ = true;
    if (final_screenshot_.empty()) viewer.quit();
    else viewer.save_window(final_screenshot_);  // the viewer quits once it is saved
}

void ScriptRunner::run(Viewer& viewer, const Action& a) {
    const auto& v = a.value;
    const std::string& k = a.kind;
    const auto& cameras = viewer.scene().cameras;
    Document& doc = viewer.document();
    auto fail = [&](const std::string& why) { throw data::InputError(a.where, why); };
    if (k == "snap") {
        int index = -1;
        if (v.is_string()) {
            auto it = std::find_if(cameras.begin(), cameras.end(), [&](auto& c) { return c.name == v.get<std::string>(); });
            if (it != cameras.end()) index = int(it - cameras.begin());
        } else {
            index = v.get<int>();
        }
        if (index < 0 || index >= int(cameras.size())) fail("no camera " + v.dump());
        viewer.snap(index);
    } else if (k == "orbit") {
        viewer.orbit(v[0].get<double>(), v[1].get<double>());
    } else if (k == "pan") {
        viewer.pan(v[0].get<double>(), v[1].get<double>());
    } else if (k == "zoom") {
        viewer.zoom(v.get<double>());
    } else if (k == "frame") {
        viewer.frame_scene();
    } else if (k == "new_object") {
        doc.add_object(v.get<std::string>());
    } else if (k == "click" || k == "click_pixel") {
        double x = v[0].get<double>(), y = v[1].get<double>();
        if (k == "click_pixel") {
            if (viewer.snapped() < 0) fail("'click_pixel' needs a dataset camera: snap first");
            const auto& c = cameras[size_t(viewer.snapped())];
            x /= c.width;
            y /= c.height;
        }
        if (x < 0 || y < 0 || x >= 1 || y >= 1) fail("the click lies outside the picture");
        viewer.click_at(x, y, !a.extra.value("negative", false));
    } else if (k == "pick") {
        const int id = viewer.object_at(v[0].get<double>(), v[1].get<double>());
        if (!id) fail("no object under " + v.dump());
        doc.select(id);
    } else if (k == "select") {
        if (!doc.select(v.get<int>()) && doc.state().selected != v.get<int>()) fail("no object " + v.dump());
    } else if (k == "rename" || k == "recolour" || k == "hide" || k == "delete") {
        const int id = doc.state().selected;
        if (!doc.selected()) fail("no object is selected");
        if (k == "rename") doc.rename(id, v.get<std::string>());
        if (k == "recolour") doc.recolour(id, glm::vec3(v[0].get<float>(), v[1].get<float>(), v[2].get<float>()));
        if (k == "hide") doc.set_hidden(id, v.get<bool>());
        if (k == "delete" && v.get<bool>()) doc.remove(id);
    } else if (k == "isolate") {
        viewer.isolate(v.get<bool>());
    } else if (k == "tints") {
        viewer.show_tints(v.get<bool>());
    } else if (k == "mask") {
        viewer.show_mask(v.get<bool>());
    } else if (k == "decoder") {
        if (!viewer.set_decoder(v.get<std::string>())) fail("decoder '" + v.get<std::string>() + "' is not available");
    } else if (k == "label_by_class") {
        viewer.label_by_class(v.is_string() ? v.get<std::string>() : std::string());
    } else if (k == "class_tints") {
        viewer.show_classes(v.get<bool>());
    } else if (k == "object_from_class") {
        const ClassLabels* classes = viewer.classes();
        if (!classes) fail("no class labels yet: run label_by_class first");
        if (v.is_array()) {
            const double x = v[0].get<double>(), y = v[1].get<double>();
            if (x < 0 || y < 0 || x >= 1 || y >= 1) fail("the point lies outside the picture");
            viewer.object_from_class_at(x, y);
        } else {
            const int cls = classes->find(v.is_string() ? v.get<std::string>() : std::to_string(v.get<int>()));
            if (cls < 0) fail("no class " + v.dump());
            if (!viewer.object_from_class(cls)) fail("class " + v.dump() + " holds no Gaussians");
        }
    } else if (k == "undo") {
        for (int i = 0; i < v.get<int>(); ++i) doc.undo();
    } else if (k == "redo") {
        for (int i = 0; i < v.get<int>(); ++i) doc.redo();
    } else if (k == "export") {
        if (v.is_string()) {
            viewer.export_to(v.get<std::string>(), true, true, true, true);
        } else {
            viewer.export_to(v["folder"].get<std::string>(), v.value("scene", true), v.value("objects", true),
                             v.value("masks", true), v.value("prompts", true), v.value("format", std::string("ply")));
        }
    } else if (k == "open") {
        if (v.is_string()) viewer.open_scene(v.get<std::string>());
        else viewer.open_scene(v["scene"].get<std::string>(), v.value("lod", 0));
    } else if (k == "screenshot") {
        if (!a.extra.value("view", false)) return viewer.save_window(v.get<std::string>());
        try {
            viewer.save_picture(v.get<std::string>());
        } catch (const std::exception& e) {
            fail(e.what());
        }
    }
}

}  // namespace pg::viewer
