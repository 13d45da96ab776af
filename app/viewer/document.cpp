#include "app/viewer/document.h"

#include <algorithm>

#include "engine/segment/mask_views.h"

namespace pg::viewer {

bool Object::has_positive() const {
    return std::any_of(clicks.begin(), clicks.end(), [](auto& c) { return c.prompt.positive; });
}

glm::vec3 default_object_colour(int id) { return seg::ViewMask::default_colour(uint32_t(std::max(id, 0))); }

const Object* Document::find(int id) const {
    auto it = std::find_if(state_.objects.begin(), state_.objects.end(), [&](auto& o) { return o.id == id; });
    return it == state_.objects.end() ? nullptr : &*it;
}

Object* Document::find_mutable(DocumentState& s, int id) {
    auto it = std::find_if(s.objects.begin(), s.objects.end(), [&](auto& o) { return o.id == id; });
    return it == s.objects.end() ? nullptr : &*it;
}

bool Document::edit(const std::string& what, const std::function<void(DocumentState&)>& change) {
    DocumentState next = state_;
    change(next);
    if (next == state_) return false;
    undo_.push_back({what, std::move(state_)});
    redo_.clear();
    state_ = std::move(next);
    ++version_;
    return true;
}

void Document::reset(DocumentState state) {
    state_ = std::move(state);
    undo_.clear();
    redo_.clear();
    ++version_;
}

bool Document::undo() {
    if (undo_.empty()) return false;
    redo_.push_back({undo_.back().what, std::move(state_)});
    state_ = std::move(undo_.back().state);
    undo_.pop_back();
    ++version_;
    return true;
}

bool Document::redo() {
    if (redo_.empty()) return false;
    undo_.push_back({redo_.back().what, std::move(state_)});
    state_ = std::move(redo_.back().state);
    redo_.pop_back();
    ++version_;
    return true;
}

const std::string& Document::undo_label() const {
    static const std::string none;
    return undo_.empty() ? none : undo_.back().what;
}

const std::string& Document::redo_label() const {
    static const std::string none;
    return redo_.empty() ? none : redo_.back().what;
}

int Document::add_object(const std::string& name) { return add_region_object(name, nullptr); }

int Document::add_region_object(const std::string& name, std::shared_ptr<const Region> region) {
    int id = state_.next_id;
    edit(region ? "object from " + region->source : "new object", [&](DocumentState& s) {
        Object o;
        o.id = s.next_id++;
        o.name = name.empty() ? "object " + std::to_string(o.id) : name;
        o.colour = default_object_colour(o.id);
        o.region = std::move(region);
        s.objects.push_back(o);
        s.selected = o.id;
    });
    return id;
}

bool Document::add_click(const Click& click) {
    const bool positive = click.prompt.positive;
    return edit(positive ? "positive click" : "negative click", [&](DocumentState& s) {
        Object* o = find_mutable(s, s.selected);
        if (!o) {
            Object fresh;
            fresh.id = s.next_id++;
            fresh.name = "object " + std::to_string(fresh.id);
            fresh.colour = default_object_colour(fresh.id);
            s.objects.push_back(fresh);
            s.selected = fresh.id;
            o = &s.objects.back();
        }
        o->clicks.push_back(click);
    });
}

bool Document::select(int id) {
    if (id != 0 && !find(id)) return false;
    if (state_.selected == id) return false;
    // Selecting is navigation, not an edit: it changes the state undo returns to, nothing more.
    state_.selected = id;
    ++version_;
    return true;
}

bool Document::rename(int id, const std::string& name) {
    return edit("rename", [&](DocumentState& s) {
        if (Object* o = find_mutable(s, id); o && !name.empty()) o->name = name;
    });
}

bool Document::recolour(int id, glm::vec3 colour) {
    return edit("recolour", [&](DocumentState& s) {
        if (Object* o = find_mutable(s, id)) o->colour = glm::clamp(colour, 0.0f, 1.0f);
    });
}

bool Document::set_hidden(int id, bool hidden) {
    return edit(hidden ? "hide" : "show", [&](DocumentState& s) {
        if (Object* o = find_mutable(s, id)) o->hidden = hidden;
    });
}

bool Document::remove(int id) {
    return edit("delete object", [&](DocumentState& s) {
        auto it = std::find_if(s.objects.begin(), s.objects.end(), [&](auto& o) { return o.id == id; });
        if (it == s.objects.end()) return;
        s.objects.erase(it);
        if (s.selected == id) s.selected = s.objects.empty() ? 0 : s.objects.back().id;
    });
}

data::Prompts Document::prompts() const {
    data::Prompts p;
    for (const auto& o : state_.objects) {
        if (!o.has_positive() || o.region) continue;
        data::ObjectPrompt op;
        op.name = o.name;
        op.id = o.id;
        for (const auto& c : o.clicks) op.clicks.push_back(c.prompt);
        p.objects.push_back(op);
    }
    return p;
}

seg::LiftedClicks Document::anchors() const {
    seg::LiftedClicks lifted;
    for (const auto& o : state_.objects) {
        if (!o.has_positive() || o.region) continue;
        auto& a = lifted.emplace_back();
        for (const auto& c : o.clicks) a.push_back(c.anchor);
    }
    return lifted;
}

}  // namespace pg::viewer
