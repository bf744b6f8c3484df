#include "stages/bpt_stages.h"

#include "kernels/mis.h"
#include "kernels/rng.h"
#include "scene/scene_lights.h"
#include "stages/bsdf_dispatch.h"
#include "stages/surface.h"
#include "stages/trace.h"

namespace wmlt {

namespace {

inline float dim(uint64_t key, BptStream s, uint32_t j) { return sampleDimension(key, bptDim(s, j)); }

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
}

}  // namespace

uint64_t bptSampleKey(uint64_t seed, uint32_t pixel, uint32_t sample) {
    return sampleKey(mix64(seed ^ 0x425054u /* "BPT" */), pixel, sample);
}

float cameraPdfDir(const Camera& c, Vec3 lens, Vec3 w) {
    float px, py, cosTheta;
    if (!cameraRasterOfRay(c, lens, w, px, py, cosTheta)) return 0.0f;
    return 1.0f / (cameraPlaneArea(c) * cosTheta * cosTheta * cosTheta);
}

void generateBptCameraPaths(const Scene& scene, BptBatch& b, const PtTile& t, int n, uint64_t seed) {
    const Camera& cam = scene.camera;
    const bool lens = cam.thinLens;
    size_t i = 0;
    for (int y = t.y0; y < t.y1; ++y)
        for (int x = t.x0; x < t.x1; ++x) {
            uint32_t pixel = uint32_t(y) * uint32_t(cam.width) + uint32_t(x);
            for (uint32_t s = t.sample0; s < t.sample1; ++s, ++i) {
                uint64_t key = bptSampleKey(seed, pixel, s);
                float px, py;
                stratifiedRasterPoint(x, y, s, n, strataKey(seed, pixel), dim(key, kBptCamera, 0), dim(key, kBptCamera, 1), px, py);
                Vec3 o, d;
                generateCameraRay(cam, px, py, lens ? dim(key, kBptCamera, 2) : 0.5f,
                                  lens ? dim(key, kBptCamera, 3) : 0.5f, o, d);
                b.pixel[i] = pixel;
                b.key[i] = key;
                b.cam.maxCount[i] = uint8_t(b.cam.capacity);
                b.light.maxCount[i] = uint8_t(b.light.capacity);
                startCameraPath(scene, b, i, o, d);
                b.pathSlot[i] = uint32_t(i);
                setRayHit(b.ray[i], o, d);
                b.pathPdf[i] = cameraPdfDir(cam, o, d);
                b.pathBeta[i] = Vec3(1.0f);
            }
        }
    b.numSlots = i;
    b.numPaths = i;
}

void generateChainCameraPaths(const Scene& scene, BptBatch& b, const StoredSamples& u) {
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
        b.pixel[i] = rasterPixel(cam, px, py);
        startCameraPath(scene, b, i, o, d);
        b.pathSlot[n] = slot;
        setRayHit(b.ray[n], o, d);
        b.pathPdf[n] = cameraPdfDir(cam, o, d);
        b.pathBeta[n] = Vec3(1.0f);
        ++n;
    }
    b.numPaths = n;
}

