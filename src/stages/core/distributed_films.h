// The films of a render split across ranks, summed on rank 0 in a fixed rank order
// (distributed.h): what the tracers' final images and snapshots are made from. Without
// ranks each returns a copy of the local film.
#pragma once
#include <algorithm>

#include "stages/core/distributed.h"
#include "stages/core/film.h"

namespace wmlt {

// The job's Film on rank 0: sums and sample counts (as doubles: exact below 2^53).
inline Film filmOfJob(Distributed* ranks, const Film& local) {
    if (!ranks || !ranks->many()) return local;
    std::vector<double> v(local.sum.size() + local.count.size());
    std::copy(local.sum.begin(), local.sum.end(), v.begin());
    std::copy(local.count.begin(), local.count.end(), v.begin() + std::ptrdiff_t(local.sum.size()));
    ranks->sumToRoot(v);
    Film job(local.width, local.height);
    std::copy(v.begin(), v.begin() + std::ptrdiff_t(job.sum.size()), job.sum.begin());
    for (size_t i = 0; i < job.count.size(); ++i) job.count[i] = uint32_t(v[job.sum.size() + i]);
    return job;
}

// The job's SplatFilm on rank 0.
inline SplatFilm filmOfJob(Distributed* ranks, const SplatFilm& local) {
    SplatFilm job = local;
    if (ranks && ranks->many()) ranks->sumToRoot(job.sum);
    return job;
}

// The job's per-length luminance sums on rank 0.
inline PathLengthSums lengthsOfJob(Distributed* ranks, const PathLengthSums& local) {
    if (!ranks || !ranks->many()) return local;
    std::vector<double> v(local.lum, local.lum + kMaxPathLength + 1);
    ranks->sumToRoot(v);
    PathLengthSums job;
    std::copy(v.begin(), v.end(), job.lum);
    return job;
}

// use(the job's film): rank 0's image of the whole job (the local film itself when the
// render is not split, without a copy).
template <class F, class Use>
auto withFilmOfJob(Distributed* ranks, const F& local, Use use) {
    if (!ranks || !ranks->many()) return use(local);
    return use(filmOfJob(ranks, local));
}

}  // namespace wmlt
