#include "app/viewer/session.h"

#include <stdexcept>

#include <nlohmann/json.hpp>

namespace pg::viewer {

namespace {

std::string signature(const data::ObjectPrompt& object, size_t index, const std::string& decoder) {
    nlohmann::json j;
    j["k"] = index;
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

seg::ObjectResult segment_job(seg::Segmenter& segmenter, const SegmentJob& job, seg::SegmentOptions options,
                              std::map<std::string, double>& stage_ms) {
    data::Prompts one;
    one.objects.push_back(job.object);
    options.seed += job.index;  // `segment` partitions object k with seed + k
    options.graph = seg::GraphUse::None;  // one object at a time: the network alone (see README)
    auto result = segmenter.segment(one, options);
    stage_ms = result.stage_ms;
    if (!result.objects.front().error.empty()) throw std::runtime_error(result.objects.front().error);
    return std::move(result.objects.front());
}

void Session::sync(const Document& doc, const std::string& decoder) {
    if (doc.version() == doc_version_ && decoder == decoder_) return;
    doc_version_ = doc.version();
    decoder_ = decoder;
    prompts_ = doc.prompts();
    signatures_.clear();
    for (size_t k = 0; k < prompts_.objects.size(); ++k)
        signatures_.push_back(signature(prompts_.objects[k], k, decoder));
    assemble();
}

const SegmentOutcome* Session::cached(size_t k) const {
    auto it = cache_.find(prompts_.objects[k].id);
    if (it == cache_.end()) return nullptr;
    for (const Cached& c : it->second)
        if (c.signature == signatures_[k]) return &c.outcome;
    return nullptr;
}

std::optional<SegmentJob> Session::next_job() {
    if (in_flight_) return std::nullopt;
    for (size_t k = 0; k < prompts_.objects.size(); ++k) {
        if (cached(k)) continue;
        in_flight_ = true;
        return SegmentJob{prompts_.objects[k], k, decoder_, signatures_[k]};
    }
    return std::nullopt;
}

void Session::store(const SegmentJob& job, SegmentOutcome outcome) {
    in_flight_ = false;
    auto& results = cache_[job.object.id];
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
            if (const SegmentOutcome* c = cached(k)) return c->error;
    return none;
}

void Session::assemble() {
    std::string key;
    for (size_t k = 0; k < prompts_.objects.size(); ++k)
        if (const SegmentOutcome* c = cached(k); c && c->result)
            key += std::to_string(prompts_.objects[k].id) + ":" + signatures_[k] + ";";
    if (key == assembled_) return;
    assembled_ = key;
    seg::SegmentResult result;
    for (size_t k = 0; k < prompts_.objects.size(); ++k)
        if (const SegmentOutcome* c = cached(k); c && c->result) result.objects.push_back(*c->result);
    result.assemble(gaussians_);
    labelled_.clear();
    for (auto& o : result.objects) labelled_[o.id] = o.labelled;
    labels_ = result.objects.empty() ? nullptr : std::make_shared<const std::vector<int32_t>>(std::move(result.labels));
    ++labels_version_;
}

}  // namespace pg::viewer
