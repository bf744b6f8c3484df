// The path-tracing driver: passes of batches (a tile of pixels times a sample range), every
// bounce of a batch run as wavefront stages (pt_stages.h), each pixel's samples added in order.
#include "stages/pt/path_tracer.h"

#include <tbb/enumerable_thread_specific.h>

#include "scene/scene_lights.h"
#include "stages/core/distributed_films.h"
#include "stages/core/film.h"
#include "stages/core/passes.h"
#include "stages/pt/pt_stages.h"

namespace wmlt {

namespace {

// One batch: every bounce of every sample of a tile's sample range.
void traceBatch(const Scene& scene, const RenderOptions& opt, const Tile& tile, PtBatch& b, Film& film, RayCounters& counters,
                ContributionTally& totals) {
    b.tally = ContributionTally();
    generateCameraRays(scene, b, tile, opt.strataPerAxis, opt.seed);
    const size_t numSlots = b.numPaths;
    const bool media = scene.features.media;  // the media stages (pt_media.cpp)
    for (int depth = 1; depth <= opt.maxPathLength && b.numPaths > 0; ++depth) {
        intersect(scene, b, depth == 1, counters);
        if (media) traverseMedia(scene, b, depth, opt.minPathLength, opt.maxPathLength, counters);
        resolveHits(scene, b, depth, opt.minPathLength, opt.maxPathLength);
        if (b.numHits == 0) break;
        groupByMaterial(b, b.bsdf.data());
        if (depth + 1 >= opt.minPathLength) {
            sampleLights(scene, b, depth);
            if (media) traceShadowsThroughMedia(scene, b, depth + 1, counters);
            else traceShadows(scene, b, depth + 1, counters);
        }
        sampleBsdfs(scene, b, depth);
        advancePaths(scene, b);
    }
    // Samples of one pixel are adjacent and added in sample order: deterministic.
    if (b.spectra)  // the film's linear sRGB from each sample's wavelengths
        for (size_t i = 0; i < numSlots; ++i) film.add(b.pixel[i], srgbOfSample(b.L[i], b.lambda[i]) * b.filmWeight[i]);
    else
        for (size_t i = 0; i < numSlots; ++i) film.add(b.pixel[i], b.L[i] * b.filmWeight[i]);
    totals.add(b.tally);  // what a tile's batches add up to besides the film: merged in tile order
}

}  // namespace

RenderResult renderPathTracing(const Scene& scene, const RenderOptions& opt) {
    const PassSchedule schedule = makePassSchedule(scene.camera.width, scene.camera.height, opt);
    Film film(scene.camera.width, scene.camera.height);
    const SpectralMode mode = chooseSpectralMode(scene, opt.spectral);  // --spectral (chosen once per render)
    tbb::enumerable_thread_specific<PtBatch> batches([&] {
        PtBatch b;
        BatchNeeds needs = batchNeeds(scene);
        needs.spectral = mode.spectral;
        b.reserve(schedule.pathsPerBatch(), needs);
        b.regularizedOffset = scene.regularizedOffset;  // pbrt's path integrator regularizes
        b.spectra = mode.spectra();
        return b;
    });
    tbb::enumerable_thread_specific<RayCounters> counters;
    std::vector<ContributionTally> totals(schedule.tiles.size());
    // Each batch adds to its own tile's pixels only: no two threads touch one pixel.
    PassResult pr = runPasses(schedule, opt,
                              [&](size_t t, const Tile& tile) { traceBatch(scene, opt, tile, batches.local(), film, counters.local(), totals[t]); },
                              {}, {[&](uint32_t) { return withFilmOfJob(opt.ranks, film, [](const Film& f) { return f.resolve(); }); }, &counters});

    RenderResult res = startResult("pt", scene, opt, pr, counters);
    res.stats.spectral = mode.spectral;
    res.stats.spectralReason = mode.reason(opt.spectral);
    PathLengthSums lengths;
    for (const ContributionTally& t : totals) {
        lengths.add(t.lengths);
        res.stats.samplesNonfiniteDiscarded += t.nonfinite;
    }
    // Split across ranks: each pixel is one rank's (tilesOfRank), so the sums are the ones a
    // single process makes, bit for bit (the other ranks add exact zeros).
    lengths = lengthsOfJob(opt.ranks, lengths);
    withFilmOfJob(opt.ranks, film, [&](const Film& f) {
        res.image = f.resolve();
        uint64_t samples = 0;
        for (uint32_t c : f.count) samples += c;
        const double pixels = double(f.count.size());
        res.stats.lengthMeanLuminance = lengths.means(pixels, pixels > 0 ? double(samples) / pixels : 0.0);
        return 0;
    });
    sumStatsToRoot(opt.ranks, res.stats);
    return res;
}

}  // namespace wmlt
