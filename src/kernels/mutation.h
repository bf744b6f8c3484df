// The primary-sample-space Metropolis kernel of MMLT (Kelemen et al. 2002; Hachisuka et al.
// 2014; pbrt-v3 16.4.2, "PrimarySample"): a lazily updated Gaussian small step, the large
// step, and the Metropolis acceptance probability. Pure functions: the stages own the state.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>

namespace wmlt {

// The standard deviation of one small step (pbrt-v3's default sigma).
constexpr float kSmallStepSigma = 0.01f;

// Phi^-1(u) = sqrt(2) erfinv(2u - 1), with Giles' single-precision erfinv ("Approximating
// the erfinv function", GPU Computing Gems, 2010). Its argument w = -log(1 - x^2) is
// computed as -log(4 u (1 - u)), which keeps precision in the lower tail where 2u - 1
// would round. u is clamped into [2^-25, 1 - 2^-24]: finite for every u, |result| < 5.42.
inline float inverseNormalCdf(float u) {
    u = std::min(std::max(u, 0x1p-25f), 0x1.fffffep-1f);
    float x = 2.0f * u - 1.0f;  // exact for u >= 1/4 (Sterbenz)
    float w = -std::log(4.0f * u * (1.0f - u)), p;
    if (w < 5.0f) {
        w -= 2.5f;
        p = 2.81022636e-08f;
        p = 3.43273939e-07f + p * w;
        p = -3.5233877e-06f + p * w;
        p = -4.39150654e-06f + p * w;
        p = 0.00021858087f + p * w;
        p = -0.00125372503f + p * w;
        p = -0.00417768164f + p * w;
        p = 0.246640727f + p * w;
        p = 1.50140941f + p * w;
    } else {
        w = std::sqrt(w) - 3.0f;
        p = -0.000200214257f;
        p = 0.000100950558f + p * w;
        p = 0.00134934322f + p * w;
        p = -0.00367342844f + p * w;
        p = 0.00573950773f + p * w;
        p = -0.0076224613f + p * w;
        p = 0.00943887047f + p * w;
        p = 1.00167406f + p * w;
        p = 2.83297682f + p * w;
    }
    return 1.41421356f * p * x;
}

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
// uFresh and uNormal are fresh uniforms in [0, 1) drawn for this proposal.
inline float proposeCoordinate(float value, uint32_t lastModified, uint32_t lastLargeStep, uint32_t n,
                               bool largeStep, float sigma, float uFresh, float uNormal) {
    if (largeStep) return uFresh;
    uint32_t since = lastModified;
    if (lastModified < lastLargeStep) {
        value = uFresh;
        since = lastLargeStep;
    }
    double nSmall = double(n - since);
    // In double: for large nSmall the step is large and float would quantise the result.
    double x = double(value) + double(sigma) * std::sqrt(nSmall) * double(inverseNormalCdf(uNormal));
    return wrapUnit(float(x - std::floor(x)));
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
