#include "stages/core/distributed.h"

#include <cstdlib>
#include <cstring>

namespace wmlt {

namespace {

class OneProcess final : public Distributed {
public:
    int rank() const override { return 0; }
    int size() const override { return 1; }
    std::vector<uint8_t> allGather(const void* data, size_t bytes, std::vector<size_t>& sizes) override {
        sizes.assign(1, bytes);
        const uint8_t* p = static_cast<const uint8_t*>(data);
        return std::vector<uint8_t>(p, p + bytes);
    }
    void sumToRoot(std::vector<double>&) override {}
    void maxAll(uint64_t*, size_t) override {}
    void sumToRoot(uint64_t*, size_t) override {}
};

bool many(const Distributed* ranks) { return ranks && ranks->many(); }

}  // namespace

std::unique_ptr<Distributed> singleProcess() { return std::make_unique<OneProcess>(); }

Agreement agree(Distributed* ranks, bool stop, bool cancel, uint64_t rootValue) {
    if (!many(ranks)) return {stop, cancel, rootValue};
    uint64_t v[3] = {stop ? 1u : 0u, cancel ? 1u : 0u, ranks->root() ? rootValue : 0};
    ranks->maxAll(v, 3);
    return {v[0] != 0, v[1] != 0, v[2]};
}

std::vector<double> sumFilmToRoot(Distributed* ranks, const std::vector<double>& local) {
    std::vector<double> sum = local;
    if (many(ranks)) ranks->sumToRoot(sum);
    return sum;
}

double offerSnapshotAcrossRanks(const RenderOptions& opt, const std::function<Snapshot()>& snapshot) {
    Distributed* ranks = opt.ranks;
    const bool wanted = ranks->root() && opt.view && opt.view->wantsFrame();
    if (!agree(ranks, false, false, wanted ? 1 : 0).value) return 0;
    Snapshot s = snapshot();  // every rank: it may sum the films
    double paused = 0;
    if (ranks->root() && opt.view) {
        opt.view->publish(std::move(s));
        paused = opt.view->waitWhilePaused();
    }
    uint64_t bits = 0;  // rank 0's seconds paused, to every rank (as bits: only rank 0's count)
    std::memcpy(&bits, &paused, sizeof bits);
    bits = agree(ranks, false, false, bits).value;
    std::memcpy(&paused, &bits, sizeof paused);
    return paused;
}

void sumStatsToRoot(Distributed* ranks, RenderStats& st) {
    if (!many(ranks)) return;
    const Distributed::Cost cost = ranks->cost();  // before the exchanges below
    uint64_t counts[3] = {st.raysIntersect, st.raysOccluded, st.samplesNonfiniteDiscarded};
    ranks->sumToRoot(counts, 3);
    st.raysIntersect = counts[0];
    st.raysOccluded = counts[1];
    st.samplesNonfiniteDiscarded = counts[2];
    std::vector<size_t> sizes;
    const std::vector<uint8_t> all = ranks->allGather(&cost, sizeof cost, sizes);
    st.ranks.count = ranks->size();
    st.ranks.bytes.clear();
    st.ranks.seconds.clear();
    for (int r = 0; r < ranks->size(); ++r) {
        Distributed::Cost c;
        std::memcpy(&c, all.data() + size_t(r) * sizeof c, sizeof c);
        st.ranks.bytes.push_back(c.bytesReceived);  // each byte once, at its receiver
        st.ranks.seconds.push_back(c.seconds);
        if (r == 0) st.ranks.exchanges = c.calls;
    }
}

}  // namespace wmlt
