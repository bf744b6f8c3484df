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
// first[slot] + i (slot * capacity, or packed): position, geometric normal (lights: emitting side), shading frame
// (n = shading normal), material, throughput up to and including the vertex, area density
// from the subpath's own walk (pdfFwd) and if the other side's walk produced it (pdfRev),
// scattering by a delta lobe (mirror, glass), kind, for a Light its index into
// Scene::lights, and the partial sum of the MIS weights' ratios up to the vertex
// (kernels/mis.h, bptSubpathMisSum; written by cacheMisSums after the walks).
#define WMLT_BPT_VERTEX_ARRAYS(X)                                                            \
    X(Vec3, p) X(Vec3, ng) X(Frame, shading) X(BsdfParams, bsdf) X(Vec3, beta)             \
    X(float, pdfFwd) X(float, pdfRev) X(uint8_t, delta) X(BptVertexKind, kind) X(int16_t, light) \
    X(double, misSum)
// Scenes with a textured emitter (BatchNeeds::texturedEmitter): at an emitter vertex, T and
// the area density of light sampling there (camera walk: s = 0; y_0: emission's).
#define WMLT_BPT_EMITTER_ARRAYS(X) X(Vec3, emitTex) X(float, emitPdfA)
// Scenes with media (BatchNeeds::media; docs/media.md): the media on the vertex's +ng and
// -ng sides (a medium vertex, the camera: its medium on both), and the free-path density of
// the segment that reached it sampled the other way (ending at the previous vertex:
// SegmentDensities::rev), which its pdfRev-side densities take; pdfFwd has the walk's own.
#define WMLT_BPT_MEDIA_VERTEX_ARRAYS(X) X(int32_t, mediumFront) X(int32_t, mediumBack) X(float, rhoRev)

