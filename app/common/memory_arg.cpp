#include "app/common/memory_arg.h"

#include <charconv>

#include "dataset/error.h"

namespace pg::app {

render::SceneBudget scene_budget(const std::string& s, bool half_sh) {
    render::SceneBudget b;
    b.half_sh = half_sh;
    if (s.empty()) return b;
    double value = 0;
    auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
    const std::string unit(ptr, s.data() + s.size());
    const double scale = unit.empty() || unit == "B"                ? 1
                         : unit == "K" || unit == "KiB"             ? 1024.0
                         : unit == "M" || unit == "MiB"             ? 1024.0 * 1024
                         : unit == "G" || unit == "GiB"             ? 1024.0 * 1024 * 1024
                                                                    : 0;
    if (ec != std::errc() || scale == 0 || !(value > 0) || value * scale > 1e15)
        throw data::InputError("--max-device-memory", "expected a size such as 512M or 2G, got '" + s + "'");
    b.max_device_bytes = uint64_t(value * scale);
    return b;
}

}  // namespace pg::app
