#include "app/viewer/viewer.h"

#include "app/common/memory_arg.h"
#include "app/common/progress.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <thread>
#include <cstdio>
#include <filesystem>

#include <GLFW/glfw3.h>
#include <imgui.h>

#include "app/common/ptv3_classifier.h"
#include "app/common/ptv3_decoder.h"
#include "app/common/up_arg.h"
#include "app/viewer/script_runner.h"
#include "dataset/error.h"
#include "dataset/formats/camera_io.h"
#include "dataset/formats/image_io.h"
#include "dataset/formats/scene_io.h"
#include "dataset/orbit.h"
#include "dataset/prompts.h"
#include "dataset/report/palette.h"

namespace pg::viewer {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

double ms_between(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
}

// Cameras beside the scene, as `pointgauss synth` and the usual datasets lay them out.
std::string cameras_beside(const fs::path& scene) {
    const fs::path dir = scene.parent_path();
    for (const char* name : {"cameras.json", "transforms.json"})
        if (fs::exists(dir / name)) return (dir / name).string();
    for (const fs::path& sub : {fs::path("sparse") / "0", fs::path("sparse")})
        if (fs::is_directory(dir / sub) &&
            (fs::exists(dir / sub / "cameras.bin") || fs::exists(dir / sub / "cameras.txt")))
            return (dir / sub).string();
    return {};
}

double median_of(std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + long(v.size() / 2), v.end());
    return v[v.size() / 2];
}

void save_rgba(const fs::path& path, const std::vector<uint8_t>& rgba, int w, int h) {
    std::vector<uint8_t> rgb(size_t(w) * h * 3);
    for (size_t p = 0; p < size_t(w) * h; ++p)
        for (int c = 0; c < 3; ++c) rgb[3 * p + c] = rgba[4 * p + c];
    if (path.has_parent_path()) fs::create_directories(path.parent_path());
    data::write_png8(path, w, h, 3, rgb);
}

}  // namespace

Viewer::Viewer(const ViewerOptions& options) : options_(options) {
    try {
        open(options);
    } catch (...) {
        release();  // a bad scene or option after the window opened: its surface goes before the instance
        throw;
    }
}

void Viewer::open(const ViewerOptions& options) {
    if (!options.script.empty() || !options.screenshot.empty())
        script_ = std::make_unique<ScriptRunner>(options.script.empty() ? std::vector<Action>{} : read_script(options.script),
                                                 options.screenshot, options.script_log);
    const auto budget = app::scene_budget(options.max_device_memory, options.half_sh);  // a bad size fails first
    window_ = std::make_unique<Window>("PointGauss - " + fs::path(options.scene).filename().string(), options.width,
                                       options.height);
    ctx_ = window_->make_context(options.device);
    int fw, fh;
    window_->framebuffer_size(fw, fh);
    presenter_ = std::make_unique<Presenter>(*ctx_, window_->surface(), fw, fh);
    imgui_ = std::make_unique<ImGuiLayer>(*ctx_, window_->handle(), *presenter_);
    load_in_window(options);
    viewed_ = upload_viewed_scene(*ctx_, scene_.cloud, budget);
    frame_engine_ = std::make_unique<FrameEngine>(*ctx_, *viewed_.scene, viewed_.preview_scene.get(),
                                                  viewed_.preview ? &viewed_.preview->ids : nullptr);
    job_engine_ = std::make_unique<JobEngine>(*ctx_, scene_, *viewed_.scene);
    inbox_.wake = [] { glfwPostEmptyEvent(); };
    frames_ = std::make_unique<Worker>(true);
    jobs_ = std::make_unique<Worker>(false);
    // The segmentation pipelines are built now, while the user looks at the first frames, not
    // on the first click (see warm_up.h).
    jobs_->post([this, decoder = decoder_] {
        try {
            job_engine_->warm_up(decoder);
        } catch (const std::exception& e) {
            std::fprintf(stderr, "viewer: warming up the segmentation pipelines failed: %s\n", e.what());
        }
    });
    if (!options.prompts.empty()) load_prompts(options.prompts);
    render_scale_ = options.render_scale > 0 ? options.render_scale
                                             : (ctx_->info().type == VK_PHYSICAL_DEVICE_TYPE_CPU ? 0.5 : 1.0);
    if (script_) render_scale_ = options.render_scale > 0 ? options.render_scale : 1.0;
}