struct BptVertices {
    int capacity = 0;
    std::vector<uint8_t> count;      // per slot: vertices stored
    std::vector<uint8_t> maxCount;   // per slot: the walk stops at this many vertices (<= capacity)
    std::vector<uint32_t> first;     // per slot: the index of its vertex 0
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
        if (texturedEmitters) { WMLT_BPT_EMITTER_ARRAYS(WMLT_SOA_RESIZE) }
        if (media) { WMLT_BPT_MEDIA_VERTEX_ARRAYS(WMLT_SOA_RESIZE) }
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
// Per strategy: slot, s, t, the light (s <= 1), the unweighted contribution or the factors
// it is finished from once the ends' f are known (setUpStrategy), the new endpoint (s = 1,
// t >= 2: the light point and its normal, `infinite` for the environment; t = 1: the lens
// point) and the film point it lands on (t = 1; with a pinhole camera also the area density at
// x_{s-1} of the camera ray through it, from pinholeCameraSamples).
#define WMLT_STRATEGY_ARRAYS(X)                                                              \
    X(uint32_t, slot) X(uint8_t, s) X(uint8_t, t) X(int16_t, light) X(Vec3, value)          \
    X(float, scale) X(float, tail) X(Vec3, endP) X(Vec3, endN) X(float, endPdfA) X(uint8_t, infinite)       \
    X(float, filmX) X(float, filmY) X(float, cameraPdfArea)
// Per end (2 i: y = x_{s-1}, a light subpath vertex; 2 i + 1: z = x_s, a camera subpath
// vertex): the vertex (kNoEnd: strategy i has no surface there), f's directions and the
// densities' directions in its shading frame (wo on the camera side, wi on the light
// side; s = 1 and t = 1 sample f towards the new endpoint, which the densities reach from
// the stored positions), and the results: f(wo, wi), pdf(wo, wi) (the camera walk's),
// pdf(wi, wo) (the light walk's).
#define WMLT_STRATEGY_END_ARRAYS(X)                                                          \
    X(uint32_t, endVertex) X(Vec3, fWo) X(Vec3, fWi) X(Vec3, wo) X(Vec3, wi) X(Vec3, f)      \
    X(float, pdfCam) X(float, pdfLight)
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

// Per slot: pixel, random key, the camera-side radiance L (t >= 2: the pixel's own film),
// the light subpath's initial throughput scale (roulette), the density of its y_0 under
// next-event estimation from y_1 (cacheMisSums; the MIS weights of s >= 2); per live path
// (compacted with the wave): the throughput carried to the next vertex and the solid-angle
// density of the sampled direction and whether some bounce of its walk so far was not a
// delta lobe (pbrt-v4's anyNonSpecularBounces, each subpath its own: its later vertices take
// the regularized table, BptBatch::regularizedOffset); per hit: its material's kind, for the kind sort; per
// light subpath started (a scene whose one light is a rectangle): its slot, numbers and
// emission sample (generateBptLightPaths' flat loop; the first two numbers in sortedU1/U2,
// the direction in localX/Y/Z).
#define WMLT_BPT_ARRAYS(X)                                                                   \
    X(uint32_t, pixel) X(uint64_t, key) X(Vec3, L) X(float, betaScale) X(float, lightNee)  \
    X(Vec3, pathBeta) X(float, pathPdf) X(uint8_t, pathNonSpecular) X(MaterialKind, hitKind)
// Allocated only for a scene with media (docs/media.md): per path its medium, this round's
// free-path sample (traverseBptMedia: a scattering event and where) and its densities.
#define WMLT_BPT_MEDIA_ARRAYS(X)                                                             \
    X(int32_t, medium) X(uint8_t, mediumEvent) X(float, mediumT) X(float, rhoFwd) X(float, rhoRev)
// Allocated only for a scene whose one light is a rectangle (soleRectLight).
#define WMLT_BPT_RECT_LIGHT_ARRAYS(X)                                                        \
    X(uint32_t, emitSlot) X(float, emitU3) X(float, emitU4) X(Vec3, emitP) X(float, emitPdfDir) \
    X(uint8_t, emitOk)
// MMLT only (reserve's `oneStrategyPerSlot`): one strategy per slot, its s and path length k,
// and the film point its path lands on (filmX, filmY: raster coordinates).
#define WMLT_BPT_STRATEGY_ARRAYS(X) X(uint8_t, strategyS) X(uint8_t, pathLength) X(float, filmX) X(float, filmY)
// A pinhole camera's samples (allocated only for one) from the light vertices that t = 1
// strategies end at, for a chunk of kCameraSampleSlots slots at a time (sampleCameraFromLightVertices): per light
// vertex, its index j in the chunk's list (cameraSampleOf); per j, the vertex's position
// and normal (gathered), the sample (pinholeCameraSamples: direction, raster point, We,
// pdf, valid) and the reverse area density.
#define WMLT_BPT_CAMERA_SAMPLE_ARRAYS(X)                                                     \
    X(Vec3, csRef) X(Vec3, csRefN) X(Vec3, csWi) X(float, csPx) X(float, csPy) X(float, csWe) \
    X(float, csPdf) X(float, csPdfArea) X(uint32_t, csValid)
constexpr uint32_t kCameraSampleSlots = 256;

// Connection shadow rays (index c < numConn; flushed when full): the slot (t = 1: the
// raster pixel, or kFilmPoint and the film point (connX, connY) to spread it about), whether it is a t = 1 splat, its path length, unweighted unoccluded
// value, MIS weight and strategy's s (strategy images).
#define WMLT_BPT_CONN_ARRAYS(X)                                                              \
    X(RTCRay, conn) X(uint32_t, connSlot) X(float, connX) X(float, connY) X(uint8_t, connSplat)  \
    X(uint8_t, connLength) X(Vec3, connValue) X(float, connWeight) X(uint8_t, connS)

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
    std::vector<uint32_t> cameraSampleOf;  // per light vertex
    bool roulette = true;            // Russian roulette in the walks (MMLT: off, lengths are fixed)
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
    std::vector<Vec3> Lqueued;       // PSSMLT: the camera side's traced connections (addCameraSide)
    StrategyFilms* strategyFilms = nullptr;  // --strategy-images: camera side added directly
    std::vector<StrategySplat> strategySplats;  // t = 1, merged in tile order
    ContributionTally tally;

