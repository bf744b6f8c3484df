// MMLT's chains (mmlt_render.h): allocated to the lengths, seeded from the pools by
// systematic resampling, replayed, and planned into batches.
#include "stages/mmlt/mmlt_render.h"

#include "kernels/check.h"

namespace wmlt::mmlt_detail {

// Chains per length: C b_k / sum b by largest remainders over the lengths whose pool has
// light (b_k: the pool's mean), then at least 1 for each such length (taken from the
// largest allocation while it has more than one). False when no pool has light.
bool MmltRender::allocateChains() {
    std::vector<double> b(size_t(kMax_) + 1, 0.0);
    double sum = 0;
    for (int k = lo_; k <= hi_; ++k) {
        stats_.poolSamples[size_t(k)] = pools_[size_t(k)].count;
        if (pools_[size_t(k)].lit.empty()) continue;
        b[size_t(k)] = pools_[size_t(k)].mean();
        sum += b[size_t(k)];
    }
    // The last pass's groups lend their arrays to the new ones (resize zeroes them): a fresh
    // allocation each pass cost page faults of the whole chain state (PSSMLT at
    // MaxPathLength 64: 27 MB for 4096 chains).
    std::vector<ChainGroup> old = std::move(groups_);
    groups_.clear();
    // A pass's weight f_p = N / (N + rho C), N the pool's samples (a count, independent of
    // their values: the weighted average of the passes stays unbiased): a pass whose pool
    // is small next to its chains mostly repeats its few seeds, and counts less. rho = 32
    // against rho = 0 (every iteration alike), 16 s renders: 7% lower RMSE on the seed room
    // at 1024 and at 65536 chains, the Cornell box unchanged (docs/mmlt-chains.md).
    constexpr double rho = 32;
    uint64_t poolSamples = 0;
    for (int k = lo_; k <= hi_; ++k) poolSamples += pools_[size_t(k)].count;
    passWeight_ = double(poolSamples) / (double(poolSamples) + rho * double(chains_));
    if (!(sum > 0)) return false;
    std::vector<uint32_t> n(b.size(), 0);
    std::vector<std::pair<double, size_t>> rem;
    uint32_t given = 0;
    for (size_t k = 0; k < b.size(); ++k) {
        const double share = double(chains_) * b[k] / sum;
        n[k] = uint32_t(std::floor(share));
        given += n[k];
        rem.push_back({share - std::floor(share), k});
    }
    std::stable_sort(rem.begin(), rem.end(), [](auto& a, auto& c) { return a.first > c.first; });
    for (size_t i = 0; given < chains_ && i < rem.size(); ++i, ++given) ++n[rem[i].second];
    for (size_t k = 0; k < b.size(); ++k) {
        if (!(b[k] > 0) || n[k] > 0) continue;
        const size_t big = size_t(std::max_element(n.begin(), n.end()) - n.begin());
        if (n[big] > 1) --n[big];
        n[k] = 1;
    }
    uint32_t first = 0;
    for (int k = lo_; k <= hi_; ++k) {
        stats_.chains[size_t(k)] = n[size_t(k)];
        if (!n[size_t(k)]) continue;
        ChainGroup g;
        if (!old.empty()) {
            g = std::move(old.back());
            old.pop_back();
        }
        g.k = k;
        g.first = first;
        g.dims = whole_ ? WholeLayout::size(kMax_, scene_.features.media, spectral_) : StrategyLayout::size(k, scene_.features.media, spectral_);
        g.points = whole_ ? uint32_t(kMax_) : 0;  // PSSMLT: a t = 1 contribution for each s = 1 .. kMax
        g.weight = float(passWeight_ * pools_[size_t(k)].mean() / double(n[size_t(k)]));
        g.sigma = sigma_[size_t(k)];
        g.filmStep = filmStep_[size_t(k)];
        first += n[size_t(k)];
        groups_.push_back(std::move(g));
        groups_.back().resize(n[size_t(k)]);
    }
    return true;
}

// Systematic resampling of each group's chains from its pool in proportion to c, and the
// replay of every seed (its c must come back bit for bit).
void MmltRender::seedChains() {
    uint64_t bytes = 0;
    for (ChainGroup& g : groups_) {
        const SamplePool& pool = pools_[size_t(g.k)];
        double total = 0;
        for (const PoolEntry& e : pool.lit) total += double(e.w) * double(e.c);
        const double offset = double(sampleDimension(mmltPoolKey(opt_.seed, pass_, g.k, 0xffffffffu), 0));
        std::unordered_set<uint64_t> distinct;
        size_t e = 0;
        double cum = double(pool.lit[0].w) * double(pool.lit[0].c);
        for (uint32_t c = 0; c < g.count; ++c) {
            const double x = (double(c) + offset) / double(g.count) * total;
            while (cum <= x && e + 1 < pool.lit.size()) {
                ++e;
                cum += double(pool.lit[e].w) * double(pool.lit[e].c);
            }
            const PoolEntry& entry = pool.lit[e];
            g.seed[c] = entry.key;
            g.F[c] = entry.F;
            g.c[c] = entry.c;
            g.filmX[c] = entry.filmX;
            g.filmY[c] = entry.filmY;
            distinct.insert(g.seed[c]);
            if (!whole_)  // (PSSMLT: a coordinate of lastModified 0 is read as its seed's, WholeSamples)
                for (uint32_t d = 0; d < g.dims; ++d) g.value[g.at(c, d)] = poolCoordinate(g.seed[c], d);
        }
        stats_.chainsSeeded[size_t(g.k)] += g.count;
        stats_.distinctSeeds[size_t(g.k)] += distinct.size();
        bytes += uint64_t(g.count) * chainBytesOf(g.k);
    }
    stats_.chainBytes = std::max(stats_.chainBytes, bytes);
    planBatches();
    mergeDigest();
    replaySeeds();
}

// Replays seeds (every one in the first pass, one in kReplayShare of them by their key's
// hash after that): the evaluation of the seed's u must give its pool entry's F, c and
// film point bit for bit, or the estimator would be wrong (counted in mmlt_replay_mismatches).
// PSSMLT replays every chain this rank runs, in its batches (plan_): a chain's t = 1
// contributions are its replay's (a pool entry keeps only the camera side's).
void MmltRender::replaySeeds() {
    constexpr uint64_t kReplayShare = 8;
    std::vector<std::vector<BatchSlice>> plan(1);
    if (whole_) plan = plan_;
    for (size_t gi = 0; gi < groups_.size() && !whole_; ++gi)
        for (uint32_t c = 0; c < groups_[gi].count; ++c) {
            if (pass_ > 0 && mix64(groups_[gi].seed[c]) % kReplayShare != 0) continue;
            if (slotsIn(plan.back()) >= kBatchChains) plan.emplace_back();
            std::vector<BatchSlice>& b = plan.back();
            if (!b.empty() && b.back().group == int(gi) && b.back().c0 + b.back().n == c) ++b.back().n;
            else b.push_back({int(gi), c, 1, slotsIn(b)});
        }
    std::vector<uint64_t> mismatches(plan.size(), 0);
    const auto [p0, p1] = shareOf(ranks_, plan.size());  // this rank's share of the replays
    tbb::parallel_for(p0, p1, [&](size_t ti) {
        MmltBatch& mb = batches_.local();
        mb.slices = plan[ti];
        mb.target = map_;
        stages_.fillSeedRows(groups_, mb);
        stages_.evaluateProposals(scene_, mb, opt_.misBeta, rays_.local());
        mismatches[ti] = stages_.countReplayMismatches(groups_, mb, opt_.plantReplayMismatch && ti == 0);
    });
    for (uint64_t m : mismatches) stats_.replayMismatches += m;
    for (size_t ti = p0; ti < p1; ++ti) stats_.replayed += slotsIn(plan[ti]);
    WMLT_DCHECK(stats_.replayMismatches == 0,
                std::to_string(stats_.replayMismatches) + " replayed seeds evaluated differently from their pool entries");
}

// Batch j holds chains [C_k j' / B, C_k (j' + 1) / B) of every length k, j' = (j + first_k)
// mod B (first_k: the global index of the length's first chain): each batch a share of every
// length, so that batches cost about the same whatever the lengths' split. A length with
// fewer chains than batches has one in every B / C_k-th batch; the rotation by first_k puts
// the rare lengths' chains in different batches (unrotated, the last batch held one chain of
// every rare length: the Cornell box at MaxPathLength 64 had a longest task 3.4 times the
// mean).
void MmltRender::planBatches() {
    const uint32_t B = (chains_ + kBatchChains - 1) / kBatchChains;
    plan_.assign(B, {});
    for (uint32_t j = 0; j < B; ++j) {
        uint32_t slot = 0;
        for (size_t gi = 0; gi < groups_.size(); ++gi) {
            const uint64_t n = groups_[gi].count, jr = (uint64_t(j) + groups_[gi].first) % B;
            const uint32_t c0 = uint32_t(n * jr / B), c1 = uint32_t(n * (jr + 1) / B);
            if (c1 > c0) plan_[j].push_back({int(gi), c0, c1 - c0, slot});
            slot += c1 - c0;
        }
    }
    stats_.tasksPerRound = B;
}
}  // namespace wmlt::mmlt_detail
