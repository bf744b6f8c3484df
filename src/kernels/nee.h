// Next-event estimation at matte hits towards rectangle lights, in floats over arrays,
// for PT's flat loops (pt_stages.cpp, sampleLights). Per hit h, bit for bit
// what the per-hit code makes of the light sample (rectLightSamples: its point, unit
// direction wi and solid-angle pdf): f = Kd / pi |cos theta_i| (matteF), the power
// heuristic of the light's density against the matte pdf (Veach 1997, eq. 9.13, ratio
// form) and the unoccluded contribution L = beta f Le w / (pdf pmf) (pbrt-v4 13.4.2); the
// shadow ray from the offset origin (Scene::offsetRayOrigin) aimed at the light point.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "kernels/sampling.h"

namespace wmlt {

// The light's radiance and its choice pmf: one value for all hits (a scene's one light).
struct RectNeeConsts {
    float Lx, Ly, Lz, pmf;
};

// Over h < n: ns[3 h ..] the shading normal (its frame's n), wo[3 h ..] the unit direction
// towards the previous vertex, (wix, wiy, wiz)[h] the light sample's unit direction and
// pdf[h] its solid-angle density (where there is one: the caller reads only those hits'
// outputs), diffuse[3 h ..] the hit's Kd, beta[3 h ..] its path's throughput. Out: the
// contribution L[3 h ..] the shadow ray carries and send[h]: f is not black (else L is
// unspecified). Restrict parameters: the loop vectorises with 64-byte vectors.
// PerHit: each hit's light radiance Le[3 h ..] and choice pmf pmfs[h] (a scene of several
// lights) instead of c's (its one light; Le and pmfs are then not read).
template <bool PerHit>
__attribute__((noinline)) inline void matteNeeValuesOf(const RectNeeConsts c, const float* __restrict Le, const float* __restrict pmfs, size_t n,
                                                       const float* __restrict ns, const float* __restrict wo, const float* __restrict wix,
                                                       const float* __restrict wiy, const float* __restrict wiz, const float* __restrict pdf,
                                                       const float* __restrict diffuse, const float* __restrict beta, float* __restrict L,
                                                       uint32_t* __restrict send) {
    for (size_t h = 0; h < n; ++h) {
        const float Lx = PerHit ? Le[3 * h] : c.Lx, Ly = PerHit ? Le[3 * h + 1] : c.Ly, Lz = PerHit ? Le[3 * h + 2] : c.Lz;
        const float pmf = PerHit ? pmfs[h] : c.pmf;
        const float nx = ns[3 * h], ny = ns[3 * h + 1], nz = ns[3 * h + 2];
        // Frame::toLocal: (dot(v, s), dot(v, t), dot(v, n)); only the z's are needed.
        const float woZ = wo[3 * h] * nx + wo[3 * h + 1] * ny + wo[3 * h + 2] * nz;
        const float wiZ = wix[h] * nx + wiy[h] * ny + wiz[h] * nz;
        const bool same = woZ * wiZ > 0;  // sameHemisphere
        const float cosI = std::fabs(wiZ);
        // Kd read whether used or not: a load under the condition did not vectorise.
        const float kx = diffuse[3 * h], ky = diffuse[3 * h + 1], kz = diffuse[3 * h + 2];
        const float fx = same ? kx * kInvPi * cosI : 0.0f * cosI;
        const float fy = same ? ky * kInvPi * cosI : 0.0f * cosI;
        const float fz = same ? kz * kInvPi * cosI : 0.0f * cosI;
        const float lightPdf = pdf[h] * pmf;
        const float bsdfPdf = same ? cosI * kInvPi : 0.0f;  // mattePdf
        const float r = bsdfPdf / lightPdf;
        const float w = lightPdf <= 0 ? 0.0f : !(bsdfPdf > 0) ? 1.0f : 1.0f / (1.0f + r * r);  // powerHeuristic
        const float k = w / lightPdf;
        L[3 * h] = beta[3 * h] * fx * Lx * k;
        L[3 * h + 1] = beta[3 * h + 1] * fy * Ly * k;
        L[3 * h + 2] = beta[3 * h + 2] * fz * Lz * k;
        send[h] = fx == 0 && fy == 0 && fz == 0 ? 0u : 1u;
    }
}

// The shadow rays from the hits (p[3 h ..], geometric normal ng[3 h ..]) to the light
// points lp[3 h ..] in the unit directions (wix, wiy, wiz)[h]: the origin offset on wi's
// side (Scene::offsetRayOrigin with the scene's epsilonScale), the direction from it to the
// light point itself (the one from the surface point would pass beside it by up to the
// offset, into the light) and tfar just short of it.
__attribute__((noinline)) inline void shadowRaysTo(float epsilonScale, size_t n, const float* __restrict p, const float* __restrict ng,
                                                   const float* __restrict wix, const float* __restrict wiy, const float* __restrict wiz,
                                                   const float* __restrict lp, float* __restrict origin, float* __restrict dir,
                                                   float* __restrict tfar) {
    for (size_t h = 0; h < n; ++h) {
        const float px = p[3 * h], py = p[3 * h + 1], pz = p[3 * h + 2];
        const float nx = ng[3 * h], ny = ng[3 * h + 1], nz = ng[3 * h + 2];
        const float mag = std::max(std::max(std::fabs(px), std::fabs(py)), std::fabs(pz));
        const float eps = 2e-5f * mag + epsilonScale;
        const float side = nx * wix[h] + ny * wiy[h] + nz * wiz[h] >= 0 ? eps : -eps;  // p - n eps = p + n (-eps)
        const float ox = px + nx * side, oy = py + ny * side, oz = pz + nz * side;
        const float tx = lp[3 * h] - ox, ty = lp[3 * h + 1] - oy, tz = lp[3 * h + 2] - oz;
        const float dist = std::sqrt(tx * tx + ty * ty + tz * tz);
        const float rd = 1.0f / dist;  // normalize: a * (1 / |a|)
        origin[3 * h] = ox;
        origin[3 * h + 1] = oy;
        origin[3 * h + 2] = oz;
        dir[3 * h] = tx * rd;
        dir[3 * h + 1] = ty * rd;
        dir[3 * h + 2] = tz * rd;
        tfar[h] = dist * (1.0f - 1e-4f);
    }
}

}  // namespace wmlt
