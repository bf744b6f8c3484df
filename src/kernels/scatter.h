// Matte scattering at every hit, in floats over arrays, for PT's flat loop (pt_stages.cpp,
// sampleBsdfs): per hit h, bit for bit what scatterHits and PT's bounce make of a
// cosine-weighted direction about the shading normal (matteSampleFrom: flipped to wo's
// side, pdf = |cos| / pi, f = Kd / pi), the throughput beta f |cos| / pdf, Russian roulette
// (survivesRoulette with scale 1) and the world direction of the next ray.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "kernels/sampling.h"

namespace wmlt {

// Over h < n: ns[3 h ..] the shading normal (the frame is made again from it,
// frameFromNormal: a loop reading the 36-byte frames does not vectorise), wo[3 h ..] the
// unit direction towards the previous vertex (world), (lx, ly, lz)[h] the cosine-weighted
// direction (sampleCosineHemispheres), kd[3 h ..] the Kd, beta[3 h ..] the path's
// throughput; with Roulette, u[h] its roulette number (a template parameter: a load under
// a run-time condition kept the loop from vectorising, as did the key's hash in it). Out:
// nextBeta, dir[3 h ..] the next ray's direction, pdf[h] its density, ok[h] whether the
// path goes on (else the other outputs are unspecified). The loop vectorises with 64-byte
// vectors.
template <bool Roulette>
__attribute__((noinline)) void matteScatter(size_t n, const float* __restrict ns, const float* __restrict wo, const float* __restrict lx,
                                            const float* __restrict ly, const float* __restrict lz, const float* __restrict kd,
                                            const float* __restrict beta, const float* __restrict u, float* __restrict nextBeta,
                                            float* __restrict dir, float* __restrict pdf, uint32_t* __restrict ok) {
    for (size_t h = 0; h < n; ++h) {
        const float nx = ns[3 * h], ny = ns[3 * h + 1], nz = ns[3 * h + 2];
        const float woZ = wo[3 * h] * nx + wo[3 * h + 1] * ny + wo[3 * h + 2] * nz;
        const float z0 = lz[h];
        const float x = lx[h], y = ly[h], z = woZ < 0 ? -z0 : z0;  // matteSampleFrom
        const float cosI = std::fabs(z);
        const float p = cosI * kInvPi;
        const float fx = kd[3 * h] * kInvPi, fy = kd[3 * h + 1] * kInvPi, fz = kd[3 * h + 2] * kInvPi;
        const float k = cosI / p;
        float bx = beta[3 * h] * fx * k, by = beta[3 * h + 1] * fy * k, bz = beta[3 * h + 2] * fz * k;
        // (as integers: with bools and && the loop did not vectorise)
        uint32_t go = uint32_t(p > 0) & uint32_t(!(fx == 0 && fy == 0 && fz == 0));
        if constexpr (Roulette) {  // survivesRoulette(beta, 1, u): q = min(1, maxComponent(beta) / 1)
            const float q = std::min(1.0f, std::max(bx, std::max(by, bz)) / 1.0f);
            go = go & uint32_t(u[h] < q);
            const float r = 1.0f / q;
            bx = bx * r;
            by = by * r;
            bz = bz * r;
        }
        nextBeta[3 * h] = bx;
        nextBeta[3 * h + 1] = by;
        nextBeta[3 * h + 2] = bz;
        toWorldUnit(frameFromNormal(nx, ny, nz), x, y, z, dir[3 * h], dir[3 * h + 1], dir[3 * h + 2]);
        pdf[h] = p;
        ok[h] = go;
    }
}

}  // namespace wmlt
