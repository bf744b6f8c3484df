// The MPI implementation of Distributed (stages/core/distributed.h), built only when CMake finds
// MPI (into wavemmlt_ranks, which only the programs that start ranks link). The MPI calls are made from the render's own thread only
// (MPI_THREAD_FUNNELED); the exchanges are plain MPI-3 collectives except the film sum,
// a pipelined chain in rank order (its order of additions is fixed, which MPI_Reduce does
// not promise).
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <string>

#include "stages/core/distributed.h"

namespace wmlt {

namespace {

using Clock = std::chrono::steady_clock;

class MpiRanks final : public Distributed {
public:
    MpiRanks() {
        MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
        MPI_Comm_size(MPI_COMM_WORLD, &size_);
    }
    ~MpiRanks() override { MPI_Finalize(); }
    int rank() const override { return rank_; }
    int size() const override { return size_; }

    std::vector<uint8_t> allGather(const void* data, size_t bytes, std::vector<size_t>& sizes) override {
        Timer t(cost_);
        const uint64_t mine = bytes;
        std::vector<uint64_t> all(static_cast<size_t>(size_), 0);
        MPI_Allgather(&mine, 1, MPI_UINT64_T, all.data(), 1, MPI_UINT64_T, MPI_COMM_WORLD);
        const size_t n = static_cast<size_t>(size_);
        std::vector<int> counts(n), displs(n);
        uint64_t total = 0;
        sizes.assign(n, 0);
        for (int r = 0; r < size_; ++r) {
            if (all[size_t(r)] > uint64_t(std::numeric_limits<int>::max()) || total + all[size_t(r)] > uint64_t(std::numeric_limits<int>::max()))
                throw std::runtime_error("an exchange between ranks of more than 2 GiB");
            sizes[size_t(r)] = size_t(all[size_t(r)]);
            counts[size_t(r)] = int(all[size_t(r)]);
            displs[size_t(r)] = int(total);
            total += all[size_t(r)];
        }
        std::vector<uint8_t> out(static_cast<size_t>(total));
        MPI_Allgatherv(data, int(bytes), MPI_BYTE, out.data(), counts.data(), displs.data(), MPI_BYTE, MPI_COMM_WORLD);
        cost_.bytesSent += (sizeof(uint64_t) + bytes) * uint64_t(size_ - 1);
        cost_.bytesReceived += (total - bytes) + sizeof(uint64_t) * uint64_t(size_ - 1);
        return out;
    }

    // acc_r = v_r + acc_{r+1}, chunk by chunk: rank N-1 sends its chunk to N-2, which adds
    // its own and passes it on; rank 0 ends with v_0 + (v_1 + (... + v_{N-1})). Chunks
    // pipeline the chain: about (film + N chunks) / bandwidth in all.
    void sumToRoot(std::vector<double>& v) override {
        Timer t(cost_);
        constexpr size_t kChunk = size_t(1) << 16;  // 512 KiB
        std::vector<double> in(std::min(kChunk, v.size()));
        for (size_t off = 0; off < v.size(); off += kChunk) {
            const int n = int(std::min(kChunk, v.size() - off));
            if (rank_ + 1 < size_) {
                MPI_Recv(in.data(), n, MPI_DOUBLE, rank_ + 1, kFilmTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
                for (int i = 0; i < n; ++i) v[off + size_t(i)] += in[size_t(i)];
                cost_.bytesReceived += uint64_t(n) * sizeof(double);
            }
            if (rank_ > 0) {
                MPI_Send(&v[off], n, MPI_DOUBLE, rank_ - 1, kFilmTag, MPI_COMM_WORLD);
                cost_.bytesSent += uint64_t(n) * sizeof(double);
            }
        }
    }

    void maxAll(uint64_t* v, size_t n) override {
        Timer t(cost_);
        MPI_Allreduce(MPI_IN_PLACE, v, int(n), MPI_UINT64_T, MPI_MAX, MPI_COMM_WORLD);
        cost_.bytesSent += n * sizeof(uint64_t);
        cost_.bytesReceived += n * sizeof(uint64_t);
    }

    void sumToRoot(uint64_t* v, size_t n) override {
        Timer t(cost_);
        if (rank_ == 0) MPI_Reduce(MPI_IN_PLACE, v, int(n), MPI_UINT64_T, MPI_SUM, 0, MPI_COMM_WORLD);
        else MPI_Reduce(v, nullptr, int(n), MPI_UINT64_T, MPI_SUM, 0, MPI_COMM_WORLD);
        (rank_ == 0 ? cost_.bytesReceived : cost_.bytesSent) += n * sizeof(uint64_t);
    }

private:
    static constexpr int kFilmTag = 7;
    struct Timer {
        explicit Timer(Cost& c) : cost(c), start(Clock::now()) {}
        ~Timer() {
            cost.seconds += std::chrono::duration<double>(Clock::now() - start).count();
            ++cost.calls;
        }
        Cost& cost;
        Clock::time_point start;
    };
    int rank_ = 0, size_ = 1;
};

// Set by a launcher of MPI processes (Open MPI's mpirun; PMI for others, e.g. srun or
// MPICH's mpiexec).
bool startedByMpirun() {
    for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
        if (std::getenv(v)) return true;
    return false;
}

}  // namespace

bool ranksBuilt() { return true; }

std::unique_ptr<Distributed> startRanks(int& argc, char**& argv) {
    if (!startedByMpirun()) return singleProcess();
    int provided = 0;
    MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
    return std::make_unique<MpiRanks>();
}

void abortRanks(int status) {
    int initialized = 0, finalized = 0;
    MPI_Initialized(&initialized);
    MPI_Finalized(&finalized);
    if (initialized && !finalized) MPI_Abort(MPI_COMM_WORLD, status);
    std::exit(status);
}

}  // namespace wmlt
