// The light tracer's wavefront stages (lt_stages.h): light paths from the emitters, each
// vertex connected to the camera (t = 1).
#include "stages/lt/lt_stages.h"

#include "kernels/rng.h"
#include "kernels/sampling.h"
#include "scene/scene_lights.h"
#include "stages/core/bsdf_dispatch.h"
#include "stages/core/media.h"
#include "stages/core/surface.h"
#include "stages/core/trace.h"
#include "stages/core/wave.h"

namespace wmlt {

namespace {

// Appends a camera connection from surface point p (normal ng) to the lens sample.
inline void addConnection(const Scene& scene, LtBatch& b, Vec3 p, Vec3 ng, const CameraSample& cs, Vec3 value) {
    Vec3 origin = scene.offsetRayOrigin(p, ng, cs.wi);
    Vec3 toLens = cs.lens - origin;
    float dist = length(toLens);
    if (!(dist > 0)) return;
    setRay(b.conn[b.numConn], origin, toLens / dist, 0.0f, dist * (1.0f - 1e-4f));
    b.connPixel[b.numConn] = scene.filter.box ? rasterPixel(scene.camera, cs.px, cs.py) : kFilmPoint;
    b.connX[b.numConn] = cs.px;
    b.connY[b.numConn] = cs.py;
    b.connValue[b.numConn] = value;
    ++b.numConn;
}

}  // namespace

uint64_t ltSampleKey(uint64_t seed, uint32_t pixel, uint32_t sample) { return sampleKey(mix64(seed ^ 0x4c54u /* "LT" */), pixel, sample); }

// Dimensions 7-10 of an LT sample (lt_state.h): the camera ray that sees the environment.
constexpr CameraDims kLtEnvCameraDims{7, 8, 9, 10};

void generateEnvCameraRays(const Scene& scene, LtBatch& b, const Tile& t, int n, uint64_t seed) {
    b.numConn = forEachCameraRay(
        scene, b, t, n, seed, kLtEnvCameraDims, [&](uint32_t pixel, uint32_t s) { return ltSampleKey(seed, pixel, s); },
        [&](size_t i, uint32_t pixel, uint64_t key, Vec3 o, Vec3 d) {
            setRay(b.conn[i], o, d, 0.0f, INFINITY);
            b.connPixel[i] = pixel;
            b.connValue[i] = scene.env.Le(d) * b.filmWeight[i];
            if (b.spectra) {  // this sample's own wavelengths (its key's)
                b.connLambda[i] = sampleWavelengths(sampleDimension(key, kWavelengthDim));
                b.connValue[i] = b.spectra->emission(scene.envLight, b.connValue[i], b.connLambda[i]);
            }
            if (scene.features.media) {
                b.connMedium[i] = scene.cameraMedium;
                b.connKey[i] = key;
            }
        });
}

void generateLightPaths(const Scene& scene, LtBatch& b, const Tile& t, uint64_t seed, bool connectLength1) {
    const Camera& cam = scene.camera;
    const bool media = scene.features.media;
    size_t n = 0;
    b.numConn = 0;
    forEachTileSample(t, cam.width, [&](size_t i, int, int, uint32_t pixel, uint32_t s) {
        const uint64_t key = ltSampleKey(seed, pixel, s);
        b.key[i] = key;
        if (b.spectra) b.lambda[i] = sampleWavelengths(sampleDimension(key, kWavelengthDim));
        float pmf;
        int li = scene.lightDistribution.sampleDiscrete(sampleDimension(key, 0), &pmf);
        LightEmission e;
        if (!(pmf > 0) ||
            !sampleLightEmission(scene, li, sampleDimension(key, 1), sampleDimension(key, 2), sampleDimension(key, 3), sampleDimension(key, 4), e))
            return;
        const bool infinite = isInfiniteLight(scene.lights[li]);
        // (media) the face it emits from: a two-sided light's back face for u2 >= 1/2
        const bool back = scene.lights[li].twoSided && sampleDimension(key, 3) >= 0.5f;
        // Light vertex: alpha = Le-carrying weight 1 / (pmf pdfPos) (Veach 10.2).
        const float invPos = 1.0f / (pmf * e.pdfPos);
        if (connectLength1 && !infinite && !isDeltaLight(scene.lights[li])) {  // (a point light is not seen)
            CameraSample cs = sampleCameraFrom(cam, e.p, sampleDimension(key, 5), sampleDimension(key, 6));
            if (cs.valid) {
                Vec3 Le = areaLe(scene.lights[li], e.n, cs.wi) * e.tex;  // (tex 1 but for textured emitters)
                if (b.spectra) {
                    Le = b.spectra->emission(li, Le, b.lambda[i]);
                    b.connLambda[b.numConn] = b.lambda[i];
                }
                float cosL = std::fabs(dot(cs.wi, e.n));
                if (!isBlack(Le)) {
                    if (media) {  // the face towards the camera (e.n is the face emission took)
                        b.connMedium[b.numConn] =
                            (back != (dot(cs.wi, e.n) < 0)) ? scene.lightMediumBack[size_t(li)] : scene.lightMediumFront[size_t(li)];
                        b.connKey[b.numConn] = key;
                    }
                    addConnection(scene, b, e.p, e.n, cs, Le * (cosL * invPos * cs.We / cs.pdf));
                }
            }
        }
        const Vec3 Le = b.spectra ? b.spectra->emission(li, e.Le, b.lambda[i]) : e.Le;
        Vec3 beta = Le * (std::fabs(dot(e.n, e.dir)) * invPos / e.pdfDir);
        if (isBlack(beta) || !isFinite(beta)) return;
        b.betaScale[i] = maxComponent(beta);
        b.pathSlot[n] = uint32_t(i);
        // Emitters are one-sided surfaces: leave the light on its normal's side.
        Vec3 o = infinite ? e.p : scene.offsetRayOrigin(e.p, e.n, e.dir);
        setRayHit(b.ray[n], o, e.dir);
        b.beta[n] = beta;
        if (media) b.medium[n] = back ? scene.lightMediumBack[size_t(li)] : scene.lightMediumFront[size_t(li)];
        ++n;
    });
    b.numPaths = n;
}

void traceConnections(const Scene& scene, LtBatch& b, int length, RayCounters& c) {
    if (scene.features.media) {  // through media and pass-through boundaries (media.h)
        const bool passThrough = scene.features.passThrough;
        SegmentDensities unused;
        for (size_t k = 0; k < b.numConn; ++k) {
            const uint64_t seed = mix64(b.connKey[k] ^ 0x434f4e4eull ^ (uint64_t(length) << 40));
            const PathMedia media{scene, b.spectra, b.spectra ? &b.connLambda[k] : nullptr};
            if (!passThrough) {  // the transmittance here, visibility by the batched occlusion rays below
                b.connValue[k] = b.connValue[k] * transmittanceUnblocked<false>(media, b.conn[k], b.connMedium[k], seed, false, false, unused);
                if (isBlack(b.connValue[k])) b.conn[k].tfar = -1.0f;  // (a ray with tfar < tnear is not traced)
                continue;
            }
            Vec3 v = b.connValue[k] * transmittanceAlong(scene, media, b.conn[k], b.connMedium[k], seed, c);
            if (b.spectra) v = srgbOfSample(v, b.connLambda[k]);
            if (!isBlack(v) && b.tally.take(v, length)) pushSplat(b.splats, b.points, b.connPixel[k], b.connX[k], b.connY[k], v);
        }
        if (passThrough) {
            b.numConn = 0;
            return;
        }
    }
    traceOccluded(scene.rtc, b.conn.data(), b.numConn);
    c.raysOccluded += b.numConn;
    for (size_t k = 0; k < b.numConn; ++k) {
        if (!(b.conn[k].tfar >= 0)) continue;
        const Vec3 v = b.spectra ? srgbOfSample(b.connValue[k], b.connLambda[k]) : b.connValue[k];  // (the film's)
        if (b.tally.take(v, length)) pushSplat(b.splats, b.points, b.connPixel[k], b.connX[k], b.connY[k], v);
    }
    b.numConn = 0;
}

namespace {

// The stage for the scene's surface features F (surface.h, withSurfaceFeatures).
template <class F>
void resolveLightHitsOf(const Scene& scene, LtBatch& b) {
    const bool media = scene.features.media;
    size_t h = 0;
    for (size_t i = 0; i < b.numPaths; ++i) {
        const RTCRayHit& rh = b.ray[i];
        prefetchSurfaceAhead(scene, b.ray.data(), i, b.numPaths);
        if (media && b.mediumEvent[i]) {  // a scattering event in the path's medium: a Phase vertex
            if (b.spectra) b.hitMaterial[h] = -1;
            recordMediumVertex(scene, b, h++, i);
            continue;
        }
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;  // leaves the scene
        SurfacePoint sp = surfaceAt<F>(scene, rh);
        if (sp.material < 0) continue;  // an emitter without a material absorbs
        if (media) {
            const GeomRecord& g = scene.geoms[rh.hit.geomID];
            b.hitMediumIn[h] = g.mediumBoundary ? g.mediumInside : b.medium[i];
            b.hitMediumOut[h] = g.mediumBoundary ? g.mediumOutside : b.medium[i];
        }
        if (b.spectra) b.hitMaterial[h] = sp.material;
        recordHit<F>(scene, b, h++, i, sp, -rayDir(rh), 0);  // (pbrt-v4's lightpath does not regularize)
    }
    b.numHits = h;
    if constexpr (F::textures) evaluateTextures(scene, b.textureJobs);
    if (b.spectra) {  // the spectral stage: every hit's colours at its path's wavelengths
        for (size_t k = 0; k < h; ++k) {
            const int m = b.hitMaterial[k];
            if (m < 0) continue;
            Wavelengths& w = b.lambda[b.pathSlot[b.hitPath[k]]];
            if (b.spectra->colours(m, scene.desc.materials[size_t(m)], b.bsdf[k], w)) terminateSecondary(w);
        }
    }
}

}  // namespace

void resolveLightHits(const Scene& scene, LtBatch& b) {
    withSurfaceFeatures(scene.features, [&](auto f) { resolveLightHitsOf<decltype(f)>(scene, b); });
}

void connectToCamera(const Scene& scene, LtBatch& b, int d) {
    b.numConn = 0;
    // The camera's kind chosen once per call (the loop is the projective one's without it).
    auto connect = [&](auto orthographic) {
        forEachHitByKind(b, [&](auto kind, uint32_t h) {
            using B = BsdfOf<decltype(kind)::value>;
            if constexpr (!B::delta) {
                const uint32_t path = b.hitPath[h];
                const uint64_t key = b.key[b.pathSlot[path]];
                CameraSample cs;
                if constexpr (decltype(orthographic)::value) cs = sampleOrthographicFrom(scene.camera, b.p[h]);
                else
                    cs = sampleProjectiveFrom(scene.camera, b.p[h], sampleDimension(key, ltVertexDim(d, 0)), sampleDimension(key, ltVertexDim(d, 1)));
                if (!cs.valid) return;
                const Frame& fr = b.shading[h];
                // Radiance view: light arrives from wo and leaves towards the camera.
                Vec3 woL = fr.toLocal(b.wo[h]), wiL = fr.toLocal(cs.wi);
                Vec3 f = B::f(b.bsdf[h], wiL, woL);
                if (isBlack(f)) return;
                // beta f |cos_s| * correction * We / pdf (pbrt-v4 16.3.3, t = 1).
                float corr = shadingCorrection(b.wo[h], cs.wi, fr.n, b.ng[h]);
                Vec3 v = b.beta[path] * f * (absCosTheta(wiL) * corr * cs.We / cs.pdf);
                if (b.spectra) b.connLambda[b.numConn] = b.lambda[b.pathSlot[path]];  // (the wavelengths as they stand now)
                if (scene.features.media) {
                    b.connMedium[b.numConn] = dot(cs.wi, b.ng[h]) < 0 ? b.hitMediumIn[h] : b.hitMediumOut[h];
                    b.connKey[b.numConn] = key;
                }
                addConnection(scene, b, b.p[h], b.ng[h], cs, v);
            }
        });
    };
    if (scene.camera.ortho) connect(std::true_type{});
    else connect(std::false_type{});
}

void sampleLightBsdfs(const Scene& scene, LtBatch& b, int d) {
    scatterHits(
        b, TransportMode::Importance, [&](uint32_t m) { return ltVertexDim(d, 2 + m); },
        [&](uint32_t h, uint32_t path, uint32_t slot, uint64_t key, const BsdfSample& s) {
            const Frame& fr = b.shading[h];
            Vec3 wi = normalize(fr.toWorld(s.wi));
            float corr = shadingCorrection(b.wo[h], wi, fr.n, b.ng[h]);
            Vec3 beta = b.beta[path] * s.f * (absCosTheta(s.wi) * corr / s.pdf);
            // Roulette relative to the initial throughput (sampling.h).
            if (d >= kRouletteDepth && !survivesRoulette(beta, b.betaScale[slot], sampleDimension(key, ltVertexDim(d, 5)))) return;
            b.alive[h] = 1;
            b.nextDir[h] = wi;
            b.nextBeta[h] = beta;
        });
}

void advanceLightPaths(const Scene& scene, LtBatch& b) {
    const bool media = scene.features.media;
    compact(
        scene, b,
        [&](size_t h, Vec3& p, Vec3& ng) {
            p = b.p[h];
            ng = b.ng[h];
        },
        [&](size_t n, uint32_t, size_t h) {
            b.beta[n] = b.nextBeta[h];
            if (media) b.medium[n] = dot(b.nextDir[h], b.ng[h]) < 0 ? b.hitMediumIn[h] : b.hitMediumOut[h];
        });
}

}  // namespace wmlt
