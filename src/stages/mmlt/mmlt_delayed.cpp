// Delayed rejection (issue 44's lever, RenderOptions::delayedRejection, `--mmlt-delayed-rejection
// on`; Tierney and Mira 1999, in light transport Rioux-Lavoie et al. 2020): a chain whose
// large step y1 is rejected proposes again in the same iteration, a small step y2 from where
// it is, x. In the wavefront the second tries are a sub-wave: acceptAndSplat lists the
// rejected chains (MmltBatch::rejectedLarge), and proposeAgain runs mutateChains,
// evaluateProposals and its own acceptance over them in the batch's slices' stead.
//
// The first stage's proposal is independent of x (a large step draws every coordinate
// afresh) and the second's is symmetric and independent of y1 (the small step), so the
// second stage's acceptance that keeps the chain reversible is (Tierney and Mira's eq. 2)
//   a2 = min(1, c(y2) (1 - a1(y2, y1)) / (c(x) (1 - a1(x, y1))))
//      = min(1, max(0, c(y2) - c(y1)) / (c(x) - c(y1))),   a1(x, y) = min(1, c(y) / c(x)),
// and c(x) > c(y1) whenever y1 was rejected. The splats (expected values over the second
// uniform, and over the first where both outcomes are at hand): a1 F(y1)/c(y1) always (in
// acceptAndSplat), then only when y1 was rejected a2 F(y2)/c(y2) and (1 - a2) F(x)/c(x):
// their expectation over the first decision is a1 f(y1) + (1 - a1) (a2 f(y2) + (1 - a2) f(x)),
// the next state's, so each iteration still adds one splat's worth in expectation.
// The second proposals join no pool (they are not independent samples). Their keys are the
// chain's iteration's under another seed, so a seed still gives one image for any thread and
// rank count. Counted in mmlt_delayed_proposals and mmlt_acceptance_delayed (--stats).
#include "stages/mmlt/mmlt_stages.h"

namespace wmlt {

void proposeAgain(const Scene& scene, std::vector<ChainGroup>& groups, MmltBatch& mb, uint64_t seed, uint32_t iteration, float misBeta,
                  RayCounters& counters) {
    if (mb.rejectedLarge.empty()) return;
    std::swap(mb.slices, mb.rejectedLarge);
    mb.secondStage = true;  // small steps only, none of them a film step
    mutateChains(groups, mb, seed ^ 0x44454c4159454452ull /* "DELAYEDR" */, iteration, 0.0f);
    mb.secondStage = false;
    evaluateProposals(scene, mb, misBeta, counters);
    for (const BatchSlice& sl : mb.slices) {
        ChainGroup& g = groups[size_t(sl.group)];
        const uint32_t i = sl.slot0, c = sl.c0;
        const uint8_t k = uint8_t(g.k);
        Vec3 F;
        const float cP = evaluatedTarget(mb, i, F), c1 = mb.rejectedC[i], cx = g.c[c];
        const float a = cP > c1 ? std::min(1.0f, (cP - c1) / (cx - c1)) : 0.0f;
        if (a > 0) mb.addSplat(scene, mb.bpt.filmX[i], mb.bpt.filmY[i], F * (a * g.weight / cP), k);
        if (a < 1) mb.addSplat(scene, g.filmX[c], g.filmY[c], g.F[c] * ((1.0f - a) * g.weight / cx), k);
        ++mb.counters.proposed[kSecondStage][k];
        if (!(sampleDimension(mb.bpt.key[i], kDimAccept) < a)) continue;
        ++mb.counters.accepted[kSecondStage][k];
        commitProposal(g, c, mb, i, false, F, cP);
    }
    std::swap(mb.slices, mb.rejectedLarge);
    mb.rejectedLarge.clear();
    mb.rejectedC.clear();
}

}  // namespace wmlt
