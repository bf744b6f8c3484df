// BPT's walk stages (bpt_stages.h), shared with MMLT and PSSMLT: the camera and light
// subpaths' starts, their hits resolved into vertices (with pbrt's regularize, BPT only: the
// regularized materials after a subpath's first non-specular bounce), BSDF sampling with
// both densities, and the compaction of the surviving paths.
#include "stages/bpt/bpt_stages.h"

#include "kernels/mis.h"
#include "kernels/rng.h"
#include "kernels/sampling.h"
#include "scene/scene_lights.h"
#include "stages/core/bsdf_dispatch.h"
#include "stages/core/surface.h"
#include "stages/core/trace.h"
#include "stages/core/wave.h"

namespace wmlt {

namespace {

// Writes slot i's camera vertex z_0 (lens point o) and its first path (direction d).
inline void startCameraPath(const Scene& scene, BptBatch& b, size_t i, Vec3 o, Vec3 d) {
    const size_t z0 = b.cam.at(uint32_t(i), 0);
    b.L[i] = Vec3(0.0f);
    b.cam.count[i] = 1;
    b.cam.p[z0] = o;
    b.cam.ng[z0] = scene.camera.forward;
    b.cam.beta[z0] = Vec3(1.0f);
    b.cam.pdfFwd[z0] = 1.0f;
    b.cam.pdfRev[z0] = 0.0f;
    b.cam.delta[z0] = 0;
    b.cam.kind[z0] = BptVertexKind::Camera;
    if (b.cam.media) b.cam.mediumFront[z0] = b.cam.mediumBack[z0] = scene.cameraMedium;
}

}  // namespace

uint64_t bptSampleKey(uint64_t seed, uint32_t pixel, uint32_t sample) { return sampleKey(mix64(seed ^ 0x425054u /* "BPT" */), pixel, sample); }

float cameraPdfOfRay(const Camera& c, Vec3 w) {
    if (c.ortho) return 1.0f / cameraPlaneArea(c);  // per unit of film area: projected at the first hit
    const float cosTheta = dot(w, c.forward);
    return cosTheta > 0 ? 1.0f / (cameraPlaneArea(c) * cosTheta * cosTheta * cosTheta) : 0.0f;
}

// The camera ray's numbers: j = 0-3 of the camera stream (bpt_state.h).
constexpr CameraDims kBptCameraDims{bptDim(kBptCamera, 0), bptDim(kBptCamera, 1), bptDim(kBptCamera, 2), bptDim(kBptCamera, 3)};

void generateBptCameraPaths(const Scene& scene, BptBatch& b, const Tile& t, int n, uint64_t seed) {
    b.numSlots = forEachCameraRay(
        scene, b, t, n, seed, kBptCameraDims, [&](uint32_t pixel, uint32_t s) { return bptSampleKey(seed, pixel, s); },
        [&](size_t i, uint32_t pixel, uint64_t key, Vec3 o, Vec3 d) {
            b.pixel[i] = pixel;
            b.key[i] = key;
            b.cam.maxCount[i] = uint8_t(b.cam.capacity);
            b.light.maxCount[i] = uint8_t(b.light.capacity);
            startCameraPath(scene, b, i, o, d);
            startPath(b, i, o, d);
            if (b.cam.media) b.medium[i] = scene.cameraMedium;
            b.pathPdf[i] = cameraPdfOfRay(scene.camera, d);
            b.pathBeta[i] = Vec3(1.0f);
            b.pathNonSpecular[i] = 0;
            if (b.spectra) b.lambda[i] = sampleWavelengths(sampleDimension(key, kWavelengthDim));
        });
    b.numPaths = b.numSlots;
}

template <class U>
void generateChainCameraPaths(const Scene& scene, BptBatch& b, const U& u) {
    const Camera& cam = scene.camera;
    const bool lens = cam.thinLens;
    size_t n = 0;
    for (size_t i = 0; i < b.numSlots; ++i) {
        const uint32_t slot = uint32_t(i);
        if (b.cam.maxCount[i] < 2) {  // t = 1: the connection samples the lens
            b.cam.count[i] = 1;
            b.L[i] = Vec3(0.0f);
            continue;
        }
        const float px = u(slot, kBptCamera, 0) * float(cam.width), py = u(slot, kBptCamera, 1) * float(cam.height);
        Vec3 o, d;
        generateCameraRay(cam, px, py, lens ? u(slot, kBptCamera, 2) : 0.5f, lens ? u(slot, kBptCamera, 3) : 0.5f, o, d);
        b.filmX[i] = px;
        b.filmY[i] = py;
        startCameraPath(scene, b, i, o, d);
        b.pathSlot[n] = slot;
        setRayHit(b.ray[n], o, d);
        b.pathPdf[n] = cameraPdfOfRay(cam, d);
        b.pathBeta[n] = Vec3(1.0f);
        b.pathNonSpecular[n] = 0;
        if (b.cam.media) b.medium[n] = scene.cameraMedium;
        ++n;
    }
    b.numPaths = n;
}

template void generateChainCameraPaths(const Scene&, BptBatch&, const StoredSamples&);
template void generateChainCameraPaths(const Scene&, BptBatch&, const WholeSamples&);

template <class U>
void generateBptLightPaths(const Scene& scene, BptBatch& b, const U& u) {
    size_t n = 0;
    // y_0 of slot i from light li (choice pmf), its emission sample e and shading frame (about
    // e.n), and its path.
    auto start = [&](size_t i, int li, float pmf, const LightEmission& e, const Frame& shading) {
        const bool infinite = isInfiniteLight(scene.lights[li]);
        const float pdfOrigin = pmf * e.pdfPos;
        const size_t y0 = b.light.at(uint32_t(i), 0);
        b.light.count[i] = 1;
        b.light.p[y0] = e.p;
        b.light.ng[y0] = e.n;
        b.light.shading[y0] = shading;
        b.light.beta[y0] = e.tex * (1.0f / pdfOrigin);  // L is applied by each connection (T, 1 untextured, here)
        if (!b.light.emitPdfA.empty())                  // a textured emitter's density of y_0 (else 1 / area: -1)
            b.light.emitPdfA[y0] = texturedMeshLight(scene, li) ? e.pdfPos : -1.0f;
        b.light.pdfFwd[y0] = pdfOrigin;
        b.light.pdfRev[y0] = 0.0f;
        b.light.delta[y0] = 0;
        b.light.kind[y0] = infinite ? BptVertexKind::Env : BptVertexKind::Light;
        b.light.light[y0] = int16_t(li);
        if (infinite) b.light.pdfFwd[y0] = pmf * e.pdfDir;  // the direction's density
        if (b.light.media) {                                // the face emission took (e.n): a two-sided light's back for u3 >= 1/2
            const bool back = scene.lights[li].twoSided && u(uint32_t(i), kBptLight, 3) >= 0.5f;
            const int front = scene.lightMediumFront[size_t(li)], behind = scene.lightMediumBack[size_t(li)];
            b.light.mediumFront[y0] = back ? behind : front;
            b.light.mediumBack[y0] = back ? front : behind;
        }
        if (b.light.maxCount[i] < 2) return;
        const Vec3 Le = b.spectra ? b.spectra->emission(li, e.Le, b.lambda[i]) : e.Le;
        Vec3 beta = Le * (std::fabs(dot(e.n, e.dir)) / (pdfOrigin * e.pdfDir));
        if (isBlack(beta) || !isFinite(beta)) return;
        b.betaScale[i] = maxComponent(beta);
        b.pathSlot[n] = uint32_t(i);
        setRayHit(b.ray[n], infinite ? e.p : scene.offsetRayOrigin(e.p, e.n, e.dir), e.dir);
        b.pathPdf[n] = infinite ? e.pdfPos : e.pdfDir;  // resolveBptHits projects the disc's
        b.pathBeta[n] = beta;
        b.pathNonSpecular[n] = 0;  // (emission is no bounce)
        if (b.light.media) b.medium[n] = b.light.mediumFront[y0];
        ++n;
    };
    if (const Light* rect = soleRectLight(scene)) {
        // One rectangle light: every slot's emission sample in one flat loop (the choice is
        // certain and reads no number).
        const Light& l = *rect;
        const float pmf = scene.lightDistribution.discretePmf(0);
        size_t m = 0;
        for (size_t i = 0; i < b.numSlots; ++i) {
            b.light.count[i] = 0;
            if (b.light.maxCount[i] < 1) continue;
            const uint32_t slot = uint32_t(i);
            b.emitSlot[m] = slot;
            b.sortedU1[m] = u(slot, kBptLight, 1);
            b.sortedU2[m] = u(slot, kBptLight, 2);
            b.emitU3[m] = u(slot, kBptLight, 3);
            b.emitU4[m] = u(slot, kBptLight, 4);
            ++m;
        }
        const FrameFloats frame = frameFromNormal(l.n.x, l.n.y, l.n.z);  // the emission's and y_0's, once
        rectEmissionSamples(rectFloats(l), frame, b.sortedU1.data(), b.sortedU2.data(), b.emitU3.data(), b.emitU4.data(), m, &b.emitP[0].x,
                            b.localX.data(), b.localY.data(), b.localZ.data(), b.emitPdfDir.data(), b.emitOk.data());
        LightEmission e;
        e.n = l.n;
        e.Le = l.L;
        e.pdfPos = 1.0f / l.area;
        for (size_t j = 0; j < m; ++j) {
            if (!(pmf > 0) || !b.emitOk[j]) continue;
            e.p = b.emitP[j];
            e.dir = Vec3(b.localX[j], b.localY[j], b.localZ[j]);
            e.pdfDir = b.emitPdfDir[j];
            start(b.emitSlot[j], 0, pmf, e, Frame::fromFloats(frame));
        }
        b.numPaths = n;
        return;
    }
    for (size_t i = 0; i < b.numSlots; ++i) {
        b.light.count[i] = 0;
        if (scene.lights.empty() || b.light.maxCount[i] < 1) continue;
        const uint32_t slot = uint32_t(i);
        float pmf;
        int li = scene.lightDistribution.sampleDiscrete(u(slot, kBptLight, 0), &pmf);
        LightEmission e;
        if (!(pmf > 0) ||
            !sampleLightEmission(scene, li, u(slot, kBptLight, 1), u(slot, kBptLight, 2), u(slot, kBptLight, 3), u(slot, kBptLight, 4), e))
            continue;
        start(i, li, pmf, e, Frame::fromNormal(e.n));
    }
    b.numPaths = n;
}
template void generateBptLightPaths(const Scene&, BptBatch&, const HashedSamples&);
template void generateBptLightPaths(const Scene&, BptBatch&, const StoredSamples&);
template void generateBptLightPaths(const Scene&, BptBatch&, const WholeSamples&);

namespace {

// The stage for the scene's surface features F (surface.h, withSurfaceFeatures).
template <class F>
void resolveBptHitsOf(const Scene& scene, BptBatch& b, BptVertices& v, bool cameraWalk) {
    const bool media = v.media;
    size_t h = 0;
    b.numNew = 0;
    for (size_t i = 0; i < b.numPaths; ++i) {
        const RTCRayHit& rh = b.ray[i];
        prefetchSurfaceAhead(scene, b.ray.data(), i, b.numPaths);
        if (media && b.mediumEvent[i]) {
            const uint32_t slot = b.pathSlot[i];
            const int idx = v.count[slot];
            if (idx >= v.maxCount[slot]) continue;
            const size_t prev = v.at(slot, idx - 1), cur = v.at(slot, idx);
            v.count[slot] = uint8_t(idx + 1);
            recordBptMediumVertex(scene, b, v, i, prev, cur);
            if (idx + 1 >= v.maxCount[slot]) continue;  // the walk ends here
            b.hitPath[h] = uint32_t(i);
            b.hitKind[h] = MaterialKind::Phase;
            ++h;
            continue;
        }
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
            if (!cameraWalk || scene.envLight < 0) continue;
            // The camera path escapes to the environment: an Env vertex ends it.
            const uint32_t slot = b.pathSlot[i];
            const int idx = v.count[slot];
            if (idx >= v.maxCount[slot]) continue;
            const size_t prev = v.at(slot, idx - 1), cur = v.at(slot, idx);
            const Vec3 d = rayDir(rh);
            v.count[slot] = uint8_t(idx + 1);
            v.p[cur] = v.p[prev] + d * (2.0f * scene.radius);
            v.ng[cur] = -d;
            v.beta[cur] = b.pathBeta[i];
            v.pdfFwd[cur] = b.pathPdf[i];  // solid angle
            v.pdfRev[cur] = 0.0f;
            v.delta[cur] = 0;
            v.kind[cur] = BptVertexKind::Env;
            v.light[cur] = int16_t(scene.envLight);
            if (media) {
                takeSegmentDensities(b, v, i, cur);
                v.mediumFront[cur] = v.mediumBack[cur] = -1;
            }
            continue;
        }
        SurfacePoint sp = surfaceAt<F>(scene, rh);
        if (sp.material < 0 && !cameraWalk) continue;  // emitters without a material absorb light subpaths
        const uint32_t slot = b.pathSlot[i];
        const int idx = v.count[slot];
        if (idx >= v.maxCount[slot]) continue;
        const size_t prev = v.at(slot, idx - 1), cur = v.at(slot, idx);
        v.count[slot] = uint8_t(idx + 1);
        v.p[cur] = sp.p;
        v.ng[cur] = sp.ng;
        v.shading[cur] = shadingFrame<F>(scene, sp);
        v.beta[cur] = b.pathBeta[i];
        const bool projected = v.kind[prev] == BptVertexKind::Env || (scene.camera.ortho && v.kind[prev] == BptVertexKind::Camera);
        v.pdfFwd[cur] = projected ? b.pathPdf[i] * std::fabs(dot(sp.ng, rayDir(rh)))  // disc's (film's) density projected
                                  : solidAngleToArea(b.pathPdf[i], v.p[prev], sp.p, sp.ng, true);
        v.pdfRev[cur] = 0.0f;
        v.delta[cur] = 0;
        v.light[cur] = int16_t(sp.light);  // a Surface on an emitter keeps its light (s = 0)
        if (media) {                       // a boundary's outside on the +ng side (media.h, mediumAcross), else the path's
            takeSegmentDensities(b, v, i, cur);
            const GeomRecord& g = scene.geoms[rh.hit.geomID];
            v.mediumFront[cur] = g.mediumBoundary ? g.mediumOutside : b.medium[i];
            v.mediumBack[cur] = g.mediumBoundary ? g.mediumInside : b.medium[i];
        }
        if (cameraWalk && sp.light >= 0 && !v.emitPdfA.empty()) {  // a textured emitter's T and density here
            v.emitTex[cur] = Vec3(1.0f);
            v.emitPdfA[cur] = -1;
            texturedEmitterHit(scene, sp.light, rh, sp.p, v.emitTex[cur], v.emitPdfA[cur]);
        }
        if (sp.material < 0) {  // camera walk: the path ends on the emitter
            v.kind[cur] = BptVertexKind::Light;
            continue;
        }
        v.kind[cur] = BptVertexKind::Surface;
        materialAt<F>(scene, sp, -rayDir(rh), v.bsdf[cur], b.textureJobs, b.pathNonSpecular[i] ? b.regularizedOffset : 0);
        if (b.spectra) b.noteNewVertex(slot, cur, sp.material);  // its colours at the slot's wavelengths, below
        const MaterialKind kind = v.bsdf[cur].kind;
        v.delta[cur] = isDeltaMaterial(kind) ? 1 : 0;
        if (idx + 1 >= v.maxCount[slot]) continue;  // the walk ends here
        b.hitPath[h] = uint32_t(i);
        b.hitKind[h] = kind;
        ++h;
    }
    b.numHits = h;
    if constexpr (F::textures) evaluateTextures(scene, b.textureJobs);  // every new vertex's, the walk's last too
    // The spectral stage: every new vertex's colours at its slot's wavelengths; a dispersive
    // dielectric keeps only the hero wavelength, for every strategy of the slot.
    for (size_t j = 0; j < b.numNew; ++j) {
        const int m = b.newMaterial[j];
        Wavelengths& w = b.lambda[b.newSlot[j]];
        if (b.spectra->colours(m, scene.desc.materials[size_t(m)], v.bsdf[b.newVertex[j]], w)) terminateSecondary(w);
    }
}

}  // namespace

