// Bidirectional path tracing's wavefront stages, in the order a batch runs them:
//   generateBptCameraPaths -> [ intersect -> resolveBptHits -> groupByMaterial
//     -> sampleBptBsdfs -> advanceBptPaths ] per camera segment (walkBpt; intersect and
//     groupByMaterial are the wave's, wave.h),
//   generateBptLightPaths  -> the same rounds for the light subpaths,
//   connectBpt (s = 0 added directly; s = 1, t = 1 and s, t >= 2 as batched shadow rays,
//     flushed by traceBptConnections).
// The stages that read primary samples are templates on their source (bpt_state.h):
// HashedSamples for BPT, StoredSamples for MMLT's proposals, which run the same stages
// with one strategy per slot (per-slot walk lengths, generateChainCameraPaths,
// connectStrategies), WholeSamples for PSSMLT's, a whole BPT sample per slot
// (generateChainCameraPaths, connectBpt). Connections live in bpt_connect.cpp (the driver, the ends' BSDFs
// kind by kind, the shadow rays) and bpt_strategy.cpp (one strategy's set-up and weight);
// the MIS weights come from kernels/mis.h (bptMisWeight) on the per-vertex densities.
#pragma once
#include <cstdint>

#include "scene/scene.h"
#include "stages/bpt/bpt_state.h"
#include "stages/core/wave.h"

