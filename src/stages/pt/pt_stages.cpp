// The path tracer's stages (pt_stages.h): camera rays, hits resolved into surfaces (with
// pbrt's regularize: the regularized materials after a path's first non-specular bounce),
// next-event estimation, BSDF sampling and the compaction of the surviving paths.
#include "stages/pt/pt_stages.h"

#include "kernels/nee.h"
#include "kernels/rng.h"
#include "kernels/sampling.h"
#include "kernels/scatter.h"
#include "scene/scene_lights.h"
#include "stages/core/bsdf_dispatch.h"
#include "stages/core/media.h"
#include "stages/core/surface.h"
#include "stages/core/trace.h"
#include "stages/core/wave.h"

namespace wmlt {

namespace {

inline Vec3 rayOrigin(const RTCRayHit& r) { return {r.ray.org_x, r.ray.org_y, r.ray.org_z}; }

inline bool inRange(int length, int minLength, int maxLength) { return length >= minLength && length <= maxLength; }

}  // namespace

void generateCameraRays(const Scene& scene, PtBatch& b, const Tile& t, int n, uint64_t seed) {
    const bool media = scene.features.media;
    const CameraDims dims{0, 1, 2, 3};
    b.numPaths = forEachCameraRay(
        scene, b, t, n, seed, dims, [&](uint32_t pixel, uint32_t s) { return sampleKey(seed, pixel, s); },
        [&](size_t i, uint32_t pixel, uint64_t key, Vec3 o, Vec3 d) {
            b.pixel[i] = pixel;
            b.key[i] = key;
            b.L[i] = Vec3(0.0f);
            if (b.spectra) b.lambda[i] = sampleWavelengths(sampleDimension(key, kWavelengthDim));
            startPath(b, i, o, d);
            b.beta[i] = Vec3(1.0f);
            b.prevPdf[i] = 0;
            b.prevDelta[i] = 1;  // the camera vertex: what it sees directly has weight 1
            b.anyNonSpecular[i] = 0;
            if (media) {
                b.medium[i] = scene.cameraMedium;
                b.vertexP[i] = o;
            }
        });
}

namespace {

// Hit h: path i's scattering event in its medium (media.h, recordMediumVertex), with PT's
// own per-hit arrays.
void recordPtMediumVertex(const Scene& scene, PtBatch& b, size_t h, size_t i, Vec3 d, bool matte) {
    recordMediumVertex(scene, b, h, i);
    b.hitKey[h] = b.key[b.pathSlot[i]];
    if (matte) {  // the matte flat loops run over every hit: harmless values
        b.hitNs[h] = -d;
        b.hitKd[h] = Vec3(0.0f);
        b.hitBeta[h] = b.beta[i];
    }
}

// The stage for the scene's surface features F (surface.h, withSurfaceFeatures).
template <class F>
void resolveHitsOf(const Scene& scene, PtBatch& b, int depth, int minLength, int maxLength) {
    const bool countEmission = inRange(depth, minLength, maxLength);
    const bool matte = scene.features.has(MaterialKind::Matte);  // the matte flat loops' inputs
    const bool media = scene.features.media;
    size_t h = 0;
    for (size_t i = 0; i < b.numPaths; ++i) {
        const RTCRayHit& rh = b.ray[i];
        prefetchSurfaceAhead(scene, b.ray.data(), i, b.numPaths);
        const uint32_t slot = b.pathSlot[i];
        const Vec3 d = rayDir(rh);
        if (media && b.mediumEvent[i]) {
            if (depth < maxLength) {
                if (b.spectra) b.hitMaterial[h] = -1;  // (no material for the spectral stage to colour)
                recordPtMediumVertex(scene, b, h++, i, d, matte);
            }
            continue;
        }
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
            if (countEmission && scene.envLight >= 0) {
                Vec3 Le = scene.env.Le(d);
                if (b.spectra) Le = b.spectra->emission(scene.envLight, Le, b.lambda[slot]);
                float w = b.prevDelta[i] ? 1.0f : powerHeuristic(b.prevPdf[i], lightPdfFrom(scene, scene.envLight, rayOrigin(rh), Vec3(), d, Vec3()));
                addRadiance(b, slot, b.beta[i] * Le * w, depth);
            }
            continue;
        }
        SurfacePoint sp = surfaceAt<F>(scene, rh);
        if (sp.light >= 0) {  // an emitter: without a material it absorbs and the path ends
            if (countEmission && emitsTowards(scene.lights[sp.light], sp.ng, -d)) {
                Vec3 tex;
                float pdfA = -1;
                const bool textured = scene.features.texturedEmitters && texturedEmitterHit(scene, sp.light, rh, sp.p, tex, pdfA);
                // (after pass-through boundaries the ray starts at the last one: the
                // density is the vertex's)
                const Vec3 ref = media ? b.vertexP[i] : rayOrigin(rh);
                float w = b.prevDelta[i] ? 1.0f : powerHeuristic(b.prevPdf[i], lightPdfFrom(scene, sp.light, ref, sp.p, d, sp.ng, pdfA));
                Vec3 Le = textured ? scene.lights[sp.light].L * tex : scene.lights[sp.light].L;
                if (b.spectra) Le = b.spectra->emission(sp.light, Le, b.lambda[slot]);
                addRadiance(b, slot, b.beta[i] * Le * w, depth);
            }
            if (sp.material < 0) continue;
        }
        if (depth >= maxLength) continue;  // no longer path can count
        recordHit<F>(scene, b, h, i, sp, -d, b.anyNonSpecular[i] ? b.regularizedOffset : 0);
        b.hitKey[h] = b.key[slot];
        if (b.spectra) b.hitMaterial[h] = sp.material;
        if (media) {
            const GeomRecord& g = scene.geoms[rh.hit.geomID];
            b.hitMediumIn[h] = g.mediumBoundary ? g.mediumInside : b.medium[i];
            b.hitMediumOut[h] = g.mediumBoundary ? g.mediumOutside : b.medium[i];
        }
        if (matte) {
            b.hitNs[h] = sp.ns;
            b.hitKd[h] = b.bsdf[h].diffuse;
            b.hitBeta[h] = b.beta[i];
        }
        ++h;
    }
    b.numHits = h;
    if constexpr (F::textures) {
        evaluateTextures(scene, b.textureJobs);
        if (matte)  // the matte flat loops' Kd, textured now
            for (size_t k = 0; k < h; ++k) b.hitKd[k] = b.bsdf[k].diffuse;
    }
    if (b.spectra) {  // the spectral stage: every hit's colours at its path's wavelengths
        for (size_t k = 0; k < h; ++k) {
            const int m = b.hitMaterial[k];
            if (m < 0) continue;  // a medium vertex (its coefficients at w: PathMedia, per segment)
            Wavelengths& w = b.lambda[b.pathSlot[b.hitPath[k]]];
            if (b.spectra->colours(m, scene.desc.materials[size_t(m)], b.bsdf[k], w)) terminateSecondary(w);
            if (matte) b.hitKd[k] = b.bsdf[k].diffuse;
        }
    }
}

}  // namespace

