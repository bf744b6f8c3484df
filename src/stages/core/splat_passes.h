// What the tracers that splat (LT, and BPT's t = 1 strategies) keep per tile of a pass and
// over the render: each batch's splats go to its tile's list; after a complete pass the
// lists are added to the film in tile order (so the image is the same for any thread
// count) and their tallies to the render's totals.
#pragma once
#include <cstdint>
#include <vector>

#include "scene/scene.h"
#include "stages/core/distributed_films.h"
#include "stages/core/film.h"
#include "stages/core/strategy_films.h"
#include "stages/core/wave.h"

namespace wmlt {

struct TileSplats {
    std::vector<Splat> splats;
    std::vector<PointSplat> points;             // filtered scenes: at film points
    std::vector<StrategySplat> strategySplats;  // BPT's --strategy-images only
    ContributionTally tally;
};

// MMLT's merge of one film stripe (pixels p with p >> shift == st): the film points'
// footprints' pixels in it, in order, also to lengthFilms[length[i]] when there are any.
inline void addPointSplatsInStripe(const Scene& scene, SplatFilm& film, std::vector<SplatFilm>& lengthFilms, const std::vector<PointSplat>& points,
                                   const std::vector<uint8_t>& length, uint32_t st, uint32_t shift) {
    for (size_t i = 0; i < points.size(); ++i)
        scene.forEachFilmPixel(points[i].px, points[i].py, [&](uint32_t p, float w) {
            if ((p >> shift) != st) return;
            const Splat s{p, points[i].value * w};
            film.add(s);
            if (!lengthFilms.empty()) lengthFilms[length[i]].add(s);
        });
}

struct SplatTotals {
    uint64_t discarded = 0;  // non-finite contributions
    PathLengthSums lengths;

    // A complete pass: every tile's splats (and strategy splats, when sf) in tile order;
    // the lists keep their capacity for the next pass.
    void addPass(const Scene& scene, std::vector<TileSplats>& tiles, SplatFilm& film, StrategyFilms* sf) {
        for (TileSplats& o : tiles) {
            film.addAll(o.splats.data(), o.splats.size());
            addPointSplats(scene, film, o.points.data(), o.points.size());
            if (sf)
                for (const StrategySplat& s : o.strategySplats) sf->addSplat(s);
            discarded += o.tally.nonfinite;
            lengths.add(o.tally.lengths);
            o.splats.clear();
            o.points.clear();
            o.strategySplats.clear();
            o.tally = ContributionTally();
        }
    }

    // The render's stats from the totals (summed over ranks on rank 0); spp: complete passes'
    // samples per pixel.
    void finish(const Scene& scene, Distributed* ranks, uint32_t spp, RenderStats& stats) const {
        stats.samplesNonfiniteDiscarded = discarded;
        sumStatsToRoot(ranks, stats);
        stats.lengthMeanLuminance = lengthsOfJob(ranks, lengths).means(double(scene.camera.width) * scene.camera.height, spp);
    }
};

}  // namespace wmlt
