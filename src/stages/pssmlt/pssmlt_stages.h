// PSSMLT's stages (Kelemen et al. 2002 over bidirectional path tracing; --tracer pssmlt):
// MMLT's chains, pools, passes and rounds (mmlt_render.h, mmlt_stages.h) run one group of
// chains (ChainGroup::k = 0) whose every proposal is a whole BPT sample: the camera and light
// walks at the longest length (with BPT's roulette) and every strategy of every length,
// MIS-weighted (connectBpt on WholeSamples, which proposes each coordinate when it is first
// read). These are PSSMLT's stages of the driver (kPssmltStages, mmlt_stages.h, chosen
// once per render): fillWholePoolSlots, fillWholeSeedSlots and mutateWholeChains set each
// slot's proposal up, evaluateWholeProposals traces it, and MMLT's acceptance (its
// whole-sample instantiation) takes the target from wholeTarget, splats with splatWhole and
// commits with commitWhole. A sample's contributions: the camera side's sum L at its raster point
// (filmX, filmY) and each t = 1 strategy's at its own film point; its target c = the
// luminance of their sum.
#pragma once
#include <cstdint>
#include <vector>

#include "scene/scene.h"
#include "stages/core/wave.h"  // RayCounters
#include "stages/mmlt/mmlt_state.h"

namespace wmlt {

// Fresh samples [index0, index0 + n) of pass `pass` (a pool's).
void fillWholePoolSlots(MmltBatch& mb, uint32_t pass, uint32_t index0, uint32_t n, uint64_t seed);
// The seeded chains of the batch's slices, to be replayed as they are.
void fillWholeSeedSlots(const std::vector<ChainGroup>& groups, MmltBatch& mb);
// Proposal `iteration` of every chain of the batch: a large step with probability
// probLarge, else a small step, each coordinate made when it is read.
void mutateWholeChains(const std::vector<ChainGroup>& groups, MmltBatch& mb, uint64_t seed, uint32_t iteration, float probLarge);
// Traces both subpaths of every slot and connects every strategy of lengths
// [bpt.minLength, bpt.maxLength]: bpt.L and (bpt.filmX, bpt.filmY) the camera side, the
// t = 1 contributions in bpt.slotSplats by slot (splatStart).
void evaluateWholeProposals(const Scene& scene, MmltBatch& mb, float misBeta, RayCounters& counters);
// Slot i's target c = luminance of its whole contribution (0 when not finite, counted in
// mb.counters.nonfinite) and F = its camera side's.
float wholeTarget(MmltBatch& mb, uint32_t i, Vec3& F);
// The expected-value splats of slot i's proposal (accepted with probability a, its target
// cP) and of chain c's current state: a / cP and (1 - a) / c times the group's weight.
void splatWhole(const Scene& scene, const ChainGroup& g, uint32_t c, MmltBatch& mb, uint32_t i, float a, float cP);
// An accepted proposal `next` of chain c (slot i): the coordinates it read.
void commitWhole(ChainGroup& g, uint32_t c, const MmltBatch& mb, uint32_t i, uint32_t next);
// Keeps slot i's t = 1 contributions as chain c's (an accepted proposal, a replayed seed).
void keepWholePoints(ChainGroup& g, uint32_t c, const MmltBatch& mb, uint32_t i);
// Bytes of chain state per PSSMLT chain (paths up to maxLength).
uint64_t pssmltChainBytes(int maxLength, bool media, bool spectral);

}  // namespace wmlt