void resolveHits(const Scene& scene, PtBatch& b, int depth, int minLength, int maxLength) {
    withSurfaceFeatures(scene.features, [&](auto f) { resolveHitsOf<decltype(f)>(scene, b, depth, minLength, maxLength); });
}

namespace {

// A scene of several lights: every hit's light choice (bounce dimension 0) in one flat loop
// (Distribution1D::sampleDiscrete: a scene's few lights are chosen without branches).
void chooseLights(const Scene& scene, PtBatch& b, int depth) {
    const uint32_t d0 = bounceDim(depth, 0);
    for (size_t h = 0; h < b.numHits; ++h)
        b.neeLight[h] = uint32_t(scene.lightDistribution.sampleDiscrete(sampleDimension(b.hitKey[h], d0), &b.neePmf[h]));
}

// A scene with rectangle lights (Scene::anyRectLight): every hit's light point's two
// numbers, then its rectangle sample, in flat loops the compiler vectorises
// (rectLightSamples on a scene's one light, rectLightSamplesOf on each hit's own, chosen by
// chooseLights: a hit whose light is no rectangle fails there and sampleLights gives it
// the per-hit path); and for a scene with matte surfaces (matte) the shadow rays and
// contributions of every hit (matteNeeValuesOf, shadowRaysTo), of which sampleLights reads
// the matte hits' that chose a rectangle.
void sampleRectLightsFlat(const Scene& scene, PtBatch& b, int depth, bool matte) {
    const size_t n = b.numHits;
    const bool one = scene.lights.size() == 1;
    const uint32_t d1 = bounceDim(depth, 1), d2 = bounceDim(depth, 2);
    for (size_t h = 0; h < n; ++h) {
        b.sortedU1[h] = sampleDimension(b.hitKey[h], d1);
        b.sortedU2[h] = sampleDimension(b.hitKey[h], d2);
    }
    if (one)
        rectLightSamples(scene.lightRects[0], b.sortedU1.data(), b.sortedU2.data(), &b.p[0].x, n, &b.neeP[0].x, b.localX.data(), b.localY.data(),
                         b.localZ.data(), b.neeDist.data(), b.neePdf.data(), b.neeOk.data());
    else
        rectLightSamplesOf(scene.lightRects.data(), b.neeLight.data(), b.sortedU1.data(), b.sortedU2.data(), &b.p[0].x, n, &b.neeP[0].x,
                           b.localX.data(), b.localY.data(), b.localZ.data(), b.neeDist.data(), b.neePdf.data(), b.neeOk.data());
    if (!matte) return;
    if (one) {
        const Light& l0 = scene.lights[0];
        // (spectral: with L = 1, times each hit's emission at its wavelengths after)
        const Vec3 L0 = b.spectra ? Vec3(1.0f) : l0.L;
        matteNeeValuesOf<false>(RectNeeConsts{L0.x, L0.y, L0.z, scene.lightDistribution.discretePmf(0)}, nullptr, nullptr, n, &b.hitNs[0].x,
                                &b.wo[0].x, b.localX.data(), b.localY.data(), b.localZ.data(), b.neePdf.data(), &b.hitKd[0].x, &b.hitBeta[0].x,
                                &b.neeL[0].x, b.neeSend.data());
        if (b.spectra)
            for (size_t h = 0; h < n; ++h) b.neeL[h] = b.neeL[h] * b.spectra->emission(0, l0.L, b.lambda[b.pathSlot[b.hitPath[h]]]);
    } else {
        for (size_t h = 0; h < n; ++h) b.neeLe[h] = scene.lights[b.neeLight[h]].L;
        if (b.spectra)
            for (size_t h = 0; h < n; ++h) b.neeLe[h] = b.spectra->emission(int(b.neeLight[h]), b.neeLe[h], b.lambda[b.pathSlot[b.hitPath[h]]]);
        matteNeeValuesOf<true>(RectNeeConsts{}, &b.neeLe[0].x, b.neePmf.data(), n, &b.hitNs[0].x, &b.wo[0].x, b.localX.data(), b.localY.data(),
                               b.localZ.data(), b.neePdf.data(), &b.hitKd[0].x, &b.hitBeta[0].x, &b.neeL[0].x, b.neeSend.data());
    }
    shadowRaysTo(scene.epsilonScale, n, &b.p[0].x, &b.ng[0].x, b.localX.data(), b.localY.data(), b.localZ.data(), &b.neeP[0].x, &b.neeOrigin[0].x,
                 &b.neeDir[0].x, b.neeTfar.data());
}

}  // namespace

