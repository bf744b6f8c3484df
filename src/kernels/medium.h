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
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "kernels/spectral.h"
#include "wavemmlt/math.h"

namespace wmlt {

// One voxel of an RGB grid in a spectral render (SpectralScene, made once per render): its
// colour's spectrum (kernels/spectral.h; a bounded one has scale 1), at the wavelengths whose
// positions in [360, 830] nm, mapped to [0, 1], are t.
inline Vec3 voxelAt(const UnboundedSpectrum& v, Vec3 t) {
    return Vec3(sigmoidPolyAtT(v.poly, t.x), sigmoidPolyAtT(v.poly, t.y), sigmoidPolyAtT(v.poly, t.z)) * v.scale;
}

// A medium as the stages read it: extinction and scattering coefficients per unit length,
// and the phase function's g; a heterogeneous one (density non-null) times the density grid
// at the point (MediumDesc), its majorant the largest density times the largest sigma_t.
struct Medium {
    Vec3 sigmaT{0.0f}, sigmaS{0.0f};
    float g = 0;
    const float* density = nullptr;                           // a density grid, or
    const Vec3 *gridSigmaA = nullptr, *gridSigmaS = nullptr;  // RGB coefficient grids
    int nx = 0, ny = 0, nz = 0;                               // > 0: heterogeneous
    Affine worldToGrid;
    bool clampEdges = false;
    float majorant = 0;          // over the whole grid
    float majorantScale = 1.0f;  // the majorant grid's cells times this (a spectral render's coefficients)
    // The majorant grid: mx x my x mz cells over the unit cube (x fastest), each the largest
    // sigma_t of any point in it (made with the scene: scene.cpp, buildMajorants); the
    // tracking walks it cell by cell.
    const float* majorants = nullptr;
    int mx = 0, my = 0, mz = 0;
    // Emission (MediumDesc::Le): the source term is sigma_a Le, Le constant or per voxel.
    bool emissive = false;
    Vec3 Le{0.0f};
    const Vec3* gridLe = nullptr;
    const Vec3* gridAlbedo = nullptr;  // a density grid's albedo per voxel: sigma_s = albedo sigma_t
    // A spectral render's copy (SpectralScene::medium, per path segment): the RGB grids above
    // as spectra per voxel, read at the path's wavelengths (lambdaT: each one's position in
    // [360, 830] nm, mapped to [0, 1]) instead of the RGB (null: the RGB grids, or none);
    // the emission's times the colour space's illuminant there (illuminant).
    const UnboundedSpectrum *specSigmaA = nullptr, *specSigmaS = nullptr, *specAlbedo = nullptr, *specLe = nullptr;
    Vec3 lambdaT{0.0f}, illuminant{0.0f};
};

// Calls f(ta, tb, majorant) for the majorant grid's cells along the ray go + t gd (grid
// space) over [t0, t1], in order; f returns false to stop (3D DDA, Amanatides and Woo 1987).
template <class F>
inline void walkMajorants(const Medium& m, Vec3 go, Vec3 gd, float t0, float t1, F&& f) {
    const int res[3] = {m.mx, m.my, m.mz};
    const Vec3 p0 = go + gd * t0;
    int cell[3], step[3];
    float tNext[3], tDelta[3];
    for (int a = 0; a < 3; ++a) {
        cell[a] = std::clamp(int(p0[a] * float(res[a])), 0, res[a] - 1);
        if (gd[a] == 0) {
            step[a] = 0, tNext[a] = INFINITY, tDelta[a] = INFINITY;
            continue;
        }
        step[a] = gd[a] > 0 ? 1 : -1;
        const float edge = float(cell[a] + (step[a] > 0 ? 1 : 0)) / float(res[a]);
        tNext[a] = t0 + (edge - p0[a]) / gd[a];
        tDelta[a] = 1.0f / (float(res[a]) * std::fabs(gd[a]));
    }
    float t = t0;
    for (;;) {
        const int a = tNext[0] < tNext[1] ? (tNext[0] < tNext[2] ? 0 : 2) : (tNext[1] < tNext[2] ? 1 : 2);
        const float tEnd = std::min(tNext[a], t1);
        const float maj = m.majorants[(size_t(cell[2]) * size_t(m.my) + size_t(cell[1])) * size_t(m.mx) + size_t(cell[0])] * m.majorantScale;
        if (tEnd > t && !f(t, tEnd, maj)) return;
        if (!(tEnd < t1)) return;
        t = tEnd;
        cell[a] += step[a];
        if (cell[a] < 0 || cell[a] >= res[a]) return;
        tNext[a] += tDelta[a];
    }
}

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

// The density with which sampleFreePath takes a segment of length d that ends at a
// scattering event (inMedium: p(d) above) or passes it (P), for BPT's MIS weights
// (bidirectional media, docs/media.md). A grid medium's tracking density has no closed
// form: its segments weigh 1 there, the same for every strategy (the weights still sum to
// one; they only lose the free-path term).
inline float freePathDensity(const Medium& m, float d, bool inMedium) {
    if (m.nx != 0) return 1.0f;
    const Vec3 T = transmittance(m, d);
    const Vec3 p = inMedium ? m.sigmaT * T : T;
    return (p.x + p.y + p.z) * (1.0f / 3.0f);
}

// ---- Heterogeneous media: a density grid, tracked against its majorant ----
// (Woodcock's delta tracking as spectral tracking, Kutz et al. 2017; ratio tracking for
// transmittance, Novak et al. 2014; both walk the majorant grid cell by cell.) Their random numbers come from a stream seeded by the
// caller (a hash of the sample's key, the bounce and the segment), as many as the tracking
// takes.

// SplitMix64 (Steele et al. 2014) from a seed.
struct MediumRng {
    uint64_t s;
    explicit MediumRng(uint64_t seed) : s(seed) {}
    float operator()() {
        s += 0x9e3779b97f4a7c15ULL;
        uint64_t z = s;
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
        z ^= z >> 31;
        return float(z >> 40) * 0x1p-24f;  // [0, 1)
    }
};

// A grid's value at q in grid space (the unit cube): trilinear between voxel centres, T
// float or Vec3, values[i] for voxel i (0 outside the cube unless m.clampEdges).
// (gridLookupBy: voxel i's value is fetch(i).)
template <class T, class Fetch>
inline T gridLookupBy(const Medium& m, Vec3 q, Fetch&& fetch) {
    const float fx = q.x * float(m.nx) - 0.5f, fy = q.y * float(m.ny) - 0.5f, fz = q.z * float(m.nz) - 0.5f;
    const float x0 = std::floor(fx), y0 = std::floor(fy), z0 = std::floor(fz);
    const float tx = fx - x0, ty = fy - y0, tz = fz - z0;
    auto at = [&](int x, int y, int z) {
        if (m.clampEdges) {
            x = std::clamp(x, 0, m.nx - 1), y = std::clamp(y, 0, m.ny - 1), z = std::clamp(z, 0, m.nz - 1);
        } else if (x < 0 || y < 0 || z < 0 || x >= m.nx || y >= m.ny || z >= m.nz) {
            return T(0.0f);
        }
        return T(fetch((size_t(z) * size_t(m.ny) + size_t(y)) * size_t(m.nx) + size_t(x)));
    };
    const int ix = int(x0), iy = int(y0), iz = int(z0);
    auto lerp = [](float t, T a, T b) { return a + (b - a) * t; };
    const T c00 = lerp(tx, at(ix, iy, iz), at(ix + 1, iy, iz)), c10 = lerp(tx, at(ix, iy + 1, iz), at(ix + 1, iy + 1, iz));
    const T c01 = lerp(tx, at(ix, iy, iz + 1), at(ix + 1, iy, iz + 1));
    const T c11 = lerp(tx, at(ix, iy + 1, iz + 1), at(ix + 1, iy + 1, iz + 1));
    return lerp(tz, lerp(ty, c00, c10), lerp(ty, c01, c11));
}
template <class T>
inline T gridLookup(const Medium& m, const T* values, Vec3 q) {
    return gridLookupBy<T>(m, q, [values](size_t i) { return values[i]; });
}
// A spectral grid (voxelAt) at the medium's wavelengths, interpolated as pbrt-v4's
// RGBGridMedium does: each voxel's spectrum at the wavelengths, then trilinearly.
inline Vec3 spectralGridLookup(const Medium& m, const UnboundedSpectrum* values, Vec3 q) {
    return gridLookupBy<Vec3>(m, q, [&](size_t i) { return voxelAt(values[i], m.lambdaT); });
}
inline float gridDensity(const Medium& m, Vec3 q) { return gridLookup(m, m.density, q); }

// A heterogeneous medium's sigma_t and sigma_s at q in grid space.
inline void gridCoefficients(const Medium& m, Vec3 q, Vec3& sigmaT, Vec3& sigmaS) {
    if (m.density) {
        const float d = gridDensity(m, q);
        sigmaT = m.sigmaT * d;
        if (m.specAlbedo) sigmaS = sigmaT * spectralGridLookup(m, m.specAlbedo, q);
        else sigmaS = m.gridAlbedo ? sigmaT * gridLookup(m, m.gridAlbedo, q) : m.sigmaS * d;
        return;
    }
    if (m.specSigmaS) {
        sigmaS = spectralGridLookup(m, m.specSigmaS, q);
        sigmaT = spectralGridLookup(m, m.specSigmaA, q) + sigmaS;
        return;
    }
    sigmaS = gridLookup(m, m.gridSigmaS, q);
    sigmaT = gridLookup(m, m.gridSigmaA, q) + sigmaS;
}

// The ray o + t d (world) in grid space, clipped to the unit cube and to [0, tMax]: its
// origin and direction there and [t0, t1]; false when it misses the cube.
inline bool gridSpan(const Medium& m, Vec3 o, Vec3 d, float tMax, Vec3& go, Vec3& gd, float& t0, float& t1) {
    go = m.worldToGrid.point(o);
    gd = m.worldToGrid.vector(d);
    t0 = 0;
    t1 = tMax;
    for (int a = 0; a < 3; ++a) {
        const float inv = 1.0f / gd[a];
        float tn = (0.0f - go[a]) * inv, tf = (1.0f - go[a]) * inv;
        if (tn > tf) std::swap(tn, tf);
        if (std::isnan(tn)) tn = -INFINITY;  // parallel to the slab: inside or not by go
        if (std::isnan(tf)) tf = INFINITY;
        if (gd[a] == 0 && (go[a] < 0 || go[a] > 1)) return false;
        t0 = std::max(t0, tn);
        t1 = std::min(t1, tf);
    }
    return t0 < t1;
}

constexpr int kMaxNullCollisions = 1 << 20;  // past it a path is taken as absorbed

// Calls f(t, majorant, sigma_t, sigma_s) at each tentative collision along [t0, t1] of the ray
// go + t gd in grid space, at the rate of each majorant cell it crosses (free paths are
// memoryless: a new start at each cell), until f returns false; returns false when f stopped
// it or after kMaxNullCollisions collisions.
template <class F>
inline bool forEachCollision(const Medium& m, Vec3 go, Vec3 gd, float t0, float t1, MediumRng& rng, F&& f) {
    int collisions = 0;
    bool completed = true;
    walkMajorants(m, go, gd, t0, t1, [&](float ta, float tb, float maj) {
        if (!(maj > 0)) return true;
        const float inv = 1.0f / maj;
        for (float t = ta;;) {
            t -= std::log1p(-rng()) * inv;
            if (!(t < tb)) return true;
            Vec3 sT, sS;
            gridCoefficients(m, go + gd * t, sT, sS);
            if (++collisions > kMaxNullCollisions || !f(t, maj, sT, sS)) {
                completed = false;
                return false;
            }
        }
    });
    return completed;
}

// A free-path sample in a grid medium along [0, tMax]: at each tentative collision scatter
// with probability P_s = mean(sigma_s w) / mean((sigma_s + sigma_n) w) (w the segment's
// weight so far, sigma_n = majorant - sigma_t per channel), the weight taking
// sigma_s / (majorant P_s), else go on with sigma_n / (majorant (1 - P_s)): unbiased per
// channel, absorption in the weights.
inline FreePath sampleGridFreePath(const Medium& m, Vec3 o, Vec3 d, float tMax, MediumRng& rng) {
    FreePath r;
    r.t = tMax;
    r.weight = Vec3(1.0f);
    Vec3 go, gd;
    float t0, t1;
    if (!(m.majorant > 0) || !gridSpan(m, o, d, tMax, go, gd, t0, t1)) return r;
    Vec3 w(1.0f);
    const bool passed = forEachCollision(m, go, gd, t0, t1, rng, [&](float t, float maj, Vec3 sT, Vec3 sS) {
        const float inv = 1.0f / maj;
        const Vec3 sN = vmax(Vec3(maj) - sT, Vec3(0.0f));
        const float ps = sS.x * w.x + sS.y * w.y + sS.z * w.z, pn = sN.x * w.x + sN.y * w.y + sN.z * w.z;
        if (!(ps + pn > 0)) return false;  // only absorption here: the path ends
        const float Ps = ps / (ps + pn);
        if (rng() < Ps) {
            r.t = t;
            r.scattered = true;
            w = w * sS * (inv / Ps);
            return false;
        }
        w = w * sN * (inv / (1.0f - Ps));
        return true;
    });
    r.weight = passed || r.scattered ? w : Vec3(0.0f);
    return r;
}

// Transmittance through a grid medium along [0, tMax] by ratio tracking: the product of
// (1 - sigma_t / majorant) at the tentative collisions (unbiased).
inline Vec3 gridTransmittance(const Medium& m, Vec3 o, Vec3 d, float tMax, MediumRng& rng) {
    Vec3 go, gd;
    float t0, t1;
    if (!(m.majorant > 0) || !gridSpan(m, o, d, tMax, go, gd, t0, t1)) return Vec3(1.0f);
    Vec3 T(1.0f);
    const bool passed = forEachCollision(m, go, gd, t0, t1, rng, [&](float, float maj, Vec3 sT, Vec3) {
        T = T * vmax(Vec3(1.0f) - sT * (1.0f / maj), Vec3(0.0f));
        return !isBlack(T);
    });
    return passed ? T : Vec3(0.0f);
}

// The radiance emitted along [0, tMax] of the ray o + t d that reaches o:
//   E = int_0^tMax T(t) sigma_a(t) Le(t) dt,
// homogeneous: sigma_a Le (1 - exp(-sigma_t tMax)) / sigma_t per channel, exactly; a grid:
// the collision estimator sum_i T_i sigma_a(t_i) Le(t_i) / majorant over the tracking's
// tentative collisions, T_i ratio tracking's transmittance up to them (unbiased).
inline Vec3 emissionAlong(const Medium& m, Vec3 o, Vec3 d, float tMax, MediumRng& rng) {
    if (m.nx == 0) {
        auto one = [&](float sA, float sT, float Le) { return sT > 0 ? sA * Le * (std::isinf(tMax) ? 1.0f : -std::expm1(-sT * tMax)) / sT : 0.0f; };
        const Vec3 sA = m.sigmaT - m.sigmaS;
        return Vec3(one(sA.x, m.sigmaT.x, m.Le.x), one(sA.y, m.sigmaT.y, m.Le.y), one(sA.z, m.sigmaT.z, m.Le.z));
    }
    Vec3 go, gd;
    float t0, t1;
    if (!(m.majorant > 0) || !gridSpan(m, o, d, tMax, go, gd, t0, t1)) return Vec3(0.0f);
    Vec3 T(1.0f), E(0.0f);
    forEachCollision(m, go, gd, t0, t1, rng, [&](float t, float maj, Vec3 sT, Vec3 sS) {
        const Vec3 Le = m.specLe   ? spectralGridLookup(m, m.specLe, go + gd * t) * m.illuminant
                        : m.gridLe ? gridLookup(m, m.gridLe, go + gd * t)
                                   : m.Le;
        E = E + T * vmax(sT - sS, Vec3(0.0f)) * Le * (1.0f / maj);
        T = T * vmax(Vec3(1.0f) - sT * (1.0f / maj), Vec3(0.0f));
        return !isBlack(T);
    });
    return E;
}

// Either kind: the free-path sample (homogeneous: from u; a grid: from the stream seeded
// by seed) and the transmittance.
inline FreePath sampleMediumFreePath(const Medium& m, Vec3 o, Vec3 d, float tMax, float u, uint64_t seed) {
    if (m.nx == 0) return sampleFreePath(m, tMax, u);
    MediumRng rng(seed);
    return sampleGridFreePath(m, o, d, tMax, rng);
}
inline Vec3 mediumTransmittance(const Medium& m, Vec3 o, Vec3 d, float tMax, uint64_t seed) {
    if (m.nx == 0) return transmittance(m, tMax);
    MediumRng rng(seed);
    return gridTransmittance(m, o, d, tMax, rng);
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
