// MMLT's output phase: the image so far (every snapshot and the final image), the counters
// summed across ranks, and the render's result with its stats (mmlt.cpp runs the passes).
#include "stages/mmlt/mmlt_render.h"

#include <cstring>

namespace wmlt {

namespace mmlt_detail {

// The image so far: pixels * film / T, T the weighted iterations per chain (each length's
// splats already weighted per pass). The final image and every snapshot (preview.h).
// Split across ranks: rank 0's image of the job (every rank calls it: the films are summed).
Image MmltRender::image() const {
    const double norm = weighted_ > 0 ? pixels_ / weighted_ : 0.0;
    Image im(scene_.camera.width, scene_.camera.height);
    withFilmOfJob(ranks_, film_, [&](const SplatFilm& film) {
        for (size_t i = 0; i < im.rgb.size(); ++i) im.rgb[i] = float(film.sum[i] * norm);
        return 0;
    });
    return im;
}

// Split across ranks: the counters of every rank's batches summed on rank 0; b_k and the
// pools' digest as every rank has them (the test that they agree: test_mpi.cpp).
void MmltRender::sumAcrossRanks(RenderResult& res) {
    stats_.bByRank = {stats_.b};
    stats_.poolDigestByRank = {poolDigest_};
    if (!ranks_) return;
    constexpr size_t kCounts = sizeof counters_.proposed / sizeof(uint64_t);  // per array: kinds times lengths
    std::vector<uint64_t> v(2 * kCounts + 2);
    std::memcpy(v.data(), counters_.proposed, sizeof counters_.proposed);
    std::memcpy(v.data() + kCounts, counters_.accepted, sizeof counters_.accepted);
    v[v.size() - 2] = stats_.replayed;
    v[v.size() - 1] = stats_.replayMismatches;
    ranks_->sumToRoot(v.data(), v.size());
    std::memcpy(counters_.proposed, v.data(), sizeof counters_.proposed);
    std::memcpy(counters_.accepted, v.data() + kCounts, sizeof counters_.accepted);
    stats_.replayed = v[v.size() - 2];
    stats_.replayMismatches = v[v.size() - 1];
    std::vector<double> lum(counters_.splatLuminance, counters_.splatLuminance + kMaxPathLength + 1);
    ranks_->sumToRoot(lum);
    std::copy(lum.begin(), lum.end(), counters_.splatLuminance);
    std::vector<uint8_t> mine(stats_.b.size() * sizeof(double) + sizeof poolDigest_);
    std::memcpy(mine.data(), stats_.b.data(), stats_.b.size() * sizeof(double));
    std::memcpy(mine.data() + stats_.b.size() * sizeof(double), &poolDigest_, sizeof poolDigest_);
    std::vector<size_t> sizes;
    const std::vector<uint8_t> all = ranks_->allGather(mine.data(), mine.size(), sizes);
    stats_.bByRank.assign(size_t(ranks_->size()), std::vector<double>(stats_.b.size()));
    stats_.poolDigestByRank.assign(size_t(ranks_->size()), 0);
    for (size_t r = 0; r < size_t(ranks_->size()); ++r) {
        const uint8_t* at = all.data() + r * mine.size();
        std::memcpy(stats_.bByRank[r].data(), at, stats_.b.size() * sizeof(double));
        std::memcpy(&stats_.poolDigestByRank[r], at + stats_.b.size() * sizeof(double), sizeof poolDigest_);
    }
}

// The image and the stats.
RenderResult MmltRender::resolve() {
    PassResult pr;
    pr.seconds = elapsed();
    pr.completedSpp = uint32_t(double(iteration_) * chains_ / pixels_);
    pr.stopped = stopped_;
    pr.cancelled = cancelled_;
    pr.passes = rounds_;
    RenderResult res = startResult(whole_ ? "pssmlt" : "mmlt", scene_, opt_, pr, rays_);
    res.stats.spectral = spectral_;
    res.stats.spectralReason = spectralMode_.reason(opt_.spectral);
    stats_.iterations = iteration_;
    stats_.passLength = passLength_;
    stats_.smallStepSigma = sigma_;
    stats_.learnedSteps = opt_.learnSteps && !whole_;
    stats_.delayedRejection = opt_.delayedRejection && !whole_;
    stats_.filmSteps = whole_ ? FilmSteps::Off : opt_.filmSteps;
    stats_.filmStepShare = filmStep_;
    stats_.targetExponent = map_.exponent;
    if (!brightness_.empty()) {
        stats_.target = MmltTarget::Relative;
        stats_.targetTileSize = uint32_t(tileSize_);
    }
    stats_.longestTaskRatio = rounds_ ? ratioSum_ / double(rounds_) : 0.0;
    res.stats.samplesNonfiniteDiscarded = counters_.nonfinite;
    for (int k = lo_; k <= hi_; ++k) stats_.b[size_t(k)] = weighted_ > 0 ? passB_[size_t(k)] / weighted_ : 0.0;
    sumAcrossRanks(res);
    for (int k = lo_; k <= hi_; ++k) {
        stats_.proposedSmall[size_t(k)] = counters_.proposed[kSmallStep][k];
        stats_.acceptedSmall[size_t(k)] = counters_.accepted[kSmallStep][k];
        stats_.proposedLarge[size_t(k)] = counters_.proposed[kLargeStep][k];
        stats_.acceptedLarge[size_t(k)] = counters_.accepted[kLargeStep][k];
        stats_.proposedDelayed[size_t(k)] = counters_.proposed[kSecondStage][k];
        stats_.acceptedDelayed[size_t(k)] = counters_.accepted[kSecondStage][k];
        stats_.proposedFilm[size_t(k)] = counters_.proposed[kFilmStep][k];
        stats_.acceptedFilm[size_t(k)] = counters_.accepted[kFilmStep][k];
        stats_.mutations += stats_.proposals[size_t(k)];
    }
    res.stats.mmlt = stats_;
    if (!whole_) {  // (PSSMLT's one b is every length's)
        // the luminance target: b_k is length k's mean luminance; another: what k splatted,
        // over the image's divisor
        res.stats.lengthMeanLuminance = stats_.b;
        if (map_.exponent != 1.0f)
            for (int k = lo_; k <= hi_; ++k) res.stats.lengthMeanLuminance[size_t(k)] = weighted_ > 0 ? counters_.splatLuminance[k] / weighted_ : 0.0;
    }
    const double norm = weighted_ > 0 ? pixels_ / weighted_ : 0.0;
    res.image = image();
    sumStatsToRoot(opt_.ranks, res.stats);  // rays, samples discarded, the exchanges' cost
    for (const SplatFilm& f : lengthFilms_) {
        res.lengthImages.emplace_back(f.width, f.height);
        for (size_t i = 0; i < f.sum.size(); ++i) res.lengthImages.back().rgb[i] = float(f.sum[i] * norm);
    }
    res.stats.buffers = {{"film", uint64_t(24 * pixels_)},
                         {"length films", uint64_t(24 * pixels_) * lengthFilms_.size()},
                         {"chain state", stats_.chainBytes},
                         {"pools", uint64_t(poolEntries_ * sizeof(PoolEntry))},
                         {"splat lists", uint64_t(kProposalsPerRound) * 2 * sizeof(Splat)}};
    return res;
}

}  // namespace mmlt_detail

}  // namespace wmlt
