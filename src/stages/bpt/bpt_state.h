// Structure-of-arrays state of one batch of bidirectional path-tracing samples (a tile of
// pixels times a range of sample indices: one camera subpath and one light subpath per
// pixel sample): a PathWave (wave.h: the live subpaths of the current walk round and their
// hits) and groups of arrays:
//   slots     - one per sample: pixel, random key, the camera-side radiance L (t >= 2);
//   vertices  - per slot, fixed-capacity arrays of the camera subpath's vertices z_0 ..
//               (capacity MaxPathLength + 1) and the light subpath's vertices y_0 ..
//               (capacity MaxPathLength), plain data at index first[slot] + i;
//   paths     - per live subpath: its throughput and direction density;
//   strategies - the strategies being connected, and their ends' BSDFs;
//   conns     - connection shadow rays (s = 1, t = 1, s, t >= 2) and their contributions;
//   splats    - t = 1 contributions, in stage order (film.h).
#pragma once
#include <embree3/rtcore.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "kernels/bsdf.h"
#include "kernels/chain_numbers.h"
#include "kernels/rng.h"
#include "scene/scene_spectra.h"
#include "stages/bpt/bpt_samples.h"  // the sample sources the stages are templates on
#include "stages/core/film.h"
#include "stages/core/strategy_films.h"
#include "stages/core/wave.h"

namespace wmlt {

// Env: a point of the environment at infinity (ng = minus the direction towards it; p on
// the line from the neighbouring vertex, so that directions to it are exact). Medium: a
// scattering event in a participating medium (ng = 0, the phase function as its BSDF,
// MaterialKind::Phase; densities in volume measure: no cosine).
enum class BptVertexKind : uint8_t { Camera, Light, Surface, Env, Medium };
// Whether a vertex's area density takes the cosine at it (surfaces and lights; the pinhole
// camera's convention and medium vertices: none).
inline bool hasCosine(BptVertexKind k) { return k != BptVertexKind::Camera && k != BptVertexKind::Medium; }

// The vertices of one kind of subpath for every slot of a batch, at index
// first[slot] + i (slot * capacity, or packed):
//   p: the position
//   ng: the geometric normal (lights: the emitting side)
//   shading: the shading frame (n = the shading normal)
//   bsdf: the material
//   beta: the throughput up to and including the vertex
//   pdfFwd: the area density from the subpath's own walk
//   pdfRev: the area density if the other side's walk produced it
//   delta: scattering here is by a delta lobe (mirror, glass)
//   kind: BptVertexKind
//   light: for a Light, its index into Scene::lights
//   misSum: the MIS weights' ratios summed up to the vertex (kernels/mis.h,
//     bptSubpathMisSum; written by cacheMisSums after the walks)
// clang-format off
#define WMLT_BPT_VERTEX_ARRAYS(X)                                                            \
    X(Vec3, p) X(Vec3, ng) X(Frame, shading) X(BsdfParams, bsdf) X(Vec3, beta)             \
    X(float, pdfFwd) X(float, pdfRev) X(uint8_t, delta) X(BptVertexKind, kind) X(int16_t, light) \
    X(double, misSum)
// clang-format on
// Scenes with a textured emitter (BatchNeeds::texturedEmitter); at an emitter vertex:
//   emitTex: the texture's value T there
//   emitPdfA: the area density of light sampling there (camera walk: s = 0; y_0: emission's)
#define WMLT_BPT_EMITTER_ARRAYS(X) X(Vec3, emitTex) X(float, emitPdfA)
// Scenes with media (BatchNeeds::media; docs/media.md):
//   mediumFront: the medium on the vertex's +ng side (a medium vertex, the camera: its medium)
//   mediumBack: the medium on its -ng side (likewise)
//   rhoRev: the free-path density of the segment that reached it, sampled the other way
//     (ending at the previous vertex: SegmentDensities::rev), which its pdfRev-side
//     densities take; pdfFwd has the walk's own
#define WMLT_BPT_MEDIA_VERTEX_ARRAYS(X) X(int32_t, mediumFront) X(int32_t, mediumBack) X(float, rhoRev)

struct BptVertices {
    int capacity = 0;
    std::vector<uint8_t> count;     // per slot: vertices stored
    std::vector<uint8_t> maxCount;  // per slot: the walk stops at this many vertices (<= capacity)
    std::vector<uint32_t> first;    // per slot: the index of its vertex 0
    WMLT_BPT_VERTEX_ARRAYS(WMLT_SOA_ARRAY)
    WMLT_BPT_EMITTER_ARRAYS(WMLT_SOA_ARRAY)
    WMLT_BPT_MEDIA_VERTEX_ARRAYS(WMLT_SOA_ARRAY)