    // The optional arrays as the scene needs them (batchNeeds).
    void reserve(size_t n, int maxLength, const BatchNeeds& needs, bool oneStrategyPerSlot = false) {
        resizeWave(n, needs);
        WMLT_BPT_ARRAYS(WMLT_SOA_RESIZE)
        if (oneStrategyPerSlot) reserveStrategies(n);
        if (needs.rectLight) { WMLT_BPT_RECT_LIGHT_ARRAYS(WMLT_SOA_RESIZE) }
        if (needs.media) { WMLT_BPT_MEDIA_ARRAYS(WMLT_SOA_RESIZE) }
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
    // The per-slot strategy and film point (MMLT's; PSSMLT's film point).
    void reserveStrategies(size_t n) { WMLT_BPT_STRATEGY_ARRAYS(WMLT_SOA_RESIZE) }
};

// Primary sample layout of a BPT sample (keys: bptSampleKey, a stream apart from the PT's
// and LT's). Three interleaved streams: number j of stream c is dimension 3 j + c, so the
// light subpath reads the same dimensions whatever the camera subpath and the
// connections use (MMLT replays them with another t).
//   stream 0, camera subpath: j = 0-1 pixel jitter, 2-3 lens point, then camera vertex
//     d >= 1 (after d segments) reads j = 4 + 4 (d - 1) + (0: BSDF lobe, 1-2: BSDF
//     direction, 3: Russian roulette);
//   stream 1, light subpath: j = 0 light choice, 1-2 point on the light, 3-4 emitted
//     direction, then light vertex d >= 1 reads j = 5 + 4 (d - 1) + (0: lobe, 1-2:
//     direction, 3: roulette);
//   stream 2, connections: s = 1 at camera vertex z_{t-1} reads j = 5 t + (0: light
//     choice, 1-2: light point); t = 1 at light vertex y_{s-1} reads j = 5 s + 3 + (0-1:
//     lens point).
enum BptStream : uint32_t { kBptCamera = 0, kBptLight = 1, kBptConnect = 2 };
constexpr uint32_t bptDim(BptStream stream, uint32_t j) { return 3 * j + uint32_t(stream); }
inline uint32_t bptCamVertexJ(int d, uint32_t m) { return 4 + 4 * uint32_t(d - 1) + m; }
inline uint32_t bptLightVertexJ(int d, uint32_t m) { return 5 + 4 * uint32_t(d - 1) + m; }
inline uint32_t bptNeeJ(int t, uint32_t m) { return 5 * uint32_t(t) + m; }
inline uint32_t bptLensJ(int s, uint32_t m) { return 5 * uint32_t(s) + 3 + m; }

// Where a batch's primary samples come from: number j of stream c of slot i. Chosen once
// per tracer (the stages are templates on it), never per number.
// BPT: hashed from the slot's key at dimension 3 j + c (the layout above); every
// strategy reads its own connection numbers.
struct HashedSamples {
    const uint64_t* key;
    float operator()(uint32_t slot, BptStream c, uint32_t j) const {
        return sampleDimension(key[slot], bptDim(c, j));
    }
    static uint32_t connectJ(int s, int t, uint32_t m) { return s == 1 && t >= 2 ? bptNeeJ(t, m) : bptLensJ(s, m); }
};

// One strategy's primary sample vector u of a path of length k (MMLT's chains), stored
// as a row per slot: u[0] picks the strategy, then a block per stream holding its
// numbers j = 0, 1, ... in the layout above (so a change of t leaves the light
// subpath's numbers where they are), the connection's block holding the one
// connection's numbers (j = 0-2). Block sizes: the most any strategy of length k reads.
struct StrategyLayout {
    static uint32_t cameraSize(int k) { return 4 * uint32_t(k); }                   // t = k + 1
    static uint32_t lightSize(int k) { return std::max<uint32_t>(5, 4 * uint32_t(k) - 3); }  // s = k
    static constexpr uint32_t kConnectSize = 3;
    static uint32_t base(int k, BptStream c) {
        return c == kBptCamera ? 1 : c == kBptLight ? 1 + cameraSize(k) : 1 + cameraSize(k) + lightSize(k);
    }
    // Scenes with media: one more block, each walk segment's free-path number (the camera
    // walk's segment d = 1 .. t - 1 at j = d - 1, the light walk's d = 1 .. s - 1 at j = k + d - 1).
    static uint32_t mediaBase(int k) { return 1 + cameraSize(k) + lightSize(k) + kConnectSize; }
    static uint32_t mediaSize(int k) { return 2 * uint32_t(k); }
    static uint32_t size(int k, bool media) { return mediaBase(k) + (media ? mediaSize(k) : 0); }
    static uint32_t blockSize(int k, BptStream c) {
        return c == kBptCamera ? cameraSize(k) : c == kBptLight ? lightSize(k) : kConnectSize;
    }
    // The numbers strategy (s, t) reads from each block (a prefix of it).
    static uint32_t cameraUsed(int t) { return t >= 2 ? 4 * uint32_t(t) - 4 : 0; }
    static uint32_t lightUsed(int s, int t) { return s >= 2 ? 4 * uint32_t(s) - 3 : s == 1 && t == 1 ? 5 : 0; }
    static uint32_t connectUsed(int s, int t) { return (s == 1 && t >= 2) || t == 1 ? kConnectSize : 0; }
    static uint32_t cameraMediaUsed(int t) { return uint32_t(std::max(t - 1, 0)); }
    static uint32_t lightMediaUsed(int s) { return uint32_t(std::max(s - 1, 0)); }
};

struct StoredSamples {
    const float* u;      // slot i's row at u + row[i]
    const uint32_t* row;
    const uint8_t* length;  // slot i's path length k
    float operator()(uint32_t slot, BptStream c, uint32_t j) const {
        return u[row[slot] + StrategyLayout::base(length[slot], c) + j];
    }
    static uint32_t connectJ(int, int, uint32_t m) { return m; }
    // The free-path number of walk segment d (media block).
    float medium(uint32_t slot, BptStream c, int d) const {
        const int k = length[slot];
        return u[row[slot] + StrategyLayout::mediaBase(k) + (c == kBptCamera ? 0u : uint32_t(k)) + uint32_t(d - 1)];
    }
};

// PSSMLT's primary sample vector (Kelemen et al. 2002 over BPT): one whole BPT sample per
// chain, every strategy of every length up to k (the walks' longest: k + 1 camera vertices,
// k light vertices). Blocks of the camera stream (StrategyLayout::cameraSize(k): the raster
// point over the whole image at j = 0-1), the light stream (lightSize(k)), the connections
// (each strategy its own numbers, as BPT's: s = 1 at z_{t-1}, t <= k, reads j = 5 t + 0-2;
// t = 1 at y_{s-1}, s <= k, j = 5 s + 3-4) and, with media, the walks' free-path numbers
// (StrategyLayout's media block at length k).
struct WholeLayout {
    static uint32_t connectSize(int k) { return 5 * uint32_t(k) + 5; }
    static uint32_t base(int k, BptStream c) {
        return c == kBptCamera ? 0 : c == kBptLight ? StrategyLayout::cameraSize(k)
                                                    : StrategyLayout::cameraSize(k) + StrategyLayout::lightSize(k);
    }
    static uint32_t mediaBase(int k) { return base(k, kBptConnect) + connectSize(k); }
    static uint32_t size(int k, bool media) { return mediaBase(k) + (media ? StrategyLayout::mediaSize(k) : 0); }
};

// PSSMLT's proposals, each coordinate made when it is first read (Kelemen et al.'s lazy
// mutation, as pbrt's MLTSampler): a walk that ends early reads, proposes and commits
// none of the numbers of the vertices it did not reach (a whole sample has 132 coordinates
// at MaxPathLength 10, 834 at 64, of which a Cornell box sample reads 27; proposing all
// that the scene's walks could read made a Cornell box render 1.5 times as long: docs/pssmlt.md).
// Per slot: its proposal's kind, key, and its chain's coordinates (value, lastModified at
// chainAt, the chain's last large step and the proposal's number n, mutation.h). A chain's
// coordinate never written since its seed (lastModified 0) is its seed's,
// poolCoordinate(seed, d): seeding writes nothing. A read of coordinate d: a fresh proposal
// (a large step, a pool sample) poolCoordinate(key, d); a small step smallStepOf the
// chain's coordinate; a replay the chain's coordinate itself. The value is kept in
// proposed and flagged in read (slot * dims + d), and d listed in the slot's readList
// (readCount of them), so that a second read gives the same number and the commit (and
// the next evaluation's clearing of the flags) visits exactly the coordinates read.
enum class WholeProposal : uint8_t { Replay, SmallStep, Fresh };
struct WholeSamples {
    const WholeProposal* kind;
    const uint64_t *key, *seed;               // per slot: the proposal's key, its chain's seed
    const uint32_t *chainAt, *lastLarge, *n;  // per slot
    const float* value;                        // the chains' coordinates (ChainGroup::value, lastModified)
    const uint32_t* lastModified;
    float* proposed;                           // per slot and coordinate: the value read
    uint8_t* read;                             // per slot and coordinate: read yet
    uint16_t* readList;                        // per slot, dims of them: the coordinates read, in order
    uint16_t* readCount;                       // per slot
    uint32_t dims;
    int k;                                     // the longest path length
    uint32_t base[3] = {WholeLayout::base(k, kBptCamera), WholeLayout::base(k, kBptLight), WholeLayout::base(k, kBptConnect)};
    uint32_t mediaBase = WholeLayout::mediaBase(k);

    float coordinate(uint32_t slot, uint32_t d) const {
        const size_t at = size_t(slot) * dims + d;
        if (read[at]) return proposed[at];
        float v;
        if (kind[slot] == WholeProposal::Fresh) {
            v = poolCoordinate(key[slot], d);
        } else {
            const size_t c = size_t(chainAt[slot]) + d;
            const uint32_t lm = lastModified[c];
            v = lm == 0 ? poolCoordinate(seed[slot], d) : value[c];
            if (kind[slot] == WholeProposal::SmallStep) v = smallStepOf(key[slot], d, v, lm, lastLarge[slot], n[slot]);
        }
        read[at] = 1;
        proposed[at] = v;
        readList[at - d + readCount[slot]++] = uint16_t(d);
        return v;
    }
    float operator()(uint32_t slot, BptStream c, uint32_t j) const { return coordinate(slot, base[c] + j); }
    static uint32_t connectJ(int s, int t, uint32_t m) { return HashedSamples::connectJ(s, t, m); }
    float medium(uint32_t slot, BptStream c, int d) const {
        return coordinate(slot, mediaBase + (c == kBptCamera ? 0u : uint32_t(k)) + uint32_t(d - 1));
    }
};

}  // namespace wmlt
