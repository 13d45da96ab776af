#include "app/cli/point_file.h"

#include <cmath>
#include <cstring>

#include "dataset/atomic_file.h"
#include "dataset/error.h"

namespace pg::app {

nn::Ptv3Input read_point_file(const std::string& path, int channels) {
    const std::vector<char> raw = data::read_file(path);
    const size_t row = sizeof(float) * size_t(3 + channels);
    if (raw.empty() || raw.size() % row)
        throw data::InputError(path, "size " + std::to_string(raw.size()) + " bytes is not a whole number of points (" +
                                         std::to_string(row) + " bytes each: coord f32 x3, feat f32 x" +
                                         std::to_string(channels) + ")");
    const size_t n = raw.size() / row;
    nn::Ptv3Input in;
    in.coord.resize(3 * n);
    in.feat.resize(n * size_t(channels));
    std::memcpy(in.coord.data(), raw.data(), in.coord.size() * sizeof(float));
    std::memcpy(in.feat.data(), raw.data() + in.coord.size() * sizeof(float), in.feat.size() * sizeof(float));
    for (float v : in.coord)
        if (!std::isfinite(v)) throw data::InputError(path, "has a non-finite coordinate");
    for (float v : in.feat)
        if (!std::isfinite(v)) throw data::InputError(path, "has a non-finite feature");
    return in;
}

}  // namespace pg::app
