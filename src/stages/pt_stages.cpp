#include "stages/pt_stages.h"

#include "kernels/rng.h"
#include "scene/scene_lights.h"
#include "stages/bsdf_dispatch.h"
#include "stages/surface.h"
#include "stages/trace.h"

namespace wmlt {

namespace {

inline Vec3 rayOrigin(const RTCRayHit& r) { return {r.ray.org_x, r.ray.org_y, r.ray.org_z}; }
// A contribution of path length `length`; NaN or Inf ones are counted and left out.
inline void addRadiance(PtBatch& b, uint32_t slot, Vec3 c, int length) {
    if (!isFinite(c)) { ++b.nonfinite; return; }
    b.L[slot] += c;
    b.lengths.add(length, c);
}

inline bool inRange(int length, int minLength, int maxLength) {
    return length >= minLength && length <= maxLength;
}

}  // namespace

void generateCameraRays(const Scene& scene, PtBatch& b, const PtTile& t, int n, uint64_t seed) {
    const Camera& cam = scene.camera;
    const bool lens = scene.features.depthOfField;
    size_t i = 0;
    for (int y = t.y0; y < t.y1; ++y)
        for (int x = t.x0; x < t.x1; ++x) {
            uint32_t pixel = uint32_t(y) * uint32_t(cam.width) + uint32_t(x);
            for (uint32_t s = t.sample0; s < t.sample1; ++s, ++i) {
                uint64_t key = sampleKey(seed, pixel, s);
                float px, py;
                stratifiedRasterPoint(x, y, s, n, strataKey(seed, pixel), sampleDimension(key, 0), sampleDimension(key, 1), px, py);
                float lu = lens ? sampleDimension(key, 2) : 0.5f;
                float lv = lens ? sampleDimension(key, 3) : 0.5f;
                Vec3 o, d;
                generateCameraRay(cam, px, py, lu, lv, o, d);
                b.pixel[i] = pixel;
                b.key[i] = key;
                b.L[i] = Vec3(0.0f);
                b.pathSlot[i] = uint32_t(i);
                setRayHit(b.ray[i], o, d);
                b.beta[i] = Vec3(1.0f);
                b.prevPdf[i] = 0;
                b.prevDelta[i] = 1;  // the camera vertex: what it sees directly has weight 1
            }
        }
    b.numPaths = i;
}

void intersectPaths(const Scene& scene, PtBatch& b, bool coherent, PtCounters& c) {
    traceClosest(scene.rtc, b.ray.data(), b.numPaths, coherent);
    c.raysIntersect += b.numPaths;
}

void resolveHits(const Scene& scene, PtBatch& b, int depth, int minLength, int maxLength) {
    const bool countEmission = inRange(depth, minLength, maxLength);
    size_t h = 0;
    for (size_t i = 0; i < b.numPaths; ++i) {
        const RTCRayHit& rh = b.ray[i];
        const uint32_t slot = b.pathSlot[i];
        const Vec3 d = rayDir(rh);
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
            if (countEmission && scene.envLight >= 0) {
                Vec3 Le = scene.env.Le(d);
                float w = b.prevDelta[i] ? 1.0f
                    : powerHeuristic(b.prevPdf[i], lightPdfFrom(scene, scene.envLight, rayOrigin(rh), Vec3(), d, Vec3()));
                addRadiance(b, slot, b.beta[i] * Le * w, depth);
            }
            continue;
        }
        SurfacePoint sp = surfaceAt(scene, rh);
        if (sp.light >= 0) {  // an emitter: without a material it absorbs and the path ends
            if (countEmission && dot(d, sp.ng) < 0) {
                float w = b.prevDelta[i] ? 1.0f
                    : powerHeuristic(b.prevPdf[i], lightPdfFrom(scene, sp.light, rayOrigin(rh), sp.p, d, sp.ng));
                addRadiance(b, slot, b.beta[i] * scene.lights[sp.light].L * w, depth);
            }
            if (sp.material < 0) continue;
        }
        if (depth >= maxLength) continue;  // no longer path can count
        recordHit(scene, b, h++, i, sp, -d);
    }
    b.numHits = h;
}

void groupByMaterial(PtBatch& b) {
    groupByMaterialKind(b.bsdf.data(), b.numHits, b.order.data(), b.kindStart);
}

