// What MMLT learns between passes (mmlt_render.h; docs/mmlt-levers.md, with the
// measurements), each fixed within a pass so that every pass stays an exact Metropolis
// estimator: the relative-error target, the small steps' sizes and the share of film steps.
//
// The relative-error target (RenderOptions::mmltTarget = Relative; the target itself:
// kernels/mmlt_target.h). One in four of the independent samples the render draws (the
// bootstrap, each pass's fresh samples, every large step), chosen by its key's hash
// (mapSample, mmlt_state.h), goes to the map instead of a pool: its luminance joins its film
// tile's sum for its length (collectBrightness). At a pass boundary those sums make a
// brightness estimate per tile, B = sum_k S_k / N_k (N_k: length k's map samples), smoothed
// over the 3 x 3 tiles around it and floored at kTargetFloor of the image's mean, and the
// next pass's target is c = luminance(F) mean(B) / B(tile) (retarget).
// Why the split: a pass is exact when its target does not depend on the pool samples it
// weighs (importance resampling, mmlt.cpp's opening comment). A map made from the pools'
// own samples lowers c where those very samples are bright, and the chains, resampled from
// them, then stay away: on the seed room at 128 x 128 that made the image 6% too dark at 512
// mutations per pixel (means of 2 and 4 seeds, where the luminance target was within 2%).
// The pools' entries are kept with weights that make sum w h unbiased for any h, so under
// a new target their c are simply evaluated again. The map samples are merged in the same
// order on every rank (mmlt_pool.cpp, mmlt_rounds.cpp), never taken from a rank's own film:
// the map is the same on every rank and for any thread count.
#include "stages/mmlt/mmlt_render.h"

