// Mouse and keys over the picture, and the click markers drawn on it.
#include <algorithm>
#include <cmath>

#include <GLFW/glfw3.h>
#include <imgui.h>

#include "app/viewer/viewer.h"

namespace pg::viewer {

// Input: SuperSplat's habits where they exist (left drag orbits, right or middle drag pans,
// wheel zooms, WASD/QE fly; a click without a drag is a prompt, Ctrl or the right button
// makes it negative).

void Viewer::handle_input() {
    ImGuiIO& io = ImGui::GetIO();
    const float sx = io.DisplayFramebufferScale.x, sy = io.DisplayFramebufferScale.y;
    const Rect r = presenter_->picture_rect();
    auto picture_fraction = [&](ImVec2 m, double& x, double& y) {
        x = (m.x * sx - r.x) / std::max(1, r.width);
        y = (m.y * sy - r.y) / std::max(1, r.height);
        return x >= 0 && y >= 0 && x < 1 && y < 1;
    };
    if (!io.WantCaptureMouse) {
        const ImVec2 m = io.MousePos;
        const bool in_view = m.x * sx >= viewport_.x && m.x * sx < viewport_.x + viewport_.width;
        for (int b : {0, 1}) {
            if (!ImGui::IsMouseReleased(b) || !in_view) continue;
            const ImVec2 drag = io.MouseDragMaxDistanceSqr[b] > 16.0f ? ImVec2(1, 1) : ImVec2(0, 0);
            double x, y;
            if (drag.x != 0 || !picture_fraction(m, x, y)) continue;
            if (io.KeyAlt) {
                doc_.select(object_at(x, y));  // Alt+click picks an object, as in the list
            } else if (pick_class_region_ && b == 0) {
                object_from_class_at(x, y);  // armed in the Classes panel: one click, then prompts again
                pick_class_region_ = false;
            } else {
                click_at(x, y, b == 0 && !io.KeyCtrl);
            }
        }
        double hx, hy;
        if (in_view && picture_fraction(m, hx, hy) && !ImGui::IsAnyMouseDown())
            if (const Object* o = doc_.find(object_at(hx, hy))) ImGui::SetTooltip("%s", o->name.c_str());
        if (in_view && ImGui::IsMouseDragging(0) && !io.KeyShift) {
            orbit(-0.3 * io.MouseDelta.x, 0.3 * io.MouseDelta.y);
        } else if (in_view && (ImGui::IsMouseDragging(1) || ImGui::IsMouseDragging(2) ||
                               (ImGui::IsMouseDragging(0) && io.KeyShift))) {
            const double per_px = 2.0 * std::tan(glm::radians(0.5 * fov_y_)) / std::max(1, viewport_.height);
            if (io.MouseDelta.x != 0 || io.MouseDelta.y != 0)
                pan(-io.MouseDelta.x * sx * per_px, -io.MouseDelta.y * sy * per_px);
        }
        if (in_view && io.MouseWheel != 0) zoom(std::pow(0.88, io.MouseWheel));
    }
    const auto presses = window_->take_key_presses();
    if (io.WantCaptureKeyboard) return;
    const double step = std::min(0.1, double(io.DeltaTime)) * 0.8;
    glm::dvec3 fly{0.0};  // right, down, forward
    if (ImGui::IsKeyDown(GLFW_KEY_W)) fly.z += step;
    if (ImGui::IsKeyDown(GLFW_KEY_S)) fly.z -= step;
    if (ImGui::IsKeyDown(GLFW_KEY_D)) fly.x += step;
    if (ImGui::IsKeyDown(GLFW_KEY_A)) fly.x -= step;
    if (ImGui::IsKeyDown(GLFW_KEY_E)) fly.y -= step;
    if (ImGui::IsKeyDown(GLFW_KEY_Q)) fly.y += step;
    if (!io.KeyCtrl && fly != glm::dvec3(0.0)) this->fly(fly);
    const int cams = int(scene_.cameras.size());
    for (const auto& [key, mods] : presses) {
        const bool ctrl = mods & GLFW_MOD_CONTROL, shift = mods & GLFW_MOD_SHIFT;
        const int selected = doc_.state().selected;
        switch (key) {
            case GLFW_KEY_RIGHT_BRACKET:
            case GLFW_KEY_PAGE_DOWN: snap(snapped_ < 0 ? 0 : (snapped_ + 1) % cams); break;
            case GLFW_KEY_LEFT_BRACKET:
            case GLFW_KEY_PAGE_UP: snap(snapped_ <= 0 ? cams - 1 : snapped_ - 1); break;
            case GLFW_KEY_F: frame_scene(); break;
            case GLFW_KEY_Z:
                if (ctrl) shift ? doc_.redo() : doc_.undo();
                break;
            case GLFW_KEY_Y:
                if (ctrl) doc_.redo();
                break;
            case GLFW_KEY_N:
                if (!ctrl) doc_.add_object();
                break;
            case GLFW_KEY_DELETE:
                if (doc_.selected()) doc_.remove(selected);
                break;
            case GLFW_KEY_H:
                if (!ctrl && doc_.selected()) doc_.set_hidden(selected, !doc_.selected()->hidden);
                break;
            case GLFW_KEY_I:
                if (!ctrl) isolate(!isolate_);
                break;
            default: break;
        }
    }
}

void Viewer::draw_markers() {
    if (!picture_valid_) return;
    ImGuiIO& io = ImGui::GetIO();
    const Rect r = presenter_->picture_rect();
    const data::Camera& c = picture_.camera;
    ImDrawList* dl = ImGui::GetBackgroundDrawList();
    for (const auto& o : doc_.state().objects) {
        if (o.hidden || (isolate_ && o.id != doc_.state().selected)) continue;
        const bool selected = o.id == doc_.state().selected;
        for (const auto& click : o.clicks) {
            const auto px = c.project(click.anchor.position);
            if (!px) continue;
            const double u = px->x / c.width, v = px->y / c.height;
            if (u < 0 || v < 0 || u > 1 || v > 1) continue;
            const ImVec2 at((r.x + u * r.width) / io.DisplayFramebufferScale.x,
                            (r.y + v * r.height) / io.DisplayFramebufferScale.y);
            const float radius = selected ? 6.0f : 4.0f;
            const ImU32 fill = click.prompt.positive ? IM_COL32(40, 200, 90, 255) : IM_COL32(230, 50, 50, 255);
            dl->AddCircleFilled(at, radius, fill);
            dl->AddCircle(at, radius + 1.0f, IM_COL32(255, 255, 255, selected ? 255 : 140), 0, 1.5f);
            const float h = radius * 0.6f;
            dl->AddLine(ImVec2(at.x - h, at.y), ImVec2(at.x + h, at.y), IM_COL32(255, 255, 255, 255), 1.5f);
            if (click.prompt.positive)
                dl->AddLine(ImVec2(at.x, at.y - h), ImVec2(at.x, at.y + h), IM_COL32(255, 255, 255, 255), 1.5f);
        }
    }
}

}  // namespace pg::viewer