void sampleLights(const Scene& scene, PtBatch& b, int depth) {
    size_t n = 0;
    forEachMaterialKind([&](auto kind) {
        using B = BsdfOf<decltype(kind)::value>;
        if constexpr (!B::delta) {
            for (uint32_t k = b.kindStart[int(kind.value)]; k < b.kindStart[int(kind.value) + 1]; ++k) {
                const uint32_t h = b.order[k];
                const uint32_t path = b.hitPath[h], slot = b.pathSlot[path];
                const uint64_t key = b.key[slot];
                float pmf;
                int li = scene.lightDistribution.sampleDiscrete(sampleDimension(key, bounceDim(depth, 0)), &pmf);
                LightSample ls;
                if (!sampleLightFrom(scene, li, b.p[h], sampleDimension(key, bounceDim(depth, 1)),
                                     sampleDimension(key, bounceDim(depth, 2)), ls))
                    continue;
                const Frame& fr = b.shading[h];
                Vec3 wo = fr.toLocal(b.wo[h]), wi = fr.toLocal(ls.wi);
                Vec3 f = B::f(b.bsdf[h], wo, wi) * absCosTheta(wi);
                if (isBlack(f) || isBlack(ls.Le)) continue;
                float lightPdf = ls.pdf * pmf;
                float w = ls.delta ? 1.0f : powerHeuristic(lightPdf, B::pdf(b.bsdf[h], wo, wi));
                // Aim from the offset origin at the light point itself: the direction from
                // the surface point would pass beside it by up to the offset, into the light.
                Vec3 origin = scene.offsetRayOrigin(b.p[h], b.ng[h], ls.wi);
                Vec3 dir = ls.wi;
                float tfar = INFINITY;
                if (!std::isinf(ls.dist)) {
                    Vec3 toLight = ls.p - origin;
                    float dist = length(toLight);
                    dir = toLight / dist;
                    tfar = dist * (1.0f - 1e-4f);
                }
                setRay(b.shadow[n], origin, dir, 0.0f, tfar);
                b.shadowSlot[n] = slot;
                b.shadowL[n] = b.beta[path] * f * ls.Le * (w / lightPdf);
                ++n;
            }
        }
    });
    b.numShadow = n;
}

void traceShadows(const Scene& scene, PtBatch& b, int length, PtCounters& c) {
    traceOccluded(scene.rtc, b.shadow.data(), b.numShadow);
    c.raysOccluded += b.numShadow;
    for (size_t i = 0; i < b.numShadow; ++i)
        if (b.shadow[i].tfar >= 0) addRadiance(b, b.shadowSlot[i], b.shadowL[i], length);
}

void sampleBsdfs(const Scene& scene, PtBatch& b, int depth) {
    // Russian roulette from the third bounce on: continue with probability
    // q = min(1, max(beta)) and divide by q (unbiased: E[beta / q * [u < q]] = beta).
    constexpr int kRouletteDepth = 3;
    forEachMaterialKind([&](auto kind) {
        using B = BsdfOf<decltype(kind)::value>;
        for (uint32_t k = b.kindStart[int(kind.value)]; k < b.kindStart[int(kind.value) + 1]; ++k) {
            const uint32_t h = b.order[k];
            const uint32_t path = b.hitPath[h];
            const uint64_t key = b.key[b.pathSlot[path]];
            b.alive[h] = 0;
            const Frame& fr = b.shading[h];
            Vec3 wo = fr.toLocal(b.wo[h]);
            BsdfSample s;
            if (!B::sample(b.bsdf[h], wo, sampleDimension(key, bounceDim(depth, 3)),
                           sampleDimension(key, bounceDim(depth, 4)), sampleDimension(key, bounceDim(depth, 5)),
                           TransportMode::Radiance, s))
                continue;
            if (!(s.pdf > 0) || isBlack(s.f)) continue;
            Vec3 beta = b.beta[path] * s.f * (absCosTheta(s.wi) / s.pdf);
            if (depth >= kRouletteDepth) {
                float q = std::min(1.0f, maxComponent(beta));
                if (!(sampleDimension(key, bounceDim(depth, 6)) < q)) continue;
                beta = beta / q;
            }
            b.alive[h] = 1;
            b.nextDir[h] = normalize(fr.toWorld(s.wi));
            b.nextBeta[h] = beta;
            b.nextPdf[h] = s.pdf;
            b.nextDelta[h] = s.delta ? 1 : 0;
        }
    });
}

void advancePaths(const Scene& scene, PtBatch& b) {
    size_t n = 0;
    for (size_t h = 0; h < b.numHits; ++h) {
        if (!b.alive[h]) continue;
        const uint32_t path = b.hitPath[h];  // path >= h >= n: compaction in place is safe
        b.pathSlot[n] = b.pathSlot[path];
        setRayHit(b.ray[n], scene.offsetRayOrigin(b.p[h], b.ng[h], b.nextDir[h]), b.nextDir[h]);
        b.beta[n] = b.nextBeta[h];
        b.prevPdf[n] = b.nextPdf[h];
        b.prevDelta[n] = b.nextDelta[h];
        ++n;
    }
    b.numPaths = n;
}

}  // namespace wmlt