Viewer::~Viewer() { release(); }

void Viewer::release() {
    if (export_) export_->cancel = true;
    if (class_job_) class_job_->cancel = true;
    jobs_.reset();
    frames_.reset();
    inbox_.drain();  // pictures waiting there hold device buffers
    picture_ = {};
    job_engine_.reset();
    frame_engine_.reset();
    imgui_.reset();
    presenter_.reset();
    viewed_ = {};
    if (window_) window_->destroy_surface();
    ctx_.reset();
}

void Viewer::load_in_window(const ViewerOptions& o) {
    // The scene loads on a thread while the window shows how far it got (a 6 M-Gaussian PLY
    // takes seconds), and the terminal line as before.
    std::atomic<double> fraction{0.0};
    std::atomic<bool> done{false};
    std::exception_ptr error;
    std::thread loader([&] {
        try {
            app::Progress line("loading " + o.scene, 100);
            load(o, [&](double f) {
                line.set(size_t(f * 100.0), "%");
                fraction = f;
                glfwPostEmptyEvent();
            });
        } catch (...) {
            error = std::current_exception();
        }
        done = true;
        glfwPostEmptyEvent();
    });
    // A frame that fails here (a submission out of memory, a lost device) must not unwind past a
    // loader still running: its thread would end the process with std::terminate, not one error.
    struct JoinOnExit {
        std::thread& t;
        ~JoinOnExit() {
            if (t.joinable()) t.join();
        }
    } join_on_exit{loader};
    while (!done) {
        glfwWaitEventsTimeout(0.1);
        int fw, fh;
        window_->framebuffer_size(fw, fh);
        imgui_->begin_frame();
        const ImGuiViewport* vp = ImGui::GetMainViewport();
        ImGui::SetNextWindowPos(ImVec2(vp->Pos.x + vp->Size.x * 0.5f, vp->Pos.y + vp->Size.y * 0.5f), ImGuiCond_Always,
                                ImVec2(0.5f, 0.5f));
        ImGui::SetNextWindowSize(ImVec2(std::min(480.0f, vp->Size.x * 0.8f), 0));
        ImGui::Begin("Loading", nullptr, ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize);
        ImGui::TextWrapped("%s", o.scene.c_str());
        ImGui::ProgressBar(float(fraction.load()));
        ImGui::End();
        imgui_->end_frame();
        presenter_->present(fw, fh, [&](VkCommandBuffer cmd) { imgui_->record(cmd); });
    }
    loader.join();
    if (error) std::rethrow_exception(error);
}

