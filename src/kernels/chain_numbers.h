// The numbers of a Markov chain's proposal (MMLT's and PSSMLT's stages), all hashed from
// the proposal's key: coordinate d's fresh value (a large step's, a pool sample's) at
// dimension 2 + 2 d, its small step's standard normal number at 3 + 2 d (dimensions 0 and 1:
// the step kind and the acceptance draw, mmlt_stages.cpp; 2^30, above every coordinate's:
// whether a small step is a film step), the lazy small step of a stored coordinate
// (mutation.h), and a film step's move of the raster point.
#pragma once
#include <cstdint>

#include "kernels/gaussian.h"
#include "kernels/mutation.h"
#include "kernels/rng.h"

namespace wmlt {

constexpr uint32_t kDimLarge = 0, kDimAccept = 1, kDimFilmStep = 1u << 30;
inline float poolCoordinate(uint64_t key, uint32_t d) { return sampleDimension(key, 2 + 2 * d); }
inline uint32_t dimNormal(uint32_t d) { return 3 + 2 * d; }

// Coordinate d's small step in proposal n from its stored (value, lastModified) and the
// chain's last accepted large step (sigma: the step's size); the fresh value is drawn only
// when it is read.
inline float smallStepOf(uint64_t key, uint32_t d, float value, uint32_t lastModified, uint32_t lastLarge, uint32_t n,
                         float sigma = kSmallStepSigma) {
    const float uFresh = lastModified < lastLarge ? poolCoordinate(key, d) : 0.0f;
    return proposeCoordinate(value, lastModified, lastLarge, n, false, sigma, uFresh, standardNormal(key, dimNormal(d)));
}

// A film step (MMLT's lever, RenderOptions::filmSteps) moves the raster point alone, by
// kFilmStepScale small steps' sigma: coordinate d (one of the two raster numbers, up to date:
// the state reads it) takes value + kFilmStepScale sigma z, wrapped, z its small step's
// normal number. Symmetric, as a small step is; the other coordinates keep their values.
constexpr float kFilmStepScale = 3.0f;
inline float filmStepOf(uint64_t key, uint32_t d, float value, float sigma) {
    return wrapUnit(value + kFilmStepScale * sigma * standardNormal(key, dimNormal(d)));
}

}  // namespace wmlt
