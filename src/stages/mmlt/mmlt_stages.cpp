#include "stages/mmlt/mmlt_stages.h"

#include <algorithm>
#include <cstring>

#include "kernels/check.h"
#include "kernels/gaussian.h"
#include "kernels/mutation.h"
#include "stages/bpt/bpt_stages.h"
#include "stages/pssmlt/pssmlt_stages.h"

namespace wmlt {

namespace {

// The random numbers of a chain's proposal (dimensions of mmltChainKey): kernels/chain_numbers.h.

// Slot i's strategy from its u0: the walks' lengths and the numbers each stream reads.
inline void setStrategy(MmltBatch& mb, uint32_t i, int k, float u0) {
    const int s = strategyOf(u0, k), t = k + 1 - s;
    BptBatch& b = mb.bpt;
    b.strategyS[i] = uint8_t(s);
    b.pathLength[i] = uint8_t(k);
    b.cam.maxCount[i] = uint8_t(t);
    b.light.maxCount[i] = uint8_t(s >= 2 || (s == 1 && t == 1) ? s : 0);
    mb.used[kBptCamera][i] = uint16_t(StrategyLayout::cameraUsed(t));
    mb.used[kBptLight][i] = uint16_t(StrategyLayout::lightUsed(s, t));
    mb.used[kBptConnect][i] = uint16_t(StrategyLayout::connectUsed(s, t));
}

// Calls fn(d) for every coordinate d > 0 that slot i (length k) reads, in order: the
// prefixes of the blocks its strategy reads (StrategyLayout), less the numbers no walk
// of the scene reads (bpt_state.h's layout: camera j = 2-3 the lens, then vertices of
// four from j = 4; light vertices from j = 5; of each vertex's four, [vertexLo, vertexHi);
// with media, the walks' free-path numbers).
template <class Fn>
void forEachUsedOf(const MmltBatch& mb, uint32_t i, int k, Fn&& fn) {
    auto run = [&](uint32_t d0, uint32_t d1) {
        for (uint32_t d = d0; d < d1; ++d) fn(d);
    };
    const uint32_t lo = mb.vertexLo, hi = mb.vertexHi;
    const uint32_t cb = StrategyLayout::base(k, kBptCamera), cn = mb.used[kBptCamera][i];
    if (cn > 0) run(cb, cb + (mb.lensRead ? 4 : 2));
    for (uint32_t j = 4; j < cn; j += 4) run(cb + j + lo, cb + j + hi);
    const uint32_t lb = StrategyLayout::base(k, kBptLight), ln = mb.used[kBptLight][i];
    if (ln > 0) run(lb, lb + 5);
    for (uint32_t j = 5; j < ln; j += 4) run(lb + j + lo, lb + j + hi);
    const uint32_t xb = StrategyLayout::base(k, kBptConnect);
    run(xb, xb + mb.used[kBptConnect][i]);
    if (mb.bpt.cam.media) {  // each walk segment's free-path number
        const int s = mb.bpt.strategyS[i], t = k + 1 - s;
        const uint32_t mbase = StrategyLayout::mediaBase(k);
        run(mbase, mbase + StrategyLayout::cameraMediaUsed(t));
        run(mbase + uint32_t(k), mbase + uint32_t(k) + StrategyLayout::lightMediaUsed(s));
    }
    if (mb.bpt.spectra) fn(StrategyLayout::size(k, mb.bpt.cam.media));  // the wavelengths' number, the row's last
}

// Both subpaths' vertices packed at the walks' lengths (bpt_state.h, BptVertices::pack).
void packVertices(BptBatch& b) {
    b.cam.pack(b.numSlots);
    b.light.pack(b.numSlots);
}

// Packs the slots' rows of u one after the other, each its length's size (mmlt_state.h).
void packRows(const std::vector<ChainGroup>& groups, MmltBatch& mb) {
    uint32_t at = 0;
    for (const BatchSlice& sl : mb.slices) {
        const uint32_t dims = groups[size_t(sl.group)].dims;
        for (uint32_t j = 0; j < sl.n; ++j, at += dims) mb.row[sl.slot0 + j] = at;
    }
}

}  // namespace

void setNumbersRead(const Scene& scene, MmltBatch& mb) {
    uint8_t reads = 0;  // of the scene's material kinds' BSDF samples
    forEachMaterialKind([&](auto kind) {
        if (scene.features.has(decltype(kind)::value)) reads |= BsdfOf<decltype(kind)::value>::reads;
    });
    // Medium vertices sample the phase function, which no shape's material stands for: with
    // only surfaces that read no direction (a medium in an interface box, a glass ball in
    // fog) their numbers were left out of the rows, and read what the row held before.
    if (scene.features.media) reads |= BsdfOf<MaterialKind::Phase>::reads;
    // Bit m of a vertex's four numbers (0 lobe, 1-2 direction, 3 roulette), then the run
    // [lo, hi) that covers the bits (a number in a gap would be proposed unread: harmless).
    const uint32_t bits = (reads & kReadsLobe ? 1 : 0) | (reads & kReadsDirection ? 6 : 0) | (mb.bpt.roulette ? 8 : 0);
    mb.lensRead = scene.camera.thinLens;
    mb.vertexLo = mb.vertexHi = 0;
    if (bits) {
        mb.vertexLo = uint8_t(__builtin_ctz(bits));
        mb.vertexHi = uint8_t(32 - __builtin_clz(bits));
    }
}

uint64_t mmltChainKey(uint64_t seed, uint32_t globalChain, uint32_t iteration) {
    return sampleKey(mix64(seed ^ 0x4d4d4c54u /* "MMLT" */), globalChain, iteration);
}

uint64_t mmltPoolKey(uint64_t seed, uint32_t pass, int k, uint32_t index) {
    return sampleKey(mix64(mix64(seed ^ 0x504f4f4cu /* "POOL" */) + pass), uint32_t(k), index);
}

void fillPoolRows(MmltBatch& mb, int k, uint32_t pass, uint32_t index0, uint32_t n, uint64_t seed) {
    const uint32_t dims = StrategyLayout::size(k, mb.bpt.cam.media, mb.bpt.spectra != nullptr);
    for (uint32_t i = 0; i < n; ++i) {
        const uint64_t key = mmltPoolKey(seed, pass, k, index0 + i);
        mb.bpt.key[i] = key;
        mb.row[i] = i * dims;
        float* row = mb.rowOf(i);
        row[0] = poolCoordinate(key, 0);
        setStrategy(mb, i, k, row[0]);
        // Only the numbers the strategy reads (the others keep what they held: unread).
        forEachUsedOf(mb, i, k, [&](uint32_t d) { row[d] = poolCoordinate(key, d); });
    }
    mb.bpt.numSlots = n;
    packVertices(mb.bpt);
}

void fillSeedRows(const std::vector<ChainGroup>& groups, MmltBatch& mb) {
    packRows(groups, mb);
    for (const BatchSlice& sl : mb.slices) {
        const ChainGroup& g = groups[size_t(sl.group)];
        for (uint32_t j = 0; j < sl.n; ++j) {
            const uint32_t i = sl.slot0 + j, c = sl.c0 + j;
            float* row = mb.rowOf(i);
            for (uint32_t d = 0; d < g.dims; ++d) row[d] = g.value[g.at(c, d)];
            mb.chain[i] = c;
            setStrategy(mb, i, g.k, row[0]);
        }
    }
    mb.bpt.numSlots = slotsIn(mb.slices);
    packVertices(mb.bpt);
}

namespace {

// The chunk's small steps (SmallStepChunk), written to their rows; the chunk is emptied.
void drawSmallSteps(MmltBatch& mb) {
    SmallStepChunk& st = *mb.steps;
    // Bit for bit proposeCoordinate(value, lastModified, lastLarge, n, false, sigma, uFresh,
    // standardNormal(key, dimNormal(d))) for the draws inside their layer (97.2%), sigma the
    // coordinate's group's (ChainGroup::sigma).
    for (uint32_t m = 0; m < st.count; ++m) {
        const uint64_t key = st.key[m];
        const uint32_t d = st.dim[m];
        const uint64_t h = normalBits(key, dimNormal(d), 0);
        const int layer = int(h & 127);
        const double u = double(h >> 11) * 0x1p-53;
        st.slow[m] = u < kZiggurat.inner[layer] ? 0 : 1;
        const float z = withNormalSign(h, u * kZiggurat.x[layer]);
        // uFresh is read only when the coordinate is stale: drawn for every one, no branch.
        st.out[m] = proposeCoordinate(st.value[m], st.lastModified[m], st.lastLarge[m], st.n[m], false, st.sigma[m], poolCoordinate(key, d), z);
    }
    for (uint32_t m = 0; m < st.count; ++m) {
        if (st.slow[m]) st.out[m] = smallStepOf(st.key[m], st.dim[m], st.value[m], st.lastModified[m], st.lastLarge[m], st.n[m], st.sigma[m]);
        mb.u[st.dst[m]] = st.out[m];
    }
    st.count = 0;
}

// Slot i proposes a film step from chain c (RenderOptions::filmSteps): the chain's state
// with its raster point moved (filmStepOf), when its strategy reads one (t >= 2; else the
// state itself, a move that changes nothing). Every coordinate the state reads is up to date
// (the last accepted proposal read it), so the row is the chain's values. The strategy,
// and so the coordinates read, are the state's: the move and its reverse both read these.
void proposeFilmStep(MmltBatch& mb, uint32_t i, const ChainGroup& g, uint32_t c) {
    mb.large[i] = kFilmStep;
    const uint64_t key = mb.bpt.key[i];
    const size_t at = g.at(c, 0);
    float* row = mb.rowOf(i);
    row[0] = g.value[at];
    setStrategy(mb, i, g.k, row[0]);
    forEachUsedOf(mb, i, g.k, [&](uint32_t d) { row[d] = g.value[at + d]; });
    if (mb.used[kBptCamera][i] == 0) return;
    const uint32_t cb = StrategyLayout::base(g.k, kBptCamera);  // the raster point: camera j = 0, 1
    for (uint32_t d = cb; d < cb + 2; ++d) row[d] = filmStepOf(key, d, g.value[at + d], g.sigma);
}

// Commits an accepted film step: the raster point's two numbers (still up to date as of the
// chain's last accepted proposal: a film step is no step of the lazy count, so lastModified
// and accepted stay), F, c and the film point.
void commitFilmStep(ChainGroup& g, uint32_t c, const MmltBatch& mb, uint32_t i, const Vec3& F, float cP) {
    if (mb.used[kBptCamera][i] > 0) {
        const uint32_t cb = StrategyLayout::base(g.k, kBptCamera);
        const float* row = &mb.u[mb.row[i]];
        for (uint32_t d = cb; d < cb + 2; ++d) g.value[g.at(c, d)] = row[d];
    }
    g.F[c] = F;
    g.c[c] = cP;
    g.filmX[c] = mb.bpt.filmX[i];
    g.filmY[c] = mb.bpt.filmY[i];
}

}  // namespace

void mutateChains(const std::vector<ChainGroup>& groups, MmltBatch& mb, uint64_t seed, uint32_t iteration, float probLarge) {
    SmallStepChunk& st = *mb.steps;
    st.count = 0;
    packRows(groups, mb);
    for (const BatchSlice& sl : mb.slices) {
        const ChainGroup& g = groups[size_t(sl.group)];
        // Slot by slot (chain c = sl.c0 + j): the step kind and u0, which picks the
        // strategy and so which other coordinates the proposal reads; then those (a small
        // step's are listed for drawSmallSteps).
        for (uint32_t j = 0; j < sl.n; ++j) {
            const uint32_t i = sl.slot0 + j, c = sl.c0 + j;
            const bool large = beginProposal(mb, i, g, c, seed, iteration, probLarge);
            const uint64_t key = mb.bpt.key[i];
            if (!large && g.filmStep > 0 && !mb.secondStage && sampleDimension(key, kDimFilmStep) < g.filmStep) {
                proposeFilmStep(mb, i, g, c);
                continue;
            }
            const size_t at = g.at(c, 0);
            const uint32_t lastLarge = g.lastLarge[c], n = g.accepted[c] + 1;
            float* row = mb.rowOf(i);
            row[0] = large ? poolCoordinate(key, 0) : smallStepOf(key, 0, g.value[at], g.lastModified[at], lastLarge, n, g.sigma);
            setStrategy(mb, i, g.k, row[0]);
            if (large) {
                forEachUsedOf(mb, i, g.k, [&](uint32_t d) { row[d] = poolCoordinate(key, d); });
                continue;
            }
            forEachUsedOf(mb, i, g.k, [&](uint32_t d) {
                if (st.count == SmallStepChunk::kSize) drawSmallSteps(mb);
                const uint32_t m = st.count++;
                st.key[m] = key;
                st.value[m] = g.value[at + d];
                st.lastModified[m] = g.lastModified[at + d];
                st.lastLarge[m] = lastLarge;
                st.n[m] = n;
                st.sigma[m] = g.sigma;
                st.dim[m] = d;
                st.dst[m] = mb.row[i] + d;
            });
        }
    }
    drawSmallSteps(mb);
    mb.bpt.numSlots = slotsIn(mb.slices);
    packVertices(mb.bpt);
}

void evaluateProposals(const Scene& scene, MmltBatch& mb, float misBeta, RayCounters& counters) {
    BptBatch& b = mb.bpt;
    const StoredSamples u = mb.samples();
    b.tally.nonfinite = 0;
    if (b.spectra)  // each slot's wavelengths, from its row's number
        for (uint32_t i = 0; i < b.numSlots; ++i) b.lambda[i] = sampleWavelengths(u.wavelength(i));
    generateChainCameraPaths(scene, b, u);
    walkBpt(scene, b, b.cam, true, false, counters, u);
    generateBptLightPaths(scene, b, u);
    walkBpt(scene, b, b.light, false, false, counters, u);
    connectStrategies(scene, b, u, misBeta, counters);
    mb.counters.nonfinite += b.tally.nonfinite;
}

namespace {

// A slot's target and F: MMLT's (evaluatedTarget) or PSSMLT's whole sample's (wholeTarget).
template <bool Whole>
float targetOfSlot(MmltBatch& mb, uint32_t i, Vec3& F) {
    if constexpr (Whole) return wholeTarget(mb, i, F);
    else return evaluatedTarget(mb, i, F);
}

template <bool Whole>
void addPoolSamplesOf(MmltBatch& mb, uint32_t n, SamplePool& pool) {
    for (uint32_t i = 0; i < n; ++i) {
        Vec3 F;
        const float c = targetOfSlot<Whole>(mb, i, F);
        mb.poolFor(mb.bpt.key[i], mb.bpt.pathLength[i], pool).addSample(mb.bpt.key[i], c, F, mb.bpt.filmX[i], mb.bpt.filmY[i]);
    }
}

template <bool Whole>
uint64_t countReplayMismatchesOf(std::vector<ChainGroup>& groups, MmltBatch& mb, bool plant) {
    uint64_t mismatches = 0;
    for (const BatchSlice& sl : mb.slices) {
        ChainGroup& g = groups[size_t(sl.group)];
        for (uint32_t j = 0; j < sl.n; ++j) {
            const uint32_t i = sl.slot0 + j, c = sl.c0 + j;
            Vec3 F = contributionOf(mb, i);
            if (plant && i == 0) F = F + Vec3(1.0f);  // (tests only)
            float cc = slotTarget(mb, i, F);
            if constexpr (Whole) {
                cc = wholeTarget(mb, i, F);
                keepWholePoints(g, c, mb, i);
            }
            if (std::memcmp(&cc, &g.c[c], sizeof cc) != 0 || std::memcmp(&F, &g.F[c], sizeof F) != 0 ||
                std::memcmp(&mb.bpt.filmX[i], &g.filmX[c], sizeof(float)) != 0 || std::memcmp(&mb.bpt.filmY[i], &g.filmY[c], sizeof(float)) != 0)
                ++mismatches;
        }
    }
    return mismatches;
}

}  // namespace

void commitProposal(ChainGroup& g, uint32_t c, const MmltBatch& mb, uint32_t i, bool large, const Vec3& F, float cP) {
    // The coordinates the proposal read (the chain's block is contiguous).
    const uint32_t next = g.accepted[c] + 1;
    const float* row = &mb.u[mb.row[i]];
    float* value = &g.value[g.at(c, 0)];
    uint32_t* lastModified = &g.lastModified[g.at(c, 0)];
    value[0] = row[0];
    lastModified[0] = next;
    forEachUsedOf(mb, i, g.k, [&](uint32_t d) {
        value[d] = row[d];
        lastModified[d] = next;
    });
    commitState(g, c, large, F, cP, mb.bpt.filmX[i], mb.bpt.filmY[i]);
}

namespace {

template <bool Whole>
void acceptAndSplatOf(const Scene& scene, std::vector<ChainGroup>& groups, MmltBatch& mb) {
    for (const BatchSlice& sl : mb.slices) {
        ChainGroup& g = groups[size_t(sl.group)];
        const uint8_t k = uint8_t(g.k);
        SamplePool& pool = mb.pools[size_t(g.k)];
        for (uint32_t j = 0; j < sl.n; ++j) {
            const uint32_t i = sl.slot0 + j, c = mb.chain[i];
            Vec3 F;  // PSSMLT: the camera side's (the t = 1 contributions are in slotSplats)
            const float cP = targetOfSlot<Whole>(mb, i, F);
            const float a = acceptance(cP, g.c[c]);
            // a chain's state is always a sample the target sees (seeded from lit pool entries,
            // moved only to proposals with cP > 0): else its splats would divide by 0
            WMLT_DCHECK(g.c[c] > 0 && std::isfinite(g.c[c]),
                        "chain " + std::to_string(c) + " of length " + std::to_string(g.k) + " has target " + std::to_string(g.c[c]));
            WMLT_DCHECK(std::isfinite(g.weight) && g.weight >= 0, "length " + std::to_string(g.k) + "'s splat weight " + std::to_string(g.weight));
            const float filmX = mb.bpt.filmX[i], filmY = mb.bpt.filmY[i];
            const int kind = mb.large[i];
            // Delayed rejection (MMLT): a large step's current state is splatted by the second
            // stage if it is rejected, and not at all if it is accepted (mmlt_delayed.cpp).
            const bool delay = !Whole && kind == kLargeStep && mb.delayed;
            if constexpr (Whole) {
                splatWhole(scene, g, c, mb, i, a, cP);
            } else {
                if (a > 0) mb.addSplat(scene, filmX, filmY, F * (a * g.weight / cP), k);
                if (a < 1 && g.c[c] > 0 && !delay) mb.addSplat(scene, g.filmX[c], g.filmY[c], g.F[c] * ((1.0f - a) * g.weight / g.c[c]), k);
            }
            ++mb.counters.proposed[kind][k];
            if (kind == kLargeStep)
                mb.poolFor(mb.bpt.key[i], g.k, pool).addSample(mb.bpt.key[i], cP, F, filmX, filmY);  // an independent uniform sample of u
            if (!(sampleDimension(mb.bpt.key[i], kDimAccept) < a)) {                                 // rejected
                if (delay) {
                    mb.rejectedLarge.push_back({sl.group, c, 1, uint32_t(mb.rejectedLarge.size())});
                    mb.rejectedC.push_back(cP);
                }
                continue;
            }
            ++mb.counters.accepted[kind][k];
            if constexpr (Whole) {
                commitWhole(g, c, mb, i, g.accepted[c] + 1);
                commitState(g, c, kind == kLargeStep, F, cP, filmX, filmY);
                keepWholePoints(g, c, mb, i);
            } else if (kind == kFilmStep) {
                commitFilmStep(g, c, mb, i, F, cP);
            } else {
                commitProposal(g, c, mb, i, kind == kLargeStep, F, cP);
            }
        }
    }
}

}  // namespace

void addPoolSamples(MmltBatch& mb, uint32_t n, SamplePool& pool) { addPoolSamplesOf<false>(mb, n, pool); }
void acceptAndSplat(const Scene& scene, std::vector<ChainGroup>& groups, MmltBatch& mb) { acceptAndSplatOf<false>(scene, groups, mb); }
uint64_t countReplayMismatches(std::vector<ChainGroup>& groups, MmltBatch& mb, bool plant) {
    return countReplayMismatchesOf<false>(groups, mb, plant);
}

const ChainStages kMmltStages = {fillPoolRows, fillSeedRows, mutateChains, evaluateProposals, addPoolSamples, acceptAndSplat, countReplayMismatches};
const ChainStages kPssmltStages = {
    [](MmltBatch& mb, int, uint32_t pass, uint32_t index0, uint32_t n, uint64_t seed) { fillWholePoolSlots(mb, pass, index0, n, seed); },
    fillWholeSeedSlots,
    mutateWholeChains,
    evaluateWholeProposals,
    addPoolSamplesOf<true>,
    acceptAndSplatOf<true>,
    countReplayMismatchesOf<true>};

}  // namespace wmlt
