// Structure-of-arrays state of MMLT (Hachisuka et al. 2014): the sample pools, the Markov
// chains of one pass, grouped by path length, and one batch of chains in flight.
//
// A chain of length k carries a primary sample vector u of StrategyLayout::size(k, media)
// coordinates (bpt_state.h: u[0] picks the strategy, then the camera, light and connection
// blocks). A chain's coordinates are side by side (ChainGroup::at). Each coordinate
// stores its value and the accepted proposal that last wrote it (kernels/mutation.h: the
// lazy small step). A proposal never writes the chain: the batch holds it, and only an
// accepted proposal is committed, so a rejection restores every coordinate by doing nothing.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "kernels/mmlt_target.h"
#include "stages/bpt/bpt_state.h"
#include "wavemmlt/render.h"

namespace wmlt {

// One in four of the independent samples of u, by its key's hash, makes the relative
// target's map instead of joining a pool (MmltBatch::splitForMap).
inline bool mapSample(uint64_t key) { return (mix64(key ^ 0x4d4150u /* "MAP" */) & 3) == 0; }

// A sample of u kept in a pool: its key (u_d = poolCoordinate(key, d)), its target c > 0,
// its weight w, the contribution F and film point its evaluation gave (a chain seeded there
// starts with them; a share of the seeds is replayed to check them, seedChains), and the
// batch of its pool it came in (SamplePool). In a batch being gathered w is 1, or 1 / the
// probability it survived the pool's thinning; in a pool of batches w also carries its
// batch's weight over the batch's count.
struct PoolEntry {
    uint64_t key;
    float c, w;
    Vec3 F;
    float filmX, filmY;
    uint32_t batch;
};

// One batch of a pool of length k (SamplePool::batches): its samples of length k (fresh of
// them drawn for the pool, the rest large steps), the share of the later batches' large
// steps its weight predicts for k (poolWeights), and its entries' factor now (its weight
// over count).
struct PoolBatch {
    uint64_t count = 0, fresh = 0;
    double share = 0;
    double factor = 1;
};

// Independent uniform samples of u of one length k (mmlt.md, "Many chains"; the design in
// docs/mmlt-chains.md): the bootstrap, each pass's fresh samples and every large-step
// proposal; those with c > 0 are kept, each with a weight, so that sum_i w_i h(x_i) is an
// unbiased estimate of E[h] for any h (once the pool is in batches; while a batch is
// gathered, of count E[h]). b = E[c] is estimated by sumWC, and chains start at entries
// chosen in proportion to w c: together an unbiased start (importance resampling). When
// the entries outgrow their capacity, thinPool keeps each with a probability and divides
// its weight by it (Russian roulette: the sums stay unbiased), so the memory stays bounded.
// A pool is a list of batches (the bootstrap's two halves; each pass's large steps with the
// next pass's fresh samples), and how many samples of length k a batch holds depends on
// values: on the chains length k had, which follow the pools' means. A mean over a count
// that depends on the values it averages is biased (optional stopping: a length whose pool
// read high got more chains, and its reading was diluted sooner than a low one's; the seed
// room, lengths 3 and 4 at 32 x 32, read 3.1% low over 1000 seeds, z = -6.9). So each
// batch weighs alpha_b, weights that sum to 1 and that no value of the batch decides
// (poolWeights): then sum_b alpha_b mean_b is unbiased for any split.
struct SamplePool {
    std::vector<PoolEntry> lit;
    double sumWC = 0;                // sum over lit of w c
    uint64_t count = 0;              // samples drawn
    std::vector<PoolBatch> batches;  // empty: a batch being gathered
    double mean() const { return !batches.empty() ? sumWC : count ? sumWC / double(count) : 0.0; }
    // One more independent sample (its key, target c, contribution F and film point).
    void addSample(uint64_t key, float c, Vec3 F, float filmX, float filmY) {
        sumWC += double(c);
        ++count;
        if (c > 0) lit.push_back({key, c, 1.0f, F, filmX, filmY, 0});
    }
    // Samples of the same batch (o has no batches).
    void add(const SamplePool& o) {
        lit.insert(lit.end(), o.lit.begin(), o.lit.end());
        sumWC += o.sumWC;
        count += o.count;
    }
    // A gathered batch o as the pool's next batch, its weight still to be set (weigh).
    void addBatch(const SamplePool& o, uint64_t fresh, double share) {
        const uint32_t b = uint32_t(batches.size());
        for (PoolEntry e : o.lit) {
            e.batch = b;
            lit.push_back(e);
        }
        count += o.count;
        batches.push_back({o.count, fresh, share, 1.0});
    }
    // The batches' weights alpha (poolWeights): each entry's w times its batch's new factor
    // over its old one.
    void weigh(const std::vector<double>& alpha) {
        std::vector<double> ratio(batches.size(), 0.0);
        for (size_t b = 0; b < batches.size(); ++b) {
            const double factor = batches[b].count ? alpha[b] / double(batches[b].count) : 0.0;
            ratio[b] = batches[b].factor > 0 ? factor / batches[b].factor : 0.0;
            batches[b].factor = factor;
        }
        sumWC = 0;
        for (PoolEntry& e : lit) {
            e.w = float(double(e.w) * ratio[e.batch]);
            sumWC += double(e.w) * double(e.c);
        }
    }
    void clear() {
        lit.clear();
        sumWC = 0;
        count = 0;
        batches.clear();
    }
};

// The chains of one path length k in the current pass (ChainGroup). Per chain and
// coordinate, at(chain, coordinate): a chain's coordinates side by side, so that a proposal
// reads one contiguous block:
//   value: the coordinate's value
//   lastModified: the accepted proposal that last wrote it (mutation.h's lazy small step)
// Per chain:
//   accepted: its accepted proposals (the lazy step's clock)
//   lastLarge: its last accepted large step
//   F: the current state's contribution, (k + 1) L_w
//   c: its target (kernels/mmlt_target.h: luminance(F), or over its tile's brightness)
//   filmX, filmY: its film point
//   seed: the key of the pool entry it started from
#define WMLT_CHAIN_COORDINATE_ARRAYS(X) X(float, value) X(uint32_t, lastModified)
// clang-format off
#define WMLT_CHAIN_ARRAYS(X)                                                                 \
    X(uint32_t, accepted) X(uint32_t, lastLarge) X(Vec3, F) X(float, c) X(float, filmX)      \
    X(float, filmY) X(uint64_t, seed)
// clang-format on

// PSSMLT (a group of whole BPT samples, k = 0): F and the film point are the camera side's
// contribution and its raster point, c the luminance of the whole sample; each chain also
// keeps its t = 1 contributions, up to `points` side by side (pointAt(chain, j); how many:
// pointCount):
//   pointX, pointY: a contribution's film point
//   pointF: its value
#define WMLT_CHAIN_POINT_ARRAYS(X) X(float, pointX) X(float, pointY) X(Vec3, pointF)

struct ChainGroup {
    int k = 0;                      // the path length; 0: PSSMLT's whole samples
    uint32_t count = 0;             // chains of this length
    uint32_t first = 0;             // global index of its first chain
    uint32_t dims = 0;              // StrategyLayout::size(k, media) (PSSMLT: WholeLayout::size)
    uint32_t points = 0;            // PSSMLT: t = 1 contributions a chain keeps at most
    float weight = 0;               // b_k of the pass's pool / count: each splat's factor
    float sigma = kSmallStepSigma;  // its small steps' size this pass (RenderOptions::learnSteps)
    float filmStep = 0;             // a small step's probability of being a film step this pass (RenderOptions::filmSteps)
    WMLT_CHAIN_COORDINATE_ARRAYS(WMLT_SOA_ARRAY)
    WMLT_CHAIN_ARRAYS(WMLT_SOA_ARRAY)
    WMLT_CHAIN_POINT_ARRAYS(WMLT_SOA_ARRAY)
    std::vector<uint8_t> pointCount;

