#pragma once
// The segmentation half of a viewer session: which objects the document's present clicks ask
// to segment, the cached results (for their last few click sets, so undo and redo need no new
// segmentation), and the labels assembled from the results that are current. No window and no
// threads: the viewer runs the jobs handed out here on its job thread (through the same
// Segmenter as `pointgauss segment`) and stores what comes back.
//
// The network alone (`ptv3`, `ground-truth`) segments object by object: a click re-segments
// its own object only. The graph decoders (`graph`, `ptv3+graph`) solve every object at once,
// since each object's clicks are the others' negatives: any click re-solves them all.
#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/viewer/document.h"
#include "engine/segment/segmenter.h"

namespace pg::viewer {

// Whether a viewer decoder ("graph", "ptv3+graph", "ptv3", "ground-truth", or a model path for
// the network alone) solves the objects together, and how it uses the graph.
seg::GraphUse decoder_graph_use(const std::string& decoder);
bool decoder_is_joint(const std::string& decoder);

// One segmentation, as `segment` would run it on prompts.json: one object (the network alone),
// or every object (graph decoders).
struct SegmentJob {
    data::Prompts prompts;
    seg::LiftedClicks anchors;  // where their clicks landed (lifted once, when they were made)
    size_t index = 0;           // a one-object job: the object's index in prompts.json (`segment` partitions object k with seed + k)
    std::string decoder;
    std::string signature;      // everything its result depends on
};

struct SegmentOutcome {
    std::vector<seg::ObjectResult> results;  // the job's objects that were segmented
    std::map<int, std::string> errors;       // object id -> why it has no result
    std::string error;                       // why the whole job failed
    bool cancelled = false;                  // stopped by a newer click: no result at all
};

// Runs `job` through `segmenter` exactly as `segment` computes those objects of prompts.json.
// `cancel` (may be null) stops it (seg::Cancelled); `coarse`, if given, receives a graph
// decoder's coarse answer before its cold solve.
SegmentOutcome segment_job(seg::Segmenter& segmenter, const SegmentJob& job, seg::SegmentOptions options,
                           std::map<std::string, double>& stage_ms, const std::atomic<bool>* cancel = nullptr,
                           const std::function<void(SegmentOutcome)>& coarse = {});

class Session {
public:
    explicit Session(size_t gaussians = 0) : gaussians_(gaussians) {}

    // Follows the document's objects and clicks and the chosen decoder; reassembles the labels
    // when the set of current results changed (an undo back to cached clicks needs no job).
    void sync(const Document& doc, const std::string& decoder);
    // The next segmentation whose result is not cached for the present clicks; none while a job
    // is out (one at a time, so results arrive in order).
    std::optional<SegmentJob> next_job();
    // The job's result (a cancelled one is dropped: the job is handed out again if still wanted).
    void store(const SegmentJob& job, SegmentOutcome outcome);
    // A coarse answer for the job in flight: shown for its objects until its result is stored.
    void store_coarse(const SegmentJob& job, SegmentOutcome outcome);
    bool in_flight() const { return in_flight_; }
    // The job in flight no longer matches the document's clicks (its result would not be shown).
    bool in_flight_stale() const;
    // The job in flight segments object `id` (a new click on it makes the job stale).
    bool in_flight_covers(int id) const;
    bool showing_coarse() const { return showing_coarse_; }  // labels() holds a coarse answer
    bool settled() const;  // nothing out and every object's result current

    // Object id per Gaussian from every current result (a Gaussian claimed twice goes to the
    // higher probability, ties to the earlier object); null while no object has a result.
    const std::shared_ptr<const std::vector<int32_t>>& labels() const { return labels_; }
    uint64_t labels_version() const { return labels_version_; }  // bumps whenever labels() is reassembled
    size_t labelled(int id) const;              // Gaussians object `id` holds in labels()
    const std::string& error(int id) const;     // why its present clicks failed to segment, else empty

    static constexpr size_t kResultsPerObject = 8;  // click sets an object (or a joint solve) keeps results for

private:
    struct Cached {
        std::string signature;
        SegmentOutcome outcome;
    };
    static constexpr int kJoint = -1;  // cache key of joint solves (object ids are positive)
    // The cached outcome that covers object k's present clicks, if any.
    const SegmentOutcome* cached(size_t k) const;
    const SegmentOutcome* find(int key, const std::string& signature) const;
    void assemble();

    size_t gaussians_;
    uint64_t doc_version_ = ~0ull;
    std::string decoder_;
    bool joint_ = false;
    data::Prompts prompts_;               // the document's objects to segment
    seg::LiftedClicks anchors_;           // where their clicks landed
    std::vector<std::string> signatures_;  // per object of prompts_
    std::string joint_signature_;          // all of them
    std::map<int, std::vector<Cached>> cache_;  // per object id (kJoint: joint solves), newest last
    bool in_flight_ = false;
    SegmentJob flying_;                    // the job in flight (its prompts, decoder and signature)
    std::optional<Cached> coarse_;         // its coarse answer, if one came
    bool showing_coarse_ = false;
    std::string assembled_;  // which results labels_ holds
    std::shared_ptr<const std::vector<int32_t>> labels_;
    uint64_t labels_version_ = 0;
    std::map<int, size_t> labelled_;
};

}  // namespace pg::viewer