    void reserve(size_t slots, int cap, bool emitters = false, bool withMedia = false) {
        texturedEmitters = emitters;
        media = withMedia;
        capacity = cap;
        count.assign(slots, 0);
        maxCount.assign(slots, uint8_t(cap));
        first.resize(slots);
        for (size_t i = 0; i < slots; ++i) first[i] = uint32_t(i * size_t(cap));
        resizeVertices(slots * size_t(cap));
    }
    bool texturedEmitters = false, media = false;
    void resizeVertices(size_t n) {
        WMLT_BPT_VERTEX_ARRAYS(WMLT_SOA_RESIZE)
        if (texturedEmitters) {
            WMLT_BPT_EMITTER_ARRAYS(WMLT_SOA_RESIZE)
        }
        if (media) {
            WMLT_BPT_MEDIA_VERTEX_ARRAYS(WMLT_SOA_RESIZE)
        }
    }
    // The medium a ray leaving vertex a along dir travels in.
    int mediumTowards(size_t a, Vec3 dir) const { return dot(dir, ng[a]) < 0 ? mediumBack[a] : mediumFront[a]; }
    // Slots whose walks stop early (MMLT's: maxCount is known before the walk) get only
    // their vertices, one after the other (at least one each), so that a batch's vertices
    // stay in cache instead of capacity apart.
    void pack(size_t slots) {
        uint32_t at = 0;
        for (size_t i = 0; i < slots; ++i) {
            first[i] = at;
            at += maxCount[i] > 0 ? maxCount[i] : 1;
        }
    }
    size_t at(uint32_t slot, int i) const { return size_t(first[slot]) + size_t(i); }
};

// The strategies being connected (bpt_connect.cpp), in the order the tracer lists them:
// set up (the new endpoint, the directions at the connection's ends), their ends' BSDFs
// evaluated kind by kind, then weighted and added or queued in that same order.
// Per strategy (setUpStrategy writes them):
//   slot: the slot whose subpaths it connects
//   s, t: its light and camera vertex counts
//   light: the light (s <= 1)
//   value: the unweighted contribution, or its part known before the ends' f
//   scale, tail: the factors it is finished from once the ends' f are known
//   endP, endN: the new endpoint and its normal (s = 1, t >= 2: the light point; t = 1:
//     the lens point)
//   endPdfA: the light point's area density (s = 1)
//   infinite: the endpoint is the environment's
//   filmX, filmY: the film point it lands on (t = 1)
//   cameraPdfArea: with a pinhole camera, the area density at x_{s-1} of the camera ray
//     through that point (pinholeCameraSamples)
// clang-format off
#define WMLT_STRATEGY_ARRAYS(X)                                                              \
    X(uint32_t, slot) X(uint8_t, s) X(uint8_t, t) X(int16_t, light) X(Vec3, value)          \
    X(float, scale) X(float, tail) X(Vec3, endP) X(Vec3, endN) X(float, endPdfA) X(uint8_t, infinite)       \
    X(float, filmX) X(float, filmY) X(float, cameraPdfArea)
// clang-format on
// Per end (2 i: y = x_{s-1}, a light subpath vertex; 2 i + 1: z = x_s, a camera subpath
// vertex), directions in the vertex's shading frame, wo on the camera side, wi on the light
// side (s = 1 and t = 1: f towards the new endpoint, the densities from the stored positions):
//   endVertex: the vertex (kNoEnd: strategy i has no surface there)
//   fWo, fWi: f's directions
//   wo, wi: the densities' directions
//   f: f(wo, wi)
//   pdfCam: pdf(wo, wi) (the camera walk's)
//   pdfLight: pdf(wi, wo) (the light walk's)
// clang-format off
#define WMLT_STRATEGY_END_ARRAYS(X)                                                          \
    X(uint32_t, endVertex) X(Vec3, fWo) X(Vec3, fWi) X(Vec3, wo) X(Vec3, wi) X(Vec3, f)      \
    X(float, pdfCam) X(float, pdfLight)
// clang-format on
constexpr uint32_t kNoEnd = UINT32_MAX;

struct StrategyWave {
    size_t n = 0, capacity = 0;
    WMLT_STRATEGY_ARRAYS(WMLT_SOA_ARRAY)
    WMLT_STRATEGY_END_ARRAYS(WMLT_SOA_ARRAY)
    std::vector<uint32_t> ends, order;  // the ends with a vertex; grouped by its kind
    uint32_t kindStart[kMaterialKinds + 1] = {};

