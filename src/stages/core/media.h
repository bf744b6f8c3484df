// The media stages' shared parts (docs/media.md), for every tracer whose batch has the media
// arrays (a path's `medium`, `mediumEvent`, `mediumT`; PT's and LT's): the free-path samples
// of a round's rays up to their hits, crossing pass-through boundaries (traverseMediaOf), and
// the transmittance of a shadow or connection ray through media and pass-through boundaries
// (transmittanceAlong, media.cpp).
#pragma once
#include <embree3/rtcore.h>

#include <cstring>

#include "kernels/medium.h"
#include "kernels/rng.h"
#include "scene/scene.h"
#include "scene/scene_spectra.h"
#include "stages/core/trace.h"
#include "stages/core/wave.h"

namespace wmlt {

// Bounce d's free-path sample on its k-th segment (k counts the pass-through boundaries
// crossed, below kMediumStride) reads its own range of dimensions, apart from the bounces'
// (a scene without media reads the same numbers as before media existed).
constexpr uint32_t kMediumBase = 1u << 24, kMediumStride = 256;
inline uint32_t mediumDim(int depth, uint32_t k) { return kMediumBase + uint32_t(depth - 1) * kMediumStride + k; }

// The media as one path sees them: the scene's (Scene::media), or in a spectral render
// (spectra set) their coefficients at the path's wavelengths w (SpectralScene::medium). The
// stages read a medium through this, a copy per segment.
struct PathMedia {
    const Scene& scene;
    const SpectralScene* spectra = nullptr;
    const Wavelengths* w = nullptr;
    Medium operator[](int m) const {
        const Medium& rgb = scene.media[size_t(m)];
        return spectra ? spectra->medium(m, rgb, *w) : rgb;
    }
};
// Batch b's slot's media (its lambda: the slot's wavelengths, in a spectral render).
template <class Batch>
inline PathMedia pathMedia(const Scene& scene, const Batch& b, uint32_t slot) {
    return PathMedia{scene, b.spectra, b.spectra ? &b.lambda[slot] : nullptr};
}

// The medium a ray along d is in after crossing the surface rh hit, from medium m.
int mediumAcross(const Scene& scene, const RTCRayHit& rh, Vec3 d, int m);
// Moves rh's ray to start just past the surface it hit, up to tMax.
void continuePast(const Scene& scene, RTCRayHit& rh, float tMax);

// The densities of a ray's free-path samples up to where it stopped (BPT's MIS weights,
// freePathDensity): fwd, the walk's own (ending at its event or surface); rev, the same
// segments sampled the other way, ending at the ray's origin (prevInMedium: a medium vertex).
struct SegmentDensities {
    float fwd = 1, rev = 1;
};

// One ray's free-path sample in medium m up to its hit (beta times its weight): a
// scattering event (event, eventT along the ray as it ends) or the surface, crossing
// pass-through boundaries (m updated, the ray continued past them). numberOf(k, u, seed)
// gives segment k's number u and the seed of a grid's stream. With Densities, rho gets the
// sample's densities. With Emission, `emitted` gets what emitting media send back along the
// ray up to its hit (emissionAlong, whole segments, times beta before each: the expected
// value, whatever the free path then samples).
template <bool Densities, bool Emission, class NumberOf>
inline void traverseMediumOf(const Scene& scene, const PathMedia& media, RTCRayHit& rh, int& m, NumberOf&& numberOf, Vec3& beta, uint8_t& event,
                             float& eventT, bool prevInMedium, SegmentDensities& rho, Vec3& emitted, RayCounters& c) {
    event = 0;
    for (uint32_t k = 0;; ++k) {
        const bool hit = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
        if (m >= 0) {
            const Medium med = media[m];
            const Vec3 o(rh.ray.org_x, rh.ray.org_y, rh.ray.org_z), d(rh.ray.dir_x, rh.ray.dir_y, rh.ray.dir_z);
            float u;
            uint64_t seed;
            numberOf(k, u, seed);
            if constexpr (Emission) {
                if (med.emissive) {
                    MediumRng rng(mix64(seed ^ 0x454d4954ull));  // "EMIT": apart from the free path's stream
                    emitted = emitted + beta * emissionAlong(med, o, d, hit ? rh.ray.tfar : INFINITY, rng);
                }
            }
            const FreePath fp = sampleMediumFreePath(med, o, d, hit ? rh.ray.tfar : INFINITY, u, seed);
            beta = beta * fp.weight;
            if constexpr (Densities) {
                rho.fwd *= freePathDensity(med, fp.t, fp.scattered);
                rho.rev *= freePathDensity(med, fp.t, k == 0 && prevInMedium);
            }
            if (fp.scattered) {
                event = 1;
                eventT = fp.t;
                return;
            }
        }
        if (!hit || !scene.geoms[rh.hit.geomID].passThrough) return;
        if (k + 1 >= kMediumStride) {  // a ray through hundreds of boundaries: dropped
            beta = Vec3(0.0f);
            return;
        }
        const Vec3 d(rh.ray.dir_x, rh.ray.dir_y, rh.ray.dir_z);
        m = mediumAcross(scene, rh, d, m);
        continuePast(scene, rh, INFINITY);
        traceClosest(scene.rtc, &rh, 1, false);
        ++c.raysIntersect;
    }
}

// Segment k's number of a sample keyed `key` at dimension dim, and its grid stream's seed.
inline void hashedFreePathNumber(uint64_t key, uint32_t dim, float& u, uint64_t& seed) {
    u = sampleDimension(key, dim);
    seed = mix64(key ^ (uint64_t(dim) << 32));
}

// Each path's free-path sample in its medium up to its hit (traverseMediumOf), for a batch
// whose paths carry beta (PT's, LT's); bounce depth's numbers (mediumDim).
template <class Batch>
void traverseMediaOf(const Scene& scene, Batch& b, int depth, RayCounters& c) {
    SegmentDensities unused;
    Vec3 noEmission;
    for (size_t i = 0; i < b.numPaths; ++i) {
        int m = b.medium[i];
        const uint64_t key = b.key[b.pathSlot[i]];
        traverseMediumOf<false, false>(
            scene, pathMedia(scene, b, b.pathSlot[i]), b.ray[i], m,
            [&](uint32_t k, float& u, uint64_t& seed) { hashedFreePathNumber(key, mediumDim(depth, k), u, seed); }, b.beta[i], b.mediumEvent[i],
            b.mediumT[i], false, unused, noEmission, c);
        b.medium[i] = m;
    }
}

// Hit h of a batch with the hit-surface and media arrays (PT's, LT's): path i's scattering
// event in its medium, at mediumT along its ray: a Phase vertex (kernels/bsdf.h) with no
// normal (rays leave it without offset), its frame's z towards the previous vertex.
template <class Batch>
void recordMediumVertex(const Scene& scene, Batch& b, size_t h, size_t i) {
    const RTCRayHit& rh = b.ray[i];
    const Vec3 d = rayDir(rh);
    const int m = b.medium[i];
    b.hitPath[h] = uint32_t(i);
    b.p[h] = Vec3(rh.ray.org_x, rh.ray.org_y, rh.ray.org_z) + d * b.mediumT[i];
    b.ng[h] = Vec3(0.0f);
    b.wo[h] = -d;
    b.shading[h] = Frame::fromNormal(-d);
    b.bsdf[h] = BsdfParams{};
    b.bsdf[h].kind = MaterialKind::Phase;
    b.bsdf[h].eta = scene.media[size_t(m)].g;  // phaseG
    b.hitMediumIn[h] = b.hitMediumOut[h] = m;
}

// Without pass-through boundaries (SceneFeatures::passThrough) a shadow or connection ray
// that nothing blocks stays in medium m: its transmittance transmittanceAlong's, without
// tracing (the caller tests visibility with the batched occlusion rays), and with Densities
// its free-path densities.
template <bool Densities>
inline Vec3 transmittanceUnblocked(const PathMedia& media, const RTCRay& r, int m, uint64_t seed, bool fromInMedium, bool toInMedium,
                                   SegmentDensities& rho) {
    if (m < 0) return Vec3(1.0f);
    const Medium med = media[m];
    if constexpr (Densities) {
        rho.fwd *= freePathDensity(med, r.tfar, toInMedium);
        rho.rev *= freePathDensity(med, r.tfar, fromInMedium);
    }
    return mediumTransmittance(med, Vec3(r.org_x, r.org_y, r.org_z), Vec3(r.dir_x, r.dir_y, r.dir_z), r.tfar, mix64(seed));
}

// A seed from a ray's origin, direction and length (BPT's connections: a grid's ratio tracking
// along a path's connection is then a function of the path alone, as MMLT's replay needs).
inline uint64_t rayHash(const RTCRay& r) {
    const float f[7] = {r.org_x, r.org_y, r.org_z, r.dir_x, r.dir_y, r.dir_z, r.tfar};
    uint64_t h = 0x434f4e4eull;
    for (float x : f) {
        uint32_t bits;
        std::memcpy(&bits, &x, sizeof bits);
        h = mix64(h ^ bits);
    }
    return h;
}

// The transmittance along ray r (up to its tfar) from medium m through media and
// pass-through boundaries; 0 when any other surface is in the way. A grid's ratio tracking
// reads streams seeded by seed and the segment.
Vec3 transmittanceAlong(const Scene& scene, const PathMedia& media, const RTCRay& r, int m, uint64_t seed, RayCounters& c);
// The same, with the densities of free-path samples along the ray (BPT's connections):
// rho.fwd of a walk from r's origin that ends at its end (toInMedium: a medium vertex there),
// rho.rev of one from its end that ends at its origin (fromInMedium).
Vec3 transmittanceAlong(const Scene& scene, const PathMedia& media, const RTCRay& r, int m, uint64_t seed, bool fromInMedium, bool toInMedium,
                        SegmentDensities& rho, RayCounters& c);

}  // namespace wmlt
