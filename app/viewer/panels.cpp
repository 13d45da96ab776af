// The side panel: scene and device, view, objects, classes, export, timings.
#include <algorithm>
#include <cstdio>
#include <filesystem>

#include <imgui.h>

#include "app/viewer/viewer.h"
#include "dataset/report/palette.h"

namespace pg::viewer {

namespace {

std::string short_name(const std::string& path) {
    const std::string name = std::filesystem::path(path).filename().string();
    return name.empty() ? path : name;
}

void timing_row(const char* name, double ms) { ImGui::Text("%-22s %9.1f ms", name, ms); }

}  // namespace

void Viewer::draw_panels() {
    ImGuiIO& io = ImGui::GetIO();
    const float width = 340.0f;
    ImGui::SetNextWindowPos(ImVec2(0, 0));
    ImGui::SetNextWindowSize(ImVec2(width, io.DisplaySize.y));
    ImGui::Begin("PointGauss", nullptr,
                 ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
                     ImGuiWindowFlags_NoTitleBar);

    ImGui::TextUnformatted(short_name(scene_.scene_path).c_str());
    ImGui::TextDisabled("%zu Gaussians, %zu cameras%s", scene_.cloud.size(), scene_.cameras.size(),
                        scene_.cameras_path.empty() ? " (orbit)" : "");
    ImGui::TextDisabled("up (%s): %.2f %.2f %.2f", scene_.up_spec.c_str(), scene_.options.up.x, scene_.options.up.y,
                        scene_.options.up.z);

    // Another scene (PLY, .splat, .spz, SOG...): this one closes, a new window opens on it.
    ImGui::SetNextItemWidth(200);
    ImGui::InputText("##open", panel_.open_path, sizeof panel_.open_path);
    ImGui::SameLine();
    ImGui::SetNextItemWidth(40);
    ImGui::InputInt("lod", &panel_.open_lod, 0);
    ImGui::SameLine();
    if (ImGui::Button("Open")) open_scene(panel_.open_path, panel_.open_lod);

    draw_view_panel();
    draw_objects_panel();
    draw_classes_panel();
    draw_export_panel();
    draw_timings_panel();
    if (!status_.empty()) {
        ImGui::Separator();
        if (status_error_) ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "%s", status_.c_str());
        else ImGui::TextWrapped("%s", status_.c_str());
    }
    ImGui::End();
}

void Viewer::draw_view_panel() {
    if (ImGui::CollapsingHeader("View", ImGuiTreeNodeFlags_DefaultOpen)) {
        const std::string current = snapped_ >= 0 ? scene_.cameras[size_t(snapped_)].name : "free camera";
        ImGui::SetNextItemWidth(200);
        if (ImGui::BeginCombo("camera", current.c_str())) {
            if (ImGui::Selectable("free camera", snapped_ < 0)) snap(-1);
            for (size_t i = 0; i < scene_.cameras.size(); ++i)
                if (ImGui::Selectable(scene_.cameras[i].name.c_str(), int(i) == snapped_)) snap(int(i));
            ImGui::EndCombo();
        }
        const int n = int(scene_.cameras.size());
        if (ImGui::ArrowButton("prev", ImGuiDir_Left)) snap(snapped_ <= 0 ? n - 1 : snapped_ - 1);
        ImGui::SameLine();
        if (ImGui::ArrowButton("next", ImGuiDir_Right)) snap(snapped_ < 0 ? 0 : (snapped_ + 1) % n);
        ImGui::SameLine();
        if (ImGui::Button("Frame scene (F)")) frame_scene();
        bool mask = show_mask_, tints = show_tints_, only = isolate_;
        if (ImGui::Checkbox("mask overlay", &mask)) show_mask(mask);
        ImGui::SameLine();
        if (ImGui::Checkbox("3D tints", &tints)) show_tints(tints);
        if (ImGui::Checkbox("only the selected object (I)", &only)) isolate(only);
        float scale = float(render_scale_);
        ImGui::SetNextItemWidth(200);
        if (ImGui::SliderFloat("render scale", &scale, 0.25f, 1.0f, "%.2f")) set_render_scale(scale);
        ImGui::TextDisabled("drag: orbit, right drag: pan, wheel: zoom\nWASD QE: fly, [ ]: cameras\n"
                            "click: positive, ctrl/right click: negative\nalt+click: select the object under it");
    }
}

