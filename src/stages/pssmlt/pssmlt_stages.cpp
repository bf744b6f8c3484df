#include "stages/pssmlt/pssmlt_stages.h"

#include <stdexcept>

#include "stages/bpt/bpt_stages.h"
#include "stages/mmlt/mmlt_stages.h"

namespace wmlt {

namespace {

// Slot i: both walks to their longest, the path length maxLength.
void setWholeSample(MmltBatch& mb, uint32_t i) {
    BptBatch& b = mb.bpt;
    b.strategyS[i] = 0;
    b.pathLength[i] = uint8_t(mb.maxLength);
    b.cam.maxCount[i] = uint8_t(b.cam.capacity);
    b.light.maxCount[i] = uint8_t(b.light.capacity);
}

}  // namespace

void fillWholePoolSlots(MmltBatch& mb, uint32_t pass, uint32_t index0, uint32_t n, uint64_t seed) {
    mb.wholeGroup = nullptr;
    for (uint32_t i = 0; i < n; ++i) {
        mb.bpt.key[i] = mmltPoolKey(seed, pass, 0, index0 + i);
        mb.wholeKind[i] = WholeProposal::Fresh;
        setWholeSample(mb, i);
    }
    mb.bpt.numSlots = n;
}

void fillWholeSeedSlots(const std::vector<ChainGroup>& groups, MmltBatch& mb) {
    for (const BatchSlice& sl : mb.slices) {
        const ChainGroup& g = groups[size_t(sl.group)];
        mb.wholeGroup = &g;
        for (uint32_t j = 0; j < sl.n; ++j) {
            const uint32_t i = sl.slot0 + j, c = sl.c0 + j;
            mb.chain[i] = c;
            mb.chainAt[i] = uint32_t(g.at(c, 0));
            mb.seedKey[i] = g.seed[c];
            mb.wholeKind[i] = WholeProposal::Replay;
            setWholeSample(mb, i);
        }
    }
    mb.bpt.numSlots = slotsIn(mb.slices);
}

void mutateWholeChains(const std::vector<ChainGroup>& groups, MmltBatch& mb, uint64_t seed, uint32_t iteration, float probLarge) {
    for (const BatchSlice& sl : mb.slices) {
        const ChainGroup& g = groups[size_t(sl.group)];
        mb.wholeGroup = &g;
        for (uint32_t j = 0; j < sl.n; ++j) {
            const uint32_t i = sl.slot0 + j, c = sl.c0 + j;
            const bool large = beginProposal(mb, i, g, c, seed, iteration, probLarge);
            mb.chainAt[i] = uint32_t(g.at(c, 0));
            mb.seedKey[i] = g.seed[c];
            mb.slotLastLarge[i] = g.lastLarge[c];
            mb.slotN[i] = g.accepted[c] + 1;
            mb.wholeKind[i] = large ? WholeProposal::Fresh : WholeProposal::SmallStep;
            setWholeSample(mb, i);
        }
    }
    mb.bpt.numSlots = slotsIn(mb.slices);
}

void evaluateWholeProposals(const Scene& scene, MmltBatch& mb, float misBeta, RayCounters& counters) {
    BptBatch& b = mb.bpt;
    for (uint32_t i = 0; i < b.numSlots; ++i) {  // the last evaluation's flags, by its lists
        const size_t row = size_t(i) * mb.wholeDims;
        for (uint32_t j = 0; j < mb.readCount[i]; ++j) mb.read[row + mb.readList[row + j]] = 0;
        mb.readCount[i] = 0;
    }
    const WholeSamples u = mb.wholeSamples();
    b.tally.nonfinite = 0;
    b.slotSplats.clear();
    if (b.spectra)  // each slot's wavelengths, from its sample's number
        for (uint32_t i = 0; i < b.numSlots; ++i) b.lambda[i] = sampleWavelengths(u.wavelength(i));
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

void commitWhole(ChainGroup& g, uint32_t c, const MmltBatch& mb, uint32_t i, uint32_t next) {
    const size_t at = g.at(c, 0), row = size_t(i) * mb.wholeDims;
    for (uint32_t j = 0; j < mb.readCount[i]; ++j) {
        const uint32_t d = mb.readList[row + j];
        g.value[at + d] = mb.proposed[row + d];
        g.lastModified[at + d] = next;
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

uint64_t pssmltChainBytes(int maxLength, bool media, bool spectral) {
    return uint64_t(WholeLayout::size(maxLength, media, spectral)) * 8 + 5 * 4 + 12 + 8 + uint64_t(maxLength) * 20 + 1;
}

}  // namespace wmlt
