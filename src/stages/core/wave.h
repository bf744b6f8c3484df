// The wavefront core that every tracer's walk is made of (docs/architecture.md, "The path
// wave"): a PathWave holds the live paths of one round (their slot and ray) and the
// surfaces they hit (path index, material order, survival, next direction); the stages
// below are the verbs a walk round is made of, written once:
//   forEachTileSample  - the samples of a tile, in a fixed order (camera rays, light paths);
//   forEachCameraRay   - a tile's camera rays: stratified raster point, lens point;
//   intersect          - closest hits for the live paths (Embree, trace.h);
//   groupByMaterial    - the hits sorted by material kind (one kernel per kind follows);
//   forEachHitByKind   - the hits of each kind, with the kind as a compile-time constant;
//   scatterHits        - BSDF sampling at every hit (PT, LT: the surface kept per hit);
//   compact            - the surviving paths moved to the front with their next rays.
// Each tracer's batch is a PathWave plus its own arrays; PT, LT and BPT differ in what a
// hit records and what a path carries, not in how a round is driven.
#pragma once
#include <embree3/rtcore.h>

#include <cstdint>
#include <vector>

#include "kernels/bsdf.h"
#include "kernels/camera.h"
#include "kernels/rng.h"
#include "scene/scene.h"
#include "scene/scene_lights.h"
#include "stages/core/bsdf_dispatch.h"
#include "stages/core/film.h"
#include "stages/core/soa.h"
#include "stages/core/textures.h"
#include "stages/core/trace.h"

namespace wmlt {

// What a scene needs of a batch's optional arrays, decided once per render (a batch
// allocates only those): its one light is a rectangle (BPT's light-sample flat loops), it
// has rectangle lights (PT's) or several lights (PT's light choice in a flat loop), it has
// matte surfaces (PT's matte flat loops), its camera is a pinhole (BPT's and MMLT's t = 1
// camera-sample loop), it has a textured emitter (BPT's emitter vertices keep T and pdfA),
// it has textures (the texture stage's queue, PathWave::textureJobs), it has media (PT's media arrays).
struct BatchNeeds {
    bool rectLight = false, matte = false, pinhole = false, texturedEmitter = false, rectLights = false, severalLights = false, textures = false,
         media = false;
    bool spectral = false;  // set by a tracer that renders spectrally (RenderOptions::spectral)
};
inline BatchNeeds batchNeeds(const Scene& scene) {
    return {soleRectLight(scene) != nullptr,
            scene.features.has(MaterialKind::Matte),
            isPinhole(scene.camera),
            scene.features.texturedEmitters,
            scene.anyRectLight,
            scene.lights.size() > 1,
            scene.features.textures,
            scene.features.media};
}

// A batch's work: pixels [x0, x1) x [y0, y1), sample indices [sample0, sample1).
struct Tile {
    int x0, y0, x1, y1;
    uint32_t sample0, sample1;
};

// Rays traced, for the throughput figures (--stats).
struct RayCounters {
    uint64_t raysIntersect = 0, raysOccluded = 0;
};

// The path wave's arrays. Per live path (index i < numPaths, compacted each round):
//   pathSlot: the slot (sample) the path belongs to
//   ray: its ray; after intersect also its hit (Embree's RTCRayHit)
// Per hit (index h < numHits, in path order):
//   hitPath: the path that made the hit
//   order: the hits in material order (groupByMaterial; kindStart bounds each kind)
//   alive: whether the path goes on after the hit
//   nextDir: the direction it goes on in
// Per hit in material order (index r of order), for the scatter stages' flat loops
// (scatterHits, sampleBptBsdfs); forEachCameraRay uses them as scratch too:
//   sortedKey: the slot's key
//   sortedU1, sortedU2: two of its numbers
//   localX, localY, localZ: a direction in the shading frame
// Per camera sample, before the first intersect (forEachCameraRay):
//   permKey: its strata permutation's key
//   permValue: its index in that permutation
//   walkKey: scratch of the permutations' walks (permuteWalks, rng.h)
//   filmWeight: the weight its pixel gives it: 1 with the box filter, else f / pdf
//     (kernels/filter.h, the density restricted to the film) times the pixel's normalisation
// clang-format off
#define WMLT_PATH_WAVE_ARRAYS(X)                                                              \
    X(uint32_t, pathSlot) X(RTCRayHit, ray) X(uint32_t, hitPath) X(uint32_t, order)         \
    X(uint8_t, alive) X(Vec3, nextDir) X(uint64_t, sortedKey) X(float, sortedU1) X(float, sortedU2)  \
    X(float, localX) X(float, localY) X(float, localZ) X(uint64_t, permKey) X(uint32_t, permValue)   \
    X(uint64_t, walkKey) X(float, filmWeight)
// clang-format on

struct PathWave {
    size_t numPaths = 0, numHits = 0;
    WMLT_PATH_WAVE_ARRAYS(WMLT_SOA_ARRAY)
    // Hits grouped by material kind: order[kindStart[k] .. kindStart[k + 1]).
    uint32_t kindStart[kMaterialKinds + 1] = {};
    TextureJobs textureJobs;  // the round's textured hits (textures.h); sized as needs.textures says

