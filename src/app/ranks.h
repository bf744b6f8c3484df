// wavemmlt across ranks (mpirun; docs/mpi.md): how the command line's start and errors are
// shared by the ranks, so that bad input gives one message and one exit status on every
// rank, and no rank waits for another that has given up.
#pragma once
#include <functional>
#include <string>

#include "stages/core/distributed.h"

namespace wmlt {

// Runs `prepare` (parse, load and check; it returns -1 to go on with the render, or an exit
// status to end with at once, e.g. 0 after --help) on rank 0 first; only when rank 0 goes
// on do the other ranks run theirs (one exchange each way). Returns -1 to go on, else the
// status every rank ends with. Errors (InputError: 2, others: 1) print one message: rank
// 0's, or each failing rank's, prefixed with its rank, when rank 0 went on.
int prepareOnRanks(Distributed& ranks, const std::function<int()>& prepare);

// An error during the render, after the ranks have started exchanging: rank 0 prints it and
// ends the job (MPI_Abort) with `status`; another rank waits 2 s first (rank 0 meets the
// same error at the same point when the error comes from the input, and its message is the
// one shown), then prints it with its rank and ends the job.
[[noreturn]] void failRanks(Distributed& ranks, int status, const std::string& message);

}  // namespace wmlt
