#include "stages/bpt_stages.h"

#include "kernels/mis.h"
#include "kernels/rng.h"
#include "scene/scene_lights.h"
#include "stages/bsdf_dispatch.h"
#include "stages/surface.h"
#include "stages/trace.h"

namespace wmlt {

namespace {

inline Vec3 rayDir(const RTCRayHit& r) { return {r.ray.dir_x, r.ray.dir_y, r.ray.dir_z}; }

inline float dim(uint64_t key, BptStream s, uint32_t j) { return sampleDimension(key, bptDim(s, j)); }

inline uint32_t rasterPixel(const Camera& cam, float px, float py) {
    int x = std::min(int(px), cam.width - 1), y = std::min(int(py), cam.height - 1);
    return uint32_t(y) * uint32_t(cam.width) + uint32_t(x);
}

// Solid-angle density at `from` towards `to` converted to area density at `to` (normal n;
// cosine omitted for the camera, whose points are not on a surface).
inline float toArea(float pdfSa, Vec3 from, Vec3 to, Vec3 n, bool onSurface) {
    Vec3 d = to - from;
    float d2 = lengthSquared(d);
    if (!(d2 > 0)) return 0.0f;
    float c = onSurface ? std::fabs(dot(n, d)) / std::sqrt(d2) : 1.0f;
    return pdfSa * c / d2;
}

// Shading-normal correction of the adjoint BSDF (as in lt_stages.cpp): wo towards the
// light side, wi onwards.
inline float shadingCorrection(Vec3 wo, Vec3 wi, Vec3 ns, Vec3 ng) {
    float den = std::fabs(dot(wo, ng)) * std::fabs(dot(wi, ns));
    return den > 0 ? std::fabs(dot(wo, ns)) * std::fabs(dot(wi, ng)) / den : 0.0f;
}

// Normal of a light's point p (the emitting side).
inline Vec3 lightNormalAt(const Light& l, Vec3 p) {
    return l.type == LightType::Sphere ? normalize(p - l.center) : l.n;
}

// Emission position density times the choice pmf (light subpaths' y_0).
inline float lightOriginPdf(const Scene& scene, int li) {
    return scene.lightDistribution.discretePmf(li) / scene.lights[li].area;
}

// Emission direction density (cosine about n) towards `to`, as area density at `to`.
inline float lightDirPdfArea(Vec3 p, Vec3 n, Vec3 to, Vec3 nTo, bool toOnSurface) {
    Vec3 d = to - p;
    float dist = length(d);
    if (!(dist > 0)) return 0.0f;
    float c = dot(n, d) / dist;
    return c > 0 ? toArea(c * kInvPi, p, to, nTo, toOnSurface) : 0.0f;
}

// A vertex of the path being weighted, in the light-to-camera order x_0 .. x_k.
struct PathVertex {
    Vec3 p, ng;
    const Frame* shading = nullptr;
    const BsdfParams* bsdf = nullptr;
    BptVertexKind kind = BptVertexKind::Surface;
};

// Density of scattering at v from direction wo towards wi (world, unit), solid angle.
inline float scatterPdf(const PathVertex& v, Vec3 wo, Vec3 wi) {
    return bsdfPdf(*v.bsdf, v.shading->toLocal(wo), v.shading->toLocal(wi));
}

inline Vec3 dirTo(Vec3 a, Vec3 b) { return normalize(b - a); }

// Solid-angle density at `from` converted to the measure of vertex `to`: area for surface
// and light points (the camera: no cosine), unchanged (solid angle) for the environment.
inline float pdfAt(float pdfSa, Vec3 from, const PathVertex& to) {
    if (to.kind == BptVertexKind::Env) return pdfSa;
    return toArea(pdfSa, from, to.p, to.ng, to.kind != BptVertexKind::Camera);
}

// Density with which a light subpath starts at x0 (light li): emission position times
// the choice pmf; the environment: its direction's density times the pmf.
inline float originPdf(const Scene& scene, int li, const PathVertex& x0) {
    if (x0.kind == BptVertexKind::Env)
        return scene.lightDistribution.discretePmf(li) * scene.env.pdf(-x0.ng);
    return lightOriginPdf(scene, li);
}

// Density of x1 as the first scattering vertex of a light subpath from x0: emitted
// direction (cosine about the normal) as area density; the environment: the emission
// disc's density 1 / (pi R^2) projected onto x1's surface.
inline float emissionPdfAt(const Scene& scene, const PathVertex& x0, const PathVertex& x1) {
    if (x0.kind == BptVertexKind::Env)
        return std::fabs(dot(x1.ng, x0.ng)) / (kPi * scene.radius * scene.radius);
    return lightDirPdfArea(x0.p, x0.ng, x1.p, x1.ng, x1.kind != BptVertexKind::Camera);
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
                stratifiedRasterPoint(x, y, s, n, dim(key, kBptCamera, 0), dim(key, kBptCamera, 1), px, py);
                Vec3 o, d;
                generateCameraRay(cam, px, py, lens ? dim(key, kBptCamera, 2) : 0.5f,
                                  lens ? dim(key, kBptCamera, 3) : 0.5f, o, d);
                b.pixel[i] = pixel;
                b.key[i] = key;
                b.L[i] = Vec3(0.0f);
                const size_t z0 = b.cam.at(uint32_t(i), 0);
                b.cam.count[i] = 1;
                b.cam.p[z0] = o;
                b.cam.ng[z0] = cam.forward;
                b.cam.beta[z0] = Vec3(1.0f);
                b.cam.pdfFwd[z0] = 1.0f;
                b.cam.pdfRev[z0] = 0.0f;
                b.cam.delta[z0] = 0;
                b.cam.kind[z0] = BptVertexKind::Camera;
                b.pathSlot[i] = uint32_t(i);
                setRayHit(b.ray[i], o, d);
                b.pathPdf[i] = cameraPdfDir(cam, o, d);
                b.pathBeta[i] = Vec3(1.0f);
            }
        }
    b.numSlots = i;
    b.numPaths = i;
}

