// The primary-sample-space Metropolis kernel of MMLT (Kelemen et al. 2002; Hachisuka et al.
// 2014; pbrt-v3 16.4.2, "PrimarySample"): a lazily updated Gaussian small step (its normal
// numbers come from gaussian.h), the large step, and the Metropolis acceptance probability.
// Pure functions: the stages own the state.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>

namespace wmlt {

// The standard deviation of one small step (pbrt-v3's default sigma).
constexpr float kSmallStepSigma = 0.01f;

// x mod 1 in [0, 1). x - floor(x) rounds to 1 for tiny negative x (-1e-30 + 1 == 1 in
// float): that is mapped to 0, as are NaN and infinities.
inline float wrapUnit(float x) {
    float r = x - std::floor(x);
    return r < 1.0f ? r : 0.0f;
}

// The value one primary-sample coordinate takes in proposal n (Kelemen et al. 2002, 4.1;
// pbrt-v3's lazy PrimarySample::Mutate with a Gaussian small step).
//
// The chain's iteration counter counts ACCEPTED proposals: proposal n is made when the chain
// has accepted n - 1, so a rejected proposal changes no state at all. The coordinate stores
// (value, lastModified): its value as of accepted proposal lastModified; lastLargeStep is the
// last accepted large step (both < n). The caller commits (value = result, lastModified = n)
// when proposal n is accepted and leaves the coordinate untouched when it is rejected; a
// coordinate that proposal n does not read is not touched either (it is brought up to date
// when it is next read).
//
// - largeStep: the coordinate is fresh: uFresh.
// - otherwise the chain's value is brought up to date: if a large step was accepted since the
//   coordinate was last written (lastModified < lastLargeStep), its stored value is stale and
//   it was uFresh at lastLargeStep; then nSmall = n - max(lastModified, lastLargeStep) small
//   steps (the missed ones and this one) are applied at once. A sum of nSmall independent
//   N(0, sigma^2) steps is N(0, nSmall sigma^2), and wrapping commutes with addition mod 1,
//   so one step of sigma sqrt(nSmall) equals nSmall eager steps in distribution.
// uFresh is a fresh uniform in [0, 1) and z a standard normal number (gaussian.h), both
// drawn for this proposal.
inline float proposeCoordinate(float value, uint32_t lastModified, uint32_t lastLargeStep, uint32_t n, bool largeStep, float sigma, float uFresh,
                               float z) {
    if (largeStep) return uFresh;
    // Written without branches (selects only), so that a loop of small steps vectorises
    // (mmlt_stages.cpp, drawSmallSteps).
    const bool stale = lastModified < lastLargeStep;
    const double v = double(stale ? uFresh : value);
    const uint32_t nSmall = n - (stale ? lastLargeStep : lastModified);
    // In double: for large nSmall the step is large and float would quantise the result.
    // (nSmall = 1, a coordinate read at every step: sigma * sqrt(1) is sigma exactly.)
    const double x = v + double(sigma) * std::sqrt(double(nSmall)) * double(z);
    // x mod 1 in double is in [0, 1); rounded to float it can reach 1, which wraps to 0.
    const float r = float(x - std::floor(x));
    return r < 1.0f ? r : 0.0f;
}

// Metropolis acceptance a = min(1, c(proposed) / c(current)) (Metropolis et al. 1953; the
// small and large step proposals are both symmetric). A proposal with c <= 0, NaN or Inf is
// never accepted; a current state with c <= 0 (never the case in a seeded chain) is always left.
inline float acceptance(float cProposed, float cCurrent) {
    if (!(cProposed > 0.0f) || !std::isfinite(cProposed)) return 0.0f;
    if (!(cCurrent > 0.0f)) return 1.0f;
    return std::min(1.0f, cProposed / cCurrent);
}

}  // namespace wmlt