namespace wmlt {

// The key of BPT sample s of pixel: a stream apart from the PT's and LT's.
uint64_t bptSampleKey(uint64_t seed, uint32_t pixel, uint32_t sample);

// Solid-angle density with which the camera generates direction w from a lens point
// (uniform on the image plane: 1 / (A cos^3 theta)), for a direction known to pass
// inside the image (the camera rays of the walks; a t = 1 strategy's camera sample): the
// raster point is not computed again (its divisions were 3% of MMLT's time).
float cameraPdfOfRay(const Camera& c, Vec3 w);

// Writes slots (pixel, key, L = 0), camera vertex z_0 and one path per slot.
void generateBptCameraPaths(const Scene& scene, BptBatch& b, const Tile& tile, int strataPerAxis, uint64_t seed);
// MMLT and PSSMLT: camera vertex z_0 and the first path of each slot whose walk has room
// for more than z_0 (t >= 2), the raster point u(camera, 0-1) over the whole image (kept in
// filmX, filmY). Slots' cam.maxCount (t) and numSlots are set by the caller.
template <class U>
void generateChainCameraPaths(const Scene& scene, BptBatch& b, const U& u);
// Writes light vertex y_0 (Env for the environment: a point on the disc of LT's
// emission, lt_stages.h) and one path per slot with a usable emission sample.
template <class U>
void generateBptLightPaths(const Scene& scene, BptBatch& b, const U& u);
// Traces the live paths (closest hit).
// Reads paths; appends the vertex each hits to v (camera walk: an emitter without a
// material ends the path with a Light vertex, one with a material is a Surface vertex
// that keeps its light index for s = 0 and scatters on; an escape ends it with an Env
// vertex when the scene has an environment; light walk: emitters without a material
// absorb); writes hits for the paths that go on (the vertex is below v's capacity - 1).
void resolveBptHits(const Scene& scene, BptBatch& b, BptVertices& v, bool cameraWalk);
// Counting sort of the hits by material kind.
// Samples each hit's BSDF (mode: Radiance for the camera walk, Importance for the light
// walk); writes the previous vertex's pdfRev, the hit vertex's delta, next* and alive.
// d: the vertex's index in its subpath (random-number layout, roulette from d = 3).
template <class U>
void sampleBptBsdfs(const Scene& scene, BptBatch& b, BptVertices& v, bool cameraWalk, const U& u);
// (media) After intersect: each path's free-path sample in its medium up to its hit
// (a scattering event becomes a Medium vertex in resolveBptHits), pass-through boundaries
// crossed, the samples' densities kept for the vertex (bpt_media.cpp); the free-path
// numbers from u.
template <class U>
void traverseBptMedia(const Scene& scene, BptBatch& b, const BptVertices& v, bool cameraWalk, const U& u, RayCounters& c);
// (media, resolveBptHits) Path i's free-path densities at its new vertex cur: pdfFwd takes
// the walk's, rhoRev keeps the reverse one; and path i's scattering event as medium vertex
// cur after prev (bpt_media.cpp).
void takeSegmentDensities(const BptBatch& b, BptVertices& v, size_t i, size_t cur);
void recordBptMediumVertex(const Scene& scene, BptBatch& b, BptVertices& v, size_t i, size_t prev, size_t cur);
// (emitting media) Light that a camera walk's segment gathered, a contribution of length k
// to the slot's camera side (strategy s = 0, MIS weight 1).
void addVolumeEmission(BptBatch& b, uint32_t slot, Vec3 emitted, int k);
// Compacts the surviving hits into the next round's paths.
void advanceBptPaths(const Scene& scene, BptBatch& b, const BptVertices& v);
// The rounds of one walk (camera or light): intersect -> resolve -> group -> sample ->
// advance until no path is alive. coherentFirst: the first round's rays are camera rays
// in tile order.
template <class U>
void walkBpt(const Scene& scene, BptBatch& b, BptVertices& v, bool cameraWalk, bool coherentFirst, RayCounters& counters, const U& u);

// Working memory of weighStrategy, kept by its caller across calls.
struct StrategyScratch {
    float pL[kMaxPathLength + 2], pE[kMaxPathLength + 2];
    uint8_t delta[kMaxPathLength + 2];
};

// One strategy's sample of a slot's subpaths.
struct StrategySample {
    Vec3 value;                 // unweighted contribution, visibility not yet tested
    float weight = 0;           // its MIS weight
    bool infinite = false;      // the shadow ray ends at infinity (the environment)
    Vec3 from, nFrom, to, nTo;  // the shadow ray's ends (infinite: `to` is a direction; nTo = 0: not on a surface)
    float px = 0, py = 0;       // t = 1: the film point (raster coordinates) the path lands on
};

// Strategy (s, t) of slot's stored subpaths with the connection numbers of u, in three
// steps (bpt_strategy.cpp, bpt_connect.cpp):
// setUpStrategy appends it to w when it exists for these subpaths: the new endpoint (s =
// 1: a light point; t = 1: a lens point), the directions at its ends, the other factors
// of its contribution. False when the strategy cannot sample this path.
template <class U>
bool setUpStrategy(const Scene& scene, const BptBatch& b, uint32_t slot, int s, int t, const U& u, StrategyWave& w);
// cacheMisSums: after both walks, each subpath vertex's partial sum of the MIS ratios
// (kernels/mis.h), so that weighStrategy reads only the densities around a connection.
void cacheMisSums(const Scene& scene, BptBatch& b, float misBeta);
// evaluateStrategyBsdfs: f and both densities at every end of w's strategies, the ends
// grouped by material kind and each kind's kernels called at compile time.
void evaluateStrategyBsdfs(const BptBatch& b, StrategyWave& w);
// weighStrategy: strategy i's unweighted contribution and MIS weight, and its shadow
// ray's ends. False when it contributes nothing. A scene with media takes the connection's
// transmittance in the contribution and its free-path densities in the weight (bpt_media.cpp's
// stage made the walks'); with pass-through boundaries it traces the connection here (the
// contribution is then visible as it stands), else only its medium (the shadow ray decides).
bool weighStrategy(const Scene& scene, const BptBatch& b, const StrategyWave& w, size_t i, float misBeta, StrategyScratch& scratch,
                   StrategySample& out, RayCounters& counters);
// The shadow ray of a strategy sample between its ends (offset off their surfaces); false
// when they coincide.
bool connectionRay(const Scene& scene, const StrategySample& ss, RTCRay& r);
// Every strategy (s, t) with s + t - 1 in [minLength, maxLength], with the connection
// numbers of u (BPT: HashedSamples; PSSMLT: WholeSamples): s = 0 to L, the others to conns
// (flushed through traceBptConnections when full and at the end); t = 1 to the splats
// (b.splatsBySlot: to slotSplats, with their slots).
template <class U>
void connectBpt(const Scene& scene, BptBatch& b, const U& u, int minLength, int maxLength, float misBeta, RayCounters& c);
// MMLT: the one strategy (strategyS, pathLength) of each slot; L = its MIS-weighted
// contribution (0 when it cannot sample the path or is occluded), pixel = where it lands.
void connectStrategies(const Scene& scene, BptBatch& b, const StoredSamples& u, float misBeta, RayCounters& c);
// Traces the conns; adds the unoccluded ones to L (camera side) or splats (t = 1).
void traceBptConnections(const Scene& scene, BptBatch& b, RayCounters& c);

}  // namespace wmlt
