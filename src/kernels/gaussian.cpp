#include "kernels/gaussian.h"

#include <cmath>

namespace wmlt {

namespace {

double f(double x) { return std::exp(-0.5 * x * x); }

// The layers' right ends from the top of the tail down (Marsaglia and Tsang 2000, section
// 2): x_{i+1} = f^-1(v / x_i + f(x_i)).
ZigguratTables makeTables() {
    ZigguratTables t{};
    const int n = ZigguratTables::kLayers;
    t.x[0] = kZigguratV / f(kZigguratR);
    t.x[1] = kZigguratR;
    for (int i = 1; i < n - 1; ++i) t.x[i + 1] = std::sqrt(-2.0 * std::log(kZigguratV / t.x[i] + f(t.x[i])));
    t.x[n] = 0.0;
    for (int i = 0; i <= n; ++i) t.f[i] = f(t.x[i]);
    t.f[0] = 0.0;  // the base strip starts at y = 0 (its part beyond r is the tail)
    for (int i = 0; i < n; ++i) t.inner[i] = t.x[i + 1] / t.x[i];
    return t;
}

// A uniform number in (0, 1] from 32 bits (the tail takes logarithms).
double open01(uint32_t b) { return (double(b) + 1.0) * 0x1p-32; }

}  // namespace

const ZigguratTables kZiggurat = makeTables();

double gaussianSlow(uint64_t key, uint32_t dim, int layer, double u) {
    const ZigguratTables& z = kZiggurat;
    uint32_t attempt = 1;
    for (;;) {
        if (layer == 0) {  // beyond r: a = -ln(u1) / r, b = -ln(u2) until 2 b >= a^2
            for (;;) {
                const uint64_t h = normalBits(key, dim, attempt++);
                const double a = -std::log(open01(uint32_t(h))) / kZigguratR, b = -std::log(open01(uint32_t(h >> 32)));
                if (b + b >= a * a) return kZigguratR + a;
            }
        }
        // The wedge: (x, y) uniform in the layer's rectangle right of x_{i+1}; under the curve?
        const double x = u * z.x[layer];
        const double y = z.f[layer] + double(normalBits(key, dim, attempt++) >> 11) * 0x1p-53 * (z.f[layer + 1] - z.f[layer]);
        if (y < f(x)) return x;
        // Rejected: a new layer and point (the sign drawn first stays: it is independent).
        const uint64_t h = normalBits(key, dim, attempt++);
        layer = int(h & 127);
        u = double(h >> 11) * 0x1p-53;
        if (u < z.inner[layer]) return u * z.x[layer];
    }
}

}  // namespace wmlt
