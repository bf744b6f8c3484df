// Warps from [0,1)^2 to directions and points, each with its pdf (pbrt-v4 ch. 2 and A.5).
#pragma once
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

// Concentric map of the unit square to the unit disc (Shirley and Chiu 1997).
inline void sampleConcentricDisk(float u1, float u2, float& x, float& y) {
    float a = 2.0f * u1 - 1.0f, b = 2.0f * u2 - 1.0f;
    if (a == 0 && b == 0) { x = y = 0; return; }
    float r, phi;
    if (std::fabs(a) > std::fabs(b)) { r = a; phi = (kPi / 4) * (b / a); }
    else { r = b; phi = kPi / 2 - (kPi / 4) * (a / b); }
    x = r * std::cos(phi);
    y = r * std::sin(phi);
}

// Cosine-weighted hemisphere around +z: pdf = cos(theta) / pi.
inline Vec3 sampleCosineHemisphere(float u1, float u2) {
    float x, y;
    sampleConcentricDisk(u1, u2, x, y);
    float z = std::sqrt(std::max(0.0f, 1.0f - x * x - y * y));
    return {x, y, z};
}
inline float cosineHemispherePdf(float cosTheta) { return cosTheta > 0 ? cosTheta * kInvPi : 0.0f; }

// Uniform direction on the unit sphere: pdf = 1 / (4 pi).
inline Vec3 sampleUniformSphere(float u1, float u2) {
    float z = 1.0f - 2.0f * u1;
    float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    float phi = 2.0f * kPi * u2;
    return {r * std::cos(phi), r * std::sin(phi), z};
}
constexpr float kUniformSpherePdf = 1.0f / (4.0f * kPi);

// Direction around +z with density (n + 1) / (2 pi) cos^n(theta) (Phong lobe).
inline Vec3 samplePowerCosine(float n, float u1, float u2) {
    // cos = (1 - u1)^(1/(n+1)); 1 - cos via expm1/log1p so that sin stays accurate when
    // cos rounds to 1 in float (large n).
    float oneMinusCos = -std::expm1(std::log1p(-u1) / (n + 1.0f));
    float cosTheta = 1.0f - oneMinusCos;
    float sinTheta = std::sqrt(std::max(0.0f, oneMinusCos * (2.0f - oneMinusCos)));
    float phi = 2.0f * kPi * u2;
    return {sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta};
}
inline float powerCosinePdf(float n, float cosTheta) {
    return cosTheta > 0 ? (n + 1.0f) * kInv2Pi * std::pow(cosTheta, n) : 0.0f;
}

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
