#pragma once
// pointgauss-viewer: the window, the view and the user's actions. Mouse, keys, panels and
// scripts all call the same public actions, so a script exercises what a user does; what to
// segment and the labels live in the Session, what is clicked in the Document.
#include <atomic>
#include <chrono>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/viewer/class_labels.h"
#include "app/viewer/document.h"
#include "dataset/formats/scene_io.h"
#include "app/viewer/frame_engine.h"
#include "app/viewer/imgui_layer.h"
#include "app/viewer/job_engine.h"
#include "app/viewer/orbit_camera.h"
#include "app/viewer/presenter.h"
#include "app/viewer/session.h"
#include "app/viewer/window.h"
#include "app/viewer/preview_scene.h"
#include "app/viewer/worker.h"

namespace pg::viewer {

class ScriptRunner;

struct ViewerOptions {
    std::string scene, cameras, model, semantic_model, decoder, up = "auto", device, script, script_log, screenshot, out, prompts;
    std::string lift = "surface";
    int lod = 0;                    // level of a streamed SOG
    std::string max_device_memory;  // a scene past it (or past the device's largest binding) is streamed
    bool half_sh = false;
    int width = 1400, height = 860;
    double render_scale = 0;  // 0: 1 on a GPU, 0.5 on a CPU device
};

class Viewer {
public:
    explicit Viewer(const ViewerOptions& options);
    ~Viewer();
    int run();  // the exit code

    // Actions.
    void click_at(double picture_x, double picture_y, bool positive);  // fractions of the picture
    int object_at(double picture_x, double picture_y) const;            // 0: none
    void snap(int camera);                                              // -1: free camera
    void orbit(double yaw, double pitch);
    void pan(double right, double down);
    void zoom(double factor);
    void fly(glm::dvec3 step);  // camera right, down, forward, in units of the distance to the target
    void frame_scene();
    Document& document() { return doc_; }  // objects, clicks, selection, undo
    bool set_decoder(const std::string& name);  // graph, ptv3+graph, ptv3 or ground-truth; false if unavailable
    void show_mask(bool on) { show_mask_ = on; }
    void show_tints(bool on) { show_tints_ = on; }
    void isolate(bool on) { isolate_ = on; }
    void set_render_scale(double scale) { render_scale_ = scale; }
    // `format`: ply or sog; empty: the Export panel's choice.
    void export_to(const std::string& folder, bool scene, bool objects, bool masks, bool prompts,
                   const std::string& format = "");
    // Label by class (classes.cpp): every Gaussian's class from the semantic model (`model`, else
    // --semantic-model or the shipped one), on the job thread; the result replaces any earlier.
    void label_by_class(const std::string& model = {});
    void cancel_label_by_class();
    void show_classes(bool on) { show_classes_ = on; }
    // A new object from class `cls`: all its Gaussians, or (at a point of the picture) the
    // connected region of the class under it. Selected once made; clicks then correct it.
    bool object_from_class(int cls);
    void object_from_class_at(double picture_x, double picture_y);
    const ClassLabels* classes() const { return classes_.get(); }  // null before label by class
    void save_picture(const std::string& png) const;   // the rendered view, without the panels
    void save_window(const std::string& png) { capture_path_ = png; }  // at the next settled frame
    void quit() { quit_ = true; }
    // Closes this scene for another (any format the CLI reads; `lod` for a streamed SOG): run()
    // returns, and main opens a viewer on it in a fresh window (reopen() says what).
    void open_scene(const std::string& path, int lod = 0);
    struct Reopen {
        std::string scene;
        int lod = 0;
    };
    const std::optional<Reopen>& reopen() const { return reopen_; }

    // What actions refer to.
    const SceneData& scene() const { return scene_; }
    int snapped() const { return snapped_; }  // the dataset camera shown, -1: the free camera
    bool idle() const;  // no work queued, every object segmented, the newest view shown
    int errors() const { return errors_; }

private:
    struct ExportProgress {
        std::atomic<size_t> done{0}, total{0};
        std::atomic<bool> cancel{false}, running{false};
    };

