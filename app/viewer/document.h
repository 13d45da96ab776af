#pragma once
// What a viewer user edits: objects with their clicks, names, colours and visibility. Every
// edit goes through Document::edit, which keeps the state before it for undo; the state is
// small (clicks, not labels; an object made from a class shares its region, never copies it),
// so whole snapshots are simpler than inverse operations.
#include <functional>
#include <memory>
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

// Gaussians an object starts from instead of a first click (a class region, see
// class_labels.h). Immutable once made, so objects share it and compare it by address.
struct Region {
    std::vector<uint32_t> gaussians;  // ascending
    std::vector<float> probability;   // per Gaussian: how strongly the object claims it (> 0)
    std::string source;               // what it was made from, for the panel and report.json
};

struct Object {
    int id = 0;
    std::string name;
    glm::vec3 colour{1.0f};
    bool hidden = false;
    std::vector<Click> clicks;
    // Null for a clicked object. Set: the object is the region as corrected by its clicks (see
    // Session): positive clicks add what they segment, negative ones take it away.
    std::shared_ptr<const Region> region;
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
    int add_region_object(const std::string& name, std::shared_ptr<const Region> region);  // likewise, from a region
    bool add_click(const Click& click);            // to the selected object (a new one if none)
    bool select(int id);                           // selection is not undoable on its own
    bool rename(int id, const std::string& name);
    bool recolour(int id, glm::vec3 colour);
    bool set_hidden(int id, bool hidden);
    bool remove(int id);

    // prompts.json for `pointgauss segment`: every object with at least one positive click, in order.
    // Region objects are left out: clicks alone do not reproduce them.
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
