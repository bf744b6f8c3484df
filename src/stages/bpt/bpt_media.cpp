// BPT's media stage (docs/media.md), run only for a scene with media or pass-through
// boundaries: after each intersect of a walk, every path's free-path sample in its medium
// (media.h, traverseMediumOf) with the densities the MIS weights take (SegmentDensities).
// Connections carry their transmittance in weighStrategy (bpt_strategy.cpp).
#include "stages/bpt/bpt_stages.h"
#include "stages/core/media.h"

namespace wmlt {

namespace {

// Segment k (the boundaries crossed) of walk segment d's free-path number and its grid
// stream's seed. BPT: hashed from the slot's key (dimension mediumDim(d, k) of the walk's
// stream). MMLT and PSSMLT: the proposal's number for the segment (the rows' media block),
// the segments past pass-through boundaries and the stream hashed from it, so that a
// replay of the same numbers traces the same path.
inline void freePathNumber(const HashedSamples& u, uint32_t slot, BptStream stream, int d, uint32_t k, float& x, uint64_t& seed) {
    hashedFreePathNumber(u.key[slot], bptDim(stream, mediumDim(d, k)), x, seed);
}
template <class U>
inline void freePathNumber(const U& u, uint32_t slot, BptStream stream, int d, uint32_t k, float& x, uint64_t& seed) {
    const float x0 = u.medium(slot, stream, d);
    uint32_t bits;
    std::memcpy(&bits, &x0, sizeof bits);
    const uint64_t h = mix64(uint64_t(bits) ^ (uint64_t(d) << 32) ^ (uint64_t(stream) << 48));
    x = k == 0 ? x0 : sampleDimension(h, k);
    seed = mix64(h + k);
}

// Whether the camera walk's segment d of slot gathers emitting media's light: BPT and
// PSSMLT, a path length rendered; MMLT, the strategy s = 0 of its length (the camera walk alone finds
// that light: it is weighed against no other strategy).
inline bool gathersEmission(const HashedSamples&, const BptBatch& b, uint32_t, int d) { return d >= b.minLength && d <= b.maxLength; }
inline bool gathersEmission(const WholeSamples&, const BptBatch& b, uint32_t, int d) { return d >= b.minLength && d <= b.maxLength; }
inline bool gathersEmission(const StoredSamples&, const BptBatch& b, uint32_t slot, int d) {
    return b.strategyS[slot] == 0 && d == b.pathLength[slot];
}

template <bool Emission, class U>
void traverseBptMediaOf(const Scene& scene, BptBatch& b, const BptVertices& v, bool cameraWalk, const U& u, RayCounters& c) {
    const BptStream stream = cameraWalk ? kBptCamera : kBptLight;
    for (size_t i = 0; i < b.numPaths; ++i) {
        const uint32_t slot = b.pathSlot[i];
        const int d = v.count[slot];  // the index of the vertex this segment reaches
        const bool prevInMedium = v.kind[v.at(slot, d - 1)] == BptVertexKind::Medium;
        int m = b.medium[i];
        SegmentDensities rho;
        Vec3 emitted(0.0f);
        traverseMediumOf<true, Emission>(
            scene, pathMedia(scene, b, slot), b.ray[i], m,
            [&](uint32_t k, float& x, uint64_t& seed) { freePathNumber(u, slot, stream, d, k, x, seed); }, b.pathBeta[i], b.mediumEvent[i],
            b.mediumT[i], prevInMedium, rho, emitted, c);
        b.medium[i] = m;
        b.rhoFwd[i] = rho.fwd;
        b.rhoRev[i] = rho.rev;
        if constexpr (Emission)
            if (!isBlack(emitted) && gathersEmission(u, b, slot, d)) addVolumeEmission(b, slot, emitted, d);
    }
}

}  // namespace

// (media) Path i's free-path densities at its new vertex cur: pdfFwd takes the walk's, rhoRev
// keeps the reverse one for the densities towards the previous vertex.
void takeSegmentDensities(const BptBatch& b, BptVertices& v, size_t i, size_t cur) {
    v.pdfFwd[cur] *= b.rhoFwd[i];
    v.rhoRev[cur] = b.rhoRev[i];
}

// Path i's scattering event in its medium (traverseBptMedia), at mediumT along its ray:
// medium vertex cur (a Phase BSDF in a frame whose z is wo).
void recordBptMediumVertex(const Scene& scene, BptBatch& b, BptVertices& v, size_t i, size_t prev, size_t cur) {
    const RTCRayHit& rh = b.ray[i];
    const Vec3 d = rayDir(rh);
    const int m = b.medium[i];
    v.p[cur] = Vec3(rh.ray.org_x, rh.ray.org_y, rh.ray.org_z) + d * b.mediumT[i];
    v.ng[cur] = Vec3(0.0f);
    v.shading[cur] = Frame::fromNormal(-d);
    v.bsdf[cur] = BsdfParams{};
    v.bsdf[cur].kind = MaterialKind::Phase;
    v.bsdf[cur].eta = scene.media[size_t(m)].g;  // phaseG
    v.beta[cur] = b.pathBeta[i];
    // volume density: the solid angle's over r^2 (from the environment's disc or an
    // orthographic film: their area density along the ray), times the free path's
    const bool projected = v.kind[prev] == BptVertexKind::Env || (scene.camera.ortho && v.kind[prev] == BptVertexKind::Camera);
    v.pdfFwd[cur] = projected ? b.pathPdf[i] : solidAngleToArea(b.pathPdf[i], v.p[prev], v.p[cur], Vec3(0.0f), false);
    takeSegmentDensities(b, v, i, cur);
    v.pdfRev[cur] = 0.0f;
    v.delta[cur] = 0;
    v.kind[cur] = BptVertexKind::Medium;
    v.light[cur] = -1;
    v.mediumFront[cur] = v.mediumBack[cur] = m;
}

template <class U>
void traverseBptMedia(const Scene& scene, BptBatch& b, const BptVertices& v, bool cameraWalk, const U& u, RayCounters& c) {
    if (cameraWalk && scene.features.emissiveMedia) traverseBptMediaOf<true>(scene, b, v, cameraWalk, u, c);
    else traverseBptMediaOf<false>(scene, b, v, cameraWalk, u, c);
}
template void traverseBptMedia(const Scene&, BptBatch&, const BptVertices&, bool, const HashedSamples&, RayCounters&);
template void traverseBptMedia(const Scene&, BptBatch&, const BptVertices&, bool, const StoredSamples&, RayCounters&);
template void traverseBptMedia(const Scene&, BptBatch&, const BptVertices&, bool, const WholeSamples&, RayCounters&);

}  // namespace wmlt