    void resizeWave(size_t n, const BatchNeeds& needs) {
        WMLT_PATH_WAVE_ARRAYS(WMLT_SOA_RESIZE)
        if (needs.textures) textureJobs.resize(n);
    }
};

// The surface a hit h found, for the tracers that keep it per hit (PT, LT; BPT keeps it in
// its subpaths' vertices), written by recordHit:
//   p: the hit's position
//   ng: its geometric normal (outward)
//   wo: the direction towards the previous vertex
//   shading: the shading frame (n = the shading normal)
//   bsdf: the material at the hit (its constants, then the texture stage's values)
#define WMLT_HIT_SURFACE_ARRAYS(X) X(Vec3, p) X(Vec3, ng) X(Vec3, wo) X(Frame, shading) X(BsdfParams, bsdf)

// Calls f(i, x, y, pixel, s) for the tile's samples in order: rows, pixels, then samples
// (i counts from 0); returns their number. The order is what makes a batch's sums the same
// for any threads.
template <class F>
inline size_t forEachTileSample(const Tile& t, int width, F&& f) {
    size_t i = 0;
    for (int y = t.y0; y < t.y1; ++y)
        for (int x = t.x0; x < t.x1; ++x) {
            const uint32_t pixel = uint32_t(y) * uint32_t(width) + uint32_t(x);
            for (uint32_t s = t.sample0; s < t.sample1; ++s, ++i) f(i, x, y, pixel, s);
        }
    return i;
}

// The dimensions of a sample's key that its camera ray reads: the jitter within its
// stratum and the lens point (read only with a thin lens).
struct CameraDims {
    uint32_t jitterX, jitterY, lensU, lensV;
};

// Calls emit(i, pixel, key, o, d) for the tile's samples in order (forEachTileSample),
// each with its key (keyOf(pixel, s)) and camera ray: raster point in stratum s of the
// pixel's n x n grid (camera.h, stratifiedRasterPoint), then the lens (pbrt-v4 5.2.3).
// Returns the number of samples. In passes over the wave's scratch arrays: the keys; the
// strata (the permutations' networks in flat loops, permuteWalks; each permutation's
// rotation made once per pixel and round); the directions in a flat loop
// (pinholeCameraDirections; a thin lens: per ray, in the last pass); the emits.
template <class KeyOf, class Emit>
inline size_t forEachCameraRay(const Scene& scene, PathWave& w, const Tile& t, int n, uint64_t seed, const CameraDims& dims, KeyOf&& keyOf,
                               Emit&& emit) {
    const Camera& cam = scene.camera;
    const uint32_t nn = uint32_t(n) * uint32_t(n);
    // The keys, and the strata permutation's key and index (stratifiedRasterPoint's).
    uint32_t lastPixel = ~0u;
    uint64_t pixelKey = 0;
    const size_t m = forEachTileSample(t, cam.width, [&](size_t i, int x, int y, uint32_t pixel, uint32_t s) {
        w.sortedKey[i] = keyOf(pixel, s);
        if (pixel != lastPixel) pixelKey = strataKey(seed, pixel);
        lastPixel = pixel;
        w.permKey[i] = mix64(pixelKey + s / nn);
        w.permValue[i] = s % nn;
        w.localX[i] = float(x);
        w.localY[i] = float(y);
    });
    permuteWalks(nn, w.permValue.data(), w.permKey.data(), m, w.order.data(), w.walkKey.data(), w.hitPath.data());
    // The strata: the walks' ends rotated (Permutation::rotate; made once per key).
    Permutation perm;
    for (size_t i = 0; i < m; ++i) {
        if (i == 0 || w.permKey[i] != perm.key) perm = Permutation(nn, w.permKey[i]);
        const uint32_t stratum = perm.rotate(w.permValue[i]);
        w.sortedU1[i] = float(stratum % uint32_t(n));
        w.sortedU2[i] = float(stratum / uint32_t(n));
    }
    const bool lens = cam.thinLens, filtered = !scene.filter.box, pinhole = isPinhole(cam);
    if (pinhole && !filtered)
        pinholeCameraDirections(cameraFloats(cam), w.sortedKey.data(), w.localX.data(), w.localY.data(), w.sortedU1.data(), w.sortedU2.data(), m,
                                float(n), dims.jitterX, dims.jitterY, &w.nextDir[0].x);
    forEachTileSample(t, cam.width, [&](size_t i, int x, int y, uint32_t pixel, uint32_t) {
        const uint64_t key = w.sortedKey[i];
        w.filmWeight[i] = 1.0f;
        if (pinhole && !filtered) {
            emit(i, pixel, key, cam.position, w.nextDir[i]);
            return;
        }
        float px, py;
        if (!filtered) {
            px = stratumPoint(w.localX[i], w.sortedU1[i], sampleDimension(key, dims.jitterX), float(n));
            py = stratumPoint(w.localY[i], w.sortedU2[i], sampleDimension(key, dims.jitterY), float(n));
        } else {  // filter importance sampling: the stratum's point through the filter's inverse cdf
            float dx, dy;
            const float ux = stratumPoint(0, w.sortedU1[i], sampleDimension(key, dims.jitterX), float(n));
            const float uy = stratumPoint(0, w.sortedU2[i], sampleDimension(key, dims.jitterY), float(n));
            const float wx = sampleFilterInFilm(scene.filter, ux, x, cam.width, dx);
            const float wy = sampleFilterInFilm(scene.filter, uy, y, cam.height, dy);
            px = (w.localX[i] + 0.5f) + dx;
            py = (w.localY[i] + 0.5f) + dy;
            w.filmWeight[i] = (wx * scene.filterNormX[size_t(x)]) * (wy * scene.filterNormY[size_t(y)]);
        }
        Vec3 o, d;
        generateCameraRay(cam, px, py, lens ? sampleDimension(key, dims.lensU) : 0.5f, lens ? sampleDimension(key, dims.lensV) : 0.5f, o, d);
        emit(i, pixel, key, o, d);
    });
    return m;
}

// Appends a light-side contribution v to `pixel`'s splats, or for pixel == kFilmPoint to
// the film points (px, py) (spread over the filter's footprint by addPointSplats).
inline void pushSplat(std::vector<Splat>& splats, std::vector<PointSplat>& points, uint32_t pixel, float px, float py, Vec3 v) {
    if (pixel != kFilmPoint) splats.push_back({pixel, v});
    else points.push_back({px, py, v});
}

// Adds film points [0, n) in order, each to every pixel whose filter footprint holds it,
// weighted (Scene::forEachFilmPixel).
inline void addPointSplats(const Scene& scene, SplatFilm& film, const PointSplat* s, size_t n) {
    for (size_t i = 0; i < n; ++i) scene.forEachFilmPixel(s[i].px, s[i].py, [&](uint32_t p, float w) { film.add({p, s[i].value * w}); });
}

// Path i of a new wave belongs to slot i and starts with the ray from o along d.
inline void startPath(PathWave& w, size_t i, Vec3 o, Vec3 d) {
    w.pathSlot[i] = uint32_t(i);
    setRayHit(w.ray[i], o, d);
}

// Closest hits of the live paths. `coherent`: camera rays in tile order (trace.h).
inline void intersect(const Scene& scene, PathWave& w, bool coherent, RayCounters& c) {
    traceClosest(scene.rtc, w.ray.data(), w.numPaths, coherent);
    c.raysIntersect += w.numPaths;
}

// Sorts the hits by material kind, stably: hit h's kind is hitBsdf[h].kind (PT, LT) or
// hitKind[h] (BPT, which keeps the materials in its vertices).
inline void groupByMaterial(PathWave& w, const BsdfParams* hitBsdf) {
    groupByMaterialKind([&](size_t h) { return hitBsdf[h].kind; }, w.numHits, w.order.data(), w.kindStart);
}
inline void groupByMaterial(PathWave& w, const MaterialKind* hitKind) {
    groupByMaterialKind([&](size_t h) { return hitKind[h]; }, w.numHits, w.order.data(), w.kindStart);
}

// Calls f(kind, h) for every hit, kind by kind (kind: std::integral_constant, so that
// BsdfOf<decltype(kind)::value> picks the kind's kernels at compile time).
template <class F>
inline void forEachHitByKind(const PathWave& w, F&& f) {
    forEachMaterialKind([&](auto kind) {
        for (uint32_t k = w.kindStart[int(kind.value)]; k < w.kindStart[int(kind.value) + 1]; ++k) f(kind, w.order[k]);
    });
}

// The scatter stage of the tracers that keep the surface per hit (PT, LT): samples each
// hit's BSDF, kind by kind, with the numbers dimOf(m) of its slot's key (m = 0: lobe, 1-2:
// direction) and calls f(h, path, slot, key, s) for a usable sample (pdf > 0, f not black;
// s in the hit's shading frame). alive[h] stays 0 unless f sets it.
// Matte hits draw their cosine-weighted directions first, all of the kind in one flat loop
// (sampleCosineHemispheres: the same numbers, vectorised); withMatte false leaves them to
// the caller (PT's matteScatter).
template <class Batch, class DimOf, class F>
inline void scatterHits(Batch& b, TransportMode mode, DimOf&& dimOf, F&& f, bool withMatte = true) {
    forEachMaterialKind([&](auto kind) {
        using B = BsdfOf<decltype(kind)::value>;
        constexpr bool matte = decltype(kind)::value == MaterialKind::Matte;
        const uint32_t r0 = b.kindStart[int(kind.value)], r1 = b.kindStart[int(kind.value) + 1];
        if constexpr (matte) {
            if (!withMatte || r0 == r1) return;  // (&v[r0] of a full wave would be past the end)
            for (uint32_t r = r0; r < r1; ++r) b.sortedKey[r] = b.key[b.pathSlot[b.hitPath[b.order[r]]]];
            sampleCosineHemispheres(&b.sortedKey[r0], r1 - r0, dimOf(1), dimOf(2), &b.localX[r0], &b.localY[r0], &b.localZ[r0]);
        }
        for (uint32_t r = r0; r < r1; ++r) {
            const uint32_t h = b.order[r], path = b.hitPath[h], slot = b.pathSlot[path];
            const uint64_t key = b.key[slot];
            b.alive[h] = 0;
            const Vec3 wo = b.shading[h].toLocal(b.wo[h]);
            BsdfSample s;
            bool sampled;
            if constexpr (matte) sampled = matteSampleFrom(b.bsdf[h], wo, Vec3(b.localX[r], b.localY[r], b.localZ[r]), s);
            else
                sampled = sampleBsdfOf<B>(
                    b.bsdf[h], wo, [&](uint32_t m) { return sampleDimension(key, dimOf(m)); }, mode, s);
            if (!sampled || !(s.pdf > 0) || isBlack(s.f)) continue;
            f(h, path, slot, key, s);
        }
    });
}

// The paths whose hit survived (alive[h]) move to the front, in order, each with a ray
// from its hit point (origin(h) gives position and geometric normal) along nextDir[h];
// carry(n, path, h) moves the tracer's own per-path data from index `path` to n.
// path >= h >= n, so moving in place is safe.
template <class Origin, class Carry>
inline void compact(const Scene& scene, PathWave& w, Origin&& origin, Carry&& carry) {
    size_t n = 0;
    for (size_t h = 0; h < w.numHits; ++h) {
        if (!w.alive[h]) continue;
        const uint32_t path = w.hitPath[h];
        Vec3 p, ng;
        origin(h, p, ng);
        w.pathSlot[n] = w.pathSlot[path];
        setRayHit(w.ray[n], scene.offsetRayOrigin(p, ng, w.nextDir[h]), w.nextDir[h]);
        carry(n, path, h);
        ++n;
    }
    w.numPaths = n;
}

}  // namespace wmlt
