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
//
// An object made from a region (a class's Gaussians: Document's Region) is that region as its
// clicks correct it: its positive clicks segment what they add, its negative clicks (taken as
// positives of their own) what they take away, both in one job through segment_job (the graph
// decoders solve the two together, the network alone each with the other's clicks as
// negatives). A Gaussian both added and taken goes to the more probable. Such a job is the
// object's alone, whatever the decoder: the other objects' solves do not see the region.
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

// Whether a graph job should hand over a coarse answer before its cold solve. The coarse answer
// costs a solve of its own (about 1 s of a 1.6 s cold click on an H100, where the full solve is
// a few frames anyway), so it is worth it only where full solves are slow: on a CPU device, or
// once a graph job on this device took longer than `slow_ms`.
bool want_coarse_answer(bool cpu_device, double slowest_graph_job_ms, double slow_ms = 1000.0);

// One segmentation, as `segment` would run it on prompts.json: one object (the network alone),
// or every object (graph decoders).
struct SegmentJob {
    data::Prompts prompts;
    seg::LiftedClicks anchors;  // where their clicks landed (lifted once, when they were made)
    size_t index = 0;           // a one-object job: the object's index in prompts.json (`segment` partitions object k with seed + k)
    std::string decoder;
    std::string signature;      // everything its result depends on
    int region = 0;             // a region object's edits (see above): that object's id
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
    // The job in flight solves every clicked object together (a click on any of them makes it stale).
    bool in_flight_joint() const;
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
    // A region object, and the job that segments its clicks' edits.
    struct RegionEdits {
        int id = 0;
        std::string name;
        std::shared_ptr<const Region> region;
        data::Prompts prompts;  // what its clicks add and take away (empty: no clicks, the region as it is)
        seg::LiftedClicks anchors;
        std::string signature;
    };
    const SegmentOutcome* cached(const RegionEdits& r) const;
    // The region object as its current edits leave it (cached per object).
    const seg::ObjectResult& region_result(const RegionEdits& r, const SegmentOutcome* edits);
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
    std::vector<RegionEdits> regions_;     // the document's region objects
    std::map<int, std::vector<Cached>> cache_;  // per object id (kJoint: joint solves), newest last
    struct RegionResult {
        std::shared_ptr<const Region> region;  // what it was made from: the region and its edits' signature
        std::string edits;
        uint64_t serial = 0;                   // which making (for assemble()'s key)
        seg::ObjectResult result;
    };
    std::map<int, RegionResult> region_results_;  // per region object
    uint64_t region_serial_ = 0;
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
