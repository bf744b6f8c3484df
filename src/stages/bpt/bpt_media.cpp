// BPT's media stage (docs/media.md), run only for a scene with media or pass-through
// boundaries: after each intersect of a walk, every path's free-path sample in its medium
// (media.h, traverseMediumOf) with the densities the MIS weights take (SegmentDensities).
// Connections carry their transmittance in weighStrategy (bpt_strategy.cpp).
#include "stages/bpt/bpt_stages.h"
#include "stages/core/media.h"

namespace wmlt {

void traverseBptMedia(const Scene& scene, BptBatch& b, const BptVertices& v, bool cameraWalk, RayCounters& c) {
    const BptStream stream = cameraWalk ? kBptCamera : kBptLight;
    for (size_t i = 0; i < b.numPaths; ++i) {
        const uint32_t slot = b.pathSlot[i];
        const int d = v.count[slot];  // the index of the vertex this segment reaches
        const bool prevInMedium = v.kind[v.at(slot, d - 1)] == BptVertexKind::Medium;
        int m = b.medium[i];
        SegmentDensities rho;
        traverseMediumOf<true>(
            scene, b.ray[i], m, b.key[slot], [&](uint32_t k) { return bptDim(stream, mediumDim(d, k)); }, b.pathBeta[i],
            b.mediumEvent[i], b.mediumT[i], prevInMedium, rho, c);
        b.medium[i] = m;
        b.rhoFwd[i] = rho.fwd;
        b.rhoRev[i] = rho.rev;
    }
}

}  // namespace wmlt
