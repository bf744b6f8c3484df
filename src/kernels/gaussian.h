// Standard normal numbers by the ziggurat method (Marsaglia and Tsang 2000, "The Ziggurat
// Method for Generating Random Variables", J. Stat. Softw. 5(8)) on counter-based bits, for
// MMLT's small step. The area under f(x) = exp(-x^2 / 2), x >= 0, is cut into 128 layers of
// equal area v: layer i is the rectangle [0, x_i) x [f(x_i), f(x_{i+1})) (layer 0: the
// base strip [0, x_0) x [0, f(r)) whose part beyond r stands for the tail). A draw hashes
// (key, dim) once: 7 bits pick the layer, 1 bit the sign, 53 bits the point x = u x_i; if
// x < x_{i+1} the point is under the curve and x is returned (97.2% of draws). Else
// gaussianSlow takes further hashes of (key, dim, attempt): the wedge test, or the tail
// beyond r by Marsaglia's method (1964). The result has exactly the normal distribution
// (to double rounding), with a cost of one hash and one table lookup in most draws; it
// replaced the inverse CDF (a logarithm and a polynomial per number) in the small step.
#pragma once
#include <cstdint>
#include <cstring>

#include "kernels/rng.h"

namespace wmlt {

struct ZigguratTables {
    static constexpr int kLayers = 128;
    double x[kLayers + 1];  // x[0] = v / f(r), x[1] = r, ..., x[128] = 0
    double f[kLayers + 1];  // f(x[i])
    double inner[kLayers];  // x[i + 1] / x[i]: u below it is inside the curve
};
extern const ZigguratTables kZiggurat;
constexpr double kZigguratR = 3.442619855899;       // x_1 (Marsaglia and Tsang, 128 layers)
constexpr double kZigguratV = 9.91256303526217e-3;  // every layer's area

// The bits of draw `attempt` of dimension dim of a key (a stream apart from sampleDimension's).
inline uint64_t normalBits(uint64_t key, uint32_t dim, uint32_t attempt) {
    return mix64(key ^ (0xd1b54a32d192ed03ull * (uint64_t(dim) + 1)) ^ (0x9e3779b97f4a7c15ull * (uint64_t(attempt) + 1)));
}

// |z| after a first draw (layer, u) that fell outside its layer's rectangle (gaussian.cpp).
double gaussianSlow(uint64_t key, uint32_t dim, int layer, double u);

// |z| = m as a float with the sign bit 7 of h gives it: a flip of the float's sign bit,
// exact (rounding is symmetric), with no branch, so that loops of it vectorise.
inline float withNormalSign(uint64_t h, double m) {
    float f = float(m);
    uint32_t bits;
    std::memcpy(&bits, &f, sizeof bits);
    bits ^= uint32_t(h & 128) << 24;
    std::memcpy(&f, &bits, sizeof f);
    return f;
}

// A standard normal number, a pure function of (key, dim).
inline float standardNormal(uint64_t key, uint32_t dim) {
    const uint64_t h = normalBits(key, dim, 0);
    const int layer = int(h & 127);
    const double u = double(h >> 11) * 0x1p-53;
    const double m = u < kZiggurat.inner[layer] ? u * kZiggurat.x[layer] : gaussianSlow(key, dim, layer, u);
    return withNormalSign(h, m);
}

}  // namespace wmlt