namespace wmlt::mmlt_detail {

// The target map's geometry, once per render: tiles of the smallest side that gives at most
// kTargetTiles of them.
void MmltRender::planTargetMap() {
    if (opt_.mmltTarget != MmltTarget::Relative || whole_) return;
    const int W = scene_.camera.width, H = scene_.camera.height;
    tileSize_ = std::max(1, int(std::ceil(std::sqrt(double(W) * double(H) / kTargetTiles))));
    map_.tilesX = (W + tileSize_ - 1) / tileSize_;
    map_.tilesY = (H + tileSize_ - 1) / tileSize_;
    map_.invTileSize = 1.0f / float(tileSize_);
    const size_t tiles = size_t(map_.tilesX) * size_t(map_.tilesY);
    brightness_.assign((size_t(kMax_) + 1) * tiles, 0.0);
    brightnessSamples_.assign(size_t(kMax_) + 1, 0);
}

// Adds map samples of length k (never thinned: every entry's weight 1, and the unlit ones
// only in the count) to the tile sums.
void MmltRender::collectBrightness(const SamplePool& p, int k) {
    if (brightness_.empty()) return;
    double* S = &brightness_[size_t(k) * size_t(map_.tilesX) * size_t(map_.tilesY)];
    const TargetMap tiles = map_;
    for (const PoolEntry& e : p.lit) S[targetTileOf(tiles, e.filmX, e.filmY)] += double(e.w) * double(luminance(e.F));
    brightnessSamples_[size_t(k)] += p.count;
}

// A new target from the tile sums so far, and every pool entry's c under it (no light seen
// yet: the target stays as it is).
void MmltRender::retarget() {
    if (brightness_.empty()) return;
    const int TX = map_.tilesX, TY = map_.tilesY, W = scene_.camera.width, H = scene_.camera.height;
    const size_t tiles = size_t(TX) * size_t(TY);
    std::vector<double> B(tiles, 0.0);
    for (int k = lo_; k <= hi_; ++k) {
        if (!brightnessSamples_[size_t(k)]) continue;
        const double* S = &brightness_[size_t(k) * tiles];
        for (size_t t = 0; t < tiles; ++t) B[t] += S[t] / double(brightnessSamples_[size_t(k)]);
    }
    double total = 0;
    for (size_t t = 0; t < tiles; ++t) total += B[t];
    if (!(total > 0) || !std::isfinite(total)) return;
    const double mean = total / (double(W) * double(H));  // per pixel
    // The 3 x 3 tiles around each: their sums over their pixels.
    scale_.assign(tiles, 1.0f);
    double least = 1e300, most = 0;
    for (int ty = 0; ty < TY; ++ty)
        for (int tx = 0; tx < TX; ++tx) {
            double sum = 0, pixels = 0;
            for (int y = std::max(0, ty - 1); y <= std::min(TY - 1, ty + 1); ++y)
                for (int x = std::max(0, tx - 1); x <= std::min(TX - 1, tx + 1); ++x) {
                    sum += B[size_t(y) * TX + x];
                    pixels += double(std::min(tileSize_, W - x * tileSize_)) * double(std::min(tileSize_, H - y * tileSize_));
                }
            const double b = std::max(sum / pixels, kTargetFloor * mean);
            const float s = float(mean / b);
            scale_[size_t(ty) * TX + tx] = s;
            least = std::min(least, double(s));
            most = std::max(most, double(s));
        }
    map_.scale = scale_.data();
    for (std::vector<SamplePool>* pools : {&pools_, &next_})
        for (SamplePool& p : *pools) {
            double sum = 0;
            for (PoolEntry& e : p.lit) {
                e.c = targetOf(e.F, e.filmX, e.filmY, map_);
                sum += double(e.w) * double(e.c);
            }
            p.sumWC = sum;
        }
    ++stats_.targetMaps;
    stats_.targetScaleLeast = least;
    stats_.targetScaleMost = most;
}

// What the pass's small steps teach (RenderOptions::learnSteps, filmSteps), at a pass
// boundary: each length's small-step size and its share of film steps for the next pass.
void MmltRender::learnFromSteps() {
    const bool learnFilm = opt_.filmSteps == FilmSteps::Learned;
    if (whole_ || (!opt_.learnSteps && !learnFilm)) return;
    const std::vector<uint64_t> counts = passSmallSteps();
    if (opt_.learnSteps) learnStepSizes(counts);
    if (learnFilm) learnFilmSteps(counts);
    passCounters_ = counters_;
}

// The pass's small steps (film steps and second stages aside) of each length k, proposed at
// [2k] and accepted at [2k + 1], over every rank (integers: their sum is the same in any
// order, so every rank learns the same).
std::vector<uint64_t> MmltRender::passSmallSteps() {
    std::vector<uint64_t> counts(2 * (size_t(kMax_) + 1));
    for (int k = lo_; k <= hi_; ++k) {
        counts[2 * size_t(k)] = counters_.proposed[kSmallStep][k] - passCounters_.proposed[kSmallStep][k];
        counts[2 * size_t(k) + 1] = counters_.accepted[kSmallStep][k] - passCounters_.accepted[kSmallStep][k];
    }
    if (ranks_) {
        std::vector<size_t> sizes;
        const std::vector<uint8_t> all = ranks_->allGather(counts.data(), counts.size() * sizeof(uint64_t), sizes);
        std::fill(counts.begin(), counts.end(), 0);
        for (size_t at = 0; at + counts.size() * sizeof(uint64_t) <= all.size(); at += counts.size() * sizeof(uint64_t))
            for (size_t i = 0; i < counts.size(); ++i) {
                uint64_t v;
                std::memcpy(&v, &all[at + i * sizeof v], sizeof v);
                counts[i] += v;
            }
    }
    return counts;
}

// Learned step sizes (RenderOptions::learnSteps): after a pass, each length's small-step
// size moves toward the acceptance kTargetAcceptance its chains' small steps should have:
// log sigma += kStepGain (a - a*), at most a factor e a pass, within [2^-10, 1/4]. Small
// steps' acceptance falls with sigma (on the seed room about 0.25 per unit of log sigma,
// 0.77 at 0.003 to 0.15 at 0.03), so a gain of 3 closes most of the gap in one pass.
void MmltRender::learnStepSizes(const std::vector<uint64_t>& counts) {
    for (int k = lo_; k <= hi_; ++k) {
        const uint64_t proposed = counts[2 * size_t(k)], accepted = counts[2 * size_t(k) + 1];
        if (proposed < 64) continue;  // too few to say
        const double a = double(accepted) / double(proposed);
        const double step = std::clamp(kStepGain * (a - kTargetAcceptance), -1.0, 1.0);
        sigma_[size_t(k)] = float(std::clamp(double(sigma_[size_t(k)]) * std::exp(step), 1.0 / 1024, 0.25));
    }
}

// Learned film steps (RenderOptions::filmSteps; the step: mmlt_stages.cpp, proposeFilmStep): a
// length whose small steps were accepted less than kFilmStepBelow of the time in the pass
// makes kFilmStepShare of its small steps film steps in the next; the others none. Where
// small steps are rejected, a chain sits on one path and splats one pixel (the seed room's
// and Veach Ajar's light through a gap: a small step of every number loses the gap); a film
// step moves the path's whole camera end across the film, most of the time still through
// the gap. Where small steps are accepted anyway (the Cornell box), film steps only
// explore less per step. A length with fewer than 64 small steps keeps its share.
void MmltRender::learnFilmSteps(const std::vector<uint64_t>& counts) {
    for (int k = lo_; k <= hi_; ++k) {
        const uint64_t proposed = counts[2 * size_t(k)], accepted = counts[2 * size_t(k) + 1];
        if (proposed < 64) continue;  // too few to say
        filmStep_[size_t(k)] = double(accepted) < kFilmStepBelow * double(proposed) ? kFilmStepShare : 0.0f;
    }
}

}  // namespace wmlt::mmlt_detail
