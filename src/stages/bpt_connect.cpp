// Connecting BPT's subpaths: one strategy (s, t) of a slot at a time (evaluateStrategy),
// used by BPT for all strategies of each slot (connectBpt) and by MMLT for the one
// strategy each chain's proposal picked (connectStrategies). Visibility is decided by
// batched shadow rays (traceBptConnections).
#include "kernels/mis.h"
#include "scene/scene_lights.h"
#include "stages/bpt_stages.h"
#include "stages/trace.h"

namespace wmlt {

namespace {

// Emission direction density (cosine about n) towards `to`, as area density at `to`.
inline float lightDirPdfArea(Vec3 p, Vec3 n, Vec3 to, Vec3 nTo, bool toOnSurface) {
    Vec3 d = to - p;
    float dist = length(d);
    if (!(dist > 0)) return 0.0f;
    float c = dot(n, d) / dist;
    return c > 0 ? solidAngleToArea(c * kInvPi, p, to, nTo, toOnSurface) : 0.0f;
}

// Density of scattering at v from direction wo towards wi (world, unit), solid angle.
inline float scatterPdf(const PathVertex& v, Vec3 wo, Vec3 wi) {
    return bsdfPdf(*v.bsdf, v.shading->toLocal(wo), v.shading->toLocal(wi));
}

inline Vec3 dirTo(Vec3 a, Vec3 b) { return normalize(b - a); }

// Solid-angle density at `from` converted to the measure of vertex `to`: area for surface
// and light points (the camera: no cosine), unchanged (solid angle) for the environment.
inline float pdfAt(float pdfSa, Vec3 from, const PathVertex& to) {
    if (to.kind == BptVertexKind::Env) return pdfSa;
    return solidAngleToArea(pdfSa, from, to.p, to.ng, to.kind != BptVertexKind::Camera);
}

// Density with which a light subpath starts at x0 (light li): emission position times
// the choice pmf; the environment: its direction's density times the pmf; a point
// light: the pmf (its position is a discrete choice).
inline float originPdf(const Scene& scene, int li, const PathVertex& x0) {
    const float pmf = scene.lightDistribution.discretePmf(li);
    if (x0.kind == BptVertexKind::Env) return pmf * scene.env.pdf(-x0.ng);
    if (isDeltaLight(scene.lights[li])) return pmf;
    return pmf / scene.lights[li].area;
}

// Density of x1 as the first scattering vertex of a light subpath from x0 (light li):
// emitted direction (cosine about the normal; a point light: uniform) as area density;
// the environment: the emission disc's density 1 / (pi R^2) projected onto x1's surface.
inline float emissionPdfAt(const Scene& scene, int li, const PathVertex& x0, const PathVertex& x1) {
    if (x0.kind == BptVertexKind::Env)
        return std::fabs(dot(x1.ng, x0.ng)) / (kPi * scene.radius * scene.radius);
    if (isDeltaLight(scene.lights[li])) return solidAngleToArea(kUniformSpherePdf, x0.p, x1.p, x1.ng, x1.kind != BptVertexKind::Camera);
    return lightDirPdfArea(x0.p, x0.ng, x1.p, x1.ng, x1.kind != BptVertexKind::Camera);
}

// Appends the shadow ray of a strategy sample (target: the slot, or for a t = 1 splat
// its raster pixel).
inline void pushConnection(const Scene& scene, BptBatch& b, const StrategySample& ss, uint32_t target, bool splat,
                           int s, int pathLength, RayCounters& c) {
    if (b.numConn == b.connCapacity) traceBptConnections(scene, b, c);
    if (ss.infinite) {  // towards the environment in direction `to`
        setRay(b.conn[b.numConn], scene.offsetRayOrigin(ss.from, ss.nFrom, ss.to), ss.to, 0.0f, INFINITY);
    } else {
        Vec3 w = ss.to - ss.from;
        if (!(lengthSquared(w) > 0)) return;
        w = normalize(w);
        Vec3 origin = scene.offsetRayOrigin(ss.from, ss.nFrom, w);
        Vec3 end = isBlack(ss.nTo) ? ss.to : scene.offsetRayOrigin(ss.to, ss.nTo, -w);
        Vec3 d = end - origin;
        float dist = length(d);
        if (!(dist > 0)) return;
        setRay(b.conn[b.numConn], origin, d / dist, 0.0f, dist * (1.0f - 1e-4f));
    }
    b.connSlot[b.numConn] = target;
    b.connSplat[b.numConn] = splat ? 1 : 0;
    b.connLength[b.numConn] = uint8_t(pathLength);
    b.connValue[b.numConn] = ss.value;
    b.connWeight[b.numConn] = ss.weight;
    b.connS[b.numConn] = uint8_t(s);
    ++b.numConn;
}

// A camera-side contribution (t >= 2) of strategy s to slot's pixel.
inline void addCameraSide(BptBatch& b, uint32_t slot, Vec3 unweighted, float weight, int s, int length) {
    const Vec3 v = unweighted * weight;
    if (!b.tally.take(v, length)) return;
    b.L[slot] += v;
    if (b.strategyFilms) b.strategyFilms->addCamera(b.pixel[slot], s, length + 1 - s, v, unweighted);
}

}  // namespace

template <class U>
bool evaluateStrategy(const Scene& scene, const BptBatch& b, uint32_t slot, int s, int t, const U& u, float misBeta,
                      StrategyScratch& scratch, StrategySample& out) {
    const Camera& cam = scene.camera;
    const int k = s + t - 1;
    const int nC = b.cam.count[slot], nL = b.light.count[slot];
    if (t < 1 || t > nC || k < 1) return false;
    const size_t zi = b.cam.at(slot, t - 1);
    const BptVertexKind zKind = b.cam.kind[zi];
    // Which strategies exist for these subpaths.
    // s = 0: the camera subpath ends on an emitter (a Surface vertex of an emitter with a
    // material both ends this path and scatters for the longer ones).
    const bool zEmits = zKind == BptVertexKind::Light || zKind == BptVertexKind::Env ||
                        (zKind == BptVertexKind::Surface && b.cam.light[zi] >= 0);
    if (s == 0 && !zEmits) return false;
    // A connection needs a non-delta lobe at both ends, whichever lobe the walk took there.
    if (s >= 1 && t >= 2 && (zKind != BptVertexKind::Surface || isDeltaMaterial(b.cam.bsdf[zi].kind))) return false;
    if (s == 1 && t >= 2 && scene.lights.empty()) return false;
    if (s >= 2 || (s == 1 && t == 1)) {
        if (s > nL) return false;
        const size_t yi = b.light.at(slot, s - 1);
        if (b.light.kind[yi] == BptVertexKind::Surface && isDeltaMaterial(b.light.bsdf[yi].kind)) return false;
        if (s == 1 && b.light.kind[yi] == BptVertexKind::Env) return false;  // at infinity
    }
    PathVertex* x = scratch.x;
    float* pL = scratch.pL;
    float* pE = scratch.pE;
    uint8_t* delta = scratch.delta;
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
    CameraSample cs;
    // s, t >= 2: the directions at the connection's ends in their shading frames, used by
    // both the BSDFs and the densities: towards the previous vertex (woY, woZ) and along
    // the connection (wy from y to z, wz from z to y).
    Vec3 woY, wy, woZ, wz;
    auto uc = [&](uint32_t m) { return u(slot, kBptConnect, U::connectJ(s, t, m)); };
    out.shadowRay = s > 0;
    out.infinite = false;
    out.nTo = Vec3(0.0f);
    // Sample the new endpoint (s = 1, t >= 2: a light point; t = 1: a lens point) and
    // evaluate the unweighted contribution.
    if (s == 0) {
        li = b.cam.light[zi];
        if (x[0].kind == BptVertexKind::Surface) x[0].kind = BptVertexKind::Light;  // the path's light end
        Vec3 Le = x[0].kind == BptVertexKind::Env ? scene.env.Le(-x[0].ng)
                                                  : areaLe(scene.lights[li], x[0].ng, dirTo(x[0].p, x[1].p));
        value = b.cam.beta[zi] * Le;
    } else if (s == 1 && t >= 2) {
        float pmf;
        li = scene.lightDistribution.sampleDiscrete(uc(0), &pmf);
        LightSample ls;
        if (!(pmf > 0) || !sampleLightFrom(scene, li, x[1].p, uc(1), uc(2), ls)) return false;
        const bool infinite = std::isinf(ls.dist);
        x[0].p = ls.p;
        x[0].ng = infinite ? -ls.wi : ls.n;
        scratch.lightFrame = Frame::fromNormal(x[0].ng);
        x[0].shading = &scratch.lightFrame;
        x[0].bsdf = &scratch.noBsdf;
        x[0].kind = infinite ? BptVertexKind::Env : BptVertexKind::Light;
        pL[0] = originPdf(scene, li, x[0]);
        pE[0] = 0;
        delta[0] = 0;
        const Frame& fr = *x[1].shading;
        Vec3 wi = fr.toLocal(ls.wi);
        Vec3 f = bsdfF(*x[1].bsdf, fr.toLocal(dirTo(x[1].p, x[2].p)), wi) * absCosTheta(wi);
        value = b.cam.beta[zi] * f * ls.Le / (pmf * ls.pdf);
        out.from = x[1].p;
        out.nFrom = x[1].ng;
        out.infinite = infinite;
        out.to = infinite ? -x[0].ng : x[0].p;
    } else if (t == 1) {
        const size_t yi = b.light.at(slot, s - 1);
        cs = sampleCameraFrom(cam, x[s - 1].p, uc(0), uc(1));
        if (!cs.valid) return false;
        x[k].p = cs.lens;
        x[k].ng = cam.forward;
        x[k].kind = BptVertexKind::Camera;
        delta[k] = 0;
        const PathVertex& y = x[s - 1];
        if (s == 1) {
            li = b.light.light[yi];
            if (isDeltaLight(scene.lights[li])) return false;  // a point light is not seen
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
        out.from = y.p;
        out.nFrom = y.ng;
        out.to = cs.lens;
        out.pixel = rasterPixel(cam, cs.px, cs.py);
    } else {  // s, t >= 2
        const size_t yi = b.light.at(slot, s - 1);
        const PathVertex& y = x[s - 1];
        const PathVertex& z = x[s];
        Vec3 d = z.p - y.p;
        float dist2 = lengthSquared(d);
        if (!(dist2 > 0)) return false;
        Vec3 w = d / std::sqrt(dist2);  // from y to z
        const Frame& fy = *y.shading;
        const Frame& fz = *z.shading;
        Vec3 toPrevY = dirTo(y.p, x[s - 2].p), toPrevZ = dirTo(z.p, x[s + 1].p);
        wy = fy.toLocal(w);
        wz = fz.toLocal(-w);
        woY = fy.toLocal(toPrevY);
        woZ = fz.toLocal(toPrevZ);
        Vec3 f1 = bsdfF(*y.bsdf, wy, woY) * shadingCorrection(toPrevY, w, fy.n, y.ng);
        Vec3 f2 = bsdfF(*z.bsdf, woZ, wz);
        float G = absCosTheta(wy) * absCosTheta(wz) / dist2;
        value = b.light.beta[yi] * f1 * f2 * b.cam.beta[zi] * G;
        out.from = y.p;
        out.nFrom = y.ng;
        out.to = z.p;
        out.nTo = z.ng;
    }
    if (isBlack(value)) return false;
    delta[0] = 0;
    delta[k] = 0;
    // The connected path scatters by the non-delta lobes at the connection's two ends.
    if (s >= 1) delta[s - 1] = delta[s] = 0;
    const bool x0Infinite = x[0].kind == BptVertexKind::Env;
    if (!bptStrategyValid(k, s, delta, x0Infinite)) return false;
    // Densities the other side's walk would have used at the connection.
    const int l0 = s == 0 ? li : (s == 1 && t >= 2) ? li : b.light.light[b.light.at(slot, 0)];
    if (s == 0) {
        pL[0] = originPdf(scene, li, x[0]);
        if (k >= 2) pL[1] = emissionPdfAt(scene, li, x[0], x[1]);
    } else if (s >= 2 && t >= 2) {  // the directions above (dirTo(x[s].p, x[s - 1].p) is -w bit for bit)
        const BsdfParams &by = *x[s - 1].bsdf, &bz = *x[s].bsdf;
        pE[s - 1] = pdfAt(bsdfPdf(bz, woZ, wz), x[s].p, x[s - 1]);
        pE[s - 2] = pdfAt(bsdfPdf(by, wy, woY), x[s - 1].p, x[s - 2]);
        pL[s] = solidAngleToArea(bsdfPdf(by, woY, wy), x[s - 1].p, x[s].p, x[s].ng, true);
        if (s + 1 < k) pL[s + 1] = solidAngleToArea(bsdfPdf(bz, wz, woZ), x[s].p, x[s + 1].p, x[s + 1].ng, true);
    } else {
        if (t == 1)
            pE[s - 1] = pdfAt(cameraPdfDir(cam, x[k].p, dirTo(x[k].p, x[s - 1].p)), x[k].p, x[s - 1]);
        else
            pE[s - 1] = pdfAt(scatterPdf(x[s], dirTo(x[s].p, x[s + 1].p), dirTo(x[s].p, x[s - 1].p)), x[s].p, x[s - 1]);
        if (s >= 2)
            pE[s - 2] = pdfAt(scatterPdf(x[s - 1], dirTo(x[s - 1].p, x[s].p), dirTo(x[s - 1].p, x[s - 2].p)),
                              x[s - 1].p, x[s - 2]);
        if (s < k) {
            pL[s] = s == 1 ? emissionPdfAt(scene, l0, x[0], x[1])
                           : solidAngleToArea(scatterPdf(x[s - 1], dirTo(x[s - 1].p, x[s - 2].p), dirTo(x[s - 1].p, x[s].p)),
                                              x[s - 1].p, x[s].p, x[s].ng, true);
            if (s + 1 < k)
                pL[s + 1] = solidAngleToArea(scatterPdf(x[s], dirTo(x[s].p, x[s - 1].p), dirTo(x[s].p, x[s + 1].p)),
                                             x[s].p, x[s + 1].p, x[s + 1].ng, true);
        }
    }
    // x_0 under next-event estimation from x_1 (k = 1: s = 1 is the light subpath's own
    // vertex connected to the camera). A point light: NEE chooses it as emission does
    // (the pmf), and no camera path reaches it (s = 0 has no density).
    const bool x0Delta = isDeltaLight(scene.lights[l0]);
    float pL0Nee = pL[0];
    if (k >= 2 && !x0Delta) {
        Vec3 w = x0Infinite ? -x[0].ng : dirTo(x[1].p, x[0].p);
        pL0Nee = pdfAt(lightPdfFrom(scene, l0, x[1].p, x[0].p, w, x[0].ng), x[1].p, x[0]);
    }
    out.weight = bptMisWeight(k, s, pL, pE, delta, pL0Nee, misBeta, x0Infinite, x0Delta);
    out.value = value;
    return out.weight > 0;
}
template bool evaluateStrategy(const Scene&, const BptBatch&, uint32_t, int, int, const HashedSamples&, float,
                               StrategyScratch&, StrategySample&);
template bool evaluateStrategy(const Scene&, const BptBatch&, uint32_t, int, int, const StoredSamples&, float,
                               StrategyScratch&, StrategySample&);

void traceBptConnections(const Scene& scene, BptBatch& b, RayCounters& c) {
    traceOccluded(scene.rtc, b.conn.data(), b.numConn);
    c.raysOccluded += b.numConn;
    for (size_t i = 0; i < b.numConn; ++i) {
        if (!(b.conn[i].tfar >= 0)) continue;
        const int s = b.connS[i], k = b.connLength[i];
        if (!b.connSplat[i]) {
            addCameraSide(b, b.connSlot[i], b.connValue[i], b.connWeight[i], s, k);
            continue;
        }
        const Vec3 v = b.connValue[i] * b.connWeight[i];
        if (!b.tally.take(v, k)) continue;
        b.splats.push_back({b.connSlot[i], v});
        if (b.strategyFilms) b.strategySplats.push_back({b.connSlot[i], uint8_t(s), v, b.connValue[i]});
    }
    b.numConn = 0;
}

void connectBpt(const Scene& scene, BptBatch& b, int minLength, int maxLength, float misBeta, RayCounters& counters) {
    StrategyScratch scratch;
    StrategySample ss;
    const HashedSamples u{b.key.data()};
    b.numConn = 0;
    for (uint32_t slot = 0; slot < b.numSlots; ++slot) {
        const int nC = b.cam.count[slot], nL = b.light.count[slot];
        for (int t = 1; t <= nC; ++t)
            for (int s = 0; s <= std::max(nL, 1); ++s) {
                const int k = s + t - 1;
                if (k < std::max(1, minLength) || k > maxLength) continue;
                if (!evaluateStrategy(scene, b, slot, s, t, u, misBeta, scratch, ss)) continue;
                if (s == 0)
                    addCameraSide(b, slot, ss.value, ss.weight, 0, k);
                else if (t == 1)
                    pushConnection(scene, b, ss, ss.pixel, true, s, k, counters);
                else
                    pushConnection(scene, b, ss, slot, false, s, k, counters);
            }
    }
    traceBptConnections(scene, b, counters);
}

void connectStrategies(const Scene& scene, BptBatch& b, const StoredSamples& u, float misBeta, RayCounters& counters) {
    StrategyScratch scratch;
    StrategySample ss;
    b.numConn = 0;
    for (uint32_t slot = 0; slot < b.numSlots; ++slot) {
        b.L[slot] = Vec3(0.0f);
        const int s = b.strategyS[slot], k = b.pathLength[slot], t = k + 1 - s;
        if (!evaluateStrategy(scene, b, slot, s, t, u, misBeta, scratch, ss)) continue;
        if (t == 1) b.pixel[slot] = ss.pixel;
        if (s == 0)
            addCameraSide(b, slot, ss.value, ss.weight, 0, k);
        else
            pushConnection(scene, b, ss, slot, false, s, k, counters);
    }
    traceBptConnections(scene, b, counters);
}

}  // namespace wmlt
