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

inline double bptRemap(float p) { return p > 0 ? double(p) : 1.0; }

// p_{j+1} / p_j: x_j moves from the camera side to the light side (densities remapped).
inline double bptStep(int j, const float* pL, const float* pE, float pL0Nee) {
    if (j == 0) return bptRemap(pL0Nee) / bptRemap(pE[0]);
    if (j == 1) return bptRemap(pL[1]) * bptRemap(pL[0]) / (bptRemap(pE[1]) * bptRemap(pL0Nee));
    return bptRemap(pL[j]) / bptRemap(pE[j]);
}

// step(j) as a fraction num / den (both > 0 and finite for finite densities).
inline void bptStepFraction(int j, const float* pL, const float* pE, float pL0Nee, double& num, double& den) {
    if (j == 0) {
        num = bptRemap(pL0Nee);
        den = bptRemap(pE[0]);
    } else if (j == 1) {
        num = bptRemap(pL[1]) * bptRemap(pL[0]);
        den = bptRemap(pE[1]) * bptRemap(pL0Nee);
    } else {
        num = bptRemap(pL[j]);
        den = bptRemap(pE[j]);
    }
}

inline double bptRatioPow(double r, float beta) { return beta == 2.0f ? r * r : beta == 1.0f ? r : std::pow(r, double(beta)); }

