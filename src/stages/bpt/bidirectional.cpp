// The BPT driver: passes of batches (a tile of pixels times a sample range: one camera
// subpath and one light subpath per pixel sample, keyed on (seed, pixel, sample)). The
// camera-side strategies (t >= 2) add to the pixel's own film in sample order, as the PT
// does; the t = 1 splats go to the batch's list, added to the splat film in tile order
// after each pass, as the LT does. The image is their sum: deterministic for any thread
// count. A render stopped mid-pass keeps that pass's camera-side samples (each pixel
// averaged over the samples it received) and only complete passes' splats: the two
// parts are separate estimators (MIS splits each path between them), each unbiased.
#include "stages/bpt/bidirectional.h"

#include <tbb/enumerable_thread_specific.h>

#include <memory>

#include "scene/scene_lights.h"
#include "stages/bpt/bpt_stages.h"
#include "stages/core/distributed_films.h"
#include "stages/core/film.h"
#include "stages/core/passes.h"
#include "stages/core/splat_passes.h"
#include "wavemmlt/error.h"

namespace wmlt {

namespace {

void traceBatch(const Scene& scene, const RenderOptions& opt, const Tile& tile, BptBatch& b, Film& film, RayCounters& counters, TileSplats& out) {
    b.splats.clear();
    b.points.clear();
    b.strategySplats.clear();
    b.tally = ContributionTally();
    b.minLength = opt.minPathLength;
    b.maxLength = opt.maxPathLength;
    generateBptCameraPaths(scene, b, tile, opt.strataPerAxis, opt.seed);
    const HashedSamples u{b.key.data()};
    walkBpt(scene, b, b.cam, true, true, counters, u);
    generateBptLightPaths(scene, b, u);
    walkBpt(scene, b, b.light, false, false, counters, u);
    connectBpt(scene, b, u, opt.minPathLength, opt.maxPathLength, opt.misBeta, counters);
    for (size_t i = 0; i < b.numSlots; ++i) film.add(b.pixel[i], b.L[i] * b.filmWeight[i]);
    out.splats.insert(out.splats.end(), b.splats.begin(), b.splats.end());
    out.points.insert(out.points.end(), b.points.begin(), b.points.end());
    out.strategySplats.insert(out.strategySplats.end(), b.strategySplats.begin(), b.strategySplats.end());
    out.tally.add(b.tally);
}

// Each strategy's sums as images: camera-side strategies averaged over each pixel's
// samples (as the main film), t = 1 splats divided by the samples per pixel.
std::vector<StrategyImage> resolveStrategies(const StrategyFilms& sf, const Film& film, uint64_t spp, int minLength) {
    std::vector<StrategyImage> out;
    const size_t pixels = size_t(sf.width) * size_t(sf.height);
    for (int k = std::max(1, minLength); k <= sf.maxLength; ++k)
        for (int s = 0; s <= k; ++s) {
            StrategyImage si{s, k + 1 - s, Image(sf.width, sf.height), Image(sf.width, sf.height)};
            for (uint32_t p = 0; p < pixels; ++p) {
                const double n = si.t == 1 ? double(spp) : double(film.count[p]);
                const double inv = n > 0 ? 1.0 / n : 0.0;
                const Vec3 w = sf.weighted[sf.at(s, k, p)], u = sf.unweighted[sf.at(s, k, p)];
                for (int c = 0; c < 3; ++c) {
                    si.weighted.rgb[p * 3 + c] = float(w[c] * inv);
                    si.unweighted.rgb[p * 3 + c] = float(u[c] * inv);
                }
            }
            out.push_back(std::move(si));
        }
    return out;
}

// The image: the camera-side strategies' per-pixel means plus the splats of the complete
// passes (spp samples per pixel).
Image imageOf(const Film& film, const SplatFilm& splatFilm, uint64_t spp) {
    Image image = film.resolve();
    const Image splats = splatFilm.resolve(spp);
    for (size_t i = 0; i < image.rgb.size(); ++i) image.rgb[i] += splats.rgb[i];
    return image;
}

// imageOf the job's films (rank 0; split across ranks, both are summed there).
Image imageOfJob(Distributed* ranks, const Film& film, const SplatFilm& splatFilm, uint64_t spp) {
    if (!ranks || !ranks->many()) return imageOf(film, splatFilm, spp);
    return imageOf(filmOfJob(ranks, film), filmOfJob(ranks, splatFilm), spp);
}

}  // namespace

RenderResult renderBidirectional(const Scene& scene, const RenderOptions& opt) {
    // A batch stores every vertex of both subpaths: fewer samples per batch for long
    // paths keep it near its size at MaxPathLength 10 (about 13 MB per thread).
    const uint32_t maxPaths = std::max<uint32_t>(kTileSize * kTileSize, kMaxPathsPerBatch * 11 / uint32_t(opt.maxPathLength + 1));
    const PassSchedule schedule = makePassSchedule(scene.camera.width, scene.camera.height, opt, maxPaths);
    Film film(scene.camera.width, scene.camera.height);
    SplatFilm splatFilm(scene.camera.width, scene.camera.height);
    std::vector<TileSplats> outputs(schedule.tiles.size());
    std::unique_ptr<StrategyFilms> strategyFilms;
    constexpr size_t kStrategyFilmsLimit = size_t(8) << 30;
    const size_t filmBytes = StrategyFilms::bytes(scene.camera.width, scene.camera.height, opt.maxPathLength);
    if ((!opt.strategyImages.empty() || opt.lengthImages) && filmBytes > kStrategyFilmsLimit)
        throw InputError(opt.strategyImages, 0,
                         "strategy images would need " + std::to_string(filmBytes >> 20) + " MiB (over 8 GiB): lower --max-length or the image size");
    if (!opt.strategyImages.empty() || opt.lengthImages)
        strategyFilms = std::make_unique<StrategyFilms>(scene.camera.width, scene.camera.height, opt.maxPathLength);
    const SpectralMode mode = chooseSpectralMode(scene, opt.spectral);  // --spectral (chosen once per render)
    tbb::enumerable_thread_specific<BptBatch> batches([&] {
        BptBatch b;
        BatchNeeds needs = batchNeeds(scene);
        needs.spectral = mode.spectral;
        b.reserve(schedule.pathsPerBatch(), opt.maxPathLength, needs);
        b.spectra = mode.spectra();
        b.regularizedOffset = scene.regularizedOffset;  // pbrt's BDPT regularizes both subpaths
        b.strategyFilms = strategyFilms.get();
        return b;
    });
    tbb::enumerable_thread_specific<RayCounters> counters;
    SplatTotals totals;
    PassResult pr = runPasses(
        schedule, opt, [&](size_t t, const Tile& tile) { traceBatch(scene, opt, tile, batches.local(), film, counters.local(), outputs[t]); },
        [&] { totals.addPass(scene, outputs, splatFilm, strategyFilms.get()); },
        {[&](uint32_t spp) { return imageOfJob(opt.ranks, film, splatFilm, spp); }, &counters});

    RenderResult res = startResult("bpt", scene, opt, pr, counters);
    res.stats.spectral = mode.spectral;
    res.stats.spectralReason = mode.reason(opt.spectral);
    res.image = imageOfJob(opt.ranks, film, splatFilm, pr.completedSpp);
    totals.finish(scene, opt.ranks, pr.completedSpp, res.stats);
    if (strategyFilms) res.strategyImages = resolveStrategies(*strategyFilms, film, pr.completedSpp, opt.minPathLength);
    if (opt.lengthImages) {  // the weighted strategies of each length add up to its image
        res.lengthImages.assign(size_t(opt.maxPathLength) + 1, Image(scene.camera.width, scene.camera.height));
        for (const StrategyImage& si : res.strategyImages)
            for (size_t i = 0; i < si.weighted.rgb.size(); ++i) res.lengthImages[size_t(si.s + si.t - 1)].rgb[i] += si.weighted.rgb[i];
    }
    if (opt.strategyImages.empty()) res.strategyImages.clear();
    return res;
}

}  // namespace wmlt