    size_t at(uint32_t chain, uint32_t d) const { return size_t(chain) * dims + d; }
    size_t pointAt(uint32_t chain, uint32_t j) const { return size_t(chain) * points + j; }

    // count chains, every array zeroed.
    void resize(uint32_t chains) {
        count = chains;
        size_t n = size_t(dims) * chains;
        WMLT_CHAIN_COORDINATE_ARRAYS(WMLT_SOA_ZERO)
        n = chains;
        WMLT_CHAIN_ARRAYS(WMLT_SOA_ZERO)
        if (points == 0) return;
        pointCount.assign(n, 0);
        n = size_t(points) * chains;
        WMLT_CHAIN_POINT_ARRAYS(WMLT_SOA_ZERO)
    }
};

// Chains [c0, c0 + n) of group `group`, in slots [slot0, slot0 + n) of a batch.
struct BatchSlice {
    int group;
    uint32_t c0, n, slot0;
};

// The slots a batch's slices fill.
inline uint32_t slotsIn(const std::vector<BatchSlice>& b) { return b.empty() ? 0 : b.back().slot0 + b.back().n; }

// The kinds of a proposal (MmltBatch::large, MmltCounters' first index): a small step, a large
// step, delayed rejection's second proposal (mmlt_delayed.cpp) and a film step
// (RenderOptions::filmSteps; mmlt_stages.cpp).
constexpr uint8_t kSmallStep = 0, kLargeStep = 1, kSecondStage = 2, kFilmStep = 3;

// Counters of one batch, per path length (merged in batch order).
struct MmltCounters {
    // [kind]: kSmallStep, kLargeStep, kSecondStage, kFilmStep
    uint64_t proposed[4][kMaxPathLength + 1] = {}, accepted[4][kMaxPathLength + 1] = {};
    uint64_t nonfinite = 0;
    // The luminance splatted per length (MmltBatch::tallyLuminance only: a target other than
    // the luminance, whose b_k is then no length's mean luminance)
    double splatLuminance[kMaxPathLength + 1] = {};
    void add(const MmltCounters& o) {
        for (int s = 0; s < 4; ++s)
            for (int k = 0; k <= kMaxPathLength; ++k) {
                proposed[s][k] += o.proposed[s][k];
                accepted[s][k] += o.accepted[s][k];
            }
        for (int k = 0; k <= kMaxPathLength; ++k) splatLuminance[k] += o.splatLuminance[k];
        nonfinite += o.nonfinite;
    }
};

// The small steps of a batch's proposals, a chunk of coordinates at a time (mutateChains):
// listed slot by slot with what the lazy step reads, drawn in one flat loop the compiler
// vectorises (the hashes, the ziggurat's fast path, the step and the wrap), then the few
// draws outside their layer's rectangle redone (gaussianSlow) and each result written to
// its row at dst.
struct SmallStepChunk {
    static constexpr uint32_t kSize = 1024;
    uint32_t count = 0;
    uint64_t key[kSize];
    float value[kSize], out[kSize], sigma[kSize];
    uint32_t lastModified[kSize], lastLarge[kSize], n[kSize], dim[kSize], dst[kSize];
    uint8_t slow[kSize];
};

// A batch of chains in flight: slices of several lengths side by side (a batch holds a
// share of every length's chains, so that batches cost about the same), their proposals
// (rows of u, as StoredSamples reads them), the BPT stages' state, and what a round
// produces: splats, the large steps for the next pass's pools, counters.
struct MmltBatch {
    BptBatch bpt;
    // Slot i's proposal: u[row[i] + coordinate], rows packed at their lengths' sizes
    // (StrategyLayout::size(k, media)), so that a batch's numbers stay in cache (rows of the
    // longest length's size were 2 KB apart at MaxPathLength 64). Per slot:
    //   row: where its row starts in u
    //   chain: its chain (its index within its group)
    //   large: the proposal's kind: kSmallStep, kLargeStep or kFilmStep (the raster point
    //     alone, RenderOptions::filmSteps)
    std::vector<float> u;
#define WMLT_MMLT_SLOT_ARRAYS(X) X(uint32_t, row) X(uint32_t, chain) X(uint8_t, large)
    WMLT_MMLT_SLOT_ARRAYS(WMLT_SOA_ARRAY)
    std::vector<uint16_t> used[3];  // the prefix of each stream's block the strategy reads (256 at k = 64, s = 0)
    // Which numbers within those prefixes the scene's walks read (setNumbersRead): the
    // lens point (a thin lens), and numbers [vertexLo, vertexHi) of each vertex's four
    // (0 lobe, 1-2 direction, 3 roulette). The others are neither proposed nor committed.
    bool lensRead = true;
    uint8_t vertexLo = 0, vertexHi = 4;
    std::vector<BatchSlice> slices;
    // Delayed rejection (RenderOptions::delayedRejection, mmlt_delayed.cpp): the chains whose
    // large step this iteration rejected, one slice each, and each one's first proposal's
    // target c(y1); the second stage runs them in slices' stead.
    bool delayed = false;
    bool secondStage = false;  // mutateChains is proposing the second stage's small steps (no film steps)
    std::vector<BatchSlice> rejectedLarge;
    std::vector<float> rejectedC;
    // The pass's target map (kernels/mmlt_target.h; no map: the luminance), set by the driver
    // for every task: pools, seeds, replays and acceptance all read it.
    TargetMap target;
    // Expected-value splats of the round, in order, grouped by film stripe (2^stripeShift
    // pixels each: the rounds merge the film one stripe per task), with their path lengths.
    static constexpr uint32_t kStripes = 64;
    uint32_t stripeShift = 31;
    // The lengths only for --length-images (splatLengths): their byte stores may alias
    // anything, so the splat lists' pointers were reloaded after each (a third of
    // acceptAndSplat's samples were in these appends).
    std::vector<Splat> splats[kStripes];
    std::vector<uint8_t> splatLength[kStripes];
    bool splatLengths = false;
    void addSplat(uint32_t pixel, Vec3 v, uint8_t k) {
        const uint32_t st = pixel >> stripeShift;
        splats[st].push_back({pixel, v});
        if (splatLengths) splatLength[st].push_back(k);
    }
    // v at film point (px, py): to the pixel holding it (box filter), or kept as a film
    // point in every stripe its filter footprint reaches (the merge spreads it over the
    // footprint's pixels of each stripe: mergeStripe, mmlt.cpp).
    std::vector<PointSplat> points[kStripes];
    std::vector<uint8_t> pointLength[kStripes];
    void clearSplats() {
        for (uint32_t st = 0; st < kStripes; ++st) {
            splats[st].clear();
            splatLength[st].clear();
            points[st].clear();
            pointLength[st].clear();
        }
    }
    bool tallyLuminance = false;  // counters.splatLuminance (a tempered target; chosen once)
    __attribute__((always_inline)) void addSplat(const Scene& scene, float px, float py, Vec3 v, uint8_t k) {
        if (tallyLuminance) counters.splatLuminance[k] += double(luminance(v));
        if (scene.filter.box) {  // the pixel holding the point, inline
            addSplat(rasterPixel(scene.camera, px, py), v, k);
            return;
        }
        addPointSplat(scene, px, py, v, k);
    }
    __attribute__((noinline)) void addPointSplat(const Scene& scene, float px, float py, Vec3 v, uint8_t k) {
        int x0, x1, y0, y1;
        filterFootprint(scene.filter, scene.camera.width, scene.camera.height, px, py, x0, x1, y0, y1);
        const uint32_t w = uint32_t(scene.camera.width);
        const uint32_t st0 = (uint32_t(y0) * w + uint32_t(x0)) >> stripeShift;
        const uint32_t st1 = (uint32_t(y1) * w + uint32_t(x1)) >> stripeShift;
        for (uint32_t st = st0; st <= st1 && st < kStripes; ++st) {
            points[st].push_back({px, py, v});
            if (splatLengths) pointLength[st].push_back(k);
        }
    }
    std::vector<SamplePool> pools;  // [k]: this batch's large-step proposals of the round
    // The relative target (RenderOptions::mmltTarget): a share of the independent samples
    // (mapSample, by key) goes to mapPools, never to a pool, so that the target map they make
    // is independent of the pools it weighs (mmlt_learn.cpp).
    bool splitForMap = false;
    std::vector<SamplePool> mapPools;  // [k]
    SamplePool& poolFor(uint64_t key, int k, SamplePool& pool) { return splitForMap && mapSample(key) ? mapPools[size_t(k)] : pool; }
    MmltCounters counters;
    std::unique_ptr<SmallStepChunk> steps = std::make_unique<SmallStepChunk>();
    // PSSMLT (pssmlt_stages.h): every slot a whole BPT sample of paths up to maxLength
    // (WholeLayout, wholeDims coordinates) whose coordinates are proposed as they are read
    // (WholeSamples), the chains' group (null for pool samples), and after an evaluation
    // slot i's t = 1 contributions bpt.slotSplats[splatStart[i], splatStart[i + 1]).
    bool whole = false;
    int maxLength = 0;
    uint32_t wholeDims = 0;
    const ChainGroup* wholeGroup = nullptr;
    // Per slot, what WholeSamples reads:
    //   wholeKind: the proposal's kind (a replay, a small step, fresh)
    //   seedKey: its chain's seed (the coordinates not written since: poolCoordinate)
    //   chainAt: its chain's first coordinate in the group
    //   slotLastLarge: its chain's last accepted large step
    //   slotN: the proposal's number n (mutation.h)
    //   readCount: the coordinates read so far (readList)
    // Per slot and coordinate (proposed, read, readList below): the value read, whether it
    // was, and the coordinates read in order.
// clang-format off
#define WMLT_WHOLE_SLOT_ARRAYS(X)                                                            \
    X(WholeProposal, wholeKind) X(uint64_t, seedKey) X(uint32_t, chainAt) X(uint32_t, slotLastLarge) X(uint32_t, slotN) \
    X(uint16_t, readCount)
    // clang-format on
    WMLT_WHOLE_SLOT_ARRAYS(WMLT_SOA_ARRAY)
    std::vector<float> proposed;
    std::vector<uint8_t> read;
    std::vector<uint16_t> readList;
    std::vector<uint32_t> splatStart;