void Viewer::load(const ViewerOptions& o, const data::LoadProgress& progress) {
    scene_.scene_path = o.scene;
    scene_.lod = o.lod;
    scene_.cloud = data::load_scene(o.scene, progress, o.lod);
    if (scene_.cloud.size() == 0) throw data::InputError(o.scene, "holds no Gaussians");
    scene_.cameras_path = o.cameras.empty() ? cameras_beside(o.scene) : o.cameras;
    if (!scene_.cameras_path.empty()) scene_.cameras = data::load_cameras(scene_.cameras_path);
    std::string up = o.up;
    // Without cameras: -y, the frame COLMAP-trained scenes (most 3DGS PLYs) are stored in.
    if (up == "auto") up = scene_.cameras.empty() ? "-y" : "cameras";
    scene_.up_spec = up;
    scene_.options.up = app::resolve_up(up, scene_.cameras, scene_.cloud);
    scene_.options.lift = seg::parse_lift_rule(o.lift, "--lift");
    if (scene_.cameras.empty()) {
        // A scene without cameras gets an orbit, so it has views to snap to, export and replay.
        data::OrbitOptions oo;
        oo.width = 960;
        oo.height = 540;
        scene_.cameras = data::orbit_cameras(scene_.cloud, scene_.options.up, oo);
    }

    std::vector<double> xs, ys, zs;
    for (auto& m : scene_.cloud.mean) xs.push_back(m.x), ys.push_back(m.y), zs.push_back(m.z);
    centre_ = {median_of(xs), median_of(ys), median_of(zs)};
    std::vector<double> d;
    for (auto& m : scene_.cloud.mean) d.push_back(glm::length(glm::dvec3(m) - centre_));
    std::nth_element(d.begin(), d.begin() + long(d.size() * 9 / 10), d.end());
    radius_ = std::max(1e-6, d[d.size() * 9 / 10]);
    const auto& c0 = scene_.cameras.front();
    fov_y_ = glm::degrees(2.0 * std::atan(0.5 * c0.height / c0.fy));
    orbit_ = OrbitCamera(scene_.options.up);
    session_ = Session(scene_.cloud.size());
    frame_scene();
    snapped_ = 0;

    // Decoders as `segment` names them: the graph needs no network; the network's file is
    // --model, else the shipped one; ground-truth (the scene's own labels) for evaluation.
    const std::string shipped = app::default_model_path();
    if (!o.model.empty() && o.model != "ground-truth") {
        if (!fs::exists(o.model)) throw data::InputError("--model", "'" + o.model + "' does not exist");
        scene_.model = o.model;
    } else {
        scene_.model = shipped;
    }
    decoders_ = {"graph"};
    if (!scene_.model.empty()) decoders_.insert(decoders_.end(), {"ptv3+graph", "ptv3"});
    if (scene_.cloud.int_property("instance")) decoders_.push_back("ground-truth");
    if (o.model == "ground-truth" && !scene_.cloud.int_property("instance"))
        throw data::InputError(o.scene, "has no 'instance' property for the ground-truth decoder");
    // As `segment`: the graph by default; a model named without a decoder means ptv3+graph.
    std::string want = o.decoder;
    if (want.empty()) want = o.model == "ground-truth" ? "ground-truth" : o.model.empty() ? "graph" : "ptv3+graph";
    if (!set_decoder(want))
        throw data::InputError("--decoder", "'" + want + "' is not available (" +
                                                (want == "ground-truth" ? "the scene has no 'instance' property"
                                                                        : "no model found: set PG_MODEL or give --model") +
                                                ")");
    // Label by class: --semantic-model, else the shipped semantic model (none: the action says so).
    if (!o.semantic_model.empty() && !fs::exists(o.semantic_model))
        throw data::InputError("--semantic-model", "'" + o.semantic_model + "' does not exist");
    scene_.semantic_model = o.semantic_model.empty() ? app::default_semantic_model_path() : o.semantic_model;
    export_folder_ = o.out.empty() ? (fs::path(o.scene).stem().string() + "-segmentation") : o.out;
}

// Objects and clicks of a prompts.json (a `segment` input or an earlier export). View clicks are
// lifted on the job thread for their markers; the file's clicks stay as they are, so exporting
// again writes the same prompts.
void Viewer::load_prompts(const std::string& path) {
    const data::Prompts prompts = data::read_prompts(path);
    for (const auto& o : prompts.objects)
        for (const auto& c : o.clicks)
            if (!c.point && std::none_of(scene_.cameras.begin(), scene_.cameras.end(),
                                         [&](auto& cam) { return cam.name == c.view; }))
                throw data::InputError(path, "object '" + o.name + "' clicks in view '" + c.view +
                                                 "', which is not one of the scene's cameras");
    jobs_->post([this, prompts, path] {
        DocumentState state;
        std::string error;
        try {
            for (const auto& op : prompts.objects) {
                Object o;
                o.id = op.id;
                o.name = op.name;
                o.colour = default_object_colour(op.id);
                for (const auto& c : op.clicks) o.clicks.push_back(Click{c, job_engine_->anchor(c)});
                state.next_id = std::max(state.next_id, o.id + 1);
                state.objects.push_back(std::move(o));
            }
            if (!state.objects.empty()) state.selected = state.objects.front().id;
        } catch (const std::exception& e) {
            error = e.what();
        }
        inbox_.post([this, state, error, path] {
            if (!error.empty()) return status(path + ": " + error, true);
            doc_.reset(state);
            status("loaded " + std::to_string(state.objects.size()) + " object(s) from " + path);
        });
    });
}

