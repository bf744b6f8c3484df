// The ranks of one render (docs/mpi.md): what the tracers exchange when a render is split
// across processes (mpirun), behind a small interface with two implementations: one
// process (every call a no-op or a copy) and MPI (src/mpi/distributed_mpi.cpp, built only
// when CMake finds MPI, into the library wavemmlt_ranks with startRanks()). Every call is collective: every rank makes it, in the same order,
// from the render's own thread (never from a TBB task). Every exchange is in a fixed rank
// order, so a seed and a rank count give one result, bit for bit.
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <utility>
#include <vector>

#include "wavemmlt/render.h"

namespace wmlt {

class Distributed {
public:
    virtual ~Distributed() = default;
    virtual int rank() const = 0;
    virtual int size() const = 0;
    bool root() const { return rank() == 0; }
    bool many() const { return size() > 1; }

    // Every rank's bytes, concatenated in rank order, on every rank; sizes[r] = rank r's.
    virtual std::vector<uint8_t> allGather(const void* data, size_t bytes, std::vector<size_t>& sizes) = 0;
    // Element-wise sums on rank 0, added in a fixed order: v_0 + (v_1 + (... + v_{N-1})).
    // The other ranks' v is left in an unspecified state.
    virtual void sumToRoot(std::vector<double>& v) = 0;
    // Element-wise maximum over the ranks, on every rank (flags, and rank 0's decisions:
    // the other ranks pass 0).
    virtual void maxAll(uint64_t* v, size_t n) = 0;
    // Element-wise integer sums on rank 0 (integers: the order does not matter).
    virtual void sumToRoot(uint64_t* v, size_t n) = 0;

    // What the exchanges cost this rank: payload bytes sent and received, seconds inside
    // the calls (waiting for the other ranks included) and calls made.
    struct Cost {
        uint64_t bytesSent = 0, bytesReceived = 0, calls = 0;
        double seconds = 0;
    };
    const Cost& cost() const { return cost_; }

protected:
    Cost cost_;
};

// One process: rank 0 of 1.
std::unique_ptr<Distributed> singleProcess();

// The ranks this process belongs to: MPI when the build has it and the process was started
// by mpirun (MPI_Init is called then; MPI_Finalize when the object is destroyed), else
// one process. Call once, first thing in main().
std::unique_ptr<Distributed> startRanks(int& argc, char**& argv);
// True when this build can run across ranks (CMake found MPI).
bool ranksBuilt();
// Ends the whole job at once with `status` (MPI_Abort) after an error that the other ranks
// may not have met (they could be waiting in an exchange); one process: std::exit.
[[noreturn]] void abortRanks(int status);

// Helpers the tracers share.

// One exchange at a boundary where any rank may stop (`stop`: out of time or cancelled;
// `cancel`: Ctrl-C) and rank 0 decides (`value`, e.g. the next round's size under a time
// budget): every rank gets the OR of the flags and rank 0's value. Without ranks (nullptr
// or one) it returns its arguments.
struct Agreement {
    bool stop = false, cancel = false;
    uint64_t value = 0;
};
Agreement agree(Distributed* ranks, bool stop, bool cancel = false, uint64_t rootValue = 0);

// The element-wise sum of a film's doubles over the ranks, on rank 0 (a copy: `local` is
// untouched); without ranks, a copy of `local`.
std::vector<double> sumFilmToRoot(Distributed* ranks, const std::vector<double>& local);

// Offers a viewer the image so far (preview.h, offerSnapshot) when the render is split
// across ranks: rank 0's viewer decides whether a frame is made, every rank then calls
// `snapshot` (it may sum the films: an exchange), rank 0 publishes it and waits while its
// viewer pauses the render; the seconds paused are returned on every rank.
double offerSnapshotAcrossRanks(const RenderOptions& opt, const std::function<Snapshot()>& snapshot);

// Sums the statistics that every rank counts for its own share (rays, discarded samples)
// on rank 0, and records the job's ranks.
void sumStatsToRoot(Distributed* ranks, RenderStats& stats);

// Rank r's share [n r / N, n (r + 1) / N) of n work items (contiguous, in order).
inline std::pair<size_t, size_t> shareOf(int ranks, int rank, size_t n) {
    const size_t r = size_t(rank), N = size_t(ranks);
    return {n * r / N, n * (r + 1) / N};
}
inline std::pair<size_t, size_t> shareOf(const Distributed* ranks, size_t n) {
    if (!ranks || ranks->size() <= 1) return {0, n};
    return shareOf(ranks->size(), ranks->rank(), n);
}

}  // namespace wmlt
