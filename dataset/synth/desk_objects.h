#pragma once
// The desk suite's catalogue: small household objects built from the analytic primitives,
// each in its own coordinates (standing on z = 0, centred on the z axis).
#include <string>
#include <vector>

#include "dataset/synth/layout.h"

namespace pg::data::synth {

enum class DeskKind { Mug, Book, Box, Ball, Bottle, Can, Plant, Lamp, Laptop, Phone, Headphones, Toy, Cube, Tape, Mouse, PencilCup };
constexpr int kDeskKinds = 16;

struct DeskObject {
    DeskKind kind = DeskKind::Box;
    std::vector<Part> parts;
    glm::dvec2 half{0.05};    // footprint half extents in x, y (before the object's yaw)
    bool round = false;       // footprint is the circle of radius half.x
    double height = 0.1;
    bool flat_top = false;    // another object can stand on its top (at z = height)
    bool leans = false;       // may lean against a neighbour (books)
};

const char* desk_kind_name(DeskKind kind);  // class names: "mug", "book", ...
int desk_kind_class(DeskKind kind);         // class id (1 + enum value)

// One object of the kind with `colour` as its main colour.
DeskObject make_desk_object(DeskKind kind, glm::vec3 colour, Rng& rng);

}  // namespace pg::data::synth
