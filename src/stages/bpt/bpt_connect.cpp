// Connecting BPT's subpaths, a wave of strategies at a time: each strategy of a slot is
// set up (setUpStrategy, bpt_strategy.cpp), the BSDFs at the connections' ends are
// evaluated kind by kind (evaluateStrategyBsdfs), then each strategy is weighted
// (weighStrategy) and added (s = 0) or queued as a shadow ray, in the order the strategies
// were listed. BPT lists all strategies of each slot (connectBpt), MMLT the one each
// chain's proposal picked (connectStrategies). Visibility is decided by batched shadow
// rays (traceBptConnections).
#include "stages/bpt/bpt_stages.h"
#include "stages/core/bsdf_dispatch.h"
#include "stages/core/trace.h"

namespace wmlt {

bool connectionRay(const Scene& scene, const StrategySample& ss, RTCRay& r) {
    if (ss.infinite) {  // towards the environment in direction `to`
        setRay(r, scene.offsetRayOrigin(ss.from, ss.nFrom, ss.to), ss.to, 0.0f, INFINITY);
        return true;
    }
    Vec3 w = ss.to - ss.from;
    if (!(lengthSquared(w) > 0)) return false;
    w = normalize(w);
    Vec3 origin = scene.offsetRayOrigin(ss.from, ss.nFrom, w);
    Vec3 end = isBlack(ss.nTo) ? ss.to : scene.offsetRayOrigin(ss.to, ss.nTo, -w);
    Vec3 d = end - origin;
    float dist = length(d);
    if (!(dist > 0)) return false;
    setRay(r, origin, d / dist, 0.0f, dist * (1.0f - 1e-4f));
    return true;
}

namespace {

// Appends the shadow ray of a strategy sample (target: the slot; a t = 1 splat: the
// pixel it lands on, or kFilmPoint to spread it about its film point, pushSplat).
inline void pushConnection(const Scene& scene, BptBatch& b, const StrategySample& ss, uint32_t slot, bool splat, int s, int pathLength,
                           RayCounters& c) {
    if (b.numConn == b.connCapacity) traceBptConnections(scene, b, c);
    if (!connectionRay(scene, ss, b.conn[b.numConn])) return;
    b.connSlot[b.numConn] = !splat || b.splatsBySlot ? slot : scene.filter.box ? rasterPixel(scene.camera, ss.px, ss.py) : kFilmPoint;
    b.connX[b.numConn] = ss.px;
    b.connY[b.numConn] = ss.py;
    b.connSplat[b.numConn] = splat ? 1 : 0;
    b.connLength[b.numConn] = uint8_t(pathLength);
    b.connValue[b.numConn] = ss.value;
    b.connWeight[b.numConn] = ss.weight;
    b.connS[b.numConn] = uint8_t(s);
    ++b.numConn;
}

// A camera-side contribution (t >= 2) of strategy s to slot's pixel. PSSMLT
// (b.splatsBySlot): one traced as a shadow ray (queued) to Lqueued, added to L at the end
// (connectBpt), so that L's sum does not depend on when the batch's rays were flushed
// (which depends on the other slots of the batch: a replay must give the same bits).
inline void addCameraSide(BptBatch& b, uint32_t slot, Vec3 unweighted, float weight, int s, int length, bool queued = false) {
    const Vec3 v = unweighted * weight;
    if (!b.tally.take(v, length)) return;
    (queued && b.splatsBySlot ? b.Lqueued : b.L)[slot] += v;
    if (b.strategyFilms) b.strategyFilms->addCamera(b.pixel[slot], s, length + 1 - s, v * b.filmWeight[slot], unweighted * b.filmWeight[slot]);
}

// A visible connection of strategy s of a path of length k: to its slot's camera side, or
// a t = 1 splat at raster pixel `target` (kFilmPoint: spread about the film point (x, y);
// b.splatsBySlot: kept with its slot `target` at (x, y)).
void addConnection(const Scene& scene, BptBatch& b, uint32_t target, float x, float y, bool splat, int s, int k, Vec3 unweighted, float weight,
                   bool queued) {
    if (!splat) {
        addCameraSide(b, target, unweighted, weight, s, k, queued);
        return;
    }
    const Vec3 v = unweighted * weight;
    if (!b.tally.take(v, k)) return;
    if (b.splatsBySlot) {  // PSSMLT: target is the slot
        b.slotSplats.push_back({target, x, y, v});
        return;
    }
    pushSplat(b.splats, b.points, target, x, y, v);
    if (!b.strategyFilms) return;
    if (target != kFilmPoint) {
        b.strategySplats.push_back({target, uint8_t(s), v, unweighted});
        return;
    }
    scene.forEachFilmPixel(x, y, [&](uint32_t p, float fw) { b.strategySplats.push_back({p, uint8_t(s), v * fw, unweighted * fw}); });
}

}  // namespace

void addVolumeEmission(BptBatch& b, uint32_t slot, Vec3 emitted, int k) {
    // Spectral: at the slot's wavelengths as the film's linear sRGB, as every strategy's
    // value (finishStrategies); a dispersion that ends the secondary wavelengths later on
    // the walk leaves this estimate unbiased, it reads nothing of what follows.
    if (b.spectra) emitted = srgbOfSample(emitted, b.lambda[slot]);
    addCameraSide(b, slot, emitted, 1.0f, 0, k);
}

void evaluateStrategyBsdfs(const BptBatch& b, StrategyWave& w) {
    size_t n = 0;
    for (uint32_t e = 0; e < 2 * w.n; ++e)
        if (w.endVertex[e] != kNoEnd) w.ends[n++] = e;
    auto params = [&](uint32_t e) -> const BsdfParams& { return (e & 1 ? b.cam : b.light).bsdf[w.endVertex[e]]; };
    groupByMaterialKind([&](size_t h) { return params(w.ends[h]).kind; }, n, w.order.data(), w.kindStart);
    forEachMaterialKind([&](auto kind) {
        using B = BsdfOf<decltype(kind)::value>;
        for (uint32_t r = w.kindStart[int(kind.value)]; r < w.kindStart[int(kind.value) + 1]; ++r) {
            const uint32_t e = w.ends[w.order[r]];
            const BsdfParams& m = params(e);
            w.f[e] = B::f(m, w.fWo[e], w.fWi[e]);
            w.pdfCam[e] = B::pdf(m, w.wo[e], w.wi[e]);
            w.pdfLight[e] = B::pdf(m, w.wi[e], w.wo[e]);
        }
    });
}

namespace {

// The strategies set up so far: their ends' BSDFs, then each one weighted and added (s =
// 0) or queued (splat: t = 1 goes to the film at its raster pixel), in order.
void finishStrategies(const Scene& scene, BptBatch& b, float misBeta, bool splat, RayCounters& counters) {
    StrategyWave& w = b.strategies;
    const bool tracedThroughMedia = scene.features.passThrough;  // weighStrategy traced the connections
    evaluateStrategyBsdfs(b, w);
    StrategyScratch scratch;
    StrategySample ss;
    for (size_t i = 0; i < w.n; ++i) {
        if (!weighStrategy(scene, b, w, i, misBeta, scratch, ss, counters)) continue;
        const uint32_t slot = w.slot[i];
        // Spectral: the value at the slot's wavelengths as the film's linear sRGB (both
        // subpaths are walked, so the wavelengths are final; the conversion is linear).
        if (b.spectra) ss.value = srgbOfSample(ss.value, b.lambda[slot]);
        const int s = w.s[i], k = s + w.t[i] - 1;
        if (w.t[i] == 1 && !splat) {
            b.filmX[slot] = ss.px;
            b.filmY[slot] = ss.py;
        }
        if (s == 0) addCameraSide(b, slot, ss.value, ss.weight, 0, k);
        else if (tracedThroughMedia) {  // visible as it stands
            const bool splatHere = w.t[i] == 1 && splat;
            const uint32_t target = !splatHere || b.splatsBySlot ? slot : scene.filter.box ? rasterPixel(scene.camera, ss.px, ss.py) : kFilmPoint;
            addConnection(scene, b, target, ss.px, ss.py, splatHere, s, k, ss.value, ss.weight, false);
        } else if (w.t[i] == 1 && splat) pushConnection(scene, b, ss, slot, true, s, k, counters);
        else pushConnection(scene, b, ss, slot, false, s, k, counters);
    }
    w.n = 0;
}

// A pinhole camera: the camera samples of the light vertices the t = 1 strategies of
// slots [slot0, slot1) end at (BPT: every light vertex; MMLT: x_{s-1} of a slot whose
// strategy has t = 1), in one flat loop (pinholeCameraSamples); setUpStrategy reads them.
void sampleCameraFromLightVertices(const Scene& scene, BptBatch& b, uint32_t slot0, uint32_t slot1, bool oneStrategyPerSlot) {
    uint32_t n = 0;
    auto list = [&](size_t a) {
        b.cameraSampleOf[a] = n;
        b.csRef[n] = b.light.p[a];
        b.csRefN[n] = b.light.ng[a];
        if (b.light.kind[a] == BptVertexKind::Medium)  // volume density: a "normal" along the ray, cosine 1
            b.csRefN[n] = normalize(b.light.p[a] - scene.camera.position);
        ++n;
    };
    for (uint32_t slot = slot0; slot < slot1; ++slot) {
        const int nL = b.light.count[slot];
        if (!oneStrategyPerSlot) {
            for (int i = 0; i < nL; ++i) list(b.light.at(slot, i));
            continue;
        }
        const int s = b.strategyS[slot], t = b.pathLength[slot] + 1 - s;
        if (t == 1 && s >= 1 && s <= nL) list(b.light.at(slot, s - 1));
    }
    pinholeCameraSamples(cameraFloats(scene.camera), n, &b.csRef[0].x, &b.csRefN[0].x, &b.csWi[0].x, b.csPx.data(), b.csPy.data(), b.csWe.data(),
                         b.csPdf.data(), b.csPdfArea.data(), b.csValid.data());
}

}  // namespace

void traceBptConnections(const Scene& scene, BptBatch& b, RayCounters& c) {
    traceOccluded(scene.rtc, b.conn.data(), b.numConn);
    c.raysOccluded += b.numConn;
    for (size_t i = 0; i < b.numConn; ++i) {
        if (!(b.conn[i].tfar >= 0)) continue;
        addConnection(scene, b, b.connSlot[i], b.connX[i], b.connY[i], b.connSplat[i] != 0, b.connS[i], b.connLength[i], b.connValue[i],
                      b.connWeight[i], true);
    }
    b.numConn = 0;
}

template <class U>
void connectBpt(const Scene& scene, BptBatch& b, const U& u, int minLength, int maxLength, float misBeta, RayCounters& counters) {
    StrategyWave& w = b.strategies;
    cacheMisSums(scene, b, misBeta);
    b.numConn = 0;
    w.n = 0;
    if (b.splatsBySlot) std::fill(b.Lqueued.begin(), b.Lqueued.begin() + ptrdiff_t(b.numSlots), Vec3(0.0f));
    const bool pinhole = isPinhole(scene.camera);
    for (uint32_t slot = 0; slot < b.numSlots; ++slot) {
        if (pinhole && slot % kCameraSampleSlots == 0)
            sampleCameraFromLightVertices(scene, b, slot, std::min<uint32_t>(uint32_t(b.numSlots), slot + kCameraSampleSlots), false);
        const int nC = b.cam.count[slot], nL = b.light.count[slot];
        for (int t = 1; t <= nC; ++t)
            for (int s = 0; s <= std::max(nL, 1); ++s) {
                const int k = s + t - 1;
                if (k < std::max(1, minLength) || k > maxLength) continue;
                if (setUpStrategy(scene, b, slot, s, t, u, w) && w.n == w.capacity) finishStrategies(scene, b, misBeta, true, counters);
            }
    }
    finishStrategies(scene, b, misBeta, true, counters);
    traceBptConnections(scene, b, counters);
    if (b.splatsBySlot)
        for (uint32_t slot = 0; slot < b.numSlots; ++slot) b.L[slot] += b.Lqueued[slot];
}

template void connectBpt(const Scene&, BptBatch&, const HashedSamples&, int, int, float, RayCounters&);
template void connectBpt(const Scene&, BptBatch&, const WholeSamples&, int, int, float, RayCounters&);

void connectStrategies(const Scene& scene, BptBatch& b, const StoredSamples& u, float misBeta, RayCounters& counters) {
    StrategyWave& w = b.strategies;
    cacheMisSums(scene, b, misBeta);
    b.numConn = 0;
    w.n = 0;
    // (L is 0 from generateChainCameraPaths, but for what emitting media gave the camera walk)
    const bool pinhole = isPinhole(scene.camera);
    for (uint32_t slot = 0; slot < b.numSlots; ++slot) {
        if (pinhole && slot % kCameraSampleSlots == 0)
            sampleCameraFromLightVertices(scene, b, slot, std::min<uint32_t>(uint32_t(b.numSlots), slot + kCameraSampleSlots), true);
        const int s = b.strategyS[slot], k = b.pathLength[slot], t = k + 1 - s;
        if (setUpStrategy(scene, b, slot, s, t, u, w) && w.n == w.capacity) finishStrategies(scene, b, misBeta, false, counters);
    }
    finishStrategies(scene, b, misBeta, false, counters);
    traceBptConnections(scene, b, counters);
}

}  // namespace wmlt
