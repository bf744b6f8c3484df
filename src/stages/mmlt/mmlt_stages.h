// MMLT's wavefront stages, in the order one iteration of a batch of chains runs them:
//   mutateChains      (chain state -> proposal rows u, strategy per slot, step kind)
//   evaluateProposals (the BPT stages on StoredSamples: camera subpath, light subpath,
//                      connectStrategies with its batched shadow rays -> L, pixel)
//   acceptAndSplat    (target c, Metropolis acceptance, expected-value splats, commit,
//                      large steps into the next pass's pools)
// A batch holds slices of chains of several lengths (MmltBatch::slices). Pools are traced
// by evaluateProposals on rows written by fillPoolRows, and seeded chains replayed on rows
// written by fillSeedRows. PSSMLT runs its own whole-sample stages (pssmlt_stages.h) in
// the same driver: ChainStages, chosen once per render, holds one tracer's set.
#pragma once
#include <cstdint>

#include "kernels/chain_numbers.h"
#include "kernels/mmlt_target.h"
#include "scene/scene.h"
#include "stages/core/wave.h"  // RayCounters
#include "stages/mmlt/mmlt_state.h"
#include "stages/pssmlt/pssmlt_stages.h"

namespace wmlt {

// The key of a chain's proposal `iteration` (its random numbers: large step, acceptance,
// two per coordinate) and of fresh pool sample `index` of length k in pass `pass`.
uint64_t mmltChainKey(uint64_t seed, uint32_t globalChain, uint32_t iteration);
// Slot i holds proposal `iteration` of chain c of g: its key, chain and step kind (a large
// step with probability probLarge); true for a large step (MMLT's and PSSMLT's mutateChains).
inline bool beginProposal(MmltBatch& mb, uint32_t i, const ChainGroup& g, uint32_t c, uint64_t seed, uint32_t iteration, float probLarge) {
    const uint64_t key = mmltChainKey(seed, g.first + c, iteration);
    const bool large = sampleDimension(key, kDimLarge) < probLarge;
    mb.bpt.key[i] = key;
    mb.chain[i] = c;
    mb.large[i] = large ? kLargeStep : kSmallStep;
    return large;
}
uint64_t mmltPoolKey(uint64_t seed, uint32_t pass, int k, uint32_t index);

// Coordinate d of the vector u of a pool entry is poolCoordinate(key, d)
// (kernels/chain_numbers.h): the numbers a large step with that key draws (so a large-step
// proposal joins the next pool as its key).

// The strategy s = min(floor(u0 (k + 1)), k) of a length-k vector (mmlt.md, step 4).
inline int strategyOf(float u0, int k) { return std::min(int(u0 * float(k + 1)), k); }

// Which numbers the scene's walks read (MmltBatch::lensRead, vertexLo, vertexHi), once per batch
// after reserve: from its camera and the BSDF kinds it has.
void setNumbersRead(const Scene& scene, MmltBatch& mb);
// Rows of fresh pool samples [index0, index0 + n) of length k in pass `pass`.
void fillPoolRows(MmltBatch& mb, int k, uint32_t pass, uint32_t index0, uint32_t n, uint64_t seed);
// Rows of the seeded chains of the batch's slices: every coordinate from the seed's key.
void fillSeedRows(const std::vector<ChainGroup>& groups, MmltBatch& mb);
// Proposal `iteration` of every chain of the batch: a large step with probability
// probLarge, else the lazy small step of each coordinate the proposal reads.
void mutateChains(const std::vector<ChainGroup>& groups, MmltBatch& mb, uint64_t seed, uint32_t iteration, float probLarge);
// Traces and connects each slot's strategy: bpt.L = its MIS-weighted contribution,
// (bpt.filmX, bpt.filmY) = the film point where it lands.
void evaluateProposals(const Scene& scene, MmltBatch& mb, float misBeta, RayCounters& counters);
// The contribution F = (k + 1) L of slot i and its target c (kernels/mmlt_target.h: the
// luminance of F, over its tile's brightness with the batch's map), 0 when it is not finite
// (evaluatedTarget counts those in mb.counters.nonfinite). PSSMLT: wholeTarget.
inline Vec3 contributionOf(const MmltBatch& mb, size_t i) { return mb.bpt.L[i] * float(mb.bpt.pathLength[i] + 1); }
inline float slotTarget(const MmltBatch& mb, size_t i, const Vec3& F) { return targetOf(F, mb.bpt.filmX[i], mb.bpt.filmY[i], mb.target); }
inline float evaluatedTarget(MmltBatch& mb, size_t i, Vec3& F) {
    F = contributionOf(mb, i);
    const float c = slotTarget(mb, i, F);
    if (c == 0.0f && !(isFinite(F) && std::isfinite(luminance(F)))) ++mb.counters.nonfinite;
    return c;
}
// Slots [0, n) of evaluated pool rows into pool (their keys, targets, F and film points).
void addPoolSamples(MmltBatch& mb, uint32_t n, SamplePool& pool);
// Accepts or rejects each slot's proposal (a = min(1, c'/c)), splats a F'/c' at the
// proposal's film point and (1 - a) F/c at the current one's (spread over the filter's
// footprint: MmltBatch::addSplat), both times the group's weight, to
// mb.splats, and commits accepted proposals. Large-step proposals join mb.pools.
void acceptAndSplat(const Scene& scene, std::vector<ChainGroup>& groups, MmltBatch& mb);
// Chain c of g takes slot i's accepted proposal: the coordinates it read (MMLT), then
// commitState. And the state alone: its count of accepted steps (and of its last large
// one), F, c and film point.
void commitProposal(ChainGroup& g, uint32_t c, const MmltBatch& mb, uint32_t i, bool large, const Vec3& F, float cP);
inline void commitState(ChainGroup& g, uint32_t c, bool large, const Vec3& F, float cP, float filmX, float filmY) {
    const uint32_t next = ++g.accepted[c];
    if (large) g.lastLarge[c] = next;
    g.F[c] = F;
    g.c[c] = cP;
    g.filmX[c] = filmX;
    g.filmY[c] = filmY;
}
// Delayed rejection's second stage (RenderOptions::delayedRejection; mmlt_delayed.cpp): the
// chains of mb.rejectedLarge propose a small step from where they are, with their own keys,
// accepted with the second stage's ratio; the lists are emptied.
void proposeAgain(const Scene& scene, std::vector<ChainGroup>& groups, MmltBatch& mb, uint64_t seed, uint32_t iteration, float misBeta,
                  RayCounters& counters);
// Replayed seeds (evaluated rows of fillSeedRows): how many differ from their chain's
// F, c or film point (an estimator bug); `plant` makes the first slot's differ (tests).
uint64_t countReplayMismatches(std::vector<ChainGroup>& groups, MmltBatch& mb, bool plant);

// One tracer's stages over a batch of chains, chosen once per render by the driver
// (MmltRender): MMLT's above (kMmltStages) or PSSMLT's whole-sample ones (kPssmltStages,
// pssmlt_stages.h). One call per stage and batch: no per-slot choice of the mode.
struct ChainStages {
    void (*fillPoolRows)(MmltBatch& mb, int k, uint32_t pass, uint32_t index0, uint32_t n, uint64_t seed);
    void (*fillSeedRows)(const std::vector<ChainGroup>& groups, MmltBatch& mb);
    void (*mutateChains)(const std::vector<ChainGroup>& groups, MmltBatch& mb, uint64_t seed, uint32_t iteration, float probLarge);
    void (*evaluateProposals)(const Scene& scene, MmltBatch& mb, float misBeta, RayCounters& counters);
    void (*addPoolSamples)(MmltBatch& mb, uint32_t n, SamplePool& pool);
    void (*acceptAndSplat)(const Scene& scene, std::vector<ChainGroup>& groups, MmltBatch& mb);
    uint64_t (*countReplayMismatches)(std::vector<ChainGroup>& groups, MmltBatch& mb, bool plant);
};
extern const ChainStages kMmltStages, kPssmltStages;
// Thins a pool to about `keep` entries, keeping each with probability min(1, w c / tau)
// (tau chosen for `keep` in expectation) and dividing its weight by that probability: an
// unbiased thinning (systematic: one comb over the entries, its offset from (seed, round)).
void thinPool(SamplePool& pool, size_t keep, uint64_t seed, uint32_t round);
// The weights of a pool's batches (large[b]: batch b's large steps of every length; the
// first `cross` are weighed against each other's predictions), mmlt_pool.cpp.
std::vector<double> poolWeights(const std::vector<PoolBatch>& batches, const std::vector<uint64_t>& large, size_t cross);
// Its tau: sum_i min(1, w_i c_i / tau) = keep over the pool's entries (more than keep).
double thinningThreshold(const std::vector<PoolEntry>& e, size_t keep);

}  // namespace wmlt