    void reserve(size_t n, int maxLength_, const BatchNeeds& needs, bool wholeSamples = false) {
        whole = wholeSamples;
        maxLength = maxLength_;
        bpt.reserve(n, maxLength, needs, !whole);
        bpt.roulette = whole;  // MMLT: off, a strategy's lengths are fixed; PSSMLT: as BPT's, from u
        if (whole) {
            bpt.reserveStrategies(n);
            bpt.splatsBySlot = true;
            bpt.Lqueued.resize(n);
            splatStart.resize(n + 1);
            WMLT_WHOLE_SLOT_ARRAYS(WMLT_SOA_RESIZE)
            wholeDims = WholeLayout::size(maxLength, needs.media, needs.spectral);
            proposed.resize(n * wholeDims);
            read.assign(n * wholeDims, 0);
            readList.resize(n * wholeDims);
        } else {
            u.assign(n * StrategyLayout::size(maxLength, needs.media, needs.spectral), 0.0f);
        }
        WMLT_MMLT_SLOT_ARRAYS(WMLT_SOA_RESIZE)
        rejectedLarge.reserve(n);  // (delayed rejection: at most a slot each, no allocation in the loop)
        rejectedC.reserve(n);
        for (auto& v : used) v.resize(n);
        pools.resize(size_t(maxLength) + 1);
        mapPools.resize(size_t(maxLength) + 1);
    }
    StoredSamples samples() const { return StoredSamples{u.data(), row.data(), bpt.pathLength.data(), bpt.cam.media}; }
    WholeSamples wholeSamples() {
        const float* value = wholeGroup ? wholeGroup->value.data() : nullptr;
        const uint32_t* lastModified = wholeGroup ? wholeGroup->lastModified.data() : nullptr;
        return WholeSamples{wholeKind.data(), bpt.key.data(),  seedKey.data(), chainAt.data(),  slotLastLarge.data(), slotN.data(), value,
                            lastModified,     proposed.data(), read.data(),    readList.data(), readCount.data(),     wholeDims,    maxLength};
    }
    float* rowOf(uint32_t i) { return &u[row[i]]; }
};

}  // namespace wmlt