void resolveBptHits(const Scene& scene, BptBatch& b, BptVertices& v, bool cameraWalk) {
    withSurfaceFeatures(scene.features, [&](auto f) { resolveBptHitsOf<decltype(f)>(scene, b, v, cameraWalk); });
}

template <class U>
void sampleBptBsdfs(const Scene& scene, BptBatch& b, BptVertices& v, bool cameraWalk, const U& u) {
    const TransportMode mode = cameraWalk ? TransportMode::Radiance : TransportMode::Importance;
    const BptStream stream = cameraWalk ? kBptCamera : kBptLight;
    auto jOf = [&](int d, uint32_t m) { return cameraWalk ? bptCamVertexJ(d, m) : bptLightVertexJ(d, m); };
    forEachMaterialKind([&](auto kind) {
        using B = BsdfOf<decltype(kind)::value>;
        constexpr bool matte = decltype(kind)::value == MaterialKind::Matte;
        const uint32_t r0 = b.kindStart[int(kind.value)], r1 = b.kindStart[int(kind.value) + 1];
        if constexpr (matte) {     // the directions first, in one flat loop (scatterHits)
            if (r0 == r1) return;  // (&v[r0] of a full wave would be past the end)
            for (uint32_t r = r0; r < r1; ++r) {
                const uint32_t slot = b.pathSlot[b.hitPath[b.order[r]]];
                const int d = v.count[slot] - 1;
                b.sortedU1[r] = u(slot, stream, jOf(d, 1));
                b.sortedU2[r] = u(slot, stream, jOf(d, 2));
            }
            sampleCosineHemispheres(&b.sortedU1[r0], &b.sortedU2[r0], r1 - r0, &b.localX[r0], &b.localY[r0], &b.localZ[r0]);
        }
        for (uint32_t r = r0; r < r1; ++r) {
            const uint32_t h = b.order[r], path = b.hitPath[h], slot = b.pathSlot[path];
            const int d = v.count[slot] - 1;
            const size_t cur = v.at(slot, d), prev = v.at(slot, d - 1);
            b.alive[h] = 0;
            v.delta[cur] = B::delta ? 1 : 0;
            const Frame& fr = v.shading[cur];
            const Vec3 woW = -rayDir(b.ray[path]);
            Vec3 wo = fr.toLocal(woW);
            BsdfSample s;
            bool sampled;
            if constexpr (matte) sampled = matteSampleFrom(v.bsdf[cur], wo, Vec3(b.localX[r], b.localY[r], b.localZ[r]), s);
            else
                sampled = sampleBsdfOf<B>(
                    v.bsdf[cur], wo, [&](uint32_t m) { return u(slot, stream, jOf(d, m)); }, mode, s);
            if (!sampled || !(s.pdf > 0) || isBlack(s.f)) continue;
            v.delta[cur] = s.delta ? 1 : 0;  // the lobe taken (Plastic: coating or base)
            Vec3 wi = normalize(fr.toWorld(s.wi));
            float corr = cameraWalk ? 1.0f : shadingCorrection(woW, wi, fr.n, v.ng[cur]);
            Vec3 beta = b.pathBeta[path] * s.f * (absCosTheta(s.wi) * corr / s.pdf);
            // Densities: forward for the next vertex, reverse for the previous one.
            float pdfFwd = 0, pdfRev = 0;
            if (!s.delta) {
                pdfFwd = s.pdf;
                pdfRev = B::pdf(v.bsdf[cur], s.wi, wo);
            }
            v.pdfRev[prev] =
                v.kind[prev] == BptVertexKind::Env ? pdfRev : solidAngleToArea(pdfRev, v.p[cur], v.p[prev], v.ng[prev], hasCosine(v.kind[prev]));
            if (v.media) v.pdfRev[prev] *= v.rhoRev[cur];  // the reverse free path's density
            // Roulette (sampling.h): the light subpath's relative to its initial throughput.
            if (b.roulette && d >= kRouletteDepth && !survivesRoulette(beta, cameraWalk ? 1.0f : b.betaScale[slot], u(slot, stream, jOf(d, 3))))
                continue;
            b.alive[h] = 1;
            b.nextDir[h] = wi;
            b.pathBeta[path] = beta;  // read back by advanceBptPaths (path >= h)
            b.pathPdf[path] = pdfFwd;
            b.pathNonSpecular[path] |= uint8_t(!s.delta);
        }
    });
}
template void sampleBptBsdfs(const Scene&, BptBatch&, BptVertices&, bool, const HashedSamples&);
template void sampleBptBsdfs(const Scene&, BptBatch&, BptVertices&, bool, const StoredSamples&);
template void sampleBptBsdfs(const Scene&, BptBatch&, BptVertices&, bool, const WholeSamples&);

