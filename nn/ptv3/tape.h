#pragma once
// What a training forward keeps for the backward: each module's tape, in the order the modules
// ran. The backward walks the modules in reverse and takes their tapes off the back.
#include <vector>

#include "nn/ptv3/block.h"
#include "nn/ptv3/embedding.h"
#include "nn/ptv3/head.h"
#include "nn/ptv3/pooling.h"
#include "nn/ptv3/unpooling.h"

namespace pg::nn {

struct Ptv3Tape {
    Embedding::Tape embedding;
    std::vector<Pooling::Tape> poolings;
    std::vector<Block::Tape> blocks;
    std::vector<Unpooling::Tape> unpoolings;
    Head::Tape head;
};

// Removes and returns the last element (a default one when there is none).
template <class T> T take_last(std::vector<T>& v) {
    if (v.empty()) return {};
    T last = std::move(v.back());
    v.pop_back();
    return last;
}

}  // namespace pg::nn
