#include "stages/core/passes.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <mutex>

#include "stages/core/distributed.h"
#include "stages/core/preview.h"

namespace wmlt {

PassSchedule makePassSchedule(int w, int h, const RenderOptions& opt, uint32_t maxPathsPerBatch) {
    constexpr uint32_t kTimedSamplesPerBatch = 4;
    PassSchedule s;
    for (int y = 0; y < h; y += kTileSize)
        for (int x = 0; x < w; x += kTileSize) s.tiles.push_back({x, y, std::min(x + kTileSize, w), std::min(y + kTileSize, h), 0, 0});
    uint32_t perBatch = uint32_t(std::max(1, opt.spp));
    if (opt.timeBudget > 0) perBatch = std::min(perBatch, kTimedSamplesPerBatch);
    s.samplesPerBatch = std::max<uint32_t>(1, std::min<uint32_t>(perBatch, maxPathsPerBatch / (kTileSize * kTileSize)));
    return s;
}

// The tiles this rank runs: tile t belongs to rank t mod N (interleaved, so that every
// rank gets a share of the image's cheap and costly parts). Each pixel is one rank's.
std::vector<size_t> tilesOfRank(const PassSchedule& s, const Distributed* ranks) {
    const size_t N = ranks ? size_t(ranks->size()) : 1, r = ranks ? size_t(ranks->rank()) : 0;
    std::vector<size_t> mine;
    for (size_t t = r; t < s.tiles.size(); t += N) mine.push_back(t);
    return mine;
}

PassResult runPasses(const PassSchedule& s, const RenderOptions& opt, const std::function<void(size_t, const Tile&)>& runBatch,
                     const std::function<void()>& endPass, const PassImage& snapshot) {
    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    double paused = 0;  // seconds a viewer held the render between passes
    auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - start).count() - paused; };
    const bool timed = opt.timeBudget > 0;
    const std::vector<size_t> tiles = tilesOfRank(s, opt.ranks);
    const uint32_t perRound = uint32_t(std::max(1, opt.spp));
    const size_t passesPerRound = (perRound + s.samplesPerBatch - 1) / s.samplesPerBatch;
    const size_t totalBatches = std::max<size_t>(1, passesPerRound * tiles.size());
    std::atomic<bool> stop{false};
    std::atomic<size_t> batchesDone{0};
    std::mutex progressMutex;

    PassResult result;
    for (uint32_t round = 0; !stop; ++round) {
        for (size_t pass = 0; pass < passesPerRound && !stop; ++pass) {
            const uint32_t s0 = round * perRound + uint32_t(pass) * s.samplesPerBatch;
            const uint32_t s1 = std::min(round * perRound + perRound, s0 + s.samplesPerBatch);
            tbb::parallel_for(
                tbb::blocked_range<size_t>(0, tiles.size(), 1),
                [&](const tbb::blocked_range<size_t>& r) {
                    for (size_t i = r.begin(); i != r.end(); ++i) {
                        if (stop.load(std::memory_order_relaxed)) return;
                        if ((opt.cancel && opt.cancel->load()) || (timed && elapsed() >= opt.timeBudget)) {
                            stop = true;
                            return;
                        }
                        const size_t t = tiles[i];
                        Tile tile = s.tiles[t];
                        tile.sample0 = s0;
                        tile.sample1 = s1;
                        runBatch(t, tile);
                        const size_t done = ++batchesDone;
                        if (opt.progress && progressMutex.try_lock()) {
                            opt.progress(timed ? std::min(1.0, elapsed() / opt.timeBudget) : double(done) / totalBatches);
                            progressMutex.unlock();
                        }
                    }
                },
                tbb::simple_partitioner());
            // Across ranks: every rank stops after the same pass, when any of them stopped.
            const Agreement a = agree(opt.ranks, stop, opt.cancel && opt.cancel->load());
            stop = a.stop;
            result.cancelled = a.cancel;
            if (stop) break;
            if (endPass) endPass();
            result.completedSpp = s1;
            const double fraction = timed ? std::min(1.0, elapsed() / opt.timeBudget) : double(batchesDone.load()) / double(totalBatches);
            paused += offerSnapshot(opt, [&] { return Snapshot{snapshot.image(s1), fraction, elapsed(), s1, raysSoFar(*snapshot.rays)}; });
            ++result.passes;
        }
        if (!timed) break;
    }
    result.seconds = elapsed();
    result.stopped = stop;
    return result;
}

RenderResult startResult(const char* tracer, const Scene& scene, const RenderOptions& opt, const PassResult& pr,
                         const tbb::enumerable_thread_specific<RayCounters>& counters) {
    RenderResult res;
    res.stats.tracer = tracer;
    res.stats.seconds = pr.seconds;
    res.stats.spp = pr.completedSpp;
    for (const RayCounters& c : counters) {
        res.stats.raysIntersect += c.raysIntersect;
        res.stats.raysOccluded += c.raysOccluded;
    }
    res.stats.cancelled = pr.cancelled || (opt.cancel && opt.cancel->load());
    res.stats.ranks.boundaries = pr.passes;
    res.featuresJson = scene.features.json();
    return res;
}

}  // namespace wmlt
