#pragma once
// GPU milliseconds per pass name (op family) over repeated runs, for the benchmarks that report
// medians per family: each run's passes are summed per name, then medians are taken per name.
#include <algorithm>
#include <map>
#include <string>
#include <vector>

#include "app/cli/commands.h"
#include "engine/vk/commands.h"

namespace pg::app {

struct PassFamilies {
    std::vector<std::string> names;  // in the order first seen
    std::map<std::string, std::vector<double>> ms;
    std::vector<double> totals;      // GPU ms per run, all passes

    void add(const std::vector<vk::PassTiming>& passes) {
        std::map<std::string, double> sum;
        double total = 0;
        for (const auto& p : passes) {
            if (std::find(names.begin(), names.end(), p.name) == names.end()) names.push_back(p.name);
            sum[p.name] += p.ms;
            total += p.ms;
        }
        for (const auto& n : names) ms[n].push_back(sum[n]);
        totals.push_back(total);
    }
    double median_ms(const std::string& name) const { return median(ms.at(name)); }
    double median_total() const { return median(totals); }
};

}  // namespace pg::app