// ---------------------------------------------------------------------------------------------
// Actions

void Viewer::status(const std::string& text, bool error) {
    status_ = text;
    status_error_ = error;
    if (error) {
        ++errors_;
        std::fprintf(stderr, "viewer: %s\n", text.c_str());
    }
}

void Viewer::leave_snap() {
    if (snapped_ < 0) return;
    const auto& c = scene_.cameras[size_t(snapped_)];
    const double ahead = glm::dot(centre_ - c.position(), c.forward());
    orbit_.match(c, ahead > 1e-6 ? ahead : radius_);
    snapped_ = -1;
}

void Viewer::snap(int camera) {
    if (camera >= int(scene_.cameras.size())) camera = int(scene_.cameras.size()) - 1;
    if (camera < 0) {
        leave_snap();
        return;
    }
    snapped_ = camera;
    last_motion_ = Clock::now();
}

void Viewer::orbit(double yaw, double pitch) {
    leave_snap();
    orbit_.orbit(yaw, pitch);
    last_motion_ = Clock::now();
}

void Viewer::pan(double right, double down) {
    leave_snap();
    orbit_.pan(right, down);
    last_motion_ = Clock::now();
}

void Viewer::zoom(double factor) {
    leave_snap();
    orbit_.dolly(factor);
    last_motion_ = Clock::now();
}

void Viewer::fly(glm::dvec3 step) {
    leave_snap();
    orbit_.fly(step);
    last_motion_ = Clock::now();
}

void Viewer::frame_scene() {
    const double d = radius_ / std::tan(glm::radians(0.5 * fov_y_)) * 1.1;
    const glm::dvec3 up = scene_.options.up;
    glm::dvec3 a, b;
    data::horizontal_axes(up, a, b);
    orbit_.look_at(centre_ + d * glm::normalize(a * 0.9 + up * 0.35), centre_);
    snapped_ = -1;
    last_motion_ = Clock::now();
}

int Viewer::object_at(double x, double y) const {
    if (!picture_valid_ || !picture_.object || x < 0 || y < 0 || x >= 1 || y >= 1) return 0;
    const int w = picture_.camera.width, h = picture_.camera.height;
    const size_t pixel = size_t(int(y * h)) * w + int(x * w);
    // One pixel read when the pointer reaches it: pictures stay on the device.
    if (picked_.picture != picture_.id || picked_.pixel != pixel) {
        picked_ = {picture_.id, pixel, 0};
        vk::download(*ctx_, *picture_.object, &picked_.object, sizeof picked_.object, pixel * sizeof picked_.object);
    }
    return doc_.find(picked_.object) ? picked_.object : 0;
}