void generateBptLightPaths(const Scene& scene, BptBatch& b) {
    size_t n = 0;
    for (size_t i = 0; i < b.numSlots; ++i) {
        b.light.count[i] = 0;
        if (scene.lights.empty() || b.light.capacity < 1) continue;
        const uint64_t key = b.key[i];
        float pmf;
        int li = scene.lightDistribution.sampleDiscrete(dim(key, kBptLight, 0), &pmf);
        LightEmission e;
        if (!(pmf > 0) || !sampleLightEmission(scene, li, dim(key, kBptLight, 1), dim(key, kBptLight, 2),
                                               dim(key, kBptLight, 3), dim(key, kBptLight, 4), e))
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
        if (b.light.capacity < 2) continue;
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
            if (idx >= v.capacity) continue;
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
        if (sp.light >= 0 && !cameraWalk) continue;  // emitters absorb light subpaths
        const uint32_t slot = b.pathSlot[i];
        const int idx = v.count[slot];
        if (idx >= v.capacity) continue;
        const size_t prev = v.at(slot, idx - 1), cur = v.at(slot, idx);
        v.count[slot] = uint8_t(idx + 1);
        v.p[cur] = sp.p;
        v.ng[cur] = sp.ng;
        v.shading[cur] = Frame::fromNormal(sp.ns);
        v.beta[cur] = b.pathBeta[i];
        v.pdfFwd[cur] = v.kind[prev] == BptVertexKind::Env
                            ? b.pathPdf[i] * std::fabs(dot(sp.ng, rayDir(rh)))  // disc density projected
                            : toArea(b.pathPdf[i], v.p[prev], sp.p, sp.ng, true);
        v.pdfRev[cur] = 0.0f;
        v.delta[cur] = 0;
        if (sp.light >= 0) {  // camera walk: the path ends on the emitter
            v.kind[cur] = BptVertexKind::Light;
            v.light[cur] = int16_t(sp.light);
            continue;
        }
        v.kind[cur] = BptVertexKind::Surface;
        v.bsdf[cur] = materialAt(scene, sp);
        v.delta[cur] = isDeltaMaterial(v.bsdf[cur].kind) ? 1 : 0;
        if (idx + 1 >= v.capacity) continue;  // no room for a further vertex
        b.hitPath[h] = uint32_t(i);
        b.hitBsdf[h] = v.bsdf[cur];
        ++h;
    }
    b.numHits = h;
}

