#include "app/ranks.h"

#include <unistd.h>

#include <chrono>
#include <csignal>
#include <exception>
#include <iostream>
#include <new>

#include "wavemmlt/error.h"

namespace wmlt {

namespace {

// prepare(), with its error printed (by rank `shown`'s rule) and turned into a status.
int tryPrepare(const Distributed& ranks, const std::function<int()>& prepare) {
    const std::string who = ranks.root() ? "" : "(rank " + std::to_string(ranks.rank()) + ") ";
    try {
        return prepare();
    } catch (const InputError& e) {
        std::cerr << "error: " << who << e.what() << "\n";
        return 2;
    } catch (const std::bad_alloc&) {
        std::cerr << "error: " << who << "out of memory\n";
        return 1;
    } catch (const std::exception& e) {
        std::cerr << "error: " << who << e.what() << "\n";
        return 1;
    }
}

}  // namespace

int prepareOnRanks(Distributed& ranks, const std::function<int()>& prepare) {
    if (!ranks.many()) return tryPrepare(ranks, prepare);
    // Rank 0 first: its outcome (status + 1; 0: go on) to every rank.
    const int first = ranks.root() ? tryPrepare(ranks, prepare) : -1;
    const Agreement a = agree(&ranks, false, false, uint64_t(first + 1));
    if (a.value != 0) return int(a.value) - 1;
    const int mine = ranks.root() ? -1 : tryPrepare(ranks, prepare);
    uint64_t worst = uint64_t(mine + 1);  // the largest status of any rank
    ranks.maxAll(&worst, 1);
    return int(worst) - 1;
}

void failRanks(Distributed& ranks, int status, const std::string& message) {
    if (!ranks.root()) {
        // mpirun ends this rank with SIGTERM once rank 0 aborts: by default, not by the
        // handler that turns it into a cancel (which would also cut the sleep short).
        std::signal(SIGTERM, SIG_DFL);
        const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(2);
        while (std::chrono::steady_clock::now() < until) usleep(20000);
    }
    std::cerr << "error: " << (ranks.root() ? "" : "(rank " + std::to_string(ranks.rank()) + ") ") << message << "\n";
    std::cerr.flush();
    abortRanks(status);
}

}  // namespace wmlt