    void open(const ViewerOptions& options);  // the constructor's work
    void release();                           // the destructor's: workers first, the context last
    void load(const ViewerOptions& options, const data::LoadProgress& progress);
    void load_in_window(const ViewerOptions& options);
    void load_prompts(const std::string& path);
    void update_segmentation();
    void cancel_segmentation();  // the job in flight stops at its next check
    void request_frame();
    FrameRequest frame_request(bool still) const;
    std::vector<glm::vec4> palette() const;
    int class_base() const;  // the palette index of class 0: past every object id
    void handle_input();
    void draw_panels();  // the side panel: one section each below
    void draw_view_panel();
    void draw_objects_panel();
    void draw_classes_panel();
    void draw_export_panel();
    void draw_timings_panel();
    void draw_markers();
    void status(const std::string& text, bool error = false);
    void leave_snap();

    ViewerOptions options_;
    SceneData scene_;
    std::unique_ptr<Window> window_;
    std::unique_ptr<vk::Context> ctx_;
    ViewedScene viewed_;  // the scene on the device, and its preview for a moving camera (streamed scenes)
    std::unique_ptr<Presenter> presenter_;
    std::unique_ptr<ImGuiLayer> imgui_;
    std::unique_ptr<FrameEngine> frame_engine_;
    std::unique_ptr<JobEngine> job_engine_;
    Inbox inbox_;
    std::unique_ptr<Worker> frames_, jobs_;  // declared last: joined first

    // View.
    OrbitCamera orbit_;
    int snapped_ = 0;
    double fov_y_ = 50;
    double render_scale_ = 1;
    glm::dvec3 centre_{0.0};
    double radius_ = 1;
    bool show_mask_ = true, show_tints_ = false, isolate_ = false;
    Rect viewport_;  // framebuffer pixels
    std::chrono::steady_clock::time_point last_motion_{};
    std::string requested_key_;
    uint64_t request_id_ = 0;
    FramePicture picture_;
    bool picture_valid_ = false;
    mutable struct {
        uint64_t picture = ~0ull;
        size_t pixel = 0;
        int32_t object = 0;
    } picked_;  // the object under the last pixel looked up

    // Segmentation.
    Document doc_;
    Session session_;
    std::vector<std::string> decoders_;
    std::string decoder_;
    std::shared_ptr<std::atomic<bool>> segment_cancel_;  // the job in flight's
    std::map<std::string, double> segment_ms_;
    double segment_wall_ms_ = 0, lift_ms_ = 0;
    std::atomic<double> slowest_graph_job_ms_{0};  // read by the job thread (want_coarse_answer)

    // Label by class.
    struct ClassJob {
        std::atomic<size_t> done{0}, total{0};
        std::atomic<bool> cancel{false}, running{false};
    };
    std::shared_ptr<ClassJob> class_job_;
    std::shared_ptr<const ClassLabels> classes_;
    uint64_t classes_version_ = 0;
    std::map<std::string, double> class_ms_;
    double class_wall_ms_ = 0;
    bool show_classes_ = true;
    int class_chosen_ = -1;           // in the legend
    bool pick_class_region_ = false;  // the next click in the view makes an object from the class region under it

    // Export and status.
    std::string export_folder_;
    std::shared_ptr<ExportProgress> export_;
    std::string status_;
    bool status_error_ = false;
    int errors_ = 0;

    // Panel edits in progress (ImGui keeps no state of its own for them).
    struct PanelState {
        char name[128] = {};
        int name_for = -1;
        uint64_t name_version = 0;
        float colour[3] = {};
        bool editing_colour = false;
        char folder[512] = {};
        bool folder_set = false;
        int format = 0;  // 0: PLY, 1: SOG
        char open_path[512] = {};
        int open_lod = 0;
    } panel_;

    std::unique_ptr<ScriptRunner> script_;  // --script or --screenshot: replay, capture, quit
    std::string capture_path_;
    bool quit_ = false;
    std::optional<Reopen> reopen_;
    double frame_ms_ = 0;
};

}  // namespace pg::viewer