void sampleLights(const Scene& scene, PtBatch& b, int depth) {
    const bool one = scene.lights.size() == 1, flat = scene.anyRectLight, media = scene.features.media;
    const bool matteFlat = flat && scene.features.has(MaterialKind::Matte);
    if (!one) chooseLights(scene, b, depth);
    if (flat) sampleRectLightsFlat(scene, b, depth, matteFlat);
    size_t n = 0;
    forEachHitByKind(b, [&](auto kind, uint32_t h) {
        using B = BsdfOf<decltype(kind)::value>;
        if constexpr (!B::delta) {
            const uint32_t path = b.hitPath[h], slot = b.pathSlot[path];
            // The light the hit chose and whether the flat loops sampled it.
            const int chosen = one ? 0 : int(b.neeLight[h]);
            const bool rect = flat && scene.lightRects[size_t(chosen)].area > 0;
            if constexpr (decltype(kind)::value == MaterialKind::Matte) {
                if (matteFlat && rect) {
                    if (!b.neeOk[h] || !b.neeSend[h]) return;
                    setRay(b.shadow[n], b.neeOrigin[h], b.neeDir[h], 0.0f, b.neeTfar[h]);
                    if (media) b.shadowMedium[n] = dot(b.neeDir[h], b.ng[h]) < 0 ? b.hitMediumIn[h] : b.hitMediumOut[h];
                    b.shadowSlot[n] = slot;
                    b.shadowL[n] = b.neeL[h];
                    ++n;
                    return;
                }
            }
            const uint64_t key = b.key[slot];
            float pmf;
            LightSample ls;
            if (rect) {
                pmf = one ? scene.lightDistribution.discretePmf(0) : b.neePmf[h];
                if (!b.neeOk[h]) return;
                const Light& l = scene.lights[size_t(chosen)];
                ls.p = b.neeP[h];
                ls.wi = Vec3(b.localX[h], b.localY[h], b.localZ[h]);
                ls.dist = b.neeDist[h];
                ls.pdf = b.neePdf[h];
                ls.n = l.n;
                ls.Le = l.L;
            } else {
                pmf = one ? scene.lightDistribution.discretePmf(0) : b.neePmf[h];
                if (!sampleLightFrom(scene, chosen, b.p[h], sampleDimension(key, bounceDim(depth, 1)), sampleDimension(key, bounceDim(depth, 2)), ls))
                    return;
            }
            if (b.spectra) ls.Le = b.spectra->emission(chosen, ls.Le, b.lambda[slot]);
            const Frame& fr = b.shading[h];
            Vec3 wo = fr.toLocal(b.wo[h]), wi = fr.toLocal(ls.wi);
            Vec3 f = B::f(b.bsdf[h], wo, wi) * absCosTheta(wi);
            if (isBlack(f) || isBlack(ls.Le)) return;
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
            if (media) b.shadowMedium[n] = dot(dir, b.ng[h]) < 0 ? b.hitMediumIn[h] : b.hitMediumOut[h];
            b.shadowSlot[n] = slot;
            b.shadowL[n] = b.beta[path] * f * ls.Le * (w / lightPdf);
            ++n;
        }
    });
    b.numShadow = n;
}