void Viewer::click_at(double x, double y, bool positive) {
    if (!picture_valid_ || x < 0 || y < 0 || x >= 1 || y >= 1) return;
    data::Camera cam = picture_.camera;
    data::PromptClick prompt;
    prompt.positive = positive;
    // A dataset view keeps its own pixels, so `segment` replays the click on the same camera.
    auto it = std::find_if(scene_.cameras.begin(), scene_.cameras.end(),
                           [&](auto& c) { return c.name == cam.name; });
    const bool dataset_view = it != scene_.cameras.end();
    if (dataset_view) cam = *it;
    const double u = x * cam.width, v = y * cam.height;
    if (dataset_view) {
        prompt.view = cam.name;
        prompt.u = u;
        prompt.v = v;
    }
    // The lift waits on the job thread behind a segmentation in flight: one this click makes
    // pointless (a joint solve, unless the click edits a region object, or its own object's) stops now.
    const Object* selected = doc_.selected();
    const bool edits_region = selected && selected->region;
    if (session_.in_flight_covers(doc_.state().selected) || (session_.in_flight_joint() && !edits_region))
        cancel_segmentation();
    jobs_->post([this, cam, u, v, prompt]() mutable {
        const auto t0 = Clock::now();
        try {
            seg::Anchor a = job_engine_->lift(cam, u, v, prompt.positive);
            const double ms = ms_between(t0, Clock::now());
            if (prompt.view.empty()) prompt.point = a.position;
            inbox_.post([this, prompt, a, ms] {
                lift_ms_ = ms;
                doc_.add_click(Click{prompt, a});
                status(std::string(prompt.positive ? "positive" : "negative") + " click added");
            });
        } catch (const std::exception& e) {
            std::string what = e.what();
            inbox_.post([this, what] { status("click ignored: " + what, true); });
        }
    });
}

void Viewer::open_scene(const std::string& path, int lod) {
    std::error_code ec;
    if (path.empty() || !fs::exists(path, ec)) {
        status("open: '" + path + "' does not exist", true);
        return;
    }
    if (lod < 0) {
        status("open: the LOD level must be 0 or more", true);
        return;
    }
    reopen_ = Reopen{path, lod};
    quit_ = true;
}

void Viewer::export_to(const std::string& folder, bool scene, bool objects, bool masks, bool prompts,
                       const std::string& format) {
    if (export_ && export_->running) {
        status("an export is already running", true);
        return;
    }
    if (!session_.labels() && !classes_) {
        status("nothing to export yet: click an object (or label by class) first", true);
        return;
    }
    ExportRequest rq;
    rq.folder = folder;
    rq.scene = scene;
    rq.objects = objects;
    rq.masks = masks;
    rq.prompts = prompts;
    rq.labels = session_.labels();
    rq.document = doc_.state();
    rq.prompts_json = doc_.prompts();
    rq.decoder = decoder_;
    rq.stage_ms = segment_ms_;
    rq.classes = classes_;
    rq.format = !format.empty() ? format : panel_.format == 1 ? "sog" : "ply";
    if (rq.format != "ply" && rq.format != "sog") {
        status("export format '" + rq.format + "': expected ply or sog", true);
        return;
    }
    export_ = std::make_shared<ExportProgress>();
    export_->running = true;
    auto progress = export_;
    jobs_->post([this, rq, progress] {
        std::string error;
        try {
            job_engine_->write(rq, progress->done, progress->total, progress->cancel);
        } catch (const std::exception& e) {
            error = e.what();
        }
        progress->running = false;
        inbox_.post([this, rq, error, progress] {
            if (!error.empty()) status("export failed: " + error, true);
            else if (progress->cancel) status("export cancelled");
            else status("exported to " + rq.folder.string());
        });
    });
}

bool Viewer::set_decoder(const std::string& want) {
    auto it = std::find(decoders_.begin(), decoders_.end(), want == "model" ? "ptv3" : want);
    if (it == decoders_.end()) return false;
    decoder_ = *it;
    return true;
}

void Viewer::save_picture(const std::string& png) const {
    if (!picture_valid_) throw std::runtime_error("no picture yet");
    const int w = picture_.camera.width, h = picture_.camera.height;
    save_rgba(png, vk::download_vector<uint8_t>(*ctx_, *picture_.rgba, size_t(w) * h * 4), w, h);
}

// ---------------------------------------------------------------------------------------------
// Segmentation: the session decides what each job covers (one object, or all for the graph).

void Viewer::cancel_segmentation() {
    if (segment_cancel_) segment_cancel_->store(true);
}

