// Homogeneous participating media (docs/media.md; pbrt-v4 11.1-11.3, 14.1): transmittance,
// free-path sampling with one-sample MIS over the RGB channels, and the Henyey-Greenstein
// phase function, which the wavefront runs as the BSDF of medium vertices (MaterialKind::
// Phase, in a frame whose z axis is wo).
//
// Free-path sampling (spectral MIS): a channel c is chosen uniformly and t drawn from
// sigma_t,c exp(-sigma_t,c t); the density over the three channels is
//   p(t) = (1/3) sum_c sigma_t,c exp(-sigma_t,c t)            (a scattering event at t < tMax),
//   P    = (1/3) sum_c exp(-sigma_t,c tMax)                     (no event before tMax),
// so the path's throughput takes sigma_s T(t) / p(t) at an event and T(tMax) / P past it:
// unbiased for every channel (each channel's estimator is a one-sample MIS of the three
// channels' samplers), and without the colour noise of sampling one channel alone.
#pragma once
#include <cmath>

#include "wavemmlt/math.h"

namespace wmlt {

// A medium as the stages read it: extinction and scattering coefficients per unit length,
// and the phase function's g.
struct Medium {
    Vec3 sigmaT{0.0f}, sigmaS{0.0f};
    float g = 0;
};

inline Vec3 expNeg(Vec3 v) { return Vec3(std::exp(-v.x), std::exp(-v.y), std::exp(-v.z)); }

// T = exp(-sigma_t d) per channel (d may be infinite: 0 where sigma_t > 0, 1 where 0).
inline Vec3 transmittance(const Medium& m, float d) {
    auto one = [&](float s) { return s > 0 ? std::exp(-s * d) : 1.0f; };
    return Vec3(one(m.sigmaT.x), one(m.sigmaT.y), one(m.sigmaT.z));
}

// A free-path sample along a segment of length tMax (INFINITY: unbounded): `scattered` with
// the event's distance t < tMax, or not (t = tMax); weight multiplies the throughput.
struct FreePath {
    float t = 0;
    Vec3 weight{0.0f};
    bool scattered = false;
};
inline FreePath sampleFreePath(const Medium& m, float tMax, float u) {
    FreePath r;
    const float u3 = u * 3.0f;
    const int c = u3 < 1.0f ? 0 : u3 < 2.0f ? 1 : 2;
    const float uc = std::min(u3 - float(c), 0.99999994f);
    const float sc = c == 0 ? m.sigmaT.x : c == 1 ? m.sigmaT.y : m.sigmaT.z;
    const float t = sc > 0 ? -std::log1p(-uc) / sc : INFINITY;
    if (t < tMax) {
        const Vec3 T = transmittance(m, t);
        const float pdf = (m.sigmaT.x * T.x + m.sigmaT.y * T.y + m.sigmaT.z * T.z) * (1.0f / 3.0f);
        r.t = t;
        r.scattered = true;
        r.weight = pdf > 0 ? m.sigmaS * T / pdf : Vec3(0.0f);
        return r;
    }
    const Vec3 T = transmittance(m, tMax);
    const float P = (T.x + T.y + T.z) * (1.0f / 3.0f);
    r.t = tMax;
    r.weight = P > 0 ? T / P : Vec3(0.0f);
    return r;
}

// Henyey-Greenstein (pbrt-v4's convention): cosTheta = dot(wo, wi), wo pointing back along
// the path, so g > 0 scatters forward (wi near -wo):
//   p = (1 - g^2) / (4 pi (1 + g^2 + 2 g cosTheta)^(3/2)).
inline float henyeyGreenstein(float cosTheta, float g) {
    const float denom = 1.0f + g * g + 2.0f * g * cosTheta;
    return (1.0f - g * g) / (4.0f * kPi * denom * std::sqrt(std::max(denom, 1e-12f)));
}
// cosTheta = dot(wo, wi) of a sample of p (inverting its cumulative distribution).
inline float sampleHenyeyGreensteinCos(float g, float u) {
    if (std::fabs(g) < 1e-3f) return 1.0f - 2.0f * u;
    const float s = (1.0f - g * g) / (1.0f + g - 2.0f * g * u);
    return std::clamp(-(1.0f + g * g - s * s) / (2.0f * g), -1.0f, 1.0f);
}

}  // namespace wmlt
