// Multiplexed Metropolis light transport (--tracer mmlt): the driver in mmlt.cpp, stages
// in mmlt_stages.h, chain state in mmlt_state.h.
#pragma once
#include <cstdint>

#include "scene/scene.h"
#include "wavemmlt/render.h"

namespace wmlt {

// Bytes of chain state per chain of path length k.
uint64_t mmltChainBytes(int k);

// Throws InputError when no light reaches the camera (every b_k is 0) or when the chains
// would not fit in memory.
RenderResult renderMmlt(const Scene& scene, const RenderOptions& opt);

}  // namespace wmlt