// The MIS weight of strategy s for a path of length k (see above). 0 when s cannot
// sample the path.
inline float bptMisWeight(int k, int s, const float* pL, const float* pE, const uint8_t* delta, float pL0Nee, float beta, bool x0AtInfinity = false,
                          bool x0Delta = false) {
    if (!bptStrategyValid(k, s, delta, x0AtInfinity, x0Delta)) return 0.0f;
    auto step = [&](int j) { return bptStep(j, pL, pE, pL0Nee); };
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

// ---- The same weight from partial sums cached per subpath vertex ----------------------
// (the recursive form of Georgiev 2012, "Implementing Vertex Connection and Merging", and
// van Antwerpen 2011, in this page's notation.) With rho(j) = step(j)^beta and v(j) =
// bptStrategyValid(k, j), the sum of bptMisWeight is 1 + Right + Left:
//   Right = sum_{j > s} v(j) prod_{s <= m < j} rho(m) = R(s),      R(m) = rho(m) (v(m + 1) + R(m + 1)), R(k) = 0,
//   Left  = sum_{j < s} v(j) prod_{j <= m < s} 1 / rho(m) = L(s - 1), L(m) = (v(m) + L(m - 1)) / rho(m), L(-1) = 0.
// R(m) for m >= s + 2 depends on the camera subpath alone (x_m = z_{k-m}): its vertex z_i
// keeps T_i = R(k - i) (T_0 = 0); L(m) for m <= s - 3 on the light subpath alone: y_m
// keeps L(m) (bptSubpathMisSum, and for y_0 and y_1 bptLightMisSum0/1). A strategy then needs only the
// densities around its connection, [s - 3, s + 2] and x_0.

// The sum at a subpath's vertex from the one before it (both sides have the same form):
// camera vertex z_i (i >= 1), T_i = rho(k - i) (v(k - i + 1) + T_{i-1}); light vertex y_m
// (m >= 2), L(m) = (v(m) + L(m - 1)) / rho(m). pdfRev: the vertex's density as the other
// side would generate it, pdfFwd: as its own walk did; delta flags of it and of the vertex
// before it (z_0, the camera, never is one).
inline double bptSubpathMisSum(double prev, float pdfRev, float pdfFwd, bool delta, bool prevDelta, float beta) {
    return bptRatioPow(bptRemap(pdfRev) / bptRemap(pdfFwd), beta) * ((delta || prevDelta ? 0.0 : 1.0) + prev);
}
// L(0) and L(1): y_0 on the light (pL0 its emission density, pL0Nee next-event
// estimation's, pE0 the camera side's; x0Delta: a point light) and y_1 (densities pL1,
// pE1, delta1).
inline double bptLightMisSum0(float pE0, float pL0Nee, bool x0Delta, float beta) {
    return x0Delta ? 0.0 : bptRatioPow(bptRemap(pE0) / bptRemap(pL0Nee), beta);
}
inline double bptLightMisSum1(double sum0, float pL0, float pL0Nee, float pL1, float pE1, bool delta1, float beta) {
    const double rho = bptRemap(pL1) * bptRemap(pL0) / (bptRemap(pE1) * bptRemap(pL0Nee));
    return ((delta1 ? 0.0 : 1.0) + sum0) / bptRatioPow(rho, beta);
}

// bptMisWeight from the partial sums: pL, pE and delta are read at x_0 and at [s - 3,
// s + 2] only; cameraSum = T_{t-3} (t >= 3), lightSum = L(s - 3) (s >= 3), else unread.
inline float bptMisWeightCached(int k, int s, const float* pL, const float* pE, const uint8_t* delta, float pL0Nee, float beta, bool x0AtInfinity,
                                bool x0Delta, double cameraSum, double lightSum) {
    if (!bptStrategyValid(k, s, delta, x0AtInfinity, x0Delta)) return 0.0f;
    auto step = [&](int j) { return bptStep(j, pL, pE, pL0Nee); };
    auto v = [&](int j) { return bptStrategyValid(k, j, delta, x0AtInfinity, x0Delta) ? 1.0 : 0.0; };
    const int t = k + 1 - s;
    if (beta == 2.0f || beta == 1.0f) {
        // The same sums as fractions, Right = rN / rD and Left = lN / lD, so that the weight
        // rD lD / (rD lD + rN lD + lN rD) takes one division instead of one per ratio (the
        // divisions' latency was most of the weighting). Densities so extreme that a
        // product leaves double's range take the form below.
        auto frac = [&](int j, double& num, double& den) {
            bptStepFraction(j, pL, pE, pL0Nee, num, den);
            if (beta == 2.0f) {
                num *= num;
                den *= den;
            }
        };
        double rN = 0, rD = 1, lN = 0, lD = 1;
        if (s + 1 <= k) {
            double c, e;
            frac(s, c, e);
            if (s + 2 <= k) {
                double a, b;
                frac(s + 1, a, b);
                rN = c * (v(s + 1) * b + a * (v(s + 2) + (t >= 3 ? cameraSum : 0.0)));
                rD = e * b;
            } else {
                rN = c * v(s + 1);
                rD = e;
            }
        }
        if (s >= 1) {
            double h, m;
            frac(s - 1, h, m);
            if (s >= 2) {
                double f, g;
                frac(s - 2, f, g);
                lN = m * (v(s - 1) * f + (v(s - 2) + (s >= 3 ? lightSum : 0.0)) * g);
                lD = h * f;
            } else {
                lN = m * v(s - 1);
                lD = h;
            }
        }
        const double den = rD * lD, sum = den + rN * lD + lN * rD;
        if (den > 0 && std::isfinite(sum)) {
            const float w = float(den / sum);
            return std::isfinite(w) ? w : 0.0f;
        }
    }
    double right = 0;  // R(s)
    if (s + 1 <= k) {
        double inner = 0;  // R(s + 1)
        if (s + 2 <= k) inner = bptRatioPow(step(s + 1), beta) * (v(s + 2) + (t >= 3 ? cameraSum : 0.0));
        right = bptRatioPow(step(s), beta) * (v(s + 1) + inner);
    }
    double left = 0;  // L(s - 1)
    if (s >= 1) {
        double inner = 0;  // L(s - 2)
        if (s >= 2) inner = (v(s - 2) + (s >= 3 ? lightSum : 0.0)) / bptRatioPow(step(s - 2), beta);
        left = (v(s - 1) + inner) / bptRatioPow(step(s - 1), beta);
    }
    float w = float(1.0 / (1.0 + right + left));
    return std::isfinite(w) ? w : 0.0f;
}

}  // namespace wmlt
