// Spectral kernels (spectral.h): the RGB-to-spectrum table's lookup, the CIE functions at a
// wavelength.
#include "kernels/spectral.h"

extern "C" {
extern const float wmlt_rgb_sigmoid_srgb[];  // generated: rgb_sigmoid_srgb.cpp (.incbin)
extern const float wmlt_rgb_sigmoid_srgb_end[];
}

namespace wmlt {

namespace {

// The integral of a function linear between 5 nm samples (the trapezoid rule is exact).
double integralOf(const double* t, int n) {
    double s = 0;
    for (int i = 0; i + 1 < n; ++i) s += 2.5 * (t[i] + t[i + 1]);
    return s;
}

struct ZNodes {
    float z[kSigmoidTableRes];
    ZNodes() {
        for (int i = 0; i < kSigmoidTableRes; ++i) z[i] = float(sigmoidTableZ(i));
    }
};

}  // namespace

SigmoidPoly sigmoidPolyOfRgb(Vec3 in) {
    const float rgb[3] = {std::clamp(in.x, 0.0f, 1.0f), std::clamp(in.y, 0.0f, 1.0f), std::clamp(in.z, 0.0f, 1.0f)};
    if (rgb[0] == rgb[1] && rgb[1] == rgb[2]) {  // a grey: S(c2) = v exactly
        const float v = rgb[0];
        SigmoidPoly c;
        c.c2 = v <= 0 ? -INFINITY : v >= 1 ? INFINITY : (v - 0.5f) / std::sqrt(v * (1.0f - v));
        return c;
    }
    constexpr int res = kSigmoidTableRes;
    const int l = rgb[0] >= rgb[1] ? (rgb[0] >= rgb[2] ? 0 : 2) : (rgb[1] >= rgb[2] ? 1 : 2);
    const float z = rgb[l];
    const float x = rgb[(l + 1) % 3] * float(res - 1) / z, y = rgb[(l + 2) % 3] * float(res - 1) / z;
    static const ZNodes nodes;
    const int zi = int(std::upper_bound(nodes.z, nodes.z + res, z) - nodes.z) - 1;
    const int i = std::clamp(zi, 0, res - 2), xi = std::min(int(x), res - 2), yi = std::min(int(y), res - 2);
    const float fz = std::clamp((z - nodes.z[i]) / (nodes.z[i + 1] - nodes.z[i]), 0.0f, 1.0f), fx = x - float(xi), fy = y - float(yi);
    auto at = [&](int di, int dj, int dk, int m) {
        return wmlt_rgb_sigmoid_srgb[((size_t(l) * res + size_t(i + di)) * res * res + size_t(yi + dj) * res + size_t(xi + dk)) * 3 + size_t(m)];
    };
    float c[3];
    for (int m = 0; m < 3; ++m) {
        auto lerp = [](float a, float b, float t) { return (1 - t) * a + t * b; };
        const float c00 = lerp(at(0, 0, 0, m), at(0, 0, 1, m), fx), c01 = lerp(at(0, 1, 0, m), at(0, 1, 1, m), fx);
        const float c10 = lerp(at(1, 0, 0, m), at(1, 0, 1, m), fx), c11 = lerp(at(1, 1, 0, m), at(1, 1, 1, m), fx);
        c[m] = lerp(lerp(c00, c01, fy), lerp(c10, c11, fy), fz);
    }
    SigmoidPoly p;
    p.c0 = c[0];
    p.c1 = c[1];
    p.c2 = c[2];
    return p;
}

UnboundedSpectrum unboundedSpectrumOfRgb(Vec3 rgb) {
    UnboundedSpectrum s;
    const float m = std::max({rgb.x, rgb.y, rgb.z});
    s.scale = 2 * m;
    s.poly = sigmoidPolyOfRgb(s.scale > 0 ? rgb * (1.0f / s.scale) : Vec3(0.0f, 0.0f, 0.0f));
    return s;
}

Vec3 rgbIlluminantAt(Vec3 rgb, const Wavelengths& w) {
    const UnboundedSpectrum s = unboundedSpectrumOfRgb(rgb);
    return sigmoidPolyAt(s.poly, w) * s.scale * Vec3(srgbIlluminant(w.lambda[0]), srgbIlluminant(w.lambda[1]), srgbIlluminant(w.lambda[2]));
}

Vec3 cieMatching(float lambda) {
    return Vec3(float(cieTableAt(cie::kXyz[0], 95, 360, lambda)), float(cieTableAt(cie::kXyz[1], 95, 360, lambda)),
                float(cieTableAt(cie::kXyz[2], 95, 360, lambda)));
}

double cieYIntegral() {
    static const double y = integralOf(cie::kXyz[1], 95);
    return y;
}

namespace {
float srgbIlluminantExact(float lambda) {
    // integral over 360..830 nm of D65 y-bar (both linear between 5 nm samples: Simpson's rule
    // on each 5 nm interval is exact for the product, a quadratic there).
    static const double scale = [] {
        double s = 0;
        for (int i = 0; i + 1 < 95; ++i) {
            const double l0 = 360 + 5.0 * i, l1 = l0 + 5, lm = l0 + 2.5;
            auto f = [](double l) { return cieTableAt(cie::kD65[0], 107, 300, l) * cieTableAt(cie::kXyz[1], 95, 360, l); };
            s += 5.0 / 6.0 * (f(l0) + 4 * f(lm) + f(l1));
        }
        return cieYIntegral() / s;
    }();
    return float(cieTableAt(cie::kD65[0], 107, 300, lambda) * scale);
}
}  // namespace

float srgbIlluminant(float lambda) {
    // D65 is linear between its 5 nm samples: tabulated every 1 nm (exact at 5 nm, the nodes
    // between on the same lines), made once
    static const DenseSpectrum d = [] {
        DenseSpectrum t;
        for (int i = 0; i < DenseSpectrum::kSamples; ++i) t.v[i] = srgbIlluminantExact(kLambdaMin + float(i));
        return t;
    }();
    return d.at(lambda);
}

namespace {
struct SrgbSpectral {
    double white[3], toRgb[3][3];
    SrgbSpectral() {  // the white: the integral of D65 cmf / that of D65 y-bar (Simpson per 5 nm: exact)
        double s[3] = {0, 0, 0};
        for (int i = 0; i + 1 < 95; ++i)
            for (int k = 0; k < 3; ++k) {
                auto f = [k](double l) { return cieTableAt(cie::kD65[0], 107, 300, l) * cieTableAt(cie::kXyz[k], 95, 360, l); };
                const double l0 = 360 + 5.0 * i;
                s[k] += 5.0 / 6.0 * (f(l0) + 4 * f(l0 + 2.5) + f(l0 + 5));
            }
        for (int k = 0; k < 3; ++k) white[k] = s[k] / s[1];
        xyzToSrgbMatrix(white, toRgb);
    }
};
const SrgbSpectral& srgbSpectral() {
    static const SrgbSpectral s;
    return s;
}
}  // namespace

Vec3 srgbWhiteXyz() {
    const SrgbSpectral& s = srgbSpectral();
    return Vec3(float(s.white[0]), float(s.white[1]), float(s.white[2]));
}

Vec3 xyzToSrgb(Vec3 c) {
    const auto& m = srgbSpectral().toRgb;
    return Vec3(float(m[0][0] * c.x + m[0][1] * c.y + m[0][2] * c.z), float(m[1][0] * c.x + m[1][1] * c.y + m[1][2] * c.z),
                float(m[2][0] * c.x + m[2][1] * c.y + m[2][2] * c.z));
}

}  // namespace wmlt
