// The light tracer's driver: passes of batches (a tile of pixels times a sample range:
// one light subpath per pixel sample, keyed on (seed, pixel, sample), so the paths do
// not depend on threads). Each batch's splats go to its own list; after a pass the lists
// are added to the film in tile order, so the image is bit-identical for any thread
// count. A pass cut short (cancel, time budget) is dropped whole: the image is the sum
// of complete passes divided by their samples per pixel (film.h, SplatFilm).
#include "stages/lt/light_tracer.h"

#include <tbb/enumerable_thread_specific.h>

#include "stages/core/distributed_films.h"
#include "stages/core/film.h"
#include "stages/core/media.h"
#include "stages/core/passes.h"
#include "stages/core/splat_passes.h"
#include "stages/lt/lt_stages.h"

namespace wmlt {

namespace {

void traceBatch(const Scene& scene, const RenderOptions& opt, const Tile& tile, LtBatch& b, RayCounters& counters, TileSplats& out) {
    b.splats.clear();
    b.points.clear();
    b.tally = ContributionTally();
    const bool length1 = opt.minPathLength <= 1 && opt.maxPathLength >= 1;
    // Length 1 from the environment: camera rays that escape (a point at infinity cannot
    // be connected to the lens).
    if (length1 && scene.envLight >= 0) {
        generateEnvCameraRays(scene, b, tile, opt.strataPerAxis, opt.seed);
        traceConnections(scene, b, 1, counters);
    }
    if (!scene.lights.empty()) {
        generateLightPaths(scene, b, tile, opt.seed, length1);
        traceConnections(scene, b, 1, counters);
        // Round d: the subpaths' d-th segment; a vertex after d segments connects to the
        // camera at path length k = d + 1.
        for (int d = 1; d + 1 <= opt.maxPathLength && b.numPaths > 0; ++d) {
            intersect(scene, b, false, counters);
            if (scene.features.media) traverseMediaOf(scene, b, d, counters);  // (media.h)
            resolveLightHits(scene, b);
            if (b.numHits == 0) break;
            groupByMaterial(b, b.bsdf.data());
            if (d + 1 >= opt.minPathLength) {
                connectToCamera(scene, b, d);
                traceConnections(scene, b, d + 1, counters);
            }
            if (d + 2 > opt.maxPathLength) break;
            sampleLightBsdfs(scene, b, d);
            advanceLightPaths(scene, b);
        }
    }
    out.splats.assign(b.splats.begin(), b.splats.end());
    out.points.assign(b.points.begin(), b.points.end());
    out.tally = b.tally;
}

}  // namespace

RenderResult renderLightTracing(const Scene& scene, const RenderOptions& opt) {
    const PassSchedule schedule = makePassSchedule(scene.camera.width, scene.camera.height, opt);
    SplatFilm film(scene.camera.width, scene.camera.height);
    std::vector<TileSplats> outputs(schedule.tiles.size());
    const SpectralMode mode = chooseSpectralMode(scene, opt.spectral);  // --spectral (chosen once per render)
    tbb::enumerable_thread_specific<LtBatch> batches([&] {
        LtBatch b;
        BatchNeeds needs = batchNeeds(scene);
        needs.spectral = mode.spectral;
        b.reserve(schedule.pathsPerBatch(), needs);
        b.spectra = mode.spectra();
        return b;
    });
    tbb::enumerable_thread_specific<RayCounters> counters;
    SplatTotals totals;
    PassResult pr = runPasses(
        schedule, opt, [&](size_t t, const Tile& tile) { traceBatch(scene, opt, tile, batches.local(), counters.local(), outputs[t]); },
        [&] { totals.addPass(scene, outputs, film, nullptr); },
        {[&](uint32_t spp) { return withFilmOfJob(opt.ranks, film, [&](const SplatFilm& f) { return f.resolve(spp); }); }, &counters});

    RenderResult res = startResult("lt", scene, opt, pr, counters);
    res.stats.spectral = mode.spectral;
    res.stats.spectralReason = mode.reason(opt.spectral);
    res.image = withFilmOfJob(opt.ranks, film, [&](const SplatFilm& f) { return f.resolve(pr.completedSpp); });
    totals.finish(scene, opt.ranks, pr.completedSpp, res.stats);
    return res;
}

}  // namespace wmlt
