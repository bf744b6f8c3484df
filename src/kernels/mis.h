// Multiple importance sampling weights of bidirectional path tracing (Veach 1997, 10.2;
// pbrt-v3 16.3.4), as a pure function of per-vertex densities, so that it can be tested
// without a scene.
//
// A path of length k has vertices x_0 .. x_k: x_0 on a light, x_k on the camera.
// Strategy s (0 <= s <= k; t = k + 1 - s >= 1) takes x_0 .. x_{s-1} from the light
// subpath and x_s .. x_k from the camera subpath and connects x_{s-1} with x_s.
// Its density is p_s = prod_{i < s} pL[i] * prod_{s <= i < k} pE[i] (area measure), where
//   pL[i]  density of x_i when the light side generates it (pL[0]: emission position
//          times the light choice, as a light subpath with s >= 2 samples it),
//   pE[i]  density of x_i when the camera side generates it (pE[k] is never used: every
//          strategy samples the camera vertex the same way),
//   pL0Nee density of x_0 under s = 1 (next-event estimation: another sampling technique
//          for the light point than emission, e.g. cone sampling of a sphere),
//   (x_0 on the environment: pL[0] and pL0Nee are the direction's solid-angle density,
//   pE[0] the solid-angle density of the direction towards it, pL[1] the density of the
//   emission disc's point, pdfPos |cos| at x_1; pbrt-v3 16.3.)
//   (x_0 a point light: pL[0] = pL0Nee = the choice pmf, pE[0] unused: s = 0 is invalid.)
//   delta[i] x_i scatters by a delta lobe: its densities are set to 0 and remapped to 1
//          (the delta factors cancel in every ratio) and no strategy may connect at it or
//          at its neighbour edge; delta[0] and delta[k] must be 0.
// The weight of strategy s with the power heuristic of exponent beta (1: balance) is
// p_s^beta / sum_j p_j^beta over the strategies j that can sample the path, computed
// from ratios p_j / p_s of neighbouring densities (never products of raw pdfs).
#pragma once
#include <cmath>
#include <cstdint>

namespace wmlt {

// Whether strategy s can sample a path with these delta flags (no connection at a delta
// vertex). x0AtInfinity: x_0 is on the environment, which cannot be connected to the
// camera (s = 1, t = 1). x0Delta: x_0 is a point light (a delta in position): no camera
// path hits it (s = 0) and the camera does not see it (s = 1, t = 1).
inline bool bptStrategyValid(int k, int s, const uint8_t* delta, bool x0AtInfinity = false, bool x0Delta = false) {
    if (s < 0 || s > k) return false;
    if (s == 0) return !delta[0] && !x0Delta;
    if (s == 1 && k == 1 && (x0AtInfinity || x0Delta)) return false;
    return !delta[s - 1] && !delta[s];
}

inline double bptRatioPow(double r, float beta) {
    return beta == 2.0f ? r * r : beta == 1.0f ? r : std::pow(r, double(beta));
}

// The MIS weight of strategy s for a path of length k (see above). 0 when s cannot
// sample the path.
inline float bptMisWeight(int k, int s, const float* pL, const float* pE, const uint8_t* delta,
                          float pL0Nee, float beta, bool x0AtInfinity = false, bool x0Delta = false) {
    if (!bptStrategyValid(k, s, delta, x0AtInfinity, x0Delta)) return 0.0f;
    auto remap = [](float p) { return p > 0 ? double(p) : 1.0; };
    // step(j) = p_{j+1} / p_j: x_j moves from the camera side to the light side.
    auto step = [&](int j) {
        if (j == 0) return remap(pL0Nee) / remap(pE[0]);
        if (j == 1) return remap(pL[1]) * remap(pL[0]) / (remap(pE[1]) * remap(pL0Nee));
        return remap(pL[j]) / remap(pE[j]);
    };
    double sum = 1.0;  // strategy s itself
    double r = 1.0;
    for (int j = s; j < k; ++j) {  // p_{j+1} / p_s
        r *= step(j);
        if (bptStrategyValid(k, j + 1, delta, x0AtInfinity, x0Delta)) sum += bptRatioPow(r, beta);
    }
    r = 1.0;
    for (int j = s - 1; j >= 0; --j) {  // p_j / p_s
        r /= step(j);
        if (bptStrategyValid(k, j, delta, x0AtInfinity, x0Delta)) sum += bptRatioPow(r, beta);
    }
    float w = float(1.0 / sum);
    return std::isfinite(w) ? w : 0.0f;
}

}  // namespace wmlt