void traceShadows(const Scene& scene, PtBatch& b, int length, RayCounters& c) {
    traceOccluded(scene.rtc, b.shadow.data(), b.numShadow);
    c.raysOccluded += b.numShadow;
    for (size_t i = 0; i < b.numShadow; ++i)
        if (b.shadow[i].tfar >= 0) addRadiance(b, b.shadowSlot[i], b.shadowL[i], length);
}

namespace {

// A scene with matte surfaces: every hit's matte bounce in flat loops the compiler
// vectorises (the cosine-weighted directions in hit order, the roulette numbers, then
// matteScatter, computed for every hit: the matte hits take theirs).
void scatterMatteFlat(PtBatch& b, int depth) {
    const size_t n = b.numHits;
    sampleCosineHemispheres(b.hitKey.data(), n, bounceDim(depth, 4), bounceDim(depth, 5), b.localX.data(), b.localY.data(), b.localZ.data());
    const bool roulette = depth >= kRouletteDepth;
    if (roulette) {
        const uint32_t d = bounceDim(depth, 6);
        for (size_t h = 0; h < n; ++h) b.sortedU1[h] = sampleDimension(b.hitKey[h], d);
    }
    (roulette ? matteScatter<true> : matteScatter<false>)(n, &b.hitNs[0].x, &b.wo[0].x, b.localX.data(), b.localY.data(), b.localZ.data(),
                                                          &b.hitKd[0].x, &b.hitBeta[0].x, b.sortedU1.data(), &b.nextBeta[0].x, &b.nextDir[0].x,
                                                          b.nextPdf.data(), b.scatterOk.data());
    for (uint32_t r = b.kindStart[int(MaterialKind::Matte)]; r < b.kindStart[int(MaterialKind::Matte) + 1]; ++r) {
        const uint32_t h = b.order[r];
        b.alive[h] = uint8_t(b.scatterOk[h]);
        b.nextDelta[h] = 0;
    }
}

}  // namespace

void sampleBsdfs(const Scene& scene, PtBatch& b, int depth) {
    const bool matteFlat = scene.features.has(MaterialKind::Matte);
    if (matteFlat) scatterMatteFlat(b, depth);
    scatterHits(
        b, TransportMode::Radiance, [&](uint32_t m) { return bounceDim(depth, 3 + m); },
        [&](uint32_t h, uint32_t path, uint32_t, uint64_t key, const BsdfSample& s) {
            Vec3 beta = b.beta[path] * s.f * (absCosTheta(s.wi) / s.pdf);
            if (depth >= kRouletteDepth && !survivesRoulette(beta, 1.0f, sampleDimension(key, bounceDim(depth, 6)))) return;
            b.alive[h] = 1;
            b.nextDir[h] = normalize(b.shading[h].toWorld(s.wi));
            b.nextBeta[h] = beta;
            b.nextPdf[h] = s.pdf;
            b.nextDelta[h] = s.delta ? 1 : 0;
        },
        !matteFlat);
}

void advancePaths(const Scene& scene, PtBatch& b) {
    const bool media = scene.features.media;
    compact(
        scene, b,
        [&](size_t h, Vec3& p, Vec3& ng) {
            p = b.p[h];
            ng = b.ng[h];
        },
        [&](size_t n, uint32_t path, size_t h) {
            b.beta[n] = b.nextBeta[h];
            b.prevPdf[n] = b.nextPdf[h];
            b.prevDelta[n] = b.nextDelta[h];
            b.anyNonSpecular[n] = uint8_t(b.anyNonSpecular[path] | (b.nextDelta[h] ^ 1));
            if (media) {  // the side the next ray leaves into (a medium vertex: its own medium)
                b.medium[n] = dot(b.nextDir[h], b.ng[h]) < 0 ? b.hitMediumIn[h] : b.hitMediumOut[h];
                b.vertexP[n] = b.p[h];
            }
        });
}

}  // namespace wmlt
