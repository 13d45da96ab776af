// The viewer's segmentation session: an edit re-segments only the objects whose result it
// changes, undo returns to cached results, and the labels are what `segment` would give.
#include <catch2/catch.hpp>

#include <algorithm>

#include "app/viewer/session.h"
#include "engine/render/renderer.h"
#include "engine/segment/prompt_encoder.h"
#include "tests/gpu_fixture.h"
#include "tests/reference/test_scenes.h"
#include "tests/viewer/stand_in_decoder.h"

using namespace pg;
using namespace pg::viewer;

namespace {

constexpr size_t kGaussians = 100;

Click click(double u, double p, bool positive = true) { return pg::test::stand_in_click(u, p, positive); }
seg::ObjectResult claims_of(const data::ObjectPrompt& object) { return pg::test::stand_in_claims(object); }

// Runs every job the session hands out, as the viewer's job thread does; returns the object ids segmented.
std::vector<int> settle(Session& session, const Document& doc, const std::string& decoder = "model") {
    std::vector<int> segmented;
    session.sync(doc, decoder);
    while (auto job = session.next_job()) {
        REQUIRE(job->prompts.objects.size() == 1);
        const auto& object = job->prompts.objects.front();
        segmented.push_back(object.id);
        session.store(*job, {{claims_of(object)}, {}, {}});
    }
    REQUIRE(session.settled());
    return segmented;
}

std::vector<int32_t> labels(const Session& s) { return s.labels() ? *s.labels() : std::vector<int32_t>(kGaussians, 0); }

size_t count(const std::vector<int32_t>& l, int id) { return size_t(std::count(l.begin(), l.end(), id)); }

// Two objects: a (Gaussians 0..9) and b (20..29).
Document two_objects(int& a, int& b) {
    Document doc;
    a = doc.add_object("a");
    doc.add_click(click(0, 0.6));
    b = doc.add_object("b");
    doc.add_click(click(20, 0.6));
    return doc;
}

}  // namespace

TEST_CASE("a click re-segments only its object, whose old labels go until the new result is in", "[viewer]") {
    int a, b;
    Document doc = two_objects(a, b);
    Session session(kGaussians);
    CHECK(settle(session, doc) == std::vector<int>{a, b});
    REQUIRE(count(labels(session), a) == 10);
    REQUIRE(count(labels(session), b) == 10);

    doc.add_click(click(40, 0.6));  // b is selected
    session.sync(doc, "model");
    auto job = session.next_job();
    REQUIRE(job);
    CHECK(job->prompts.objects.front().id == b);
    CHECK_FALSE(session.next_job());  // one job at a time
    CHECK_FALSE(session.settled());
    // While b is re-segmented its stale labels are not shown; a's are.
    CHECK(count(labels(session), a) == 10);
    CHECK(count(labels(session), b) == 0);
    session.store(*job, {{claims_of(job->prompts.objects.front())}, {}, {}});
    CHECK(settle(session, doc).empty());
    CHECK(count(labels(session), b) == 20);
    CHECK(session.labelled(b) == 20);
    CHECK(session.labelled(a) == 10);
}

TEST_CASE("renaming, recolouring and hiding keep every result and the labels", "[viewer]") {
    int a, b;
    Document doc = two_objects(a, b);
    Session session(kGaussians);
    settle(session, doc);
    const auto before = labels(session);
    const uint64_t version = session.labels_version();
    doc.rename(a, "mug");
    doc.recolour(b, {1, 0, 0});
    doc.set_hidden(a, true);  // hidden objects keep their labels; only the picture leaves them out
    CHECK(settle(session, doc).empty());
    CHECK(labels(session) == before);
    CHECK(session.labels_version() == version);  // nothing for the frame thread to upload again
}

TEST_CASE("undo and redo return to cached results without segmenting again", "[viewer]") {
    int a, b;
    Document doc = two_objects(a, b);
    Session session(kGaussians);
    settle(session, doc);
    const auto two = labels(session);
    doc.add_click(click(25, 0.6, false));  // b: a negative click takes 25..29 back
    CHECK(settle(session, doc) == std::vector<int>{b});
    const auto edited = labels(session);
    CHECK(count(edited, b) == 5);

    doc.undo();
    CHECK(settle(session, doc).empty());
    CHECK(labels(session) == two);
    doc.redo();
    CHECK(settle(session, doc).empty());
    CHECK(labels(session) == edited);
}