    void reserve(size_t cap) {
        capacity = cap;
        size_t n = cap;
        WMLT_STRATEGY_ARRAYS(WMLT_SOA_RESIZE)
        n = 2 * cap;
        WMLT_STRATEGY_END_ARRAYS(WMLT_SOA_RESIZE)
        ends.resize(n);
        order.resize(n);
    }
};

// Per slot:
//   pixel: the sample's pixel
//   key: its random key (dimensions: bptDim, bpt_samples.h)
//   L: the camera-side radiance (t >= 2: the pixel's own film)
//   betaScale: the light subpath's initial throughput scale (roulette)
//   lightNee: the density of its y_0 under next-event estimation from y_1 (cacheMisSums;
//     the MIS weights of s >= 2)
// Per live path (compacted with the wave):
//   pathBeta: the throughput carried to the next vertex
//   pathPdf: the solid-angle density of the sampled direction
//   pathNonSpecular: some bounce of its walk so far was not a delta lobe (pbrt-v4's
//     anyNonSpecularBounces, each subpath its own: later vertices take the regularized
//     table, BptBatch::regularizedOffset)
// Per hit:
//   hitKind: its material's kind, for the kind sort
// clang-format off
#define WMLT_BPT_ARRAYS(X)                                                                   \
    X(uint32_t, pixel) X(uint64_t, key) X(Vec3, L) X(float, betaScale) X(float, lightNee)  \
    X(Vec3, pathBeta) X(float, pathPdf) X(uint8_t, pathNonSpecular) X(MaterialKind, hitKind)
// clang-format on
// Allocated only for a scene with media (docs/media.md); per path:
//   medium: its medium
//   mediumEvent: this round's free-path sample is a scattering event (traverseBptMedia)
//   mediumT: where
//   rhoFwd, rhoRev: the sample's free-path densities, forward and reverse
// clang-format off
#define WMLT_BPT_MEDIA_ARRAYS(X)                                                             \
    X(int32_t, medium) X(uint8_t, mediumEvent) X(float, mediumT) X(float, rhoFwd) X(float, rhoRev)
// clang-format on
// Allocated only for a scene whose one light is a rectangle (soleRectLight); per light
// subpath started, for generateBptLightPaths' flat loop (the first two numbers in
// sortedU1/U2, the direction in localX/Y/Z):
//   emitSlot: its slot
//   emitU3, emitU4: its direction's numbers
//   emitP: the emission sample's point
//   emitPdfDir: its direction's density
//   emitOk: the sample is valid
// clang-format off
#define WMLT_BPT_RECT_LIGHT_ARRAYS(X)                                                        \
    X(uint32_t, emitSlot) X(float, emitU3) X(float, emitU4) X(Vec3, emitP) X(float, emitPdfDir) \
    X(uint8_t, emitOk)
// clang-format on
// MMLT's (reserve's `oneStrategyPerSlot`) and PSSMLT's (its film point); per slot:
//   strategyS: the one strategy's s
//   pathLength: its path length k
//   filmX, filmY: the film point its path lands on (raster coordinates)
#define WMLT_BPT_STRATEGY_ARRAYS(X) X(uint8_t, strategyS) X(uint8_t, pathLength) X(float, filmX) X(float, filmY)
// A pinhole camera's samples (allocated only for one) from the light vertices that t = 1
// strategies end at, for a chunk of kCameraSampleSlots slots at a time
// (sampleCameraFromLightVertices; per light vertex, its index j in the chunk's list:
// cameraSampleOf). Per j:
//   csRef, csRefN: the vertex's position and normal (gathered)
//   csWi: the sample's direction (pinholeCameraSamples)
//   csPx, csPy: its raster point
//   csWe: its importance We
//   csPdf: its density
//   csPdfArea: the reverse area density at the vertex
//   csValid: the sample is valid
// clang-format off
#define WMLT_BPT_CAMERA_SAMPLE_ARRAYS(X)                                                     \
    X(Vec3, csRef) X(Vec3, csRefN) X(Vec3, csWi) X(float, csPx) X(float, csPy) X(float, csWe) \
    X(float, csPdf) X(float, csPdfArea) X(uint32_t, csValid)
// clang-format on
constexpr uint32_t kCameraSampleSlots = 256;

// Connection shadow rays (index c < numConn; flushed when full):
//   conn: the ray
//   connSlot: its slot (t = 1: the raster pixel, or kFilmPoint)
//   connX, connY: the film point to spread a kFilmPoint splat about
//   connSplat: it is a t = 1 splat
//   connLength: its path length
//   connValue: the unweighted unoccluded value
//   connWeight: the MIS weight
//   connS: the strategy's s (strategy images)
// clang-format off
#define WMLT_BPT_CONN_ARRAYS(X)                                                              \
    X(RTCRay, conn) X(uint32_t, connSlot) X(float, connX) X(float, connY) X(uint8_t, connSplat)  \
    X(uint8_t, connLength) X(Vec3, connValue) X(float, connWeight) X(uint8_t, connS)
// clang-format on

// Allocated only for a spectral render (RenderOptions::spectral; docs/spectral.md):
//   lambda: per slot, its wavelengths (the colour channels' meaning), shared by both
//     subpaths and every strategy of the slot
//   newSlot, newVertex, newMaterial: per new surface vertex of the walk's round (its slot,
//     vertex index and material, SceneDesc::materials), for the spectral stage after the
//     textures (resolveBptHits)
// clang-format off
#define WMLT_BPT_SPECTRAL_ARRAYS(X)                                                          \
    X(Wavelengths, lambda) X(uint32_t, newSlot) X(uint32_t, newVertex) X(int32_t, newMaterial)
// clang-format on

// A t = 1 contribution kept with its slot (PSSMLT: a sample's splats are its chain's).
struct SlotSplat {
    uint32_t slot;
    float px, py;
    Vec3 value;
};

struct BptBatch : PathWave {
    size_t numSlots = 0;
    WMLT_BPT_ARRAYS(WMLT_SOA_ARRAY)
    WMLT_BPT_STRATEGY_ARRAYS(WMLT_SOA_ARRAY)
    WMLT_BPT_RECT_LIGHT_ARRAYS(WMLT_SOA_ARRAY)
    WMLT_BPT_MEDIA_ARRAYS(WMLT_SOA_ARRAY)
    WMLT_BPT_CAMERA_SAMPLE_ARRAYS(WMLT_SOA_ARRAY)
    WMLT_BPT_SPECTRAL_ARRAYS(WMLT_SOA_ARRAY)
    const SpectralScene* spectra = nullptr;  // a spectral render's (chosen once per render); nullptr: RGB
    size_t numNew = 0;                       // spectral: the round's new surface vertices (newVertex)
    std::vector<uint32_t> cameraSampleOf;    // per light vertex
    bool roulette = true;                    // Russian roulette in the walks (MMLT: off, lengths are fixed)
    // pbrt's regularize, chosen once per render: Scene::regularizedOffset in BPT's batches
    // (renderBidirectional), the table a subpath's vertices take once pathNonSpecular; 0 in
    // MMLT's and PSSMLT's (it would bias their chains' target) and without regularize.
    uint32_t regularizedOffset = 0;
    int minLength = 1, maxLength = kMaxPathLength;  // BPT: the path lengths rendered (emitting media's, bpt_media.cpp)

