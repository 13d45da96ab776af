#pragma once
// The paper's two-class view of a semantic suite (its Campus table: building vs background):
// one class of suite.json is kept and every other class of the GT and the prediction becomes
// background (id 0) before scoring, so a many-class suite still gives the paper's numbers.
#include <cstdint>
#include <string>
#include <vector>

#include "dataset/eval/suite_info.h"

namespace pg::data::eval {

// Switches `suite` to the view of class `which` (a name or an id of suite.json's classes):
// sets suite.two_class and reduces suite.classes to {0 background, the class}. InputError
// ("--two-class") on an instance suite, for an unknown class, or for class 0.
void use_two_class_view(SuiteInfo& suite, const std::string& which);

// In place: ids equal to `keep` stay, other ids become 0; negative ("unlabelled") ids stay.
void to_two_class(std::vector<int32_t>& labels, int32_t keep);
void to_two_class(std::vector<uint16_t>& labels, int32_t keep);

}  // namespace pg::data::eval