void Viewer::draw_objects_panel() {
    if (ImGui::CollapsingHeader("Objects", ImGuiTreeNodeFlags_DefaultOpen)) {
        if (decoders_.size() > 1) {
            ImGui::SetNextItemWidth(200);
            if (ImGui::BeginCombo("decoder", short_name(decoder_).c_str())) {
                for (auto& d : decoders_)
                    if (ImGui::Selectable(short_name(d).c_str(), d == decoder_)) set_decoder(d);
                ImGui::EndCombo();
            }
        } else {
            ImGui::TextDisabled("decoder: %s", short_name(decoder_).c_str());
        }
        if (ImGui::Button("New object (N)")) doc_.add_object();
        ImGui::SameLine();
        ImGui::BeginDisabled(!doc_.can_undo());
        if (ImGui::Button("Undo")) doc_.undo();
        ImGui::EndDisabled();
        ImGui::SameLine();
        ImGui::BeginDisabled(!doc_.can_redo());
        if (ImGui::Button("Redo")) doc_.redo();
        ImGui::EndDisabled();
        if (doc_.can_undo()) ImGui::TextDisabled("undo: %s", doc_.undo_label().c_str());

        ImGui::BeginChild("objects", ImVec2(0, 150), true);
        for (const auto& o : doc_.state().objects) {
            ImGui::PushID(o.id);
            ImGui::ColorButton("##c", ImVec4(o.colour.r, o.colour.g, o.colour.b, 1), ImGuiColorEditFlags_NoTooltip,
                               ImVec2(14, 14));
            ImGui::SameLine();
            char label[256];
            std::snprintf(label, sizeof label, "%s%s  (%zu)", o.name.c_str(), o.hidden ? " [hidden]" : "",
                          session_.labelled(o.id));
            if (ImGui::Selectable(label, o.id == doc_.state().selected)) doc_.select(o.id);
            ImGui::PopID();
        }
        ImGui::EndChild();

        if (const Object* sel = doc_.selected()) {
            const int id = sel->id;
            auto& ps = panel_;
            if (ps.name_for != id || ps.name_version != doc_.version()) {
                std::snprintf(ps.name, sizeof ps.name, "%s", sel->name.c_str());
                ps.name_for = id;
                ps.name_version = doc_.version();
            }
            ImGui::SetNextItemWidth(200);
            ImGui::InputText("name", ps.name, sizeof ps.name);
            if (ImGui::IsItemDeactivatedAfterEdit()) doc_.rename(id, ps.name);
            // One undo step per colour pick: the edit lands when the picker is let go.
            if (!ps.editing_colour)
                for (int c = 0; c < 3; ++c) ps.colour[c] = sel->colour[c];
            ImGui::ColorEdit3("colour", ps.colour, ImGuiColorEditFlags_NoInputs);
            ps.editing_colour = ImGui::IsItemActive();
            if (ImGui::IsItemDeactivatedAfterEdit())
                doc_.recolour(id, glm::vec3(ps.colour[0], ps.colour[1], ps.colour[2]));
            bool hidden = sel->hidden;
            if (ImGui::Checkbox("hidden (H)", &hidden)) doc_.set_hidden(id, hidden);
            ImGui::SameLine();
            if (ImGui::Button("Delete")) doc_.remove(id);
            size_t pos = 0, neg = 0;
            for (auto& c : sel->clicks) (c.prompt.positive ? pos : neg)++;
            ImGui::TextDisabled("%zu positive, %zu negative clicks", pos, neg);
            if (sel->region) ImGui::TextDisabled("from %s", sel->region->source.c_str());
            if (const std::string& error = session_.error(id); !error.empty())
                ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "%s", error.c_str());
        }
    }
}

void Viewer::draw_classes_panel() {
    if (ImGui::CollapsingHeader("Classes", ImGuiTreeNodeFlags_DefaultOpen)) {
        const bool running = class_job_ && class_job_->running;
        ImGui::BeginDisabled(running);
        if (ImGui::Button("Label by class")) label_by_class();
        ImGui::EndDisabled();
        ImGui::SameLine();
        ImGui::TextDisabled("model: %s", scene_.semantic_model.empty() ? "none found"
                                                                       : short_name(scene_.semantic_model).c_str());
        if (running) {
            const size_t total = std::max<size_t>(1, class_job_->total);
            char text[64];
            std::snprintf(text, sizeof text, "%zu / %zu tiles", size_t(class_job_->done), size_t(class_job_->total));
            ImGui::ProgressBar(float(class_job_->done) / float(total), ImVec2(220, 0), text);
            ImGui::SameLine();
            if (ImGui::Button("Cancel##classes")) cancel_label_by_class();
        }
        if (!classes_) return;
        bool tints = show_classes_;
        if (ImGui::Checkbox("class tints", &tints)) show_classes(tints);
        // The legend: swatch, name and count per class; choosing one is what the button below takes.
        const ImGuiStyle& style = ImGui::GetStyle();
        const float row = std::max(ImGui::GetTextLineHeightWithSpacing(), 14 + style.ItemSpacing.y);  // the swatch's
        const float rows = float(std::min<size_t>(classes_->counts.size(), 8));
        ImGui::BeginChild("classes", ImVec2(0, row * rows + 2 * style.WindowPadding.y), true);
        for (size_t c = 0; c < classes_->counts.size(); ++c) {
            ImGui::PushID(int(c));
            const glm::vec3 colour = c == 0 ? glm::vec3(1.0f) : data::report::class_colour(int(c));
            ImGui::ColorButton("##c", ImVec4(colour.r, colour.g, colour.b, 1), ImGuiColorEditFlags_NoTooltip,
                               ImVec2(14, 14));
            ImGui::SameLine();
            char label[256];
            std::snprintf(label, sizeof label, "%s%s  (%zu)", classes_->name(int(c)).c_str(),
                          c == 0 ? " (no tint)" : "", classes_->counts[c]);
            if (ImGui::Selectable(label, int(c) == class_chosen_)) class_chosen_ = int(c);
            ImGui::PopID();
        }
        ImGui::EndChild();
        ImGui::BeginDisabled(class_chosen_ < 0);
        if (ImGui::Button("Object from the chosen class")) object_from_class(class_chosen_);
        ImGui::EndDisabled();
        ImGui::Checkbox("next click: object from its class region", &pick_class_region_);
    }
}

