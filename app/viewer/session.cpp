#include "app/viewer/session.h"

#include <algorithm>
#include <stdexcept>
#include <unordered_map>

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

constexpr int kAdd = 1, kTake = 2;  // a region edit job's two objects

// A click of a region object's "take" side: its negative clicks are that side's positives.
Click flipped(Click c) {
    c.prompt.positive = !c.prompt.positive;
    c.anchor.positive = !c.anchor.positive;
    return c;
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

bool want_coarse_answer(bool cpu_device, double slowest_graph_job_ms, double slow_ms) {
    return cpu_device || slowest_graph_job_ms > slow_ms;
}

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
    regions_.clear();
    for (const Object& o : doc.state().objects) {
        if (!o.region) continue;
        RegionEdits r{o.id, o.name, o.region, {}, {}, {}};
        // The add side: the positive clicks, with the negative ones as negatives (network alone).
        // The take side: the other way round. Solved jointly, each side's clicks seed its own label.
        for (const bool take : {false, true}) {
            data::ObjectPrompt side;
            side.id = take ? kTake : kAdd;
            side.name = o.name + (take ? " -" : " +");
            std::vector<seg::Anchor> anchors;
            for (const Click& c : o.clicks) {
                const Click mine = take ? flipped(c) : c;
                if (!mine.prompt.positive && joint_) continue;
                side.clicks.push_back(mine.prompt);
                anchors.push_back(mine.anchor);
            }
            if (std::none_of(side.clicks.begin(), side.clicks.end(), [](auto& c) { return c.positive; })) continue;
            r.prompts.objects.push_back(std::move(side));
            r.anchors.push_back(std::move(anchors));
        }
        if (!r.prompts.objects.empty()) {
            r.signature = "region " + std::to_string(o.id) + "\n";
            for (size_t k = 0; k < r.prompts.objects.size(); ++k)
                r.signature += signature(r.prompts.objects[k], k, decoder) + "\n";
        }
        regions_.push_back(std::move(r));
    }
    assemble();
}

const SegmentOutcome* Session::cached(const RegionEdits& r) const {
    return r.signature.empty() ? nullptr : find(r.id, r.signature);
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
    for (const RegionEdits& r : regions_) {
        if (r.signature.empty() || cached(r)) continue;
        in_flight_ = true;
        coarse_.reset();
        flying_ = SegmentJob{r.prompts, r.anchors, 0, decoder_, r.signature, r.id};
        return flying_;
    }
    return std::nullopt;
}

bool Session::in_flight_stale() const {
    if (!in_flight_) return false;
    if (flying_.region)
        return std::none_of(regions_.begin(), regions_.end(),
                            [&](auto& r) { return r.signature == flying_.signature; });
    if (decoder_is_joint(flying_.decoder)) return !joint_ || flying_.signature != joint_signature_;
    return std::find(signatures_.begin(), signatures_.end(), flying_.signature) == signatures_.end();
}

bool Session::in_flight_covers(int id) const {
    if (!in_flight_) return false;
    if (flying_.region) return flying_.region == id;  // its objects are the edit's two sides
    for (auto& o : flying_.prompts.objects)
        if (o.id == id) return true;
    return false;
}

bool Session::in_flight_joint() const {
    return in_flight_ && !flying_.region && decoder_is_joint(flying_.decoder);
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
    if (job.region) {
        // Errors belong to the region object, not to the edit's sides.
        std::map<int, std::string> errors;
        for (auto& [side, e] : outcome.errors) errors.emplace(job.region, e);
        outcome.errors = std::move(errors);
    }
    const bool joint = decoder_is_joint(job.decoder) && !job.region;
    if (!joint && !job.region && job.prompts.objects.size() != 1)
        throw std::logic_error("Session::store: a one-object job expected");
    auto& results = cache_[job.region ? job.region : joint ? kJoint : job.prompts.objects.front().id];
    results.push_back({job.signature, std::move(outcome)});
    if (results.size() > kResultsPerObject) results.erase(results.begin());
    assemble();
}

bool Session::settled() const {
    if (in_flight_) return false;
    for (size_t k = 0; k < prompts_.objects.size(); ++k)
        if (!cached(k)) return false;
    for (const RegionEdits& r : regions_)
        if (!r.signature.empty() && !cached(r)) return false;
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
    for (const RegionEdits& r : regions_)
        if (r.id == id)
            if (const SegmentOutcome* c = cached(r)) {
                if (auto e = c->errors.find(id); e != c->errors.end()) return e->second;
                return c->error;
            }
    return none;
}

const seg::ObjectResult& Session::region_result(const RegionEdits& r, const SegmentOutcome* edits) {
    RegionResult& made = region_results_[r.id];
    made.result.name = r.name;
    const std::string signature = edits ? r.signature : std::string();
    if (made.region == r.region && made.edits == signature && made.serial) return made.result;
    made.region = r.region;
    made.edits = signature;
    made.serial = ++region_serial_;
    // What the clicks add and take away (their ROIs: small beside the region).
    std::unordered_map<uint32_t, float> add, take;
    if (edits)
        for (const seg::ObjectResult& side : edits->results)
            for (auto [g, p] : side.claims) {
                float& to = (side.id == kTake ? take : add)[g];
                to = std::max(to, p);
            }
    auto taken = [&](uint32_t g, float added) {
        auto t = take.find(g);
        return t != take.end() && t->second >= added;  // both: the more probable side, ties taken
    };
    seg::ObjectResult& result = made.result;
    result = seg::ObjectResult{};
    result.id = r.id;
    result.name = r.name;
    const Region& region = *r.region;
    for (size_t i = 0; i < region.gaussians.size(); ++i) {
        const uint32_t g = region.gaussians[i];
        if (g >= gaussians_) continue;
        auto a = add.find(g);
        const float added = a == add.end() ? 0.0f : a->second;
        if (a != add.end()) add.erase(a);
        if (!taken(g, added)) result.claims.emplace_back(g, std::max(region.probability[i], added));
    }
    for (auto [g, p] : add)
        if (g < gaussians_ && !taken(g, p)) result.claims.emplace_back(g, p);
    std::sort(result.claims.begin(), result.claims.end());
    return result;
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
    // Region objects: the region with the edits of their present clicks; the bare region while
    // those are being segmented.
    for (const RegionEdits& r : regions_) {
        const SegmentOutcome* edits = cached(r);
        current.push_back(&region_result(r, edits));
        key += std::to_string(r.id) + "R" + std::to_string(region_results_[r.id].serial) + ";";
    }
    std::erase_if(region_results_, [&](auto& entry) {
        return std::none_of(regions_.begin(), regions_.end(), [&](auto& r) { return r.id == entry.first; });
    });
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
