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

// Calls f(coordinate) for each coordinate slot i's proposal reads (u0 excluded).
template <class F>
inline void forEachUsed(const MmltBatch& mb, uint32_t i, int k, F&& f) {
    for (int c = 0; c < 3; ++c) {
        const uint32_t base = StrategyLayout::base(k, BptStream(c));
        for (uint32_t j = 0; j < mb.used[c][i]; ++j) f(base + j);
    }
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
    for (uint32_t i = 0; i < n; ++i) {
        const uint32_t c = c0 + i;
        const uint64_t key = mmltChainKey(seed, g.first + c, iteration);
        const bool large = sampleDimension(key, kDimLarge) < probLarge;
        const uint32_t next = g.accepted[c] + 1, lastLarge = g.lastLarge[c];
        auto propose = [&](uint32_t d) {
            const size_t at = size_t(d) * g.count + c;
            return proposeCoordinate(g.value[at], g.lastModified[at], lastLarge, next, large, sigma,
                                     sampleDimension(key, dimFresh(d)), sampleDimension(key, dimNormal(d)));
        };
        float* row = &mb.u[size_t(i) * mb.stride];
        mb.chain[i] = c;
        mb.large[i] = large ? 1 : 0;
        row[0] = propose(0);  // the strategy first: it decides what else is read
        setStrategy(mb, i, g.k, row[0]);
        forEachUsed(mb, i, g.k, [&](uint32_t d) { row[d] = propose(d); });
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
    for (uint32_t i = 0; i < mb.bpt.numSlots; ++i) {
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
        if (a < 1) mb.splats.push_back({g.pixel[c], g.F[c] * ((1.0f - a) * scale / g.c[c])});
        const int kind = mb.large[i];
        ++mb.counters.proposed[kind];
        const uint64_t key = mmltChainKey(seed, g.first + c, iteration);
        if (!(sampleDimension(key, kDimAccept) < a)) continue;
        // Accept: commit the coordinates the proposal wrote.
        ++mb.counters.accepted[kind];
        const uint32_t next = g.accepted[c] + 1;
        const float* row = &mb.u[size_t(i) * mb.stride];
        auto commit = [&](uint32_t d) {
            const size_t at = size_t(d) * g.count + c;
            g.value[at] = row[d];
            g.lastModified[at] = next;
        };
        commit(0);
        forEachUsed(mb, i, g.k, commit);
        g.accepted[c] = next;
        if (kind) g.lastLarge[c] = next;
        g.F[c] = F;
        g.c[c] = cP;
        g.pixel[c] = pixel;
    }
}

}  // namespace wmlt
