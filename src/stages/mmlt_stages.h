// MMLT's wavefront stages, in the order one iteration of a batch of chains runs them:
//   mutateChains     (chain state -> proposal rows u, strategy per slot, step kind)
//   evaluateProposals (the BPT stages on StoredSamples: camera subpath, light subpath,
//                      connectStrategies with its batched shadow rays -> L, pixel)
//   acceptAndSplat   (target c, Metropolis acceptance, expected-value splats, commit)
// A batch holds chains [c0, c0 + n) of one length group. The bootstrap and the replay of
// seeded chains run evaluateProposals on rows written by fillBootstrapRows/fillCurrentRows.
#pragma once
#include <cstdint>

#include "scene/scene.h"
#include "stages/mmlt_state.h"
#include "stages/pt_stages.h"  // PtCounters

namespace wmlt {

// The key of a chain's proposal `iteration` (its random numbers: large step, acceptance,
// two per coordinate) and of bootstrap sample `index` of length k (its vector u).
uint64_t mmltChainKey(uint64_t seed, uint32_t globalChain, uint32_t iteration);
uint64_t mmltBootstrapKey(uint64_t seed, int k, uint32_t index);

// The strategy s = min(floor(u0 (k + 1)), k) of a length-k vector (mmlt.md, step 4).
inline int strategyOf(float u0, int k) { return std::min(int(u0 * float(k + 1)), k); }

// Rows of bootstrap samples [index0, index0 + n) of length k (every coordinate hashed).
void fillBootstrapRows(MmltBatch& mb, int k, uint32_t index0, uint32_t n, uint64_t seed);
// Rows of chains [c0, c0 + n) of g: their current vectors (the replay of a seeded chain).
void fillCurrentRows(const ChainGroup& g, MmltBatch& mb, uint32_t c0, uint32_t n);
// Proposal `iteration` of chains [c0, c0 + n) of g: a large step with probability
// probLarge, else the lazy small step of each coordinate the proposal reads.
void mutateChains(const ChainGroup& g, MmltBatch& mb, uint32_t c0, uint32_t n, uint64_t seed, uint32_t iteration,
                  float probLarge);
// Traces and connects each slot's strategy: bpt.L = its MIS-weighted contribution,
// bpt.pixel = where it lands.
void evaluateProposals(const Scene& scene, MmltBatch& mb, float misBeta, PtCounters& counters);
// The contribution F = (k + 1) L of slot i and its target c = luminance(F) (0 when not
// finite: counted as discarded by the caller).
inline Vec3 contributionOf(const MmltBatch& mb, size_t i) { return mb.bpt.L[i] * float(mb.bpt.pathLength[i] + 1); }
// Accepts or rejects each slot's proposal (a = min(1, c'/c)), splats a F'/c' at the
// proposal's pixel and (1 - a) F/c at the current one's, both times `scale`, to mb.splats,
// and commits accepted proposals into g. Large steps' c are summed (they refine b_k).
void acceptAndSplat(ChainGroup& g, MmltBatch& mb, uint64_t seed, uint32_t iteration, float scale);

}  // namespace wmlt
