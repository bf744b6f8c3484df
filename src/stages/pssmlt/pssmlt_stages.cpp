#include "stages/pssmlt/pssmlt_stages.h"

#include <stdexcept>

#include "stages/bpt/bpt_stages.h"
#include "stages/mmlt/mmlt_stages.h"

namespace wmlt {

void setWholeNumbersRead(MmltBatch& mb, bool media) {
    const int K = mb.maxLength;
    const uint32_t lo = mb.vertexLo, hi = mb.vertexHi;
    std::vector<uint16_t>& dims = mb.wholeDims;
    dims.clear();
    auto run = [&](uint32_t d0, uint32_t d1) {
        for (uint32_t d = std::max<uint32_t>(d0, 1); d < d1; ++d) dims.push_back(uint16_t(d));
    };
    // Camera stream: the raster point (and lens), then z_1 .. z_{K-1}, which sample a BSDF.
    const uint32_t cb = WholeLayout::base(K, kBptCamera);
    run(cb, cb + (mb.lensRead ? 4 : 2));
    for (int d = 1; d <= K - 1; ++d) run(cb + bptCamVertexJ(d, lo), cb + bptCamVertexJ(d, hi));
    // Light stream: y_0's light, point and direction, then y_1 .. y_{K-2}.
    const uint32_t lb = WholeLayout::base(K, kBptLight);
    run(lb, lb + 5);
    for (int d = 1; d <= K - 2; ++d) run(lb + bptLightVertexJ(d, lo), lb + bptLightVertexJ(d, hi));
    // Connections, in order: s = 1 at z_{t-1} for t = 2 .. K (light choice and point) and
    // t = 1 at y_{s-1} for s = 1 .. K (the lens point: a thin lens only).
    const uint32_t xb = WholeLayout::base(K, kBptConnect);
    for (int n = 1; n <= K; ++n) {
        if (n >= 2) run(xb + bptNeeJ(n, 0), xb + bptNeeJ(n, 3));
        if (mb.lensRead) run(xb + bptLensJ(n, 0), xb + bptLensJ(n, 2));
    }
    if (media) {  // camera segments 1 .. K, light segments 1 .. K - 1
        const uint32_t m = WholeLayout::mediaBase(K);
        run(m, m + uint32_t(K));
        run(m + uint32_t(K), m + 2 * uint32_t(K) - 1);
    }
    if (WholeLayout::size(K, media) > 65536) throw std::logic_error("PSSMLT: a whole sample's coordinates exceed 16 bits");
}

void setWholeSample(MmltBatch& mb, uint32_t i) {
    BptBatch& b = mb.bpt;
    b.strategyS[i] = 0;
    b.pathLength[i] = uint8_t(mb.maxLength);
    b.cam.maxCount[i] = uint8_t(b.cam.capacity);
    b.light.maxCount[i] = uint8_t(b.light.capacity);
}

void evaluateWholeProposals(const Scene& scene, MmltBatch& mb, float misBeta, RayCounters& counters) {
    BptBatch& b = mb.bpt;
    const WholeSamples u = mb.wholeSamples();
    b.tally.nonfinite = 0;
    b.slotSplats.clear();
    generateChainCameraPaths(scene, b, u);
    walkBpt(scene, b, b.cam, true, false, counters, u);
    generateBptLightPaths(scene, b, u);
    walkBpt(scene, b, b.light, false, false, counters, u);
    connectBpt(scene, b, u, b.minLength, b.maxLength, misBeta, counters);
    mb.counters.nonfinite += b.tally.nonfinite;
    // Each slot's range of slotSplats: connectBpt lists the strategies slot by slot and adds
    // the visible ones in that order.
    size_t at = 0;
    for (uint32_t i = 0; i <= b.numSlots; ++i) {
        while (at < b.slotSplats.size() && b.slotSplats[at].slot < i) ++at;
        mb.splatStart[i] = uint32_t(at);
    }
    if (at != b.slotSplats.size()) throw std::logic_error("PSSMLT: t = 1 contributions out of slot order");
}

float wholeTarget(MmltBatch& mb, uint32_t i, Vec3& F) {
    F = mb.bpt.L[i];
    Vec3 sum = F;
    for (uint32_t j = mb.splatStart[i]; j < mb.splatStart[i + 1]; ++j) sum += mb.bpt.slotSplats[j].value;
    const float c = targetOf(sum);
    if (c == 0.0f && !(isFinite(sum) && std::isfinite(luminance(sum)))) ++mb.counters.nonfinite;
    return c;
}

void splatWhole(const Scene& scene, const ChainGroup& g, uint32_t c, MmltBatch& mb, uint32_t i, float a, float cP) {
    if (a > 0) {  // the proposal: a / c' of each contribution
        const float scale = a * g.weight / cP;
        if (!isBlack(mb.bpt.L[i])) mb.addSplat(scene, mb.bpt.filmX[i], mb.bpt.filmY[i], mb.bpt.L[i] * scale, 0);
        for (uint32_t j = mb.splatStart[i]; j < mb.splatStart[i + 1]; ++j) {
            const SlotSplat& sp = mb.bpt.slotSplats[j];
            mb.addSplat(scene, sp.px, sp.py, sp.value * scale, 0);
        }
    }
    if (a < 1 && g.c[c] > 0) {  // the current state: (1 - a) / c
        const float scale = (1.0f - a) * g.weight / g.c[c];
        if (!isBlack(g.F[c])) mb.addSplat(scene, g.filmX[c], g.filmY[c], g.F[c] * scale, 0);
        for (uint32_t j = 0; j < g.pointCount[c]; ++j) {
            const size_t at = g.pointAt(c, j);
            mb.addSplat(scene, g.pointX[at], g.pointY[at], g.pointF[at] * scale, 0);
        }
    }
}

void keepWholePoints(ChainGroup& g, uint32_t c, const MmltBatch& mb, uint32_t i) {
    const uint32_t n = mb.splatStart[i + 1] - mb.splatStart[i];
    if (n > g.points) throw std::logic_error("PSSMLT: more t = 1 contributions than strategies");
    for (uint32_t j = 0; j < n; ++j) {
        const SlotSplat& sp = mb.bpt.slotSplats[mb.splatStart[i] + j];
        const size_t at = g.pointAt(c, j);
        g.pointX[at] = sp.px;
        g.pointY[at] = sp.py;
        g.pointF[at] = sp.value;
    }
    g.pointCount[c] = uint8_t(n);
}

uint64_t pssmltChainBytes(int maxLength, bool media) {
    return uint64_t(WholeLayout::size(maxLength, media)) * 8 + 5 * 4 + 12 + 8 + uint64_t(maxLength) * 20 + 1;
}

}  // namespace wmlt
