#include "dataset/eval/two_class.h"

#include <charconv>

#include "dataset/error.h"

namespace pg::data::eval {

void use_two_class_view(SuiteInfo& suite, const std::string& which) {
    if (!suite.semantic())
        throw InputError("--two-class",
                         "the " + suite.suite + " suite is an instance suite; the two-class view needs a semantic one");
    int32_t id = -1;
    const auto [end, ec] = std::from_chars(which.data(), which.data() + which.size(), id);
    const bool numeric = ec == std::errc() && end == which.data() + which.size();
    std::string names;
    for (const ClassInfo& c : suite.classes) {
        if ((numeric && c.id == id) || (!numeric && c.name == which)) {
            if (c.id == 0)
                throw InputError("--two-class", "'" + which + "' is class 0, the background of the two-class view");
            suite.two_class = c;
            suite.own_classes = std::move(suite.classes);
            suite.classes = {{0, "background"}, c};
            return;
        }
        names += (names.empty() ? "" : ", ") + c.name;
    }
    throw InputError("--two-class", "no class '" + which + "' in the " + suite.suite + " suite (" + names + ")");
}

void to_two_class(std::vector<int32_t>& labels, int32_t keep) {
    for (int32_t& v : labels)
        if (v != keep && v > 0) v = 0;
}

void to_two_class(std::vector<uint16_t>& labels, int32_t keep) {
    for (uint16_t& v : labels)
        if (int32_t(v) != keep) v = 0;
}

}  // namespace pg::data::eval
