#pragma once
// Compiling a device's compute pipelines is the larger part of a process's first click beyond
// a later one (128 ms of 49 pipelines on lavapipe at 150 k Gaussians). warm_up segments a small
// made-up scene the way a click on the real one would be segmented (lifted in a view, the
// graph built and walked, the coarse answer handed over), so the context holds those pipelines
// before the user's first click: what a viewer does while its scene loads.
#include <cstddef>

#include "engine/segment/segmenter.h"

namespace pg::vk {
class Context;
}

namespace pg::seg {

// Segments the made-up scene with GraphUse::Alone and `options`' graph, walk and forest
// settings, once per walk kernel width that up to `objects` objects at once use (the kernels
// are built per width: 1-3, 4-7, 8-11 and 12 or more objects). Returns the milliseconds spent.
// The network decoders' pipelines are not made: their decoder is bound to its scene.
double warm_up(vk::Context& ctx, const SegmentOptions& options, size_t objects = 1);

}  // namespace pg::seg