template <class U>
void generateBptLightPaths(const Scene& scene, BptBatch& b, const U& u) {
    size_t n = 0;
    for (size_t i = 0; i < b.numSlots; ++i) {
        b.light.count[i] = 0;
        if (scene.lights.empty() || b.light.maxCount[i] < 1) continue;
        const uint32_t slot = uint32_t(i);
        float pmf;
        int li = scene.lightDistribution.sampleDiscrete(u(slot, kBptLight, 0), &pmf);
        LightEmission e;
        if (!(pmf > 0) || !sampleLightEmission(scene, li, u(slot, kBptLight, 1), u(slot, kBptLight, 2),
                                               u(slot, kBptLight, 3), u(slot, kBptLight, 4), e))
            continue;
        const bool infinite = scene.lights[li].type == LightType::Env;
        const float pdfOrigin = pmf * e.pdfPos;
        const size_t y0 = b.light.at(uint32_t(i), 0);
        b.light.count[i] = 1;
        b.light.p[y0] = e.p;
        b.light.ng[y0] = e.n;
        b.light.shading[y0] = Frame::fromNormal(e.n);
        b.light.beta[y0] = Vec3(1.0f / pdfOrigin);  // Le is applied by each connection
        b.light.pdfFwd[y0] = pdfOrigin;
        b.light.pdfRev[y0] = 0.0f;
        b.light.delta[y0] = 0;
        b.light.kind[y0] = infinite ? BptVertexKind::Env : BptVertexKind::Light;
        b.light.light[y0] = int16_t(li);
        if (infinite) b.light.pdfFwd[y0] = pmf * e.pdfDir;  // the direction's density
        if (b.light.maxCount[i] < 2) continue;
        Vec3 beta = e.Le * (std::fabs(dot(e.n, e.dir)) / (pdfOrigin * e.pdfDir));
        if (isBlack(beta) || !isFinite(beta)) continue;
        b.betaScale[i] = maxComponent(beta);
        b.pathSlot[n] = uint32_t(i);
        setRayHit(b.ray[n], infinite ? e.p : scene.offsetRayOrigin(e.p, e.n, e.dir), e.dir);
        b.pathPdf[n] = infinite ? e.pdfPos : e.pdfDir;  // resolveBptHits projects the disc's
        b.pathBeta[n] = beta;
        ++n;
    }
    b.numPaths = n;
}
template void generateBptLightPaths(const Scene&, BptBatch&, const HashedSamples&);
template void generateBptLightPaths(const Scene&, BptBatch&, const StoredSamples&);

void intersectBptPaths(const Scene& scene, BptBatch& b, bool coherent, PtCounters& c) {
    traceClosest(scene.rtc, b.ray.data(), b.numPaths, coherent);
    c.raysIntersect += b.numPaths;
}

void resolveBptHits(const Scene& scene, BptBatch& b, BptVertices& v, bool cameraWalk) {
    size_t h = 0;
    for (size_t i = 0; i < b.numPaths; ++i) {
        const RTCRayHit& rh = b.ray[i];
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
            continue;
        }
        SurfacePoint sp = surfaceAt(scene, rh);
        if (sp.material < 0 && !cameraWalk) continue;  // emitters without a material absorb light subpaths
        const uint32_t slot = b.pathSlot[i];
        const int idx = v.count[slot];
        if (idx >= v.maxCount[slot]) continue;
        const size_t prev = v.at(slot, idx - 1), cur = v.at(slot, idx);
        v.count[slot] = uint8_t(idx + 1);
        v.p[cur] = sp.p;
        v.ng[cur] = sp.ng;
        v.shading[cur] = Frame::fromNormal(sp.ns);
        v.beta[cur] = b.pathBeta[i];
        v.pdfFwd[cur] = v.kind[prev] == BptVertexKind::Env
                            ? b.pathPdf[i] * std::fabs(dot(sp.ng, rayDir(rh)))  // disc density projected
                            : solidAngleToArea(b.pathPdf[i], v.p[prev], sp.p, sp.ng, true);
        v.pdfRev[cur] = 0.0f;
        v.delta[cur] = 0;
        v.light[cur] = int16_t(sp.light);  // a Surface on an emitter keeps its light (s = 0)
        if (sp.material < 0) {  // camera walk: the path ends on the emitter
            v.kind[cur] = BptVertexKind::Light;
            continue;
        }
        v.kind[cur] = BptVertexKind::Surface;
        v.bsdf[cur] = materialAt(scene, sp, -rayDir(rh));
        v.delta[cur] = isDeltaMaterial(v.bsdf[cur].kind) ? 1 : 0;
        if (idx + 1 >= v.maxCount[slot]) continue;  // the walk ends here
        b.hitPath[h] = uint32_t(i);
        b.hitBsdf[h] = v.bsdf[cur];
        ++h;
    }
    b.numHits = h;
}

void groupBptHits(BptBatch& b) {
    groupByMaterialKind(b.hitBsdf.data(), b.numHits, b.order.data(), b.kindStart);
}

