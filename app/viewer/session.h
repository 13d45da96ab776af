#pragma once
// The segmentation half of a viewer session: which objects the document's present clicks ask
// to segment, each object's cached results (for its last few click sets, so undo and redo need
// no new segmentation), and the labels assembled from the results that are current. No window
// and no threads: the viewer runs the jobs handed out here on its job thread (through the same
// Segmenter as `pointgauss segment`) and stores what comes back.
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/viewer/document.h"
#include "engine/segment/segmenter.h"

namespace pg::viewer {

// One object to segment, as `segment` would for the object at `index` of prompts.json.
struct SegmentJob {
    data::ObjectPrompt object;
    size_t index = 0;  // `segment` partitions object k with seed + k
    std::string decoder;
    std::string signature;  // everything its result depends on
};

struct SegmentOutcome {
    std::optional<seg::ObjectResult> result;
    std::string error;  // why there is no result
};

// Runs one job through `segmenter`, exactly as `segment` computes object `job.index` of prompts.json.
seg::ObjectResult segment_job(seg::Segmenter& segmenter, const SegmentJob& job, seg::SegmentOptions options,
                              std::map<std::string, double>& stage_ms);

class Session {
public:
    explicit Session(size_t gaussians = 0) : gaussians_(gaussians) {}

    // Follows the document's objects and clicks and the chosen decoder; reassembles the labels
    // when the set of current results changed (an undo back to cached clicks needs no job).
    void sync(const Document& doc, const std::string& decoder);
    // The first object, in prompts.json order, whose cached result is not for its present clicks;
    // none while a job is out (one at a time, so results arrive in order).
    std::optional<SegmentJob> next_job();
    void store(const SegmentJob& job, SegmentOutcome outcome);
    bool in_flight() const { return in_flight_; }
    bool settled() const;  // nothing out and every object's result current

    // Object id per Gaussian from every current result (a Gaussian claimed twice goes to the
    // higher probability, ties to the earlier object); null while no object has a result.
    const std::shared_ptr<const std::vector<int32_t>>& labels() const { return labels_; }
    uint64_t labels_version() const { return labels_version_; }  // bumps whenever labels() is reassembled
    size_t labelled(int id) const;              // Gaussians object `id` holds in labels()
    const std::string& error(int id) const;     // why its present clicks failed to segment, else empty

    static constexpr size_t kResultsPerObject = 8;  // click sets an object keeps results for

private:
    struct Cached {
        std::string signature;
        SegmentOutcome outcome;
    };
    const SegmentOutcome* cached(size_t k) const;  // object k's result for its present clicks
    void assemble();

    size_t gaussians_;
    uint64_t doc_version_ = ~0ull;
    std::string decoder_;
    data::Prompts prompts_;               // the document's objects to segment
    std::vector<std::string> signatures_;  // per object of prompts_
    std::map<int, std::vector<Cached>> cache_;  // per object id, newest last
    bool in_flight_ = false;
    std::string assembled_;  // which results labels_ holds
    std::shared_ptr<const std::vector<int32_t>> labels_;
    uint64_t labels_version_ = 0;
    std::map<int, size_t> labelled_;
};

}  // namespace pg::viewer
