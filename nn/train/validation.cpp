#include "nn/train/validation.h"

#include <cstdio>

namespace pg::nn::train {

std::string Validation::text() const {
    std::string out;
    char buf[64];
    for (const auto& [name, value] : scores) {
        std::snprintf(buf, sizeof buf, "%s%s %.3f", out.empty() ? "" : ", ", name.c_str(), value);
        out += buf;
    }
    return out;
}

}  // namespace pg::nn::train
