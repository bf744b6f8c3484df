// Multiplexed Metropolis light transport (--tracer mmlt): the driver in mmlt.cpp, stages
// in mmlt_stages.h, chain state in mmlt_state.h.
#pragma once
#include <cstdint>

#include "scene/scene.h"
#include "wavemmlt/render.h"

namespace wmlt {

// --chains auto (RenderOptions::chains = 0, the command line's default; docs/mmlt-chains.md,
// "How many chains: --chains auto"). More chains than a scene's pools have distinct lit
// seeds are correlated copies until their iterations take them apart: measured on the seed
// room and the Cornell box at 4-32 s, 4096 chains were as accurate as the best of 1024 to
// 65536 on both, and more chains paid on the seed room only from about 8000 iterations each.
constexpr double kAutoIterationsPerChain = 8000;
constexpr uint32_t kAutoChainsLeast = 4096;       // with --spp: 16 batches of 256 chains
constexpr uint32_t kAutoChainsLeastTimed = 1024;  // under --time, with 2 batches per worker
constexpr uint32_t kAutoChainsMost = 65536;

// The chains for `mutations` mutations in all: mutations / iterationsPerChain, rounded down
// to whole batches of 256 chains, within [least, most]. Pure: with --spp it is called with
// the mutations asked for and kAutoChainsLeast, so that the count (and the image) does not
// depend on the thread or rank count (16 batches: enough for 16 workers; a machine with
// more runs a short render narrower than it could, a long one gets more chains anyway);
// under --time with the mutations the bootstrap's rate predicts and a least of 2 batches
// per worker of the job, at least 1024 (where the mutations are few, as on 2 cores in
// seconds, fewer chains were the more accurate on the seed room).
uint32_t autoChains(double mutations, double iterationsPerChain = kAutoIterationsPerChain, uint32_t least = kAutoChainsLeast,
                    uint32_t most = kAutoChainsMost);

// Bytes of chain state per chain of path length k (in a scene with media or not).
uint64_t mmltChainBytes(int k, bool media, bool spectral);

// Throws InputError when no light reaches the camera (every b_k is 0) or when the chains
// would not fit in memory.
RenderResult renderMmlt(const Scene& scene, const RenderOptions& opt);

}  // namespace wmlt
