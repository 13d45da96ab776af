#pragma once
// The point files `infer` and `bench ptv3` read: coord f32 [N,3] then feat f32 [N,C],
// little-endian (the layout of the PTv3 golden fixtures).
#include <string>

#include "nn/ptv3/model.h"

namespace pg::app {

// InputError naming the file unless it holds a whole number of finite points.
nn::Ptv3Input read_point_file(const std::string& path, int channels);

}  // namespace pg::app