void Viewer::draw_export_panel() {
    if (ImGui::CollapsingHeader("Export", ImGuiTreeNodeFlags_DefaultOpen)) {
        if (!panel_.folder_set) std::snprintf(panel_.folder, sizeof panel_.folder, "%s", export_folder_.c_str());
        panel_.folder_set = true;
        ImGui::SetNextItemWidth(250);
        if (ImGui::InputText("folder", panel_.folder, sizeof panel_.folder)) export_folder_ = panel_.folder;
        // SOG (PlayCanvas, for the web viewers) holds no labels: the scene file is the scene alone.
        ImGui::RadioButton("PLY", &panel_.format, 0);
        ImGui::SameLine();
        ImGui::RadioButton("SOG (scene and objects)", &panel_.format, 1);
        const bool running = export_ && export_->running;
        ImGui::BeginDisabled(running || (!session_.labels() && !classes_));
        if (ImGui::Button("Everything")) export_to(export_folder_, true, true, true, true);
        ImGui::SameLine();
        if (ImGui::Button(panel_.format == 1 ? "Scene SOG" : "Scene PLY")) export_to(export_folder_, true, false, false, false);
        ImGui::SameLine();
        if (ImGui::Button("Objects")) export_to(export_folder_, false, true, false, false);
        if (ImGui::Button("Masks + overlays")) export_to(export_folder_, false, false, true, false);
        ImGui::SameLine();
        if (ImGui::Button("prompts.json")) export_to(export_folder_, false, false, false, true);
        ImGui::EndDisabled();
        if (export_ && (running || export_->total > 0)) {
            const size_t total = std::max<size_t>(1, export_->total);
            char text[64];
            std::snprintf(text, sizeof text, "%zu / %zu views", size_t(export_->done), size_t(export_->total));
            ImGui::ProgressBar(float(export_->done) / float(total), ImVec2(220, 0), text);
            if (running) {
                ImGui::SameLine();
                if (ImGui::Button("Cancel")) export_->cancel = true;
            }
        }
    }
}

void Viewer::draw_timings_panel() {
    if (ImGui::CollapsingHeader("Timings", ImGuiTreeNodeFlags_DefaultOpen)) {
        ImGui::TextWrapped("%s (%s)", ctx_->info().name.c_str(), vk::device_type_name(ctx_->info().type).c_str());
        timing_row("window frame", frame_ms_);
        if (picture_valid_) {
            ImGui::Text("picture %dx%d%s", picture_.camera.width, picture_.camera.height,
                        picture_.preview ? " (preview: 1 of every " : "");
            if (picture_.preview && viewed_.preview) {
                ImGui::SameLine(0, 0);
                ImGui::Text("%u Gaussians)", viewed_.preview->stride);
            }
            timing_row("splat render (GPU)", picture_.render_ms);
            if (picture_.mask) timing_row("2D mask (GPU)", picture_.mask_ms);
            timing_row("overlay (GPU)", picture_.overlay_ms);
            timing_row("picture (wall)", picture_.wall_ms);
        }
        if (lift_ms_ > 0) timing_row("lift click", lift_ms_);
        if (class_wall_ms_ > 0) {
            timing_row("label by class (wall)", class_wall_ms_);
            for (auto& [name, ms] : class_ms_) timing_row(("  " + name).c_str(), ms);
        }
        if (segment_wall_ms_ > 0) {
            timing_row("segment (wall)", segment_wall_ms_);
            for (auto& [name, ms] : segment_ms_) timing_row(("  " + name).c_str(), ms);
        }
        const bool working = jobs_->busy() || session_.in_flight();
        if (working)
            ImGui::TextColored(ImVec4(1, 0.8f, 0.3f, 1),
                               session_.showing_coarse() ? "coarse answer shown; refining..." : "working...");
    }
}

}  // namespace pg::viewer
