#pragma once
// What a viewer user edits: objects with their clicks, names, colours and visibility. Every
// edit goes through Document::edit, which keeps the state before it for undo; the state is
// small (clicks, not labels), so whole snapshots are simpler than inverse operations.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "dataset/prompts.h"
#include "engine/segment/anchor.h"

namespace pg::viewer {

struct Click {
    data::PromptClick prompt;  // a dataset view pixel, or a 3D point from a free view
    seg::Anchor anchor;        // where it landed in 3D: the marker, and what the segmenter starts from
    bool operator==(const Click&) const = default;
};

struct Object {
    int id = 0;
    std::string name;
    glm::vec3 colour{1.0f};
    bool hidden = false;
    std::vector<Click> clicks;
    bool has_positive() const;
    bool operator==(const Object&) const = default;
};

struct DocumentState {
    std::vector<Object> objects;
    int selected = 0;  // object id, 0 for none
    int next_id = 1;
    bool operator==(const DocumentState&) const = default;
};

class Document {
public:
    const DocumentState& state() const { return state_; }
    const Object* selected() const { return find(state_.selected); }
    const Object* find(int id) const;

    // Applies `change` to a copy of the state; if it changed anything the old state goes on the
    // undo stack (labelled `what`) and the redo stack is cleared. Returns whether it changed.
    bool edit(const std::string& what, const std::function<void(DocumentState&)>& change);
    // Starts over from `state` with no history (a loaded prompts.json).
    void reset(DocumentState state);
    bool undo();
    bool redo();
    bool can_undo() const { return !undo_.empty(); }
    bool can_redo() const { return !redo_.empty(); }
    const std::string& undo_label() const;
    const std::string& redo_label() const;
    uint64_t version() const { return version_; }  // bumps on every change, undo and redo

    // The common edits, each one undo step.
    int add_object(const std::string& name = {});  // selected afterwards; returns its id
    bool add_click(const Click& click);            // to the selected object (a new one if none)
    bool select(int id);                           // selection is not undoable on its own
    bool rename(int id, const std::string& name);
    bool recolour(int id, glm::vec3 colour);
    bool set_hidden(int id, bool hidden);
    bool remove(int id);

    // prompts.json for `pointgauss segment`: every object with at least one positive click, in order.
    data::Prompts prompts() const;
    seg::LiftedClicks anchors() const;  // the anchors of prompts()' clicks, in the same order

private:
    struct Entry {
        std::string what;
        DocumentState state;
    };
    Object* find_mutable(DocumentState& s, int id);
    DocumentState state_;
    std::vector<Entry> undo_, redo_;
    uint64_t version_ = 0;
};

// A distinct default colour per object id (the exported overlays' palette).
glm::vec3 default_object_colour(int id);

}  // namespace pg::viewer