TEST_CASE("a Gaussian claimed twice goes to the more confident object, ties to the earlier one", "[viewer]") {
    Document doc;
    const int a = doc.add_object("a");
    doc.add_click(click(0, 0.6));   // 0..9
    const int b = doc.add_object("b");
    doc.add_click(click(5, 0.8));   // 5..14, more confident than a
    const int c = doc.add_object("c");
    doc.add_click(click(10, 0.8));  // 10..19, ties with b on 10..14
    Session session(kGaussians);
    settle(session, doc);
    const auto l = labels(session);
    CHECK(l[4] == a);
    CHECK(l[5] == b);
    CHECK(l[12] == b);
    CHECK(l[15] == c);
    CHECK(l[20] == 0);
    CHECK(session.labelled(b) == 10);

    // Deleting b: a and c take back what they had claimed.
    doc.remove(b);
    settle(session, doc);
    CHECK(labels(session)[7] == a);
    CHECK(labels(session)[12] == c);
}

TEST_CASE("deleting an object re-segments the ones after it, as segment would replay the prompts", "[viewer]") {
    Document doc;
    const int a = doc.add_object("a");
    doc.add_click(click(0, 0.6));
    const int b = doc.add_object("b");
    doc.add_click(click(20, 0.6));
    const int c = doc.add_object("c");
    doc.add_click(click(40, 0.6));
    Session session(kGaussians);
    settle(session, doc);
    const auto before = labels(session);
    doc.remove(a);
    // `segment` partitions object k with seed + k: b and c moved up one place.
    session.sync(doc, "model");
    std::vector<std::pair<int, size_t>> jobs;
    while (auto job = session.next_job()) {
        jobs.push_back({job->prompts.objects.front().id, job->index});
        session.store(*job, {{claims_of(job->prompts.objects.front())}, {}, {}});
    }
    CHECK(jobs == std::vector<std::pair<int, size_t>>{{b, 0}, {c, 1}});
    CHECK(count(labels(session), a) == 0);
    doc.undo();  // b and c return to their places, whose results are still cached
    CHECK(settle(session, doc).empty());
    CHECK(labels(session) == before);
}

TEST_CASE("another decoder re-segments every object, switching back needs nothing", "[viewer]") {
    int a, b;
    Document doc = two_objects(a, b);
    Session session(kGaussians);
    settle(session, doc, "model");
    CHECK(settle(session, doc, "ground-truth") == std::vector<int>{a, b});
    CHECK(settle(session, doc, "ground-truth").empty());
}

TEST_CASE("a failed object shows its error and no labels, and is retried once its clicks change", "[viewer]") {
    int a, b;
    Document doc = two_objects(a, b);
    Session session(kGaussians);
    session.sync(doc, "model");
    while (auto job = session.next_job()) {
        const auto& object = job->prompts.objects.front();
        if (object.id == a) session.store(*job, {{}, {{a, "the click hit nothing"}}, {}});
        else session.store(*job, {{claims_of(object)}, {}, {}});
    }
    CHECK(session.settled());  // a failure is a result: not retried in a loop
    CHECK(session.error(a) == "the click hit nothing");
    CHECK(count(labels(session), a) == 0);
    CHECK(count(labels(session), b) == 10);
    doc.select(a);
    doc.add_click(click(60, 0.6));
    CHECK(settle(session, doc) == std::vector<int>{a});
    CHECK(session.error(a).empty());
    CHECK(count(labels(session), a) == 20);
}

namespace {

// Two objects with a positive and a negative click each, in two views of a random scene whose
// Gaussians belong to instances i % 3; clicks lifted once, as the viewer lifts them for markers.
struct ClickedScene {
    ref::TestScene scene = ref::random_scene(5, 4000, 0);
    std::vector<int32_t> instance;
    render::GpuScene gpu;
    seg::SegmentOptions options;
    Document doc;

    ClickedScene() : gpu(test::gpu(), scene.cloud) {
        instance.resize(scene.cloud.size());
        for (size_t i = 0; i < instance.size(); ++i) instance[i] = int32_t(i % 3);
        options.scale = 0.5;
        render::Renderer probe(test::gpu());
        for (size_t view = 0; view < 2; ++view) {
            const auto& cam = scene.cameras[view];
            probe.render(gpu, cam, options.render);
            const auto img = probe.read();
            doc.add_object("object " + std::to_string(view));
            int found = 0;
            for (int y = 3 + int(view) * 5; y < img.height && found < 2; y += 11)
                for (int x = 2; x < img.width && found < 2; x += 13) {
                    if (img.rgba[(size_t(y) * img.width + x) * 4 + 3] < seg::kMinLiftCoverage) continue;
                    Click c;
                    c.prompt.view = cam.name;
                    c.prompt.u = x + 0.5;
                    c.prompt.v = y + 0.5;
                    c.prompt.positive = found == 0;
                    c.anchor = seg::lift_click(probe, gpu, cam, c.prompt.u, c.prompt.v, c.prompt.positive,
                                               options.render, options.lift, "test click");
                    if (found == 0 && instance[size_t(c.anchor.gaussian)] == 0) continue;  // the positive click lands on an instance
                    doc.add_click(c);
                    ++found;
                }
            REQUIRE(found == 2);
        }
    }
};

}  // namespace