    BptVertices cam, light;

    size_t numConn = 0, connCapacity = 0;
    WMLT_BPT_CONN_ARRAYS(WMLT_SOA_ARRAY)
    StrategyWave strategies;

    std::vector<Splat> splats;
    std::vector<PointSplat> points;  // filtered scenes: t = 1 contributions at film points
    bool splatsBySlot = false;       // PSSMLT: t = 1 contributions to slotSplats instead, in slot order
    std::vector<SlotSplat> slotSplats;
    std::vector<Vec3> Lqueued;                  // PSSMLT: the camera side's traced connections (addCameraSide)
    StrategyFilms* strategyFilms = nullptr;     // --strategy-images: camera side added directly
    std::vector<StrategySplat> strategySplats;  // t = 1, merged in tile order
    ContributionTally tally;

    // The optional arrays as the scene needs them (batchNeeds).
    void reserve(size_t n, int maxLength, const BatchNeeds& needs, bool oneStrategyPerSlot = false) {
        resizeWave(n, needs);
        WMLT_BPT_ARRAYS(WMLT_SOA_RESIZE)
        if (oneStrategyPerSlot) reserveStrategies(n);
        if (needs.rectLight) {
            WMLT_BPT_RECT_LIGHT_ARRAYS(WMLT_SOA_RESIZE)
        }
        if (needs.media) {
            WMLT_BPT_MEDIA_ARRAYS(WMLT_SOA_RESIZE)
        }
        if (needs.spectral) {
            WMLT_BPT_SPECTRAL_ARRAYS(WMLT_SOA_RESIZE)
        }
        cam.reserve(n, maxLength + 1, needs.texturedEmitter, needs.media);
        light.reserve(n, maxLength, needs.texturedEmitter, needs.media);
        if (needs.pinhole) {
            const size_t samples = std::min<size_t>(kCameraSampleSlots, std::max<size_t>(n, 1)) *
                                   (oneStrategyPerSlot ? 1 : size_t(maxLength));  // a chunk's light vertices
            {
                const size_t n = samples;
                WMLT_BPT_CAMERA_SAMPLE_ARRAYS(WMLT_SOA_RESIZE)
            }
            cameraSampleOf.resize(light.p.size());
        }
        connCapacity = std::max<size_t>(n * 4, 1024);
        resizeConnections(connCapacity);
        strategies.reserve(std::clamp<size_t>(n, 1, 1024));
        splats.reserve(n);
    }
    void resizeConnections(size_t n) { WMLT_BPT_CONN_ARRAYS(WMLT_SOA_RESIZE) }
    // Spectral: slot's new vertex cur (material m) takes its colours after the round's textures.
    void noteNewVertex(uint32_t slot, size_t cur, int m) {
        newSlot[numNew] = slot;
        newVertex[numNew] = uint32_t(cur);
        newMaterial[numNew++] = m;
    }
    // The per-slot strategy and film point (MMLT's; PSSMLT's film point).
    void reserveStrategies(size_t n) { WMLT_BPT_STRATEGY_ARRAYS(WMLT_SOA_RESIZE) }
};

}  // namespace wmlt
