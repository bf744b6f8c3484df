// Warps from [0,1)^2 to directions and points, each with its pdf (pbrt-v4 ch. 2 and A.5).
#pragma once
#include "kernels/rng.h"
#include "wavemmlt/math.h"

namespace wmlt {

// Russian roulette (Arvo and Kirk 1990): from vertex kRouletteDepth of a subpath on, it
// goes on with probability q = min(1, max(beta) / scale) (scale: the largest component of
// the throughput it started with, 1 for camera subpaths) and beta becomes beta / q, so
// E[beta'] = beta. u is the vertex's roulette number; false: the subpath ends.
constexpr int kRouletteDepth = 3;
inline bool survivesRoulette(Vec3& beta, float scale, float u) {
    const float q = std::min(1.0f, maxComponent(beta) / scale);
    if (!(u < q)) return false;
    beta = beta / q;
    return true;
}

// sin t and cos t for |t| <= pi/4: their Taylor polynomials to t^9 and t^10 in Horner form
// (the truncation errors are below 2e-9 and 2e-10 there, under float's half ulp), so no
// call into libm, no range reduction, and loops over them vectorise. Within 2 ulp of the
// correctly rounded values (test_sampling.cpp).
inline void sinCosQuarter(float t, float& s, float& c) {
    const float t2 = t * t;
    s = t * (1.0f + t2 * (-1.0f / 6 + t2 * (1.0f / 120 + t2 * (-1.0f / 5040 + t2 * (1.0f / 362880)))));
    c = 1.0f + t2 * (-0.5f + t2 * (1.0f / 24 + t2 * (-1.0f / 720 + t2 * (1.0f / 40320 + t2 * (-1.0f / 3628800)))));
}

// sin and cos of phi = 2 pi u, u in [0, 1]: phi = q pi / 2 + t with q the nearest quarter
// turn (4 u - q is exact) and |t| <= pi / 4, then (cos, sin) turned by q quarters.
inline void sinCos2Pi(float u, float& s, float& c) {
    const float q = std::nearbyint(4.0f * u);
    float st, ct;
    sinCosQuarter((kPi / 2) * (4.0f * u - q), st, ct);
    switch (int(q) & 3) {
        case 0:
            s = st;
            c = ct;
            break;
        case 1:
            s = ct;
            c = -st;
            break;
        case 2:
            s = -st;
            c = -ct;
            break;
        default:
            s = -ct;
            c = st;
            break;
    }
}

// Concentric map of the unit square to the unit disc (Shirley and Chiu 1997). The angle is
// pi/4 (b/a) or pi/2 - pi/4 (a/b): sin and cos of |t| <= pi/4 serve both (cos(pi/2 - t) =
// sin t). Its branches are selects (the centre's 0 / 0 is discarded), so that loops of it
// vectorise (sampleCosineHemispheres).
inline void sampleConcentricDisk(float u1, float u2, float& x, float& y) {
    const float a = 2.0f * u1 - 1.0f, b = 2.0f * u2 - 1.0f;
    const bool aBig = std::fabs(a) > std::fabs(b), centre = a == 0 && b == 0;
    float s, c;
    sinCosQuarter((kPi / 4) * ((aBig ? b : a) / (aBig ? a : b)), s, c);
    x = centre ? 0.0f : aBig ? a * c : b * s;
    y = centre ? 0.0f : aBig ? a * s : b * c;
}

// Cosine-weighted hemisphere around +z: pdf = cos(theta) / pi.
inline void sampleCosineHemisphere(float u1, float u2, float& x, float& y, float& z) {
    sampleConcentricDisk(u1, u2, x, y);
    z = std::sqrt(std::max(0.0f, 1.0f - x * x - y * y));
}
inline Vec3 sampleCosineHemisphere(float u1, float u2) {
    Vec3 w;
    sampleCosineHemisphere(u1, u2, w.x, w.y, w.z);
    return w;
}
inline float cosineHemispherePdf(float cosTheta) { return cosTheta > 0 ? cosTheta * kInvPi : 0.0f; }

// sampleCosineHemisphere(sampleDimension(key[i], d1), sampleDimension(key[i], d2)) for i < n,
// bit for bit, into (x[i], y[i], z[i]), in one loop the compiler vectorises (the hashes,
// the polynomials, the square root).
inline void sampleCosineHemispheres(const uint64_t* __restrict key, size_t n, uint32_t d1, uint32_t d2, float* __restrict x, float* __restrict y,
                                    float* __restrict z) {
    for (size_t i = 0; i < n; ++i) sampleCosineHemisphere(sampleDimension(key[i], d1), sampleDimension(key[i], d2), x[i], y[i], z[i]);
}
// The same from the numbers (u1[i], u2[i]).
inline void sampleCosineHemispheres(const float* __restrict u1, const float* __restrict u2, size_t n, float* __restrict x, float* __restrict y,
                                    float* __restrict z) {
    for (size_t i = 0; i < n; ++i) sampleCosineHemisphere(u1[i], u2[i], x[i], y[i], z[i]);
}

// Uniform direction on the unit sphere: pdf = 1 / (4 pi).
inline Vec3 sampleUniformSphere(float u1, float u2) {
    float z = 1.0f - 2.0f * u1;
    float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    float s, c;
    sinCos2Pi(u2, s, c);
    return {r * c, r * s, z};
}
constexpr float kUniformSpherePdf = 1.0f / (4.0f * kPi);

// Direction around +z with density (n + 1) / (2 pi) cos^n(theta) (Phong lobe).
inline Vec3 samplePowerCosine(float n, float u1, float u2) {
    // cos = (1 - u1)^(1/(n+1)); 1 - cos via expm1/log1p so that sin stays accurate when
    // cos rounds to 1 in float (large n).
    float oneMinusCos = -std::expm1(std::log1p(-u1) / (n + 1.0f));
    float cosTheta = 1.0f - oneMinusCos;
    float sinTheta = std::sqrt(std::max(0.0f, oneMinusCos * (2.0f - oneMinusCos)));
    float s, c;
    sinCos2Pi(u2, s, c);
    return {sinTheta * c, sinTheta * s, cosTheta};
}
inline float powerCosinePdf(float n, float cosTheta) { return cosTheta > 0 ? (n + 1.0f) * kInv2Pi * std::pow(cosTheta, n) : 0.0f; }

// Uniform point on a triangle, as barycentrics (b0, b1) (Heitz 2019 is more uniform;
// this is the square-root warp of pbrt-v3 and Osada et al. 2002).
inline void sampleUniformTriangle(float u1, float u2, float& b0, float& b1) {
    float su = std::sqrt(u1);
    b0 = 1.0f - su;
    b1 = u2 * su;
}

// Solid-angle density at `from` of the direction to `to`, as area density at `to`
// (Veach 1997, eq. 8.10: p_A = p_sigma |cos theta_to| / d^2; normal n at `to`; the cosine
// is left out for points not on a surface, such as the lens).
inline float solidAngleToArea(float pdfSa, Vec3 from, Vec3 to, Vec3 n, bool onSurface) {
    Vec3 d = to - from;
    float d2 = lengthSquared(d);
    if (!(d2 > 0)) return 0.0f;
    float c = onSurface ? std::fabs(dot(n, d)) / std::sqrt(d2) : 1.0f;
    return pdfSa * c / d2;
}

// Power heuristic with exponent beta (Veach 1997, eq. 9.13); beta = 1 is the balance heuristic.
inline float powerHeuristic(float pdfA, float pdfB, float beta = 2.0f) {
    if (pdfA <= 0) return 0.0f;
    if (!(pdfB > 0)) return 1.0f;
    float r = pdfB / pdfA;  // ratio form: no overflow for large pdfs
    if (beta == 2.0f) return 1.0f / (1.0f + r * r);
    return 1.0f / (1.0f + std::pow(r, beta));
}
// Power heuristic weight of strategy i among n strategies (one sample each):
// pdfs[i]^beta / sum_j pdfs[j]^beta, in ratio form as above.
inline float powerHeuristicN(const float* pdfs, int n, int i, float beta = 2.0f) {
    if (!(pdfs[i] > 0)) return 0.0f;
    float sum = 0;
    for (int j = 0; j < n; ++j) {
        if (!(pdfs[j] > 0)) continue;
        float r = pdfs[j] / pdfs[i];
        sum += beta == 2.0f ? r * r : std::pow(r, beta);
    }
    return 1.0f / sum;
}

}  // namespace wmlt
