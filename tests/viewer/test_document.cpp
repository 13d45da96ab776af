// The viewer's document: every edit is one undo step, undo/redo restore exact states, and the
// prompts it exports are what `segment` reads.
#include <catch2/catch.hpp>

#include "app/viewer/document.h"

using namespace pg::viewer;

namespace {
Click click(double u, double v, bool positive = true) {
    Click c;
    c.prompt.view = "view_000";
    c.prompt.u = u;
    c.prompt.v = v;
    c.prompt.positive = positive;
    c.anchor.position = {u, v, 1.0};
    return c;
}
}  // namespace

TEST_CASE("a click without a selected object starts one, each edit is one undo step", "[viewer]") {
    Document d;
    REQUIRE_FALSE(d.can_undo());
    REQUIRE(d.add_click(click(10, 20)));
    REQUIRE(d.state().objects.size() == 1);
    const int id = d.state().selected;
    REQUIRE(d.find(id)->clicks.size() == 1);
    REQUIRE(d.add_click(click(11, 21, false)));
    REQUIRE(d.rename(id, "mug"));
    REQUIRE(d.recolour(id, {1.0f, 0.5f, 0.0f}));
    REQUIRE(d.set_hidden(id, true));
    const DocumentState full = d.state();

    REQUIRE(d.undo_label() == "hide");
    REQUIRE(d.undo());  // hide
    REQUIRE_FALSE(d.find(id)->hidden);
    REQUIRE(d.undo());  // recolour
    REQUIRE(d.find(id)->colour != glm::vec3(1.0f, 0.5f, 0.0f));
    REQUIRE(d.undo());  // rename
    REQUIRE(d.find(id)->name != "mug");
    REQUIRE(d.undo());  // negative click
    REQUIRE(d.find(id)->clicks.size() == 1);
    REQUIRE(d.undo());  // first click and the object it made
    REQUIRE(d.state().objects.empty());
    REQUIRE_FALSE(d.undo());

    for (int i = 0; i < 5; ++i) REQUIRE(d.redo());
    REQUIRE_FALSE(d.redo());
    REQUIRE(d.state() == full);
}

TEST_CASE("an edit after undo drops the redo history, no-op edits add no step", "[viewer]") {
    Document d;
    int a = d.add_object("a");
    d.add_click(click(1, 1));
    REQUIRE(d.undo());
    REQUIRE(d.can_redo());
    d.rename(a, "b");
    REQUIRE_FALSE(d.can_redo());
    const auto version = d.version();
    REQUIRE_FALSE(d.rename(a, "b"));  // same name
    REQUIRE_FALSE(d.rename(a, ""));   // empty names are refused
    REQUIRE_FALSE(d.remove(999));
    REQUIRE(d.version() == version);
}

TEST_CASE("delete selects another object and undo brings the deleted one back intact", "[viewer]") {
    Document d;
    int a = d.add_object("a");
    d.add_click(click(1, 1));
    int b = d.add_object("b");
    d.add_click(click(2, 2));
    d.add_click(click(3, 3, false));
    const Object before = *d.find(b);
    REQUIRE(d.remove(b));
    REQUIRE(d.find(b) == nullptr);
    REQUIRE(d.state().selected == a);
    REQUIRE(d.undo());
    REQUIRE(*d.find(b) == before);
    REQUIRE(d.state().selected == b);
}

TEST_CASE("selection is navigation: it is not an undo step of its own", "[viewer]") {
    Document d;
    int a = d.add_object("a");
    int b = d.add_object("b");
    REQUIRE(d.state().selected == b);
    REQUIRE(d.select(a));
    REQUIRE(d.state().selected == a);
    REQUIRE_FALSE(d.select(42));
    REQUIRE(d.undo_label() == "new object");
    d.add_click(click(5, 5));  // goes to the selected object
    REQUIRE(d.find(a)->clicks.size() == 1);
    REQUIRE(d.find(b)->clicks.empty());
}

TEST_CASE("prompts keep ids, names and clicks, and skip objects without a positive click", "[viewer]") {
    Document d;
    int a = d.add_object("mug");
    d.add_click(click(1, 2));
    Click point;
    point.prompt.point = glm::dvec3(0.5, -0.25, 2.0);
    point.prompt.positive = false;
    d.add_click(point);
    d.add_object("empty");
    int c = d.add_object("only negative");
    d.add_click(click(9, 9, false));
    int e = d.add_object("lamp");
    d.add_click(click(7, 8));

    auto p = d.prompts();
    REQUIRE(p.objects.size() == 2);
    REQUIRE(p.objects[0].id == a);
    REQUIRE(p.objects[0].name == "mug");
    REQUIRE(p.objects[0].clicks.size() == 2);
    REQUIRE(p.objects[0].clicks[1].point == glm::dvec3(0.5, -0.25, 2.0));
    REQUIRE_FALSE(p.objects[0].clicks[1].positive);
    REQUIRE(p.objects[1].id == e);
    (void)c;
}

TEST_CASE("default colours differ between neighbouring ids", "[viewer]") {
    for (int id = 1; id < 20; ++id) REQUIRE(default_object_colour(id) != default_object_colour(id + 1));
}
