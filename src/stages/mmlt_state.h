// Structure-of-arrays state of MMLT (Hachisuka et al. 2014): the Markov chains, grouped by
// path length, and one batch of chains in flight.
//
// A chain of length k carries a primary sample vector u of StrategyLayout::size(k)
// coordinates (bpt_state.h: u[0] picks the strategy, then the camera, light and connection
// blocks). Coordinate i of all chains of a length is one contiguous array. Each coordinate
// stores its value and the accepted proposal that last wrote it (kernels/mutation.h: the
// lazy small step). A proposal never writes the chain: the batch holds it, and only an
// accepted proposal is committed, so a rejection restores every coordinate by doing nothing.
#pragma once
#include <cstdint>
#include <vector>

#include "stages/bpt_state.h"

namespace wmlt {

// The chains of one path length k.
struct ChainGroup {
    int k = 0;
    uint32_t count = 0;               // chains of this length
    uint32_t first = 0;               // global index of its first chain
    uint32_t dims = 0;                // StrategyLayout::size(k)
    uint32_t steps = 1;               // proposals per chain per iteration
    double b = 0;                     // bootstrap estimate of b_k = E[c]
    std::vector<float> value;         // [coordinate * count + chain]
    std::vector<uint32_t> lastModified;
    // Per chain.
    std::vector<uint32_t> accepted;   // accepted proposals (the lazy step's clock)
    std::vector<uint32_t> lastLarge;  // the last accepted large step
    std::vector<Vec3> F;              // current state: contribution (k + 1) L_w
    std::vector<float> c;             // current state: luminance of F (the target)
    std::vector<uint32_t> pixel;      // current state: where F lands
};

// Counters of one batch (merged in batch order).
struct MmltCounters {
    uint64_t proposed[2] = {0, 0}, accepted[2] = {0, 0};  // [0]: small steps, [1]: large
    uint64_t nonfinite = 0;
    double largeSum = 0;  // sum of c over large-step proposals: independent samples of b_k
};

// A batch of chains of one length group in flight: their proposals (rows of u, as
// StoredSamples reads them), the BPT stages' state, and the splats of a round.
struct MmltBatch {
    BptBatch bpt;
    uint32_t stride = 0;              // row length: StrategyLayout::size(maxLength)
    std::vector<float> u;             // [slot * stride + coordinate]
    std::vector<uint32_t> chain;      // slot -> chain index within its group
    std::vector<uint8_t> large;       // the slot's proposal is a large step
    std::vector<uint8_t> accept;      // the slot's proposal was accepted
    std::vector<uint8_t> used[3];     // numbers the proposal reads from each stream
    std::vector<Splat> splats;        // expected-value splats of the round, in order
    MmltCounters counters;

    void reserve(size_t n, int maxLength) {
        bpt.reserve(n, maxLength);
        bpt.roulette = false;
        stride = StrategyLayout::size(maxLength);
        u.assign(n * stride, 0.0f);
        chain.resize(n);
        large.resize(n);
        accept.resize(n);
        for (auto& v : used) v.resize(n);
    }
    StoredSamples samples() const { return StoredSamples{u.data(), stride, bpt.pathLength.data()}; }
};

}  // namespace wmlt