void Viewer::update_segmentation() {
    session_.sync(doc_, decoder_);
    if (session_.in_flight_stale()) cancel_segmentation();  // an undo, a deletion, another decoder
    auto job = session_.next_job();
    if (!job) return;
    auto cancel = std::make_shared<std::atomic<bool>>(false);
    segment_cancel_ = cancel;
    jobs_->post([this, job = *job, cancel] {
        SegmentOutcome outcome;
        std::map<std::string, double> ms;
        const auto t0 = Clock::now();
        // A cold graph solve's coarse answer is shown while the full one runs, where solves are slow.
        std::function<void(SegmentOutcome)> coarse;
        if (want_coarse_answer(ctx_->info().type == VK_PHYSICAL_DEVICE_TYPE_CPU, slowest_graph_job_ms_))
            coarse = [this, job](SegmentOutcome answer) {
                inbox_.post([this, job, answer = std::move(answer)]() mutable { session_.store_coarse(job, std::move(answer)); });
            };
        try {
            outcome = job_engine_->segment(job, ms, cancel.get(), coarse);
        } catch (const std::exception& e) {
            outcome.error = e.what();
        }
        const double wall = ms_between(t0, Clock::now());
        inbox_.post([this, job, outcome, ms, wall] {
            session_.store(job, outcome);
            if (outcome.cancelled) return;
            if (!outcome.error.empty()) status("segmentation failed: " + outcome.error, true);
            else if (!outcome.errors.empty()) status("segmentation failed: " + outcome.errors.begin()->second, true);
            else segment_ms_ = ms, segment_wall_ms_ = wall;
            if (ms.count("graph solve")) slowest_graph_job_ms_ = std::max(slowest_graph_job_ms_.load(), wall);
        });
    });
}

bool Viewer::idle() const {
    return !frames_->busy() && !jobs_->busy() && session_.settled() && picture_valid_ && picture_.id == request_id_;
}

// ---------------------------------------------------------------------------------------------
// Frames

std::vector<glm::vec4> Viewer::palette() const {
    int max_id = 0;
    for (auto& o : doc_.state().objects) max_id = std::max(max_id, o.id);
    const int selected = doc_.state().selected;
    std::vector<glm::vec4> p(size_t(max_id) + 1, glm::vec4(0, 0, 0, isolate_ ? -1.0f : 0.0f));
    for (auto& o : doc_.state().objects) {
        float a = show_tints_ ? 0.5f : 0.0f;
        if (o.hidden || (isolate_ && o.id != selected)) a = -1.0f;
        p[size_t(o.id)] = glm::vec4(o.colour, a);
    }
    // Classes past the objects: tinted as the class overlays of segment --semantic, class 0 not at all.
    if (classes_ && show_classes_) {
        p.resize(size_t(class_base()), p.front());
        for (size_t c = 0; c < classes_->counts.size(); ++c) {
            const float a = isolate_ ? -1.0f : c == 0 ? 0.0f : 0.5f;
            p.push_back(glm::vec4(data::report::class_colour(int(c)), a));
        }
    }
    return p;
}

int Viewer::class_base() const {
    // A multiple of 64 past every object id: it moves (and the frame thread rebuilds its tint
    // labels) once every 64 new objects, not with each.
    int max_id = 0;
    for (auto& o : doc_.state().objects) max_id = std::max(max_id, o.id);
    return (max_id / 64 + 1) * 64;
}

FrameRequest Viewer::frame_request(bool still) const {
    FrameRequest rq;
    // A moving camera gets half the resolution: four times fewer pixels keep the motion fluid.
    const double scale = render_scale_ * (still ? 1.0 : 0.5);
    const int vw = std::max(1, int(viewport_.width * scale));
    const int vh = std::max(1, int(viewport_.height * scale));
    if (snapped_ >= 0) {
        const auto& c = scene_.cameras[size_t(snapped_)];
        const double s = std::min(double(vw) / c.width, double(vh) / c.height);
        rq.camera = c.resized(std::max(1, int(std::lround(c.width * s))), std::max(1, int(std::lround(c.height * s))));
    } else {
        rq.camera = orbit_.camera(vw, vh, fov_y_);
    }
    rq.labels = session_.labels();
    rq.labels_version = session_.labels_version();
    if (classes_ && show_classes_) {
        rq.classes = std::shared_ptr<const std::vector<int32_t>>(classes_, &classes_->classes);
        rq.classes_version = classes_version_;
        rq.class_base = class_base();
    }
    rq.palette = palette();
    rq.mask = still && show_mask_ && rq.labels;
    rq.preview = !still;
    return rq;
}