template <class U>
void sampleBptBsdfs(const Scene& scene, BptBatch& b, BptVertices& v, bool cameraWalk, const U& u) {
    constexpr int kRouletteDepth = 3;
    const TransportMode mode = cameraWalk ? TransportMode::Radiance : TransportMode::Importance;
    const BptStream stream = cameraWalk ? kBptCamera : kBptLight;
    forEachMaterialKind([&](auto kind) {
        using B = BsdfOf<decltype(kind)::value>;
        for (uint32_t k = b.kindStart[int(kind.value)]; k < b.kindStart[int(kind.value) + 1]; ++k) {
            const uint32_t h = b.order[k], path = b.hitPath[h], slot = b.pathSlot[path];
            const int d = v.count[slot] - 1;
            const size_t cur = v.at(slot, d), prev = v.at(slot, d - 1);
            auto j = [&](uint32_t m) { return cameraWalk ? bptCamVertexJ(d, m) : bptLightVertexJ(d, m); };
            b.alive[h] = 0;
            v.delta[cur] = B::delta ? 1 : 0;
            const Frame& fr = v.shading[cur];
            const Vec3 woW = -rayDir(b.ray[path]);
            Vec3 wo = fr.toLocal(woW);
            BsdfSample s;
            if (!B::sample(v.bsdf[cur], wo, u(slot, stream, j(0)), u(slot, stream, j(1)), u(slot, stream, j(2)), mode, s))
                continue;
            if (!(s.pdf > 0) || isBlack(s.f)) continue;
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
            v.pdfRev[prev] = v.kind[prev] == BptVertexKind::Env
                                 ? pdfRev
                                 : solidAngleToArea(pdfRev, v.p[cur], v.p[prev], v.ng[prev],
                                                    v.kind[prev] != BptVertexKind::Camera);
            if (b.roulette && d >= kRouletteDepth) {
                float q = cameraWalk ? std::min(1.0f, maxComponent(beta))
                                     : std::min(1.0f, maxComponent(beta) / b.betaScale[slot]);
                if (!(u(slot, stream, j(3)) < q)) continue;
                beta = beta / q;
            }
            b.alive[h] = 1;
            b.nextDir[h] = wi;
            b.pathBeta[path] = beta;  // read back by advanceBptPaths (path >= h)
            b.pathPdf[path] = pdfFwd;
        }
    });
}
template void sampleBptBsdfs(const Scene&, BptBatch&, BptVertices&, bool, const HashedSamples&);
template void sampleBptBsdfs(const Scene&, BptBatch&, BptVertices&, bool, const StoredSamples&);

template <class U>
void walkBpt(const Scene& scene, BptBatch& b, BptVertices& v, bool cameraWalk, bool coherentFirst, PtCounters& counters,
             const U& u) {
    for (bool first = true; b.numPaths > 0; first = false) {
        intersectBptPaths(scene, b, coherentFirst && first, counters);
        resolveBptHits(scene, b, v, cameraWalk);
        if (b.numHits == 0) break;
        groupBptHits(b);
        sampleBptBsdfs(scene, b, v, cameraWalk, u);
        advanceBptPaths(scene, b, v);
    }
}
template void walkBpt(const Scene&, BptBatch&, BptVertices&, bool, bool, PtCounters&, const HashedSamples&);
template void walkBpt(const Scene&, BptBatch&, BptVertices&, bool, bool, PtCounters&, const StoredSamples&);

void advanceBptPaths(const Scene& scene, BptBatch& b, const BptVertices& v) {
    size_t n = 0;
    for (size_t h = 0; h < b.numHits; ++h) {
        if (!b.alive[h]) continue;
        const uint32_t path = b.hitPath[h];  // path >= h >= n: in place is safe
        const uint32_t slot = b.pathSlot[path];
        const size_t cur = v.at(slot, v.count[slot] - 1);
        b.pathSlot[n] = slot;
        b.pathBeta[n] = b.pathBeta[path];
        b.pathPdf[n] = b.pathPdf[path];
        setRayHit(b.ray[n], scene.offsetRayOrigin(v.p[cur], v.ng[cur], b.nextDir[h]), b.nextDir[h]);
        ++n;
    }
    b.numPaths = n;
}

}  // namespace wmlt
