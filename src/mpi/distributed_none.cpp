// startRanks() and abortRanks() of a build without MPI (stages/core/distributed.h): one
// process. The build with MPI links src/mpi/distributed_mpi.cpp instead; only the programs
// that start ranks (wavemmlt, the tests' mpi runner) link either, so nothing else loads MPI.
#include <cstdlib>

#include "stages/core/distributed.h"

namespace wmlt {

bool ranksBuilt() { return false; }
std::unique_ptr<Distributed> startRanks(int&, char**&) { return singleProcess(); }
void abortRanks(int status) { std::exit(status); }

}  // namespace wmlt