template <class U>
void walkBpt(const Scene& scene, BptBatch& b, BptVertices& v, bool cameraWalk, bool coherentFirst, RayCounters& counters, const U& u) {
    for (bool first = true; b.numPaths > 0; first = false) {
        intersect(scene, b, coherentFirst && first, counters);
        if (v.media) traverseBptMedia(scene, b, v, cameraWalk, u, counters);  // (bpt_media.cpp)
        resolveBptHits(scene, b, v, cameraWalk);
        if (b.numHits == 0) break;
        groupByMaterial(b, b.hitKind.data());
        sampleBptBsdfs(scene, b, v, cameraWalk, u);
        advanceBptPaths(scene, b, v);
    }
}
template void walkBpt(const Scene&, BptBatch&, BptVertices&, bool, bool, RayCounters&, const HashedSamples&);
template void walkBpt(const Scene&, BptBatch&, BptVertices&, bool, bool, RayCounters&, const StoredSamples&);
template void walkBpt(const Scene&, BptBatch&, BptVertices&, bool, bool, RayCounters&, const WholeSamples&);

void advanceBptPaths(const Scene& scene, BptBatch& b, const BptVertices& v) {
    compact(
        scene, b,
        [&](size_t h, Vec3& p, Vec3& ng) {
            const uint32_t slot = b.pathSlot[b.hitPath[h]];
            const size_t cur = v.at(slot, v.count[slot] - 1);
            p = v.p[cur];
            ng = v.ng[cur];
        },
        [&](size_t n, uint32_t path, size_t h) {
            b.pathBeta[n] = b.pathBeta[path];
            b.pathPdf[n] = b.pathPdf[path];
            b.pathNonSpecular[n] = b.pathNonSpecular[path];
            if (v.media) {  // the side the next ray leaves into (a medium vertex: its own medium)
                const uint32_t slot = b.pathSlot[path];
                b.medium[n] = v.mediumTowards(v.at(slot, v.count[slot] - 1), b.nextDir[h]);
            }
        });
}

}  // namespace wmlt
