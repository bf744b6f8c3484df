// The light tracer's driver: passes of batches (a tile of pixels times a sample range:
// one light subpath per pixel sample, keyed on (seed, pixel, sample), so the paths do
// not depend on threads). Each batch's splats go to its own list; after a pass the lists
// are added to the film in tile order, so the image is bit-identical for any thread
// count. A pass cut short (cancel, time budget) is dropped whole: the image is the sum
// of complete passes divided by their samples per pixel (film.h, SplatFilm).
#include "stages/light_tracer.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <chrono>
#include <mutex>

#include "stages/film.h"
#include "stages/lt_stages.h"

namespace wmlt {

namespace {

constexpr int kTileSize = 16;
constexpr uint32_t kMaxPathsPerBatch = 4096;

using Clock = std::chrono::steady_clock;

struct TileOutput {
    std::vector<Splat> splats;
    uint64_t nonfinite = 0;
};

void traceBatch(const Scene& scene, const RenderOptions& opt, const PtTile& tile, LtBatch& b,
                PtCounters& counters, TileOutput& out) {
    b.splats.clear();
    b.nonfinite = 0;
    const bool length1 = opt.minPathLength <= 1 && opt.maxPathLength >= 1;
    // Length 1 from the environment: camera rays that escape (a point at infinity cannot
    // be connected to the lens).
    if (length1 && scene.envLight >= 0) {
        generateEnvCameraRays(scene, b, tile, opt.strataPerAxis, opt.seed);
        traceConnections(scene, b, counters);
    }
    if (!scene.lights.empty()) {
        generateLightPaths(scene, b, tile, opt.seed, length1);
        traceConnections(scene, b, counters);
        // Round d: the subpaths' d-th segment; a vertex after d segments connects to the
        // camera at path length k = d + 1.
        for (int d = 1; d + 1 <= opt.maxPathLength && b.numPaths > 0; ++d) {
            intersectLightPaths(scene, b, counters);
            resolveLightHits(scene, b);
            if (b.numHits == 0) break;
            groupLightHits(b);
            if (d + 1 >= opt.minPathLength) {
                connectToCamera(scene, b, d);
                traceConnections(scene, b, counters);
            }
            if (d + 2 > opt.maxPathLength) break;
            sampleLightBsdfs(scene, b, d);
            advanceLightPaths(scene, b);
        }
    }
    out.splats.assign(b.splats.begin(), b.splats.end());
    out.nonfinite = b.nonfinite;
}

}  // namespace

RenderResult renderLightTracing(const Scene& scene, const RenderOptions& opt) {
    const int w = scene.camera.width, h = scene.camera.height;
    const uint32_t perRound = uint32_t(std::max(1, opt.spp));
    const uint32_t samplesPerBatch = std::max<uint32_t>(1, std::min<uint32_t>(perRound, kMaxPathsPerBatch / (kTileSize * kTileSize)));
    std::vector<PtTile> tiles;
    for (int y = 0; y < h; y += kTileSize)
        for (int x = 0; x < w; x += kTileSize)
            tiles.push_back({x, y, std::min(x + kTileSize, w), std::min(y + kTileSize, h), 0, 0});

    SplatFilm film(w, h);
    std::vector<TileOutput> outputs(tiles.size());
    tbb::enumerable_thread_specific<LtBatch> batches([&] {
        LtBatch b;
        b.reserve(size_t(kTileSize) * kTileSize * samplesPerBatch);
        return b;
    });
    tbb::enumerable_thread_specific<PtCounters> counters;
    uint64_t discarded = 0;
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
                    traceBatch(scene, opt, tile, batches.local(), counters.local(), outputs[t]);
                    size_t done = ++batchesDone;
                    if (opt.progress && progressMutex.try_lock()) {
                        opt.progress(timed ? std::min(1.0, elapsed() / opt.timeBudget) : double(done) / totalBatches);
                        progressMutex.unlock();
                    }
                }
            }, tbb::simple_partitioner());
            if (stop) break;  // an incomplete pass: dropped
            for (TileOutput& o : outputs) {
                for (const Splat& s : o.splats) film.add(s);
                discarded += o.nonfinite;
                o.splats.clear();
                o.nonfinite = 0;
            }
            completedSpp = s1;
        }
        if (!timed) break;
    }

    RenderResult res;
    res.image = film.resolve(completedSpp);
    res.stats.tracer = "lt";
    res.stats.seconds = elapsed();
    res.stats.spp = completedSpp;
    for (const PtCounters& c : counters) {
        res.stats.raysIntersect += c.raysIntersect;
        res.stats.raysOccluded += c.raysOccluded;
    }
    res.stats.samplesNonfiniteDiscarded = discarded;
    res.stats.cancelled = opt.cancel && opt.cancel->load();
    res.featuresJson = scene.features.json();
    return res;
}

}  // namespace wmlt