void Viewer::request_frame() {
    if (viewport_.width <= 0 || viewport_.height <= 0) return;
    // While the camera moves, frames skip the mask passes; they come back once it rests.
    const bool still = script_ || ms_between(last_motion_, Clock::now()) > 250;
    FrameRequest rq = frame_request(still);
    const auto& c = rq.camera;
    char key[256];
    std::snprintf(key, sizeof key, "%s %d %d %.9g %.9g %.9g %.9g %.9g %.9g %.9g %llu %llu %d %d %d|", c.name.c_str(),
                  c.width, c.height, c.fx, c.fy, c.cx, c.cy, c.t.x, c.t.y, c.t.z, (unsigned long long)rq.labels_version,
                  (unsigned long long)(rq.classes ? rq.classes_version : 0), rq.class_base, int(rq.mask),
                  int(rq.preview));
    std::string k = key;
    for (int i = 0; i < 9; ++i) k += std::to_string(c.R[i / 3][i % 3]) + ",";
    for (auto& p : rq.palette) k += std::to_string(p.r + 2 * p.g + 4 * p.b) + "/" + std::to_string(p.a) + ",";
    if (k == requested_key_) return;
    requested_key_ = k;
    rq.id = ++request_id_;
    frames_->post([this, rq] {
        try {
            FramePicture pic = frame_engine_->render(rq);
            inbox_.post([this, pic = std::move(pic)]() mutable {
                presenter_->set_picture(pic.rgba, pic.camera.width, pic.camera.height);
                picture_ = std::move(pic);
                picture_valid_ = true;
            });
        } catch (const std::exception& e) {
            std::string what = e.what();
            inbox_.post([this, what] { status("render failed: " + what, true); });
        }
    });
}

// ---------------------------------------------------------------------------------------------
// The loop

int Viewer::run() {
    auto last = Clock::now();
    while (!window_->should_close() && !quit_) {
        const bool busy = frames_->busy() || jobs_->busy() || script_ || ms_between(last_motion_, Clock::now()) < 400;
        if (busy) glfwPollEvents();
        else glfwWaitEventsTimeout(0.25);
        // Idle is judged before the inbox is drained: what arrives now is shown by this frame.
        const bool workers_idle = !frames_->busy() && !jobs_->busy();
        inbox_.drain();
        update_segmentation();

        int fw, fh;
        window_->framebuffer_size(fw, fh);
        imgui_->begin_frame();
        ImGuiIO& io = ImGui::GetIO();
        const int panel = int(340 * io.DisplayFramebufferScale.x);
        viewport_ = {panel, 0, std::max(0, fw - panel), fh};
        presenter_->set_viewport(viewport_);
        handle_input();
        draw_panels();
        draw_markers();
        imgui_->end_frame();
        request_frame();

        if (script_) script_->step(*this, workers_idle && idle());
        const bool capture = !capture_path_.empty() && script_ && script_->settled();
        presenter_->present(fw, fh, [&](VkCommandBuffer cmd) { imgui_->record(cmd); }, capture);
        if (capture) {
            save_rgba(capture_path_, presenter_->captured(), presenter_->captured_width(),
                      presenter_->captured_height());
            capture_path_.clear();
            if (script_->finished()) quit_ = true;
        }
        const auto now = Clock::now();
        frame_ms_ = ms_between(last, now);
        last = now;
    }
    if (errors_ > 0 && script_) return 1;
    if (vk::Context::validation_message_count() > 0) {
        std::fprintf(stderr, "viewer: %llu Vulkan validation message(s)\n",
                     (unsigned long long)vk::Context::validation_message_count());
        return 1;
    }
    return 0;
}

}  // namespace pg::viewer