void groupBptHits(BptBatch& b) {
    groupByMaterialKind(b.hitBsdf.data(), b.numHits, b.order.data(), b.kindStart);
}

void sampleBptBsdfs(const Scene& scene, BptBatch& b, BptVertices& v, bool cameraWalk) {
    constexpr int kRouletteDepth = 3;
    const TransportMode mode = cameraWalk ? TransportMode::Radiance : TransportMode::Importance;
    const BptStream stream = cameraWalk ? kBptCamera : kBptLight;
    forEachMaterialKind([&](auto kind) {
        using B = BsdfOf<decltype(kind)::value>;
        for (uint32_t k = b.kindStart[int(kind.value)]; k < b.kindStart[int(kind.value) + 1]; ++k) {
            const uint32_t h = b.order[k], path = b.hitPath[h], slot = b.pathSlot[path];
            const uint64_t key = b.key[slot];
            const int d = v.count[slot] - 1;
            const size_t cur = v.at(slot, d), prev = v.at(slot, d - 1);
            auto j = [&](uint32_t m) { return cameraWalk ? bptCamVertexJ(d, m) : bptLightVertexJ(d, m); };
            b.alive[h] = 0;
            v.delta[cur] = B::delta ? 1 : 0;
            const Frame& fr = v.shading[cur];
            const Vec3 woW = -rayDir(b.ray[path]);
            Vec3 wo = fr.toLocal(woW);
            BsdfSample s;
            if (!B::sample(v.bsdf[cur], wo, dim(key, stream, j(0)), dim(key, stream, j(1)), dim(key, stream, j(2)),
                           mode, s))
                continue;
            if (!(s.pdf > 0) || isBlack(s.f)) continue;
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
                                 : toArea(pdfRev, v.p[cur], v.p[prev], v.ng[prev], v.kind[prev] != BptVertexKind::Camera);
            if (d >= kRouletteDepth) {
                float q = cameraWalk ? std::min(1.0f, maxComponent(beta))
                                     : std::min(1.0f, maxComponent(beta) / b.betaScale[slot]);
                if (!(dim(key, stream, j(3)) < q)) continue;
                beta = beta / q;
            }
            b.alive[h] = 1;
            b.nextDir[h] = wi;
            b.pathBeta[path] = beta;  // read back by advanceBptPaths (path >= h)
            b.pathPdf[path] = pdfFwd;
        }
    });
}

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

namespace {

// Appends a shadow ray from `from` (normal nFrom) to `to` (normal nTo; nTo = 0: a point
// not on a surface, the lens or a light point aimed at as the PT does) with its value.
inline void pushConnection(const Scene& scene, BptBatch& b, Vec3 from, Vec3 nFrom, Vec3 to, Vec3 nTo,
                           uint32_t target, bool splat, int pathLength, Vec3 value, PtCounters& c,
                           bool infinite = false) {
    if (b.numConn == b.connCapacity) traceBptConnections(scene, b, c);
    if (infinite) {  // towards the environment in direction `to`
        setRay(b.conn[b.numConn], scene.offsetRayOrigin(from, nFrom, to), to, 0.0f, INFINITY);
        b.connSlot[b.numConn] = target;
        b.connSplat[b.numConn] = splat ? 1 : 0;
        b.connLength[b.numConn] = uint8_t(pathLength);
        b.connValue[b.numConn] = value;
        ++b.numConn;
        return;
    }
    Vec3 w = to - from;
    if (!(lengthSquared(w) > 0)) return;
    w = normalize(w);
    Vec3 origin = scene.offsetRayOrigin(from, nFrom, w);
    Vec3 end = isBlack(nTo) ? to : scene.offsetRayOrigin(to, nTo, -w);
    Vec3 d = end - origin;
    float dist = length(d);
    if (!(dist > 0)) return;
    setRay(b.conn[b.numConn], origin, d / dist, 0.0f, dist * (1.0f - 1e-4f));
    b.connSlot[b.numConn] = target;
    b.connSplat[b.numConn] = splat ? 1 : 0;
    b.connLength[b.numConn] = uint8_t(pathLength);
    b.connValue[b.numConn] = value;
    ++b.numConn;
}

inline void addCameraSide(BptBatch& b, uint32_t slot, Vec3 v, int length) {
    if (!isFinite(v)) { ++b.nonfinite; return; }
    if (isBlack(v)) return;
    b.L[slot] += v;
    b.lengths.add(length, v);
}

}  // namespace

