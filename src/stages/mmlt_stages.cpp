#include "stages/mmlt_stages.h"

#include "kernels/mutation.h"
#include "kernels/rng.h"
#include "stages/bpt_stages.h"

namespace wmlt {

namespace {

// Random numbers of a chain's proposal (dimensions of mmltChainKey).
constexpr uint32_t kDimLarge = 0, kDimAccept = 1;
inline uint32_t dimFresh(uint32_t i) { return 2 + 2 * i; }
inline uint32_t dimNormal(uint32_t i) { return 3 + 2 * i; }

// Slot i's strategy from its u0: the walks' lengths and the numbers each stream reads.
inline void setStrategy(MmltBatch& mb, uint32_t i, int k, float u0) {
    const int s = strategyOf(u0, k), t = k + 1 - s;
    BptBatch& b = mb.bpt;
    b.strategyS[i] = uint8_t(s);
    b.pathLength[i] = uint8_t(k);
    b.cam.maxCount[i] = uint8_t(t);
    b.light.maxCount[i] = uint8_t(s >= 2 || (s == 1 && t == 1) ? s : 0);
    mb.used[kBptCamera][i] = uint8_t(StrategyLayout::cameraUsed(t));
    mb.used[kBptLight][i] = uint8_t(StrategyLayout::lightUsed(s, t));
    mb.used[kBptConnect][i] = uint8_t(StrategyLayout::connectUsed(s, t));
}

}  // namespace

uint64_t mmltChainKey(uint64_t seed, uint32_t globalChain, uint32_t iteration) {
    return sampleKey(mix64(seed ^ 0x4d4d4c54u /* "MMLT" */), globalChain, iteration);
}

uint64_t mmltBootstrapKey(uint64_t seed, int k, uint32_t index) {
    return sampleKey(mix64(seed ^ 0x424f4f54u /* "BOOT" */), uint32_t(k), index);
}

void fillBootstrapRows(MmltBatch& mb, int k, uint32_t index0, uint32_t n, uint64_t seed) {
    const uint32_t dims = StrategyLayout::size(k);
    for (uint32_t i = 0; i < n; ++i) {
        const uint64_t key = mmltBootstrapKey(seed, k, index0 + i);
        float* row = &mb.u[size_t(i) * mb.stride];
        for (uint32_t d = 0; d < dims; ++d) row[d] = sampleDimension(key, d);
        setStrategy(mb, i, k, row[0]);
    }
    mb.bpt.numSlots = n;
}

void fillCurrentRows(const ChainGroup& g, MmltBatch& mb, uint32_t c0, uint32_t n) {
    for (uint32_t i = 0; i < n; ++i) {
        float* row = &mb.u[size_t(i) * mb.stride];
        for (uint32_t d = 0; d < g.dims; ++d) row[d] = g.value[size_t(d) * g.count + c0 + i];
        mb.chain[i] = c0 + i;
        setStrategy(mb, i, g.k, row[0]);
    }
    mb.bpt.numSlots = n;
}

void mutateChains(const ChainGroup& g, MmltBatch& mb, uint32_t c0, uint32_t n, uint64_t seed, uint32_t iteration,
                  float probLarge) {
    const float sigma = kSmallStepSigma;
    // The proposal's value of coordinate d of slot i (chain c); uFresh is drawn only when
    // the kernel reads it (a large step, or a stale coordinate).
    auto propose = [&](uint32_t i, uint32_t c, uint32_t d) {
        const size_t at = size_t(d) * g.count + c;
        const uint64_t key = mb.bpt.key[i];
        const uint32_t lastModified = g.lastModified[at], lastLarge = g.lastLarge[c];
        const bool large = mb.large[i];
        const float uFresh = large || lastModified < lastLarge ? sampleDimension(key, dimFresh(d)) : 0.0f;
        const float uNormal = large ? 0.5f : sampleDimension(key, dimNormal(d));
        return proposeCoordinate(g.value[at], lastModified, lastLarge, g.accepted[c] + 1, large, sigma, uFresh,
                                 uNormal);
    };
    // Per slot: the step kind and u0, which picks the strategy and so what else is read.
    for (uint32_t i = 0; i < n; ++i) {
        const uint32_t c = c0 + i;
        const uint64_t key = mmltChainKey(seed, g.first + c, iteration);
        mb.bpt.key[i] = key;
        mb.chain[i] = c;
        mb.large[i] = sampleDimension(key, kDimLarge) < probLarge ? 1 : 0;
        float* row = &mb.u[size_t(i) * mb.stride];
        row[0] = propose(i, c, 0);
        setStrategy(mb, i, g.k, row[0]);
    }
    // Coordinate by coordinate across the batch: coordinate d of consecutive chains is
    // contiguous in the chain state.
    for (int stream = 0; stream < 3; ++stream) {
        const uint32_t base = StrategyLayout::base(g.k, BptStream(stream));
        const uint32_t size = StrategyLayout::blockSize(g.k, BptStream(stream));
        for (uint32_t j = 0; j < size; ++j)
            for (uint32_t i = 0; i < n; ++i)
                if (j < mb.used[stream][i]) mb.u[size_t(i) * mb.stride + base + j] = propose(i, c0 + i, base + j);
    }
    mb.bpt.numSlots = n;
}

void evaluateProposals(const Scene& scene, MmltBatch& mb, float misBeta, PtCounters& counters) {
    BptBatch& b = mb.bpt;
    const StoredSamples u = mb.samples();
    b.nonfinite = 0;
    generateChainCameraPaths(scene, b, u);
    walkBpt(scene, b, b.cam, true, false, counters, u);
    generateBptLightPaths(scene, b, u);
    walkBpt(scene, b, b.light, false, false, counters, u);
    connectStrategies(scene, b, u, misBeta, counters);
    mb.counters.nonfinite += b.nonfinite;
}

void acceptAndSplat(ChainGroup& g, MmltBatch& mb, uint64_t seed, uint32_t iteration, float scale) {
    const uint32_t n = uint32_t(mb.bpt.numSlots);
    for (uint32_t i = 0; i < n; ++i) {
        const uint32_t c = mb.chain[i];
        const Vec3 F = contributionOf(mb, i);
        float cP = luminance(F);
        if (!std::isfinite(cP) || !isFinite(F)) {
            ++mb.counters.nonfinite;
            cP = 0;
        }
        const float a = acceptance(cP, g.c[c]);
        const uint32_t pixel = mb.bpt.pixel[i];
        if (a > 0) mb.splats.push_back({pixel, F * (a * scale / cP)});
        if (a < 1 && g.c[c] > 0) mb.splats.push_back({g.pixel[c], g.F[c] * ((1.0f - a) * scale / g.c[c])});
        const int kind = mb.large[i];
        ++mb.counters.proposed[kind];
        if (kind) mb.counters.largeSum += double(cP);
        const uint64_t key = mmltChainKey(seed, g.first + c, iteration);
        mb.accept[i] = sampleDimension(key, kDimAccept) < a ? 1 : 0;
        if (!mb.accept[i]) continue;
        ++mb.counters.accepted[kind];
        const uint32_t next = g.accepted[c] + 1;
        const size_t at0 = c;  // coordinate 0
        g.value[at0] = mb.u[size_t(i) * mb.stride];
        g.lastModified[at0] = next;
        g.accepted[c] = next;
        if (kind) g.lastLarge[c] = next;
        g.F[c] = F;
        g.c[c] = cP;
        g.pixel[c] = pixel;
    }
    // Commit the accepted proposals' coordinates, coordinate by coordinate (contiguous).
    for (int stream = 0; stream < 3; ++stream) {
        const uint32_t base = StrategyLayout::base(g.k, BptStream(stream));
        const uint32_t size = StrategyLayout::blockSize(g.k, BptStream(stream));
        for (uint32_t j = 0; j < size; ++j)
            for (uint32_t i = 0; i < n; ++i) {
                if (!mb.accept[i] || j >= mb.used[stream][i]) continue;
                const uint32_t c = mb.chain[i];
                const size_t at = size_t(base + j) * g.count + c;
                g.value[at] = mb.u[size_t(i) * mb.stride + base + j];
                g.lastModified[at] = g.accepted[c];  // already advanced to this proposal
            }
    }
}

}  // namespace wmlt
