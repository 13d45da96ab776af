#include "dataset/eval/report.h"

#include <cstdio>
#include <map>
#include <optional>

namespace pg::data::eval {

using nlohmann::json;

namespace {

json opt(const std::optional<double>& v) { return v ? json(*v) : json(nullptr); }

// Mean of the values given, skipping absent ones.
struct Mean {
    double sum = 0.0;
    size_t n = 0;
    void add(const std::optional<double>& v) {
        if (v) sum += *v, ++n;
    }
    std::optional<double> value() const { return n ? std::optional<double>(sum / double(n)) : std::nullopt; }
};

std::string instance_name(const SceneEval& s, int32_t id) {
    for (const auto& i : s.instances)
        if (i.id == id) return i.name;
    return {};
}

std::string class_name(const SuiteInfo& info, int32_t id) {
    for (const auto& c : info.classes)
        if (c.id == id) return c.name;
    return {};
}

json click_json(const ClickScores& c) {
    json j{{"objects", c.objects}, {"iou_at", json::object()}, {"noc", json::object()}};
    for (size_t i = 0; i < kIouAtClicks.size(); ++i) j["iou_at"][std::to_string(kIouAtClicks[i])] = c.iou_at[i];
    for (size_t i = 0; i < kNocThresholds.size(); ++i)
        j["noc"][std::to_string(int(kNocThresholds[i] * 100 + 0.5))] = c.noc[i];
    return j;
}

json classes_json(const SuiteInfo& info, const SemanticScores& s) {
    json out = json::array();
    for (const auto& c : s.classes)
        out.push_back({{"id", c.id}, {"name", class_name(info, c.id)}, {"iou", opt(c.iou)}, {"in_gt", c.in_gt}});
    return out;
}

json scene_json(const SuiteInfo& info, const SceneEval& s) {
    json j{{"name", s.name}, {"3d", nullptr}, {"2d", nullptr}, {"clicks", nullptr}};
    if (s.instance_3d) {
        json objects = json::array();
        for (const auto& o : s.instance_3d->objects)
            objects.push_back({{"id", o.id}, {"name", instance_name(s, o.id)}, {"iou", o.iou}});
        j["3d"] = {{"miou", opt(s.instance_3d->miou)}, {"oa", opt(s.instance_3d->oa)},
                   {"gaussians", s.instance_3d->gaussians}, {"objects", objects}};
    }
    if (s.instance_2d) {
        json objects = json::array(), views = json::array();
        for (const auto& o : s.instance_2d->objects)
            objects.push_back({{"id", o.id}, {"name", instance_name(s, o.id)}, {"iou", o.iou}, {"views", o.views}});
        for (const auto& v : s.instance_2d->views) {
            json vo = json::array();
            for (const auto& o : v.objects) vo.push_back({{"id", o.id}, {"iou", o.iou}});
            views.push_back({{"name", v.name}, {"miou", opt(v.miou)}, {"objects", vo}});
        }
        j["2d"] = {{"miou", opt(s.instance_2d->miou)}, {"oa", opt(s.instance_2d->oa)}, {"pixels", s.instance_2d->pixels},
                   {"objects", objects}, {"views", views}};
    }
    if (s.semantic_3d)
        j["3d"] = {{"miou", opt(s.semantic_3d->miou)}, {"oa", opt(s.semantic_3d->oa)},
                   {"gaussians", s.semantic_3d->elements}, {"classes", classes_json(info, *s.semantic_3d)}};
    if (s.semantic_2d)
        j["2d"] = {{"miou", opt(s.semantic_2d->miou)}, {"oa", opt(s.semantic_2d->oa)}, {"pixels", s.semantic_2d->elements},
                   {"classes", classes_json(info, *s.semantic_2d)}};
    if (s.click_scores) {
        json c = click_json(*s.click_scores), per = json::array();
        for (const auto& o : s.clicks) {
            json po{{"id", o.id}, {"name", instance_name(s, o.id)}, {"clicks", o.iou_per_click.size()},
                    {"iou_at", json::object()}, {"noc", json::object()}};
            for (int k : kIouAtClicks) po["iou_at"][std::to_string(k)] = iou_after_clicks(o, k);
            for (double t : kNocThresholds) po["noc"][std::to_string(int(t * 100 + 0.5))] = clicks_to_reach(o, t);
            per.push_back(po);
        }
        c["per_object"] = per;
        j["clicks"] = c;
    }
    return j;
}

// The table's columns per scene, as fractions.
struct Row {
    std::optional<double> iou3d, iou2d, oa;
    std::map<int32_t, std::optional<double>> class3d, class2d;  // semantic suites
};

std::optional<double> class_iou(const std::optional<SemanticScores>& s, int32_t id) {
    if (s)
        for (const auto& c : s->classes)
            if (c.id == id && c.in_gt) return c.iou;
    return std::nullopt;
}

Row scene_row(const SuiteInfo& info, const SceneEval& s) {
    Row r;
    if (info.semantic()) {
        if (s.semantic_3d) r.iou3d = s.semantic_3d->miou;
        if (s.semantic_2d) r.iou2d = s.semantic_2d->miou, r.oa = s.semantic_2d->oa;
        for (const auto& c : info.classes) {
            r.class3d[c.id] = class_iou(s.semantic_3d, c.id);
            r.class2d[c.id] = class_iou(s.semantic_2d, c.id);
        }
    } else {
        if (s.instance_3d) r.iou3d = s.instance_3d->miou;
        if (s.instance_2d) r.iou2d = s.instance_2d->miou, r.oa = s.instance_2d->oa;
    }
    return r;
}

Row mean_row(const SuiteEval& e) {
    Mean m3, m2, moa;
    std::map<int32_t, Mean> c3, c2;
    for (const auto& s : e.scenes) {
        const Row r = scene_row(e.info, s);
        m3.add(r.iou3d), m2.add(r.iou2d), moa.add(r.oa);
        for (auto& [id, v] : r.class3d) c3[id].add(v);
        for (auto& [id, v] : r.class2d) c2[id].add(v);
    }
    Row r{m3.value(), m2.value(), moa.value(), {}, {}};
    for (auto& [id, m] : c3) r.class3d[id] = m.value();
    for (auto& [id, m] : c2) r.class2d[id] = m.value();
    return r;
}

std::optional<double> at(const std::map<int32_t, std::optional<double>>& m, int32_t id) {
    auto it = m.find(id);
    return it == m.end() ? std::nullopt : it->second;
}

std::optional<ClickScores> pooled_clicks(const SuiteEval& e) {
    std::vector<ObjectClicks> all;
    for (const auto& s : e.scenes) all.insert(all.end(), s.clicks.begin(), s.clicks.end());
    return click_scores(all);
}

std::string pct(const std::optional<double>& v) {
    if (!v) return "--";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2f", *v * 100.0);
    return buf;
}

std::string fixed2(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2f", v);
    return buf;
}

// Markdown cells appended one by one ("| a | b |").
std::string cells(const std::vector<std::string>& values) {
    std::string line = "|";
    for (const auto& v : values) {
        line += ' ';
        line += v;
        line += " |";
    }
    line += '\n';
    return line;
}

std::string table_row(const SuiteInfo& info, const std::string& label, const Row& r) {
    std::vector<std::string> v{label};
    if (info.semantic())
        for (const auto& c : info.classes) {
            v.push_back(pct(at(r.class3d, c.id)));
            v.push_back(pct(at(r.class2d, c.id)));
        }
    for (const auto& x : {r.iou3d, r.iou2d, r.oa}) v.push_back(pct(x));
    return cells(v);
}

std::string click_row(const std::string& label, const std::optional<ClickScores>& c) {
    std::vector<std::string> v{label, c ? std::to_string(c->objects) : "0"};
    for (size_t i = 0; i < kIouAtClicks.size(); ++i) v.push_back(c ? pct(c->iou_at[i]) : "--");
    for (size_t i = 0; i < kNocThresholds.size(); ++i) v.push_back(c ? fixed2(c->noc[i]) : "--");
    return cells(v);
}

}  // namespace

json report_json(const SuiteEval& e) {
    json j{{"suite", e.info.suite}, {"task", e.info.task}, {"seed", e.info.seed}, {"split", e.split},
           {"two_class", nullptr}, {"scenes", json::array()}, {"skipped", e.skipped}};
    if (e.info.two_class) j["two_class"] = {{"id", e.info.two_class->id}, {"name", e.info.two_class->name}};
    for (const auto& s : e.scenes) j["scenes"].push_back(scene_json(e.info, s));
    const Row m = mean_row(e);
    j["mean"] = {{"3d", opt(m.iou3d)}, {"2d", opt(m.iou2d)}, {"oa", opt(m.oa)}, {"clicks", nullptr}};
    if (e.info.semantic()) {
        json classes = json::array();
        for (const auto& c : e.info.classes)
            classes.push_back({{"id", c.id}, {"name", c.name}, {"3d", opt(at(m.class3d, c.id))},
                               {"2d", opt(at(m.class2d, c.id))}});
        j["mean"]["classes"] = classes;
    }
    if (auto c = pooled_clicks(e)) j["mean"]["clicks"] = click_json(*c);
    return j;
}

std::string report_markdown(const SuiteEval& e) {
    const SuiteInfo& info = e.info;
    std::string out = "### ";
    out += info.suite + ", " + e.split + " split (" + info.task;
    if (info.two_class) out += ", two-class view: " + info.two_class->name + " vs background (every other class)";
    out += ", %)\n\n";
    std::vector<std::string> head{"scene"};
    if (info.semantic())
        for (const auto& c : info.classes) {
            head.push_back(c.name + " 3D");
            head.push_back(c.name + " 2D");
        }
    for (const char* h : {"3D", "2D", "OA"}) head.push_back(h);
    std::vector<std::string> rule(head.size(), "---:");
    rule[0] = "---";
    out += cells(head) + cells(rule);
    for (const auto& s : e.scenes) out += table_row(info, s.name, scene_row(info, s));
    out += table_row(info, "**mean**", mean_row(e));

    bool any_clicks = false;
    for (const auto& s : e.scenes) any_clicks |= s.click_scores.has_value();
    if (any_clicks) {
        std::vector<std::string> ch{"scene", "objects"};
        for (int k : kIouAtClicks) ch.push_back("IoU@" + std::to_string(k));
        for (double t : kNocThresholds) ch.push_back("NoC@" + std::to_string(int(t * 100 + 0.5)));
        std::vector<std::string> crule(ch.size(), "---:");
        crule[0] = "---";
        out += "\n" + cells(ch) + cells(crule);
        for (const auto& s : e.scenes) out += click_row(s.name, s.click_scores);
        out += click_row("**all objects**", pooled_clicks(e));
    }
    if (!e.skipped.empty()) {
        out += "\nNo prediction for:";
        for (const auto& s : e.skipped) out += " " + s;
        out += "\n";
    }
    return out;
}

}  // namespace pg::data::eval
