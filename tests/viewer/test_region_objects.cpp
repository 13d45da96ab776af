// Objects made from a region (a class's Gaussians): the region is their labels until clicked;
// positive clicks add what they segment, negative ones take it away, through the same session
// jobs (and cache, and undo) as clicked objects; and they stay out of prompts.json.
#include <catch2/catch.hpp>

#include <algorithm>
#include <map>

#include "app/viewer/session.h"
#include "tests/viewer/stand_in_decoder.h"

using namespace pg;
using namespace pg::viewer;

namespace {

constexpr size_t kGaussians = 100;

Click click(double u, double p, bool positive = true) { return pg::test::stand_in_click(u, p, positive); }
seg::ObjectResult claims_of(const data::ObjectPrompt& object) { return pg::test::stand_in_claims(object); }

// Runs every job; returns the region objects whose edits were segmented.
std::vector<int> settle(Session& session, const Document& doc, const std::string& decoder = "model") {
    std::vector<int> regions;
    session.sync(doc, decoder);
    while (auto job = session.next_job()) {
        SegmentOutcome outcome;
        for (auto& o : job->prompts.objects) outcome.results.push_back(claims_of(o));
        if (job->region) regions.push_back(job->region);
        session.store(*job, outcome);
    }
    REQUIRE(session.settled());
    return regions;
}

size_t count(const Session& s, int id) {
    return s.labels() ? size_t(std::count(s.labels()->begin(), s.labels()->end(), id)) : 0;
}

// Gaussians first .. first + n - 1, each claimed with probability p.
std::shared_ptr<const Region> region(uint32_t first, uint32_t n, float p) {
    auto r = std::make_shared<Region>();
    for (uint32_t g = first; g < first + n; ++g) r->gaussians.push_back(g), r->probability.push_back(p);
    r->source = "class building";
    return r;
}

}  // namespace

TEST_CASE("an object made from a region is its labels at once, one undo step, and not in prompts.json", "[viewer]") {
    Document doc;
    const int id = doc.add_region_object("building", region(50, 20, 0.7f));
    CHECK(doc.state().selected == id);
    CHECK(doc.undo_label() == "object from class building");
    CHECK(doc.prompts().objects.empty());  // clicks alone would not make it: segment cannot replay it
    Session session(kGaussians);
    CHECK(settle(session, doc).empty());  // no job: nothing to segment
    CHECK(count(session, id) == 20);
    CHECK((*session.labels())[50] == id);
    doc.undo();
    CHECK(settle(session, doc).empty());
    CHECK(count(session, id) == 0);
}

TEST_CASE("positive clicks add to a region object, negative ones take away, undo returns without a job", "[viewer]") {
    Document doc;
    const int id = doc.add_region_object("building", region(50, 20, 0.7f));
    Session session(kGaussians);
    settle(session, doc);

    doc.add_click(click(80, 0.6));  // adds 80..89
    session.sync(doc, "model");
    auto job = session.next_job();
    REQUIRE(job);
    CHECK(job->region == id);
    CHECK(job->prompts.objects.size() == 1);  // only an add side: no negative click yet
    CHECK(session.in_flight_covers(id));
    CHECK_FALSE(session.in_flight_joint());
    CHECK(count(session, id) == 20);  // the bare region while its edits are segmented
    session.store(*job, {{claims_of(job->prompts.objects.front())}, {}, {}});
    CHECK(count(session, id) == 30);
    const auto added = *session.labels();

    doc.add_click(click(60, 0.9, false));  // takes 60..69
    session.sync(doc, "model");
    job = session.next_job();
    REQUIRE(job);
    // The network alone: each side has the other's clicks as negatives.
    REQUIRE(job->prompts.objects.size() == 2);
    const auto& add = job->prompts.objects[0];
    const auto& take = job->prompts.objects[1];
    CHECK(add.clicks.size() == 2);
    CHECK(add.clicks[0].positive);
    CHECK_FALSE(add.clicks[1].positive);
    CHECK(take.clicks.size() == 2);
    CHECK_FALSE(take.clicks[0].positive);
    CHECK(take.clicks[1].positive);  // the negative click, as the take side's positive
    CHECK(job->anchors[1][1].positive);
    SegmentOutcome outcome;
    for (auto& o : job->prompts.objects) outcome.results.push_back(claims_of(o));
    session.store(*job, outcome);
    CHECK(count(session, id) == 20);  // 50..59 and 80..89
    CHECK((*session.labels())[65] == 0);
    CHECK((*session.labels())[85] == id);

    doc.undo();
    CHECK(settle(session, doc).empty());  // cached
    CHECK(*session.labels() == added);
}

TEST_CASE("a region object's edits are its own job under a graph decoder, and its errors are its own", "[viewer]") {
    Document doc;
    const int plain = doc.add_object("plain");
    doc.add_click(click(0, 0.6));
    const int id = doc.add_region_object("building", region(50, 20, 0.7f));
    doc.add_click(click(80, 0.6));
    doc.add_click(click(60, 0.9, false));
    Session session(kGaussians);
    session.sync(doc, "graph");
    auto first = session.next_job();
    REQUIRE(first);
    CHECK(first->region == 0);  // the joint solve of the clicked objects, without the region object
    CHECK(first->prompts.objects.size() == 1);
    CHECK(first->prompts.objects[0].id == plain);
    CHECK(session.in_flight_joint());
    session.store(*first, {{claims_of(first->prompts.objects[0])}, {}, {}});
    auto edits = session.next_job();
    REQUIRE(edits);
    CHECK(edits->region == id);
    // Solved together, each side's clicks seed its own label: no negatives of the other side.
    REQUIRE(edits->prompts.objects.size() == 2);
    CHECK(edits->prompts.objects[0].clicks.size() == 1);
    CHECK(edits->prompts.objects[1].clicks.size() == 1);
    CHECK(edits->prompts.objects[1].clicks[0].positive);
    session.store(*edits, {{}, {{2, "the click hit nothing"}}, {}});
    CHECK(session.settled());
    CHECK(session.error(id) == "the click hit nothing");
    CHECK(session.error(plain).empty());
    CHECK(count(session, id) == 20);  // the failed edits leave the region as it is
    CHECK(count(session, plain) == 10);
}

TEST_CASE("a region object and a clicked object share a Gaussian by probability, as two clicked objects do",
          "[viewer]") {
    Document doc;
    const int id = doc.add_region_object("building", region(50, 20, 0.7f));
    const int b = doc.add_object("b");
    doc.add_click(click(65, 0.9));  // 65..74, more confident than the region on 65..69
    Session session(kGaussians);
    settle(session, doc);
    CHECK((*session.labels())[64] == id);
    CHECK((*session.labels())[65] == b);
    CHECK(session.labelled(id) == 15);
    // A click on the plain object does not re-segment the region object's edits.
    doc.add_click(click(90, 0.9));
    CHECK(settle(session, doc).empty());
}