TEST_CASE("object by object, the session labels every Gaussian as segment labels the whole prompts.json", "[viewer]") {
    ClickedScene s;
    seg::GroundTruthDecoder decoder(s.instance);
    seg::Segmenter segmenter(test::gpu(), s.scene.cloud, s.gpu, s.scene.cameras, decoder);
    Session session(s.scene.cloud.size());
    session.sync(s.doc, "ground-truth");
    std::map<std::string, double> ms;
    while (auto job = session.next_job()) {
        CHECK(job->prompts.objects.size() == 1);
        session.store(*job, segment_job(segmenter, *job, s.options, ms));
    }
    const auto whole = segmenter.segment(s.doc.prompts(), s.options);
    REQUIRE(session.labels());
    CHECK(std::count_if(whole.labels.begin(), whole.labels.end(), [](int32_t l) { return l != 0; }) > 10);
    CHECK(*session.labels() == whole.labels);
}

TEST_CASE("graph decoder: the session solves every object at once, as segment --decoder graph does", "[viewer]") {
    ClickedScene s;
    seg::Segmenter segmenter(test::gpu(), s.scene.cloud, s.gpu, s.scene.cameras);  // no network
    Session session(s.scene.cloud.size());
    std::map<std::string, double> ms;
    const auto solve = [&] {
        session.sync(s.doc, "graph");
        auto job = session.next_job();
        REQUIRE(job);
        CHECK(job->prompts.objects.size() == 2);
        CHECK_FALSE(session.next_job());  // one job at a time
        session.store(*job, segment_job(segmenter, *job, s.options, ms));
        CHECK(session.settled());
    };
    solve();
    seg::SegmentOptions graph = s.options;
    graph.graph = seg::GraphUse::Alone;
    const auto whole = segmenter.segment(s.doc.prompts(), graph);
    REQUIRE(session.labels());
    for (int id : {1, 2}) CHECK(std::count(whole.labels.begin(), whole.labels.end(), id) > 0);
    CHECK(*session.labels() == whole.labels);

    // Undoing the second object's negative click changes what both objects compete for: one new
    // joint solve. Redo returns to the cached solve without a job.
    REQUIRE(s.doc.undo());
    solve();
    REQUIRE(s.doc.redo());
    session.sync(s.doc, "graph");
    CHECK_FALSE(session.next_job());
    CHECK(*session.labels() == whole.labels);
}

TEST_CASE("a newer click makes the job in flight stale: its cancelled result is dropped, a coarse answer shows until the full one", "[viewer]") {
    int a, b;
    Document doc = two_objects(a, b);
    Session session(kGaussians);
    settle(session, doc);

    doc.add_click(click(40, 0.6));  // b is selected
    session.sync(doc, "model");
    auto job = session.next_job();
    REQUIRE(job);
    CHECK(session.in_flight_covers(b));
    CHECK_FALSE(session.in_flight_covers(a));
    CHECK_FALSE(session.in_flight_stale());
    doc.add_click(click(60, 0.6));  // b again, before the job is done
    session.sync(doc, "model");
    CHECK(session.in_flight_stale());

    // The job stopped: nothing is cached for those clicks, and the newer ones are handed out.
    SegmentOutcome stopped;
    stopped.cancelled = true;
    session.store(*job, stopped);
    CHECK_FALSE(session.in_flight());
    CHECK(count(labels(session), b) == 0);
    auto newer = session.next_job();
    REQUIRE(newer);
    REQUIRE(newer->prompts.objects.front().id == b);
    CHECK(newer->prompts.objects.front().clicks.size() == 3);

    // A coarse answer for an older job is ignored; the job in flight's shows until its result.
    session.store_coarse(*job, {{claims_of(job->prompts.objects.front())}, {}, {}});
    CHECK(count(labels(session), b) == 0);
    data::ObjectPrompt rough = newer->prompts.objects.front();
    rough.clicks.resize(1);
    session.store_coarse(*newer, {{claims_of(rough)}, {}, {}});
    CHECK(session.showing_coarse());
    CHECK(count(labels(session), b) == 10);
    CHECK(count(labels(session), a) == 10);
    session.store(*newer, {{claims_of(newer->prompts.objects.front())}, {}, {}});
    CHECK_FALSE(session.showing_coarse());
    CHECK(count(labels(session), b) == 30);
    CHECK(settle(session, doc).empty());
}

TEST_CASE("a coarse answer is asked for only where full graph solves are slow", "[viewer]") {
    // lavapipe: always (a cold click is seconds there); a GPU: not until a graph job took > 1 s.
    CHECK(viewer::want_coarse_answer(true, 0.0));
    CHECK_FALSE(viewer::want_coarse_answer(false, 0.0));
    CHECK_FALSE(viewer::want_coarse_answer(false, 240.0));
    CHECK(viewer::want_coarse_answer(false, 1650.0));
}
