#pragma once
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace pg::test {
// Checks run after all test cases of the process; any that returns false fails the run.
inline std::vector<std::pair<std::string, std::function<bool()>>>& exit_checks() {
    static std::vector<std::pair<std::string, std::function<bool()>>> checks;
    return checks;
}
}  // namespace pg::test
