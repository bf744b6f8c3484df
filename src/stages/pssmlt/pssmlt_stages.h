// PSSMLT's stages (Kelemen et al. 2002 over bidirectional path tracing; --tracer pssmlt):
// MMLT's chains, pools, passes and rounds (mmlt_render.h, mmlt_stages.h) run one group of
// chains (ChainGroup::k = 0) whose every proposal is a whole BPT sample: the camera and light
// walks at the longest length and every strategy of every length, MIS-weighted (connectBpt
// on WholeSamples). MMLT's stages take this mode per batch (MmltBatch::whole): mutateChains
// proposes the coordinates in wholeDims, evaluateProposals calls evaluateWholeProposals,
// acceptAndSplat takes the target from wholeTarget and splats with splatWhole. A sample's
// contributions: the camera side's sum L at its raster point (filmX, filmY) and each t = 1
// strategy's at its own film point; its target c = luminance of their sum.
#pragma once
#include <cstdint>

#include "scene/scene.h"
#include "stages/core/wave.h"  // RayCounters
#include "stages/mmlt/mmlt_state.h"

namespace wmlt {

// The coordinates d > 0 a whole sample of the scene reads, in order (MmltBatch::wholeDims;
// d = 0, the raster point's x, is always read): the raster point and the lens (a thin lens),
// numbers [vertexLo, vertexHi) of each walk vertex that samples a BSDF, the light's
// emission sample, every strategy's connection numbers and, with media, every walk
// segment's free-path number. After setNumbersRead.
void setWholeNumbersRead(MmltBatch& mb, bool media);
// Both walks to their longest (every slot's); the path length maxLength.
void setWholeSample(MmltBatch& mb, uint32_t i);
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
// Keeps slot i's t = 1 contributions as chain c's (an accepted proposal, a replayed seed).
void keepWholePoints(ChainGroup& g, uint32_t c, const MmltBatch& mb, uint32_t i);
// Bytes of chain state per PSSMLT chain (paths up to maxLength).
uint64_t pssmltChainBytes(int maxLength, bool media);

}  // namespace wmlt
