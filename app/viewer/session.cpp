#include "app/viewer/session.h"

#include <algorithm>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace pg::viewer {

namespace {

std::string signature(const data::ObjectPrompt& object, size_t index, const std::string& decoder) {
    nlohmann::json j;
    j["k"] = index;
    j["id"] = object.id;
    j["decoder"] = decoder;
    for (auto& c : object.clicks) {
        nlohmann::json jc{{"positive", c.positive}};
        if (c.point) jc["point"] = {c.point->x, c.point->y, c.point->z};
        else jc["view"] = {c.view, c.u, c.v};
        j["clicks"].push_back(jc);
    }
    return j.dump();
}

}  // namespace

seg::GraphUse decoder_graph_use(const std::string& decoder) {
    if (decoder == "graph") return seg::GraphUse::Alone;
    if (decoder == "ptv3+graph") return seg::GraphUse::Unary;
    return seg::GraphUse::None;
}

bool decoder_is_joint(const std::string& decoder) { return decoder_graph_use(decoder) != seg::GraphUse::None; }

namespace {

SegmentOutcome outcome_of(seg::SegmentResult result) {
    SegmentOutcome outcome;
    for (auto& o : result.objects)
        if (o.error.empty()) outcome.results.push_back(std::move(o));
        else outcome.errors[o.id] = o.error;
    return outcome;
}

}  // namespace

SegmentOutcome segment_job(seg::Segmenter& segmenter, const SegmentJob& job, seg::SegmentOptions options,
                           std::map<std::string, double>& stage_ms, const std::atomic<bool>* cancel,
                           const std::function<void(SegmentOutcome)>& coarse) {
    options.graph = decoder_graph_use(job.decoder);
    if (job.prompts.objects.size() == 1) options.seed += job.index;  // `segment` partitions object k with seed + k
    options.cancel = cancel;
    if (coarse) options.on_coarse = [&](const seg::SegmentResult& r) { coarse(outcome_of(r)); };
    try {
        auto result = segmenter.segment(job.prompts, options, job.anchors);
        stage_ms = result.stage_ms;
        return outcome_of(std::move(result));
    } catch (const seg::Cancelled&) {
        SegmentOutcome outcome;
        outcome.cancelled = true;
        return outcome;
    }
}

void Session::sync(const Document& doc, const std::string& decoder) {
    if (doc.version() == doc_version_ && decoder == decoder_) return;
    doc_version_ = doc.version();
    decoder_ = decoder;
    joint_ = decoder_is_joint(decoder);
    prompts_ = doc.prompts();
    anchors_ = doc.anchors();
    signatures_.clear();
    joint_signature_.clear();
    for (size_t k = 0; k < prompts_.objects.size(); ++k) {
        signatures_.push_back(signature(prompts_.objects[k], k, decoder));
        joint_signature_ += signatures_.back() + "\n";
    }
    assemble();
}

const SegmentOutcome* Session::find(int key, const std::string& sig) const {
    auto it = cache_.find(key);
    if (it == cache_.end()) return nullptr;
    for (const Cached& c : it->second)
        if (c.signature == sig) return &c.outcome;
    return nullptr;
}

const SegmentOutcome* Session::cached(size_t k) const {
    return joint_ ? find(kJoint, joint_signature_) : find(prompts_.objects[k].id, signatures_[k]);
}

std::optional<SegmentJob> Session::next_job() {
    if (in_flight_) return std::nullopt;
    for (size_t k = 0; k < prompts_.objects.size(); ++k) {
        if (cached(k)) continue;
        in_flight_ = true;
        coarse_.reset();
        if (joint_) flying_ = SegmentJob{prompts_, anchors_, 0, decoder_, joint_signature_};
        else flying_ = SegmentJob{{{prompts_.objects[k]}}, {anchors_[k]}, k, decoder_, signatures_[k]};
        return flying_;
    }
    return std::nullopt;
}

bool Session::in_flight_stale() const {
    if (!in_flight_) return false;
    if (decoder_is_joint(flying_.decoder)) return !joint_ || flying_.signature != joint_signature_;
    return std::find(signatures_.begin(), signatures_.end(), flying_.signature) == signatures_.end();
}

bool Session::in_flight_covers(int id) const {
    if (!in_flight_) return false;
    for (auto& o : flying_.prompts.objects)
        if (o.id == id) return true;
    return false;
}

void Session::store_coarse(const SegmentJob& job, SegmentOutcome outcome) {
    if (!in_flight_ || job.signature != flying_.signature) return;
    coarse_ = Cached{job.signature, std::move(outcome)};
    assemble();
}

void Session::store(const SegmentJob& job, SegmentOutcome outcome) {
    in_flight_ = false;
    coarse_.reset();
    if (outcome.cancelled) {
        assemble();
        return;
    }
    const bool joint = decoder_is_joint(job.decoder);
    if (!joint && job.prompts.objects.size() != 1) throw std::logic_error("Session::store: a one-object job expected");
    auto& results = cache_[joint ? kJoint : job.prompts.objects.front().id];
    results.push_back({job.signature, std::move(outcome)});
    if (results.size() > kResultsPerObject) results.erase(results.begin());
    assemble();
}

bool Session::settled() const {
    if (in_flight_) return false;
    for (size_t k = 0; k < prompts_.objects.size(); ++k)
        if (!cached(k)) return false;
    return true;
}

size_t Session::labelled(int id) const {
    auto it = labelled_.find(id);
    return it == labelled_.end() ? 0 : it->second;
}

const std::string& Session::error(int id) const {
    static const std::string none;
    for (size_t k = 0; k < prompts_.objects.size(); ++k)
        if (prompts_.objects[k].id == id)
            if (const SegmentOutcome* c = cached(k)) {
                if (auto e = c->errors.find(id); e != c->errors.end()) return e->second;
                return c->error;
            }
    return none;
}

void Session::assemble() {
    // The current results, object by object in prompts.json order.
    // An object with no result for its present clicks shows the job in flight's coarse answer
    // when that job is for those clicks.
    std::string key;
    std::vector<const seg::ObjectResult*> current;
    showing_coarse_ = false;
    for (size_t k = 0; k < prompts_.objects.size(); ++k) {
        const std::string& sig = joint_ ? joint_signature_ : signatures_[k];
        const SegmentOutcome* c = cached(k);
        const bool coarse = !c && coarse_ && coarse_->signature == sig;
        if (coarse) c = &coarse_->outcome;
        if (!c) continue;
        for (const auto& r : c->results)
            if (r.id == prompts_.objects[k].id) {
                current.push_back(&r);
                showing_coarse_ = showing_coarse_ || coarse;
                key += std::to_string(r.id) + (coarse ? "~" : ":") + sig + ";";
            }
    }
    if (key == assembled_) return;
    assembled_ = key;
    seg::SegmentResult result;
    for (const auto* r : current) result.objects.push_back(*r);
    result.assemble(gaussians_);
    labelled_.clear();
    for (auto& o : result.objects) labelled_[o.id] = o.labelled;
    labels_ = result.objects.empty() ? nullptr : std::make_shared<const std::vector<int32_t>>(std::move(result.labels));
    ++labels_version_;
}

}  // namespace pg::viewer
