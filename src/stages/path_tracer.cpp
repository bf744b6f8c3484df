#include "stages/path_tracer.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <chrono>
#include <mutex>

#include "stages/film.h"
#include "stages/pt_stages.h"

namespace wmlt {

namespace {

constexpr int kTileSize = 16;
constexpr uint32_t kMaxPathsPerBatch = 4096;

using Clock = std::chrono::steady_clock;

// One batch: every bounce of every sample of a tile's sample range.
void traceBatch(const Scene& scene, const RenderOptions& opt, const PtTile& tile, PtBatch& b,
                Film& film, PtCounters& counters, uint64_t& discarded) {
    generateCameraRays(scene, b, tile, opt.strataPerAxis, opt.seed);
    const size_t numSlots = b.numPaths;
    for (int depth = 1; depth <= opt.maxPathLength && b.numPaths > 0; ++depth) {
        intersectPaths(scene, b, depth == 1, counters);
        resolveHits(scene, b, depth, opt.minPathLength, opt.maxPathLength);
        if (b.numHits == 0) break;
        groupByMaterial(b);
        if (depth + 1 >= opt.minPathLength) {
            sampleLights(scene, b, depth);
            traceShadows(scene, b, counters);
        }
        sampleBsdfs(scene, b, depth);
        advancePaths(scene, b);
    }
    // Samples of one pixel are adjacent and added in sample order: deterministic.
    for (size_t i = 0; i < numSlots; ++i) {
        if (b.nonfinite[i]) { ++discarded; film.add(b.pixel[i], Vec3(0.0f)); }
        else film.add(b.pixel[i], b.L[i]);
    }
}

}  // namespace

RenderResult renderPathTracing(const Scene& scene, const RenderOptions& opt) {
    const int w = scene.camera.width, h = scene.camera.height;
    const uint32_t perRound = uint32_t(std::max(1, opt.spp));  // samples per pixel per round
    const uint32_t samplesPerBatch = std::max<uint32_t>(1, std::min<uint32_t>(perRound, kMaxPathsPerBatch / (kTileSize * kTileSize)));
    std::vector<PtTile> tiles;
    for (int y = 0; y < h; y += kTileSize)
        for (int x = 0; x < w; x += kTileSize)
            tiles.push_back({x, y, std::min(x + kTileSize, w), std::min(y + kTileSize, h), 0, 0});

    Film film(w, h);
    tbb::enumerable_thread_specific<PtBatch> batches([&] {
        PtBatch b;
        b.reserve(size_t(kTileSize) * kTileSize * samplesPerBatch);
        return b;
    });
    tbb::enumerable_thread_specific<PtCounters> counters;
    tbb::enumerable_thread_specific<uint64_t> discarded(0);
    std::atomic<bool> stop{false};
    std::atomic<size_t> batchesDone{0};
    std::mutex progressMutex;
    const auto start = Clock::now();
    auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
    const bool timed = opt.timeBudget > 0;
    const size_t passesPerRound = (perRound + samplesPerBatch - 1) / samplesPerBatch;
    const size_t totalBatches = passesPerRound * tiles.size();

    uint32_t completedSpp = 0;
    for (uint32_t round = 0; !stop; ++round) {
        for (size_t pass = 0; pass < passesPerRound && !stop; ++pass) {
            uint32_t s0 = round * perRound + uint32_t(pass) * samplesPerBatch;
            uint32_t s1 = std::min(round * perRound + perRound, s0 + samplesPerBatch);
            tbb::parallel_for(tbb::blocked_range<size_t>(0, tiles.size(), 1), [&](const tbb::blocked_range<size_t>& r) {
                for (size_t t = r.begin(); t != r.end(); ++t) {
                    if (stop.load(std::memory_order_relaxed)) return;
                    if ((opt.cancel && opt.cancel->load()) || (timed && elapsed() >= opt.timeBudget)) {
                        stop = true;
                        return;
                    }
                    PtTile tile = tiles[t];
                    tile.sample0 = s0;
                    tile.sample1 = s1;
                    traceBatch(scene, opt, tile, batches.local(), film, counters.local(), discarded.local());
                    size_t done = ++batchesDone;
                    if (opt.progress && progressMutex.try_lock()) {
                        opt.progress(timed ? std::min(1.0, elapsed() / opt.timeBudget) : double(done) / totalBatches);
                        progressMutex.unlock();
                    }
                }
            }, tbb::simple_partitioner());
            if (!stop) completedSpp = s1;
        }
        if (!timed) break;
    }

    RenderResult res;
    res.image = film.resolve();
    res.stats.tracer = "pt";
    res.stats.seconds = elapsed();
    res.stats.spp = completedSpp;
    for (const PtCounters& c : counters) {
        res.stats.raysIntersect += c.raysIntersect;
        res.stats.raysOccluded += c.raysOccluded;
    }
    for (uint64_t d : discarded) res.stats.samplesNonfiniteDiscarded += d;
    res.stats.cancelled = opt.cancel && opt.cancel->load();
    res.featuresJson = scene.features.json();
    return res;
}

}  // namespace wmlt
