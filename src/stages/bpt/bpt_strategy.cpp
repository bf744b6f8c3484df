// One BPT strategy (s, t) of a slot, in the two steps around its ends' BSDFs
// (bpt_connect.cpp evaluates those kind by kind in between):
//   setUpStrategy  - which strategies exist for the slot's subpaths; the new endpoint
//                    (s = 1: a light point; t = 1: a lens point); the directions at the
//                    connection's ends; the factors of the contribution other than f;
//   weighStrategy  - the contribution, and its MIS weight from the per-vertex densities
//                    with those the connection changes (Veach 1997, 10.2; kernels/mis.h).
#include "kernels/mis.h"
#include "scene/scene_lights.h"
#include "stages/bpt/bpt_stages.h"
#include "stages/core/media.h"

namespace wmlt {

namespace {

// A vertex of the path being weighted, in the light-to-camera order x_0 .. x_k: what the
// densities need of it.
struct PathPoint {
    Vec3 p, ng;
    BptVertexKind kind = BptVertexKind::Surface;
    float pdfA = -1;  // x_0 on a textured emitter: its area density under light sampling (else < 0)
};

// Emission direction density (cosine about n) towards `to`, as area density at `to`.
inline float lightDirPdfArea(Vec3 p, Vec3 n, Vec3 to, Vec3 nTo, bool toOnSurface) {
    Vec3 d = to - p;
    float dist = length(d);
    if (!(dist > 0)) return 0.0f;
    float c = dot(n, d) / dist;
    return c > 0 ? solidAngleToArea(c * kInvPi, p, to, nTo, toOnSurface) : 0.0f;
}

inline Vec3 dirTo(Vec3 a, Vec3 b) { return normalize(b - a); }

// Solid-angle density at `from` converted to the measure of vertex `to`: area for surface
// and light points (the camera: no cosine; a medium vertex: volume, no cosine), unchanged
// (solid angle) for the environment.
inline float pdfAt(float pdfSa, Vec3 from, const PathPoint& to) {
    if (to.kind == BptVertexKind::Env) return pdfSa;
    return solidAngleToArea(pdfSa, from, to.p, to.ng, hasCosine(to.kind));
}

// Density with which a light subpath starts at x0 (light li): emission position times
// the choice pmf; the environment: its direction's density times the pmf; a point
// light: the pmf (its position is a discrete choice), a directional light too (its
// direction).
inline float originPdf(const Scene& scene, int li, const PathPoint& x0) {
    const float pmf = scene.lightDistribution.discretePmf(li);
    if (isDeltaLight(scene.lights[li])) return pmf;  // (directional: its one direction)
    if (x0.kind == BptVertexKind::Env) return pmf * scene.env.pdf(-x0.ng);
    return x0.pdfA >= 0 ? pmf * x0.pdfA : pmf / scene.lights[li].area;
}

// Density of x1 as the first scattering vertex of a light subpath from x0 (light li):
// emitted direction (cosine about the normal; a point light: uniform, a spot: uniform in its
// cone) as area density;
// the environment: the emission disc's density 1 / (pi R^2) projected onto x1's surface
// (a medium vertex: along the ray, no cosine, as the light walk's own density of it).
inline float emissionPdfAt(const Scene& scene, int li, const PathPoint& x0, const PathPoint& x1) {
    if (x0.kind == BptVertexKind::Env) return (hasCosine(x1.kind) ? std::fabs(dot(x1.ng, x0.ng)) : 1.0f) / (kPi * scene.radius * scene.radius);
    if (const Light& l = scene.lights[li]; isDeltaLight(l)) {
        const float pdf = isSpot(l) ? pointEmissionPdf(l, dirTo(x0.p, x1.p)) : kUniformSpherePdf;
        return solidAngleToArea(pdf, x0.p, x1.p, x1.ng, hasCosine(x1.kind));
    }
    if (scene.lights[li].twoSided) {  // either face with probability 1/2: the one facing x1
        const Vec3 n = dot(x0.ng, x1.p - x0.p) < 0 ? -x0.ng : x0.ng;
        return 0.5f * lightDirPdfArea(x0.p, n, x1.p, x1.ng, hasCosine(x1.kind));
    }
    return lightDirPdfArea(x0.p, x0.ng, x1.p, x1.ng, hasCosine(x1.kind));
}

// Vertex i of the path of strategy (s, t) of slot, k = s + t - 1: the light subpath's
// y_i below s, the camera subpath's z_{k-i} from s on.
inline const BptVertices& sideOf(const BptBatch& b, int i, int s) { return i < s ? b.light : b.cam; }
inline size_t indexOf(const BptBatch& b, uint32_t slot, int i, int s, int k) { return i < s ? b.light.at(slot, i) : b.cam.at(slot, k - i); }

// x_0's density under next-event estimation from x_1 (light l0; k >= 2, not a point light).
inline float neePdf(const Scene& scene, int l0, const PathPoint& x0, const PathPoint& x1) {
    Vec3 dir = x0.kind == BptVertexKind::Env ? -x0.ng : dirTo(x1.p, x0.p);
    return pdfAt(lightPdfFrom(scene, l0, x1.p, x0.p, dir, x0.ng, x0.pdfA), x1.p, x0);
}

// (media) Strategy i's connection through media and pass-through boundaries (out: its
// ends; without such boundaries only its medium, its visibility left to the shadow ray):
// value takes its transmittance (false: blocked); the densities that would sample
// the connection's segment take its free-path densities (pE at y = x_{s-1}, pL at z =
// x_s), and those of the segments next to it, sampled backwards, the walks' kept ones
// (rhoRev). s = 0: the emission's density at x_1 crosses the camera walk's last segment.
bool throughMedia(const Scene& scene, const BptBatch& b, const StrategyWave& w, size_t i, RayCounters& c, float* pL, float* pE,
                  const StrategySample& out, Vec3& value) {
    const uint32_t slot = w.slot[i];
    const int s = w.s[i], t = w.t[i], k = s + t - 1;
    const size_t zi = b.cam.at(slot, t - 1);
    if (s == 0) {
        if (k >= 2) pL[1] *= b.cam.rhoRev[zi];
        return true;
    }
    RTCRay r;
    if (!connectionRay(scene, out, r)) return false;
    const bool fromZ = s == 1 && t >= 2;  // the ray leaves z for the light point; else y
    const BptVertices& fv = fromZ ? b.cam : b.light;
    const size_t fa = fromZ ? zi : b.light.at(slot, s - 1);
    const int m = fv.mediumTowards(fa, Vec3(r.dir_x, r.dir_y, r.dir_z));
    const bool fromInMedium = fv.kind[fa] == BptVertexKind::Medium;
    const bool toInMedium = s >= 2 && t >= 2 && b.cam.kind[zi] == BptVertexKind::Medium;
    SegmentDensities rho;
    // (without pass-through boundaries: here, unblocked, the shadow ray tests visibility)
    const PathMedia media = pathMedia(scene, b, slot);
    const Vec3 T = scene.features.passThrough ? transmittanceAlong(scene, media, r, m, rayHash(r), fromInMedium, toInMedium, rho, c)
                                              : transmittanceUnblocked<true>(media, r, m, rayHash(r), fromInMedium, toInMedium, rho);
    if (isBlack(T)) return false;
    value = value * T;
    pE[s - 1] *= fromZ ? rho.fwd : rho.rev;          // ending at y
    if (t >= 2) pL[s] *= fromZ ? rho.rev : rho.fwd;  // ending at z
    if (t >= 2 && s + 1 < k) pL[s + 1] *= b.cam.rhoRev[zi];
    if (s >= 2) pE[s - 2] *= b.light.rhoRev[b.light.at(slot, s - 1)];
    return true;
}

}  // namespace

void cacheMisSums(const Scene& scene, BptBatch& b, float misBeta) {
    for (uint32_t slot = 0; slot < b.numSlots; ++slot) {
        // The camera subpath: T_0 = 0 at the camera, T_i from T_{i-1}. A strategy with t
        // camera vertices reads T_{t-3}, so the last two vertices need none.
        const BptVertices& c = b.cam;
        for (int i = 0; i < c.count[slot] - 2; ++i) {
            const size_t a = c.at(slot, i);
            if (i == 0) {
                b.cam.misSum[a] = 0;
                continue;
            }
            const size_t p = c.at(slot, i - 1);
            b.cam.misSum[a] = bptSubpathMisSum(c.misSum[p], c.pdfRev[a], c.pdfFwd[a], c.delta[a], i > 1 && c.delta[p], misBeta);
        }
        // The light subpath: next-event estimation's density of y_0 from y_1 (every
        // strategy with s >= 2 weighs with it), L(0) and L(1), then L(m) from L(m - 1)
        // (strategy s reads L(s - 3): none for the last two vertices).
        const BptVertices& l = b.light;
        const int nL = l.count[slot];
        if (nL < 2) continue;
        const size_t y0 = l.at(slot, 0), y1 = l.at(slot, 1);
        const int l0 = l.light[y0];
        const bool x0Delta = isDeltaLight(scene.lights[l0]);
        const float pdfA0 = l.emitPdfA.empty() ? -1.0f : l.emitPdfA[y0];
        const float nee = x0Delta ? l.pdfFwd[y0] : neePdf(scene, l0, {l.p[y0], l.ng[y0], l.kind[y0], pdfA0}, {l.p[y1], l.ng[y1], l.kind[y1]});
        b.lightNee[slot] = nee;
        if (nL < 3) continue;
        b.light.misSum[y0] = bptLightMisSum0(l.pdfRev[y0], nee, x0Delta, misBeta);
        if (nL < 4) continue;
        b.light.misSum[y1] = bptLightMisSum1(l.misSum[y0], l.pdfFwd[y0], nee, l.pdfFwd[y1], l.pdfRev[y1], l.delta[y1], misBeta);
        for (int m = 2; m < nL - 2; ++m) {
            const size_t a = l.at(slot, m), p = l.at(slot, m - 1);
            b.light.misSum[a] = bptSubpathMisSum(l.misSum[p], l.pdfRev[a], l.pdfFwd[a], l.delta[a], l.delta[p], misBeta);
        }
    }
}

template <class U>
bool setUpStrategy(const Scene& scene, const BptBatch& b, uint32_t slot, int s, int t, const U& u, StrategyWave& w) {
    const Camera& cam = scene.camera;
    const int k = s + t - 1;
    const int nC = b.cam.count[slot], nL = b.light.count[slot];
    if (t < 1 || t > nC || k < 1) return false;
    const size_t zi = b.cam.at(slot, t - 1);
    const BptVertexKind zKind = b.cam.kind[zi];
    // Which strategies exist for these subpaths.
    // s = 0: the camera subpath ends on an emitter (a Surface vertex of an emitter with a
    // material both ends this path and scatters for the longer ones).
    const bool zEmits = zKind == BptVertexKind::Light || zKind == BptVertexKind::Env || (zKind == BptVertexKind::Surface && b.cam.light[zi] >= 0);
    if (s == 0 && !zEmits) return false;
    // A connection needs a non-delta lobe at both ends, whichever lobe the walk took there
    // (a medium vertex's phase function is one).
    if (s >= 1 && t >= 2 && zKind != BptVertexKind::Medium && (zKind != BptVertexKind::Surface || isDeltaMaterial(b.cam.bsdf[zi].kind))) return false;
    if (s == 1 && t >= 2 && scene.lights.empty()) return false;
    if (s >= 2 || (s == 1 && t == 1)) {
        if (s > nL) return false;
        const size_t yi = b.light.at(slot, s - 1);
        if (b.light.kind[yi] == BptVertexKind::Surface && isDeltaMaterial(b.light.bsdf[yi].kind)) return false;
        if (s == 1 && b.light.kind[yi] == BptVertexKind::Env) return false;  // at infinity
    }
    // (media) An end at its predecessor's point (a free path below float rounding): no direction.
    auto moved = [&](const BptVertices& v, int i) { return lengthSquared(v.p[v.at(slot, i)] - v.p[v.at(slot, i - 1)]) > 0; };
    if (b.cam.media && ((t >= 2 && !moved(b.cam, t - 1)) || (s >= 2 && !moved(b.light, s - 1)))) return false;
    const size_t i = w.n, ey = 2 * i, ez = 2 * i + 1;
    w.endVertex[ey] = w.endVertex[ez] = kNoEnd;
    auto uc = [&](uint32_t m) { return u(slot, kBptConnect, U::connectJ(s, t, m)); };
    // The new endpoint, and the contribution but for the ends' f: finished by weighStrategy.
    if (s == 0) {  // value = beta_z Le
        const int li = b.cam.light[zi];
        const size_t x1 = b.cam.at(slot, t - 2);  // k >= 1: t >= 2
        Vec3 Le = zKind == BptVertexKind::Env ? scene.env.Le(-b.cam.ng[zi]) : areaLe(scene.lights[li], b.cam.ng[zi], dirTo(b.cam.p[zi], b.cam.p[x1]));
        if (!b.cam.emitTex.empty() && zKind != BptVertexKind::Env) Le = Le * b.cam.emitTex[zi];
        if (b.spectra) Le = b.spectra->emission(li, Le, b.lambda[slot]);
        w.value[i] = b.cam.beta[zi] * Le;
        w.light[i] = int16_t(li);
    } else if (s == 1 && t >= 2) {  // value = beta_z f(z) |cos| Le / (pmf pdf)
        float pmf;
        const int li = scene.lightDistribution.sampleDiscrete(uc(0), &pmf);
        LightSample ls;
        if (!(pmf > 0) || !sampleLightFrom(scene, li, b.cam.p[zi], uc(1), uc(2), ls)) return false;
        const bool infinite = std::isinf(ls.dist);
        const Frame& fr = b.cam.shading[zi];
        const Vec3 toPrev = dirTo(b.cam.p[zi], b.cam.p[b.cam.at(slot, t - 2)]);
        w.endVertex[ez] = uint32_t(zi);
        w.fWo[ez] = w.wo[ez] = fr.toLocal(toPrev);
        w.fWi[ez] = fr.toLocal(ls.wi);
        w.wi[ez] = fr.toLocal(dirTo(b.cam.p[zi], ls.p));
        w.scale[i] = absCosTheta(w.fWi[ez]);
        w.value[i] = b.spectra ? b.spectra->emission(li, ls.Le, b.lambda[slot]) : ls.Le;
        w.tail[i] = pmf * ls.pdf;
        w.light[i] = int16_t(li);
        w.endP[i] = ls.p;
        w.endN[i] = infinite ? -ls.wi : ls.n;
        w.endPdfA[i] = ls.pdfA;
        w.infinite[i] = infinite ? 1 : 0;
    } else if (t == 1) {  // s = 1: value = beta_y Le |cos| We / pdf; s >= 2: beta_y f(y) tail
        const size_t yi = b.light.at(slot, s - 1);
        const Vec3 y = b.light.p[yi], yN = b.light.ng[yi];
        CameraSample cs;
        if (isPinhole(cam)) {  // sampleCameraFromLightVertices made it
            const uint32_t j = b.cameraSampleOf[yi];
            cs.valid = b.csValid[j] != 0;
            cs.lens = cam.position;
            cs.wi = b.csWi[j];
            cs.px = b.csPx[j];
            cs.py = b.csPy[j];
            cs.We = b.csWe[j];
            cs.pdf = b.csPdf[j];
            w.cameraPdfArea[i] = b.csPdfArea[j];
        } else {
            cs = cam.ortho ? sampleOrthographicFrom(cam, y) : sampleProjectiveFrom(cam, y, uc(0), uc(1));  // (ortho reads no number)
        }
        if (!cs.valid) return false;
        if (s == 1) {
            const int li = b.light.light[yi];
            if (isDeltaLight(scene.lights[li])) return false;  // a point light is not seen
            Vec3 Le = areaLe(scene.lights[li], yN, cs.wi);
            // (spectral: y_0's beta holds the emitter's texture over its density, which the
            // emitter's spectrum must see: emission is linear in its RGB's scale)
            const Vec3 betaLe = b.spectra ? b.spectra->emission(li, b.light.beta[yi] * Le, b.lambda[slot]) : b.light.beta[yi] * Le;
            w.value[i] = betaLe * (std::fabs(dot(cs.wi, yN)) * cs.We / cs.pdf);
        } else {
            const Frame& fr = b.light.shading[yi];
            const Vec3 toPrev = dirTo(y, b.light.p[b.light.at(slot, s - 2)]);
            w.endVertex[ey] = uint32_t(yi);
            w.fWo[ey] = fr.toLocal(cs.wi);
            w.fWi[ey] = w.wi[ey] = fr.toLocal(toPrev);
            w.wo[ey] = fr.toLocal(dirTo(y, cs.lens));
            const float corr = shadingCorrection(toPrev, cs.wi, fr.n, yN);
            w.tail[i] = absCosTheta(w.fWo[ey]) * corr * cs.We / cs.pdf;
        }
        w.endP[i] = cs.lens;
        w.filmX[i] = cs.px;
        w.filmY[i] = cs.py;
    } else {  // s, t >= 2: value = beta_y f(y) corr f(z) beta_z G
        const size_t yi = b.light.at(slot, s - 1);
        const Vec3 y = b.light.p[yi], z = b.cam.p[zi];
        Vec3 d = z - y;
        float dist2 = lengthSquared(d);
        if (!(dist2 > 0)) return false;
        Vec3 dir = d / std::sqrt(dist2);  // from y to z
        const Frame& fy = b.light.shading[yi];
        const Frame& fz = b.cam.shading[zi];
        Vec3 toPrevY = dirTo(y, b.light.p[b.light.at(slot, s - 2)]), toPrevZ = dirTo(z, b.cam.p[b.cam.at(slot, t - 2)]);
        w.endVertex[ey] = uint32_t(yi);
        w.endVertex[ez] = uint32_t(zi);
        w.fWo[ey] = w.wo[ey] = fy.toLocal(dir);
        w.fWi[ey] = w.wi[ey] = fy.toLocal(toPrevY);
        w.fWo[ez] = w.wo[ez] = fz.toLocal(toPrevZ);
        w.fWi[ez] = w.wi[ez] = fz.toLocal(-dir);
        w.scale[i] = shadingCorrection(toPrevY, dir, fy.n, b.light.ng[yi]);
        w.tail[i] = absCosTheta(w.wo[ey]) * absCosTheta(w.wi[ez]) / dist2;
    }
    w.slot[i] = slot;
    w.s[i] = uint8_t(s);
    w.t[i] = uint8_t(t);
    ++w.n;
    return true;
}
template bool setUpStrategy(const Scene&, const BptBatch&, uint32_t, int, int, const HashedSamples&, StrategyWave&);
template bool setUpStrategy(const Scene&, const BptBatch&, uint32_t, int, int, const StoredSamples&, StrategyWave&);
template bool setUpStrategy(const Scene&, const BptBatch&, uint32_t, int, int, const WholeSamples&, StrategyWave&);

bool weighStrategy(const Scene& scene, const BptBatch& b, const StrategyWave& w, size_t i, float misBeta, StrategyScratch& scratch,
                   StrategySample& out, RayCounters& counters) {
    const Camera& cam = scene.camera;
    const uint32_t slot = w.slot[i];
    const int s = w.s[i], t = w.t[i], k = s + t - 1;
    const size_t ey = 2 * i, ez = 2 * i + 1;
    const size_t zi = b.cam.at(slot, t - 1);
    // The contribution (setUpStrategy's factors, in the same order).
    Vec3 value;
    if (s == 0 || (s == 1 && t == 1)) value = w.value[i];
    else if (s == 1) value = b.cam.beta[zi] * (w.f[ez] * w.scale[i]) * w.value[i] / w.tail[i];
    else if (t == 1) value = b.light.beta[w.endVertex[ey]] * w.f[ey] * w.tail[i];
    else value = b.light.beta[w.endVertex[ey]] * (w.f[ey] * w.scale[i]) * w.f[ez] * b.cam.beta[zi] * w.tail[i];
    if (isBlack(value)) return false;
    // The shadow ray's ends.
    out.infinite = false;
    out.nTo = Vec3(0.0f);
    if (s == 1 && t >= 2) {
        out.from = b.cam.p[zi];
        out.nFrom = b.cam.ng[zi];
        out.infinite = w.infinite[i] != 0;
        out.to = out.infinite ? -w.endN[i] : w.endP[i];
    } else if (s >= 1) {
        const size_t yi = b.light.at(slot, s - 1);
        out.from = b.light.p[yi];
        out.nFrom = b.light.ng[yi];
        out.to = t == 1 ? w.endP[i] : b.cam.p[zi];
        if (t >= 2) out.nTo = b.cam.ng[zi];
        if (t == 1) {
            out.px = w.filmX[i];
            out.py = w.filmY[i];
        }
    }
    // The path's stored densities around the connection, x_{s-3} .. x_{s+2}, and at x_0
    // (the rest of the path is in the subpaths' cached sums); the new endpoint's (s = 1,
    // t >= 2: x_0; t = 1: x_k) and the connection's follow.
    float* pL = scratch.pL;
    float* pE = scratch.pE;
    uint8_t* delta = scratch.delta;
    auto load = [&](int j) {
        const BptVertices& v = sideOf(b, j, s);
        const size_t a = indexOf(b, slot, j, s, k);
        pL[j] = j < s ? v.pdfFwd[a] : v.pdfRev[a];
        pE[j] = j < s ? v.pdfRev[a] : v.pdfFwd[a];
        delta[j] = v.delta[a];
    };
    load(0);
    for (int j = std::max(1, s - 3); j <= std::min(k, s + 2); ++j) load(j);
    auto x = [&](int j) {
        if (s == 1 && t >= 2 && j == 0)
            return PathPoint{w.endP[i], w.endN[i], w.infinite[i] ? BptVertexKind::Env : BptVertexKind::Light, w.endPdfA[i]};
        if (t == 1 && j == k) return PathPoint{w.endP[i], cam.forward, BptVertexKind::Camera};
        const BptVertices& v = sideOf(b, j, s);
        const size_t a = indexOf(b, slot, j, s, k);
        PathPoint q{v.p[a], v.ng[a], v.kind[a], j == 0 && !v.emitPdfA.empty() ? v.emitPdfA[a] : -1.0f};
        if (s == 0 && j == 0 && q.kind == BptVertexKind::Surface) q.kind = BptVertexKind::Light;  // the path's light end
        return q;
    };
    const PathPoint x0 = x(0);
    const int li = w.light[i];
    if (s == 1 && t >= 2) pL[0] = originPdf(scene, li, x0);
    // The connected path scatters by the non-delta lobes at the connection's two ends.
    delta[0] = 0;
    delta[k] = 0;
    if (s >= 1) delta[s - 1] = delta[s] = 0;
    const bool x0Infinite = x0.kind == BptVertexKind::Env;
    if (!bptStrategyValid(k, s, delta, x0Infinite)) return false;
    // Densities the other side's walk would have used at the connection.
    const int l0 = s == 0 ? li : (s == 1 && t >= 2) ? li : b.light.light[b.light.at(slot, 0)];
    if (s == 0) {
        pL[0] = originPdf(scene, li, x0);
        if (k >= 2) pL[1] = emissionPdfAt(scene, li, x0, x(1));
    } else if (s >= 2 && t >= 2) {
        const PathPoint y = x(s - 1), z = x(s);
        pE[s - 1] = pdfAt(w.pdfCam[ez], z.p, y);
        pE[s - 2] = pdfAt(w.pdfCam[ey], y.p, x(s - 2));
        pL[s] = solidAngleToArea(w.pdfLight[ey], y.p, z.p, z.ng, hasCosine(z.kind));
        if (s + 1 < k) {
            const PathPoint next = x(s + 1);
            pL[s + 1] = solidAngleToArea(w.pdfLight[ez], z.p, next.p, next.ng, hasCosine(next.kind));
        }
    } else if (t == 1) {
        const PathPoint y = x(s - 1);
        // The direction is -wi of setUpStrategy's camera sample bit for bit (the same
        // difference and length), whose raster point was inside the image: no check again.
        // (An orthographic film's density projected onto y; a medium vertex: along the ray.)
        const float filmCos = hasCosine(y.kind) ? std::fabs(dot(y.ng, cam.forward)) : 1.0f;
        pE[s - 1] = isPinhole(cam) ? w.cameraPdfArea[i]
                    : cam.ortho    ? cameraPdfOfRay(cam, cam.forward) * filmCos
                                   : pdfAt(cameraPdfOfRay(cam, dirTo(w.endP[i], y.p)), w.endP[i], y);
        if (s >= 2) pE[s - 2] = pdfAt(w.pdfCam[ey], y.p, x(s - 2));
    } else {  // s = 1, t >= 2
        const PathPoint z = x(1);
        pE[0] = pdfAt(w.pdfCam[ez], z.p, x0);
        pL[1] = emissionPdfAt(scene, l0, x0, z);
        if (2 < k) {
            const PathPoint next = x(2);
            pL[2] = solidAngleToArea(w.pdfLight[ez], z.p, next.p, next.ng, hasCosine(next.kind));
        }
    }
    if (b.cam.media && !throughMedia(scene, b, w, i, counters, pL, pE, out, value)) return false;
    // x_0 under next-event estimation from x_1 (k = 1: s = 1 is the light subpath's own
    // vertex connected to the camera). A point light: NEE chooses it as emission does
    // (the pmf), and no camera path reaches it (s = 0 has no density).
    const bool x0Delta = isDeltaLight(scene.lights[l0]);
    // (s >= 2: x_0, x_1 are y_0, y_1, whose density cacheMisSums keeps.)
    const float pL0Nee = !(k >= 2 && !x0Delta) ? pL[0] : s >= 2 ? b.lightNee[slot] : neePdf(scene, l0, x0, x(1));
    const double cameraSum = t >= 3 ? b.cam.misSum[b.cam.at(slot, t - 3)] : 0.0;
    const double lightSum = s >= 3 ? b.light.misSum[b.light.at(slot, s - 3)] : 0.0;
    out.weight = bptMisWeightCached(k, s, pL, pE, delta, pL0Nee, misBeta, x0Infinite, x0Delta, cameraSum, lightSum);
    out.value = value;
    return out.weight > 0;
}

}  // namespace wmlt