void traceBptConnections(const Scene& scene, BptBatch& b, PtCounters& c) {
    traceOccluded(scene.rtc, b.conn.data(), b.numConn);
    c.raysOccluded += b.numConn;
    for (size_t i = 0; i < b.numConn; ++i) {
        if (!(b.conn[i].tfar >= 0)) continue;
        const Vec3 v = b.connValue[i];
        if (b.connSplat[i]) {
            if (!isFinite(v)) { ++b.nonfinite; continue; }
            if (isBlack(v)) continue;
            b.splats.push_back({b.connSlot[i], v});
            b.lengths.add(b.connLength[i], v);
        } else {
            addCameraSide(b, b.connSlot[i], v, b.connLength[i]);
        }
    }
    b.numConn = 0;
}

void connectBpt(const Scene& scene, BptBatch& b, int minLength, int maxLength, float misBeta, PtCounters& counters) {
    const Camera& cam = scene.camera;
    constexpr int N = kMaxPathLength + 2;
    PathVertex x[N];
    float pL[N], pE[N];
    uint8_t delta[N];
    const bool haveLights = !scene.lights.empty();
    b.numConn = 0;
    for (uint32_t slot = 0; slot < b.numSlots; ++slot) {
        const uint64_t key = b.key[slot];
        const int nC = b.cam.count[slot], nL = b.light.count[slot];
        for (int t = 1; t <= nC; ++t) {
            const size_t zi = b.cam.at(slot, t - 1);
            const BptVertexKind zKind = b.cam.kind[zi];
            for (int s = 0; s <= std::max(nL, 1); ++s) {
                const int k = s + t - 1;
                if (k < std::max(1, minLength) || k > maxLength) continue;
                // Which strategies exist for these subpaths.
                if (s == 0 && zKind != BptVertexKind::Light && zKind != BptVertexKind::Env) continue;
                if (s >= 1 && t >= 2 && (zKind != BptVertexKind::Surface || b.cam.delta[zi])) continue;
                if (s == 1 && t >= 2 && !haveLights) continue;
                if (s >= 2 || (s == 1 && t == 1)) {
                    if (s > nL) continue;
                    const size_t yi = b.light.at(slot, s - 1);
                    if (b.light.delta[yi]) continue;
                    if (s == 1 && b.light.kind[yi] == BptVertexKind::Env) continue;  // at infinity
                }
                // The path x_0 .. x_k from the stored vertices.
                for (int i = 0; i <= k; ++i) {
                    const BptVertices& v = i < s ? b.light : b.cam;
                    const size_t a = i < s ? b.light.at(slot, i) : b.cam.at(slot, k - i);
                    x[i].p = v.p[a];
                    x[i].ng = v.ng[a];
                    x[i].shading = &v.shading[a];
                    x[i].bsdf = &v.bsdf[a];
                    x[i].kind = v.kind[a];
                    pL[i] = i < s ? v.pdfFwd[a] : v.pdfRev[a];
                    pE[i] = i < s ? v.pdfRev[a] : v.pdfFwd[a];
                    delta[i] = v.delta[a];
                }
                Vec3 value(0.0f);
                int li = -1;
                Frame lightFrame;
                BsdfParams noBsdf;
                CameraSample cs;
                // Sample the new endpoint (s = 1, t >= 2: a light point; t = 1: a lens
                // point) and evaluate the unweighted contribution.
                if (s == 0) {
                    li = b.cam.light[zi];
                    Vec3 Le = x[0].kind == BptVertexKind::Env ? scene.env.Le(-x[0].ng)
                                                              : areaLe(scene.lights[li], x[0].ng, dirTo(x[0].p, x[1].p));
                    value = b.cam.beta[zi] * Le;
                } else if (s == 1 && t >= 2) {
                    float pmf;
                    li = scene.lightDistribution.sampleDiscrete(dim(key, kBptConnect, bptNeeJ(t, 0)), &pmf);
                    LightSample ls;
                    if (!(pmf > 0) || !sampleLightFrom(scene, li, x[1].p, dim(key, kBptConnect, bptNeeJ(t, 1)),
                                                       dim(key, kBptConnect, bptNeeJ(t, 2)), ls))
                        continue;
                    const bool infinite = std::isinf(ls.dist);
                    x[0].p = ls.p;
                    x[0].ng = infinite ? -ls.wi : lightNormalAt(scene.lights[li], ls.p);
                    lightFrame = Frame::fromNormal(x[0].ng);
                    x[0].shading = &lightFrame;
                    x[0].bsdf = &noBsdf;
                    x[0].kind = infinite ? BptVertexKind::Env : BptVertexKind::Light;
                    pL[0] = originPdf(scene, li, x[0]);
                    pE[0] = 0;
                    delta[0] = 0;
                    const Frame& fr = *x[1].shading;
                    Vec3 wi = fr.toLocal(ls.wi);
                    Vec3 f = bsdfF(*x[1].bsdf, fr.toLocal(dirTo(x[1].p, x[2].p)), wi) * absCosTheta(wi);
                    value = b.cam.beta[zi] * f * ls.Le / (pmf * ls.pdf);
                } else if (t == 1) {
                    const size_t yi = b.light.at(slot, s - 1);
                    cs = sampleCameraFrom(cam, x[s - 1].p, dim(key, kBptConnect, bptLensJ(s, 0)),
                                          dim(key, kBptConnect, bptLensJ(s, 1)));
                    if (!cs.valid) continue;
                    x[k].p = cs.lens;
                    x[k].ng = cam.forward;
                    x[k].kind = BptVertexKind::Camera;
                    delta[k] = 0;
                    const PathVertex& y = x[s - 1];
                    if (s == 1) {
                        li = b.light.light[yi];
                        Vec3 Le = areaLe(scene.lights[li], y.ng, cs.wi);
                        value = b.light.beta[yi] * Le * (std::fabs(dot(cs.wi, y.ng)) * cs.We / cs.pdf);
                    } else {
                        const Frame& fr = *y.shading;
                        Vec3 toPrev = dirTo(y.p, x[s - 2].p);
                        Vec3 wiL = fr.toLocal(cs.wi);
                        Vec3 f = bsdfF(*y.bsdf, wiL, fr.toLocal(toPrev));
                        float corr = shadingCorrection(toPrev, cs.wi, fr.n, y.ng);
                        value = b.light.beta[yi] * f * (absCosTheta(wiL) * corr * cs.We / cs.pdf);
                    }
                } else {  // s, t >= 2
                    const size_t yi = b.light.at(slot, s - 1);
                    const PathVertex& y = x[s - 1];
                    const PathVertex& z = x[s];
                    Vec3 d = z.p - y.p;
                    float dist2 = lengthSquared(d);
                    if (!(dist2 > 0)) continue;
                    Vec3 w = d / std::sqrt(dist2);  // from y to z
                    const Frame& fy = *y.shading;
                    const Frame& fz = *z.shading;
                    Vec3 toPrevY = dirTo(y.p, x[s - 2].p), toPrevZ = dirTo(z.p, x[s + 1].p);
                    Vec3 wy = fy.toLocal(w), wz = fz.toLocal(-w);
                    Vec3 f1 = bsdfF(*y.bsdf, wy, fy.toLocal(toPrevY)) * shadingCorrection(toPrevY, w, fy.n, y.ng);
                    Vec3 f2 = bsdfF(*z.bsdf, fz.toLocal(toPrevZ), wz);
                    float G = absCosTheta(wy) * absCosTheta(wz) / dist2;
                    value = b.light.beta[yi] * f1 * f2 * b.cam.beta[zi] * G;
                }
                if (isBlack(value)) continue;
                delta[0] = 0;
                delta[k] = 0;
                const bool x0Infinite = x[0].kind == BptVertexKind::Env;
                if (!bptStrategyValid(k, s, delta, x0Infinite)) continue;
                // Densities the other side's walk would have used at the connection.
                if (s == 0) {
                    pL[0] = originPdf(scene, li, x[0]);
                    if (k >= 2) pL[1] = emissionPdfAt(scene, x[0], x[1]);
                } else {
                    if (t == 1)
                        pE[s - 1] = pdfAt(cameraPdfDir(cam, x[k].p, dirTo(x[k].p, x[s - 1].p)), x[k].p, x[s - 1]);
                    else
                        pE[s - 1] = pdfAt(scatterPdf(x[s], dirTo(x[s].p, x[s + 1].p), dirTo(x[s].p, x[s - 1].p)),
                                          x[s].p, x[s - 1]);
                    if (s >= 2)
                        pE[s - 2] = pdfAt(scatterPdf(x[s - 1], dirTo(x[s - 1].p, x[s].p), dirTo(x[s - 1].p, x[s - 2].p)),
                                          x[s - 1].p, x[s - 2]);
                    if (s < k) {
                        pL[s] = s == 1 ? emissionPdfAt(scene, x[0], x[1])
                                       : toArea(scatterPdf(x[s - 1], dirTo(x[s - 1].p, x[s - 2].p),
                                                           dirTo(x[s - 1].p, x[s].p)),
                                                x[s - 1].p, x[s].p, x[s].ng, true);
                        if (s + 1 < k)
                            pL[s + 1] = toArea(scatterPdf(x[s], dirTo(x[s].p, x[s - 1].p), dirTo(x[s].p, x[s + 1].p)),
                                               x[s].p, x[s + 1].p, x[s + 1].ng, true);
                    }
                }
                // x_0 under next-event estimation from x_1 (k = 1: s = 1 is the light
                // subpath's own vertex connected to the camera).
                int l0 = s == 0 ? li : (s == 1 && t >= 2) ? li : b.light.light[b.light.at(slot, 0)];
                float pL0Nee = pL[0];
                if (k >= 2) {
                    Vec3 w = dirTo(x[1].p, x[0].p);
                    if (x0Infinite) w = -x[0].ng;
                    pL0Nee = pdfAt(lightPdfFrom(scene, l0, x[1].p, x[0].p, w), x[1].p, x[0]);
                }
                const float wgt = bptMisWeight(k, s, pL, pE, delta, pL0Nee, misBeta, x0Infinite);
                if (!(wgt > 0)) continue;
                value = value * wgt;
                if (s == 0) {
                    addCameraSide(b, slot, value, k);
                } else if (t == 1) {
                    pushConnection(scene, b, x[s - 1].p, x[s - 1].ng, x[k].p, Vec3(0.0f),
                                   rasterPixel(cam, cs.px, cs.py), true, k, value, counters);
                } else if (s == 1) {
                    if (x0Infinite)
                        pushConnection(scene, b, x[1].p, x[1].ng, -x[0].ng, Vec3(0.0f), slot, false, k, value, counters, true);
                    else
                        pushConnection(scene, b, x[1].p, x[1].ng, x[0].p, Vec3(0.0f), slot, false, k, value, counters);
                } else {
                    pushConnection(scene, b, x[s - 1].p, x[s - 1].ng, x[s].p, x[s].ng, slot, false, k, value, counters);
                }
            }
        }
    }
    traceBptConnections(scene, b, counters);
}

}  // namespace wmlt
