// Spectral rendering's per-element functions (issue 45, docs/spectral.md): sampled
// wavelengths, RGB turned into smooth spectra, and a path's sampled radiance turned into XYZ.
//  - Wavelengths: kWavelengths (3) per path, carried in the colour channels of every Vec3
//    (docs/spectral.md: the RGB kernels are then the spectral ones), the first sampled from the visible-importance density
//    p(lambda) ~ sech^2(a (lambda - 538 nm)), a = 0.0072 / nm, on 360..830 nm (the density
//    pbrt-v4 uses), the others stratified from it in the density's CDF: u_i = frac(u + i / n).
//  - RGB to spectrum (Jakob and Hanika 2019, "A low-dimensional function space for efficient
//    spectral upsampling"): s(lambda) = S(c0 t^2 + c1 t + c2), S(x) = 1/2 + x / (2 sqrt(1 + x^2)),
//    t = (lambda - 360) / 470 (the table keeps the coefficients of t, not of nm: better
//    conditioned in float). The coefficients of an RGB in [0,1]^3 come from a table fitted at
//    build time (cmake/rgb_sigmoid_fit.cpp) from Debian's CIE tables: for each RGB on a grid,
//    the c whose spectrum, seen under the colour space's illuminant (sRGB: D65), has that RGB.
//    Bounded (reflectances): the table's spectrum. Unbounded (pbrt-v4's RGBUnboundedSpectrum):
//    m = max(rgb), 2m times the spectrum of rgb / 2m. Illuminant: the unbounded spectrum times
//    the colour space's illuminant, normalised so that its Y is 1.
//  - Dispersion: a glass's index from its Sellmeier coefficients (sellmeierEta).
//  - XYZ of a path's radiance L(lambda_i): the estimate (1/n) sum_i L_i cmf(lambda_i) / p_i,
//    over the integral of y-bar, so that a constant 1 has Y = 1 in expectation.
#pragma once
#include <algorithm>
#include <cmath>

#include "wavemmlt/math.h"

namespace wmlt {

constexpr int kWavelengths = 3;  // one per colour channel
constexpr float kLambdaMin = 360.0f, kLambdaMax = 830.0f;

// The dimension of a hashed sample's key (PT's, BPT's, LT's) its wavelengths' one number reads.
constexpr uint32_t kWavelengthDim = 0xfffffff0u;

// A path's wavelengths and their sampling densities (per nm).
struct Wavelengths {
    float lambda[kWavelengths];
    float pdf[kWavelengths];
};

namespace cie {
extern const double kXyz[3][95];   // x-bar, y-bar, z-bar at 360, 365, ..., 830 nm (generated: cie_tables.cpp)
extern const double kD65[1][107];  // D65 at 300, 305, ..., 830 nm
}  // namespace cie

// A table of n samples every 5 nm from lambda0 (the CIE tables), linear between them, 0
// outside.
inline double cieTableAt(const double* t, int n, double lambda0, double lambda) {
    const double x = (lambda - lambda0) / 5.0;
    if (!(x >= 0) || x > n - 1) return 0;
    const int i = std::min(int(x), n - 2);
    const double f = x - i;
    return t[i] * (1 - f) + t[i + 1] * f;
}

namespace spectral_detail {
constexpr double kA = 0.0072;      // 1 / nm
constexpr double kCentre = 538.0;  // nm
// tanh(a (lambda - centre)) at the range's ends: the unnormalised CDF's values.
inline double cdfLow() {
    static const double v = std::tanh(kA * (double(kLambdaMin) - kCentre));
    return v;
}
inline double cdfHigh() {
    static const double v = std::tanh(kA * (double(kLambdaMax) - kCentre));
    return v;
}
}  // namespace spectral_detail

// p(lambda) = a sech^2(a (lambda - 538)) / (tanh(a (830 - 538)) - tanh(a (360 - 538))).
inline float visibleWavelengthPdf(float lambda) {
    using namespace spectral_detail;
    if (!(lambda >= kLambdaMin && lambda <= kLambdaMax)) return 0.0f;
    const double ch = std::cosh(kA * (double(lambda) - kCentre));
    return float(kA / (ch * ch) / (cdfHigh() - cdfLow()));
}

// The inverse of the CDF: lambda = 538 + atanh(lo + u (hi - lo)) / a, in [360, 830].
inline float sampleVisibleWavelength(float u) {
    using namespace spectral_detail;
    const double lo = cdfLow(), hi = cdfHigh();
    const double l = kCentre + std::atanh(lo + double(u) * (hi - lo)) / kA;
    return float(std::clamp(l, double(kLambdaMin), double(kLambdaMax)));
}

// The path's wavelengths from one number u in [0, 1); each density from the CDF's value
// t = tanh(a (lambda - 538)) the inversion passes through: p = a (1 - t^2) / (hi - lo).
inline Wavelengths sampleWavelengths(float u) {
    using namespace spectral_detail;
    const double lo = cdfLow(), hi = cdfHigh();
    Wavelengths w;
    for (int i = 0; i < kWavelengths; ++i) {
        float ui = u + float(i) / float(kWavelengths);
        if (ui >= 1.0f) ui -= 1.0f;
        const float t = float(lo + double(ui) * (hi - lo));
        const float at = 0.5f * std::log((1 + t) / (1 - t));  // atanh(t), in float (one log)
        w.lambda[i] = std::clamp(float(kCentre) + at / float(kA), kLambdaMin, kLambdaMax);
        w.pdf[i] = float(kA * (1 - double(t) * double(t)) / (hi - lo));
    }
    return w;
}

// Keeps only the hero wavelength (a dispersive refraction: the others would leave in other
// directions): the others' densities 0, the hero's divided by their count, so that the XYZ
// estimate is the hero's alone (pbrt-v4's TerminateSecondary). Once per path.
inline void terminateSecondary(Wavelengths& w) {
    if (!(w.pdf[1] > 0)) return;
    for (int i = 1; i < kWavelengths; ++i) w.pdf[i] = 0;
    w.pdf[0] /= float(kWavelengths);
}

// s(lambda) = S(c0 t^2 + c1 t + c2), t = (lambda - 360) / 470.
struct SigmoidPoly {
    float c0 = 0, c1 = 0, c2 = 0;
};

inline float sigmoid(float x) {
    if (std::isinf(x)) return x > 0 ? 1.0f : 0.0f;
    return 0.5f + x / (2.0f * std::sqrt(1.0f + x * x));
}

// (At t, the wavelength's position in [360, 830] nm mapped to [0, 1].)
inline float sigmoidPolyAtT(SigmoidPoly c, float t) { return sigmoid((c.c0 * t + c.c1) * t + c.c2); }
inline float sigmoidPolyAt(SigmoidPoly c, float lambda) { return sigmoidPolyAtT(c, (lambda - kLambdaMin) / (kLambdaMax - kLambdaMin)); }

// The table's grid: res nodes per axis; the nodes of z = max(rgb) crowd towards 0 and 1,
// z_i = smoothstep(smoothstep(i / (res - 1))).
constexpr int kSigmoidTableRes = 64;
inline double sigmoidTableZ(int i) {
    auto smooth = [](double x) { return x * x * (3.0 - 2.0 * x); };
    return smooth(smooth(double(i) / double(kSigmoidTableRes - 1)));
}

// The inverse of a 3 x 3 matrix (false: singular).
inline bool invert3(const double m[3][3], double inv[3][3]) {
    const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                       m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    if (!(std::abs(det) > 1e-300)) return false;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            const int a = (j + 1) % 3, b = (j + 2) % 3, c = (i + 1) % 3, d = (i + 2) % 3;
            inv[i][j] = (m[a][c] * m[b][d] - m[a][d] * m[b][c]) / det;  // the cofactor of m[j][i]
        }
    return true;
}

// XYZ to linear sRGB for spectral rendering: from sRGB's primaries (x, y) = (0.64, 0.33),
// (0.30, 0.60), (0.15, 0.06) and the white whiteXyz (the tabulated D65 with Y = 1), so that
// the illuminant's own spectrum is exactly (1, 1, 1) (as a colour space is built from its
// primaries and its illuminant; the rounded IEC matrix maps the tables' D65 within 1e-3).
inline void xyzToSrgbMatrix(const double whiteXyz[3], double out[3][3]) {
    const double xy[3][2] = {{0.64, 0.33}, {0.30, 0.60}, {0.15, 0.06}};
    double P[3][3], Pinv[3][3];  // columns: the primaries' XYZ at Y = 1
    for (int c = 0; c < 3; ++c) {
        P[0][c] = xy[c][0] / xy[c][1];
        P[1][c] = 1.0;
        P[2][c] = (1.0 - xy[c][0] - xy[c][1]) / xy[c][1];
    }
    invert3(P, Pinv);
    double M[3][3];  // RGB -> XYZ: the primaries scaled so that (1, 1, 1) is the white
    for (int c = 0; c < 3; ++c) {
        const double sc = Pinv[c][0] * whiteXyz[0] + Pinv[c][1] * whiteXyz[1] + Pinv[c][2] * whiteXyz[2];
        for (int r = 0; r < 3; ++r) M[r][c] = P[r][c] * sc;
    }
    invert3(M, out);
}

// The coefficients of a reflectance rgb (each channel clamped to [0, 1]) in linear sRGB,
// interpolated trilinearly in the build-time table; a grey is exact (c0 = c1 = 0).
SigmoidPoly sigmoidPolyOfRgb(Vec3 rgb);

// pbrt-v4's RGBUnboundedSpectrum: scale 2 max(rgb) and the bounded spectrum of rgb / scale.
struct UnboundedSpectrum {
    float scale = 0;
    SigmoidPoly poly;
};
UnboundedSpectrum unboundedSpectrumOfRgb(Vec3 rgb);
inline float unboundedAt(const UnboundedSpectrum& s, float lambda) { return s.scale * sigmoidPolyAt(s.poly, lambda); }

// The CIE 1931 matching functions (linear between Debian's 5 nm samples, 0 outside
// 360..830 nm) and their y-bar's integral (nm).
Vec3 cieMatching(float lambda);
double cieYIntegral();
// The sRGB colour space's illuminant, CIE D65, scaled so that the integral of D65 y-bar
// equals that of y-bar (a constant spectrum of 1 under it has Y = 1).
float srgbIlluminant(float lambda);
// The white of that illuminant (Y = 1), and XYZ to linear sRGB for it (xyzToSrgbMatrix).
Vec3 srgbWhiteXyz();
Vec3 xyzToSrgb(Vec3 xyz);

// The Monte Carlo estimate of a path's XYZ from its radiance at the wavelengths w
// (a wavelength of pdf 0, terminated by dispersion, contributes nothing).
inline Vec3 xyzOfSample(const float L[kWavelengths], const Wavelengths& w) {
    Vec3 xyz(0.0f, 0.0f, 0.0f);
    for (int i = 0; i < kWavelengths; ++i)
        if (w.pdf[i] > 0) xyz = xyz + cieMatching(w.lambda[i]) * (L[i] / w.pdf[i]);
    return xyz * float(1.0 / (double(kWavelengths) * cieYIntegral()));
}

// A glass's index by the Sellmeier equation, n^2 = 1 + sum_i B_i l^2 / (l^2 - C_i), l in um
// (C_i in um^2): the form glass catalogues publish their dispersion in.
struct Sellmeier {
    float B[3] = {0, 0, 0}, C[3] = {0, 0, 0};
};
inline float sellmeierEta(const Sellmeier& g, float lambdaNm) {
    const double l2 = double(lambdaNm) * double(lambdaNm) * 1e-6;
    double n2 = 1;
    for (int i = 0; i < 3; ++i) n2 += double(g.B[i]) * l2 / (l2 - double(g.C[i]));
    return float(std::sqrt(n2));
}

// A spectrum tabulated every nm over 360..830 nm (a file's pairs, a blackbody: made once per
// scene), linear between.
struct DenseSpectrum {
    static constexpr int kSamples = 471;
    float v[kSamples] = {};
    float at(float lambda) const {
        const float x = lambda - kLambdaMin;
        if (!(x >= 0) || x > float(kSamples - 1)) return 0.0f;
        const int i = std::min(int(x), kSamples - 2);
        const float t = x - float(i);
        return v[i] * (1 - t) + v[i + 1] * t;
    }
};

inline Vec3 sigmoidPolyAt(SigmoidPoly c, const Wavelengths& w) {
    return Vec3(sigmoidPolyAt(c, w.lambda[0]), sigmoidPolyAt(c, w.lambda[1]), sigmoidPolyAt(c, w.lambda[2]));
}
inline Vec3 denseAt(const DenseSpectrum& s, const Wavelengths& w) { return Vec3(s.at(w.lambda[0]), s.at(w.lambda[1]), s.at(w.lambda[2])); }
// An RGB emitter's radiance at the path's wavelengths: its unbounded spectrum times the
// colour space's illuminant (so that (1, 1, 1) is the illuminant, white on the film).
Vec3 rgbIlluminantAt(Vec3 rgb, const Wavelengths& w);
// A sample's radiance at its wavelengths as linear sRGB (the film's input).
inline Vec3 srgbOfSample(Vec3 L, const Wavelengths& w) {
    const float l[kWavelengths] = {L.x, L.y, L.z};
    return xyzToSrgb(xyzOfSample(l, w));
}

// Planck's law normalised to 1 at its peak (pbrt-v4's "blackbody" spectrum): the emitted
// spectral radiance of a black body at T kelvin relative to its maximum (Wien's displacement).
inline double blackbodyNormalized(double lambdaNm, double kelvin) {
    if (!(kelvin > 0)) return 0;
    constexpr double c = 299792458.0, h = 6.62606957e-34, kb = 1.3806488e-23;  // SI
    auto planck = [&](double nm) {
        const double l = nm * 1e-9;
        return (2 * h * c * c) / (std::pow(l, 5) * (std::exp((h * c) / (l * kb * kelvin)) - 1));
    };
    return planck(lambdaNm) / planck(2.8977721e-3 / kelvin * 1e9);  // the peak: Wien's displacement law
}
// Planck's spectral radiance at its peak, in W m^-2 sr^-1 nm^-1 (Mitsuba 3's "blackbody" is
// blackbodyNormalized times this).
inline double blackbodyPeakPerNm(double kelvin) {
    if (!(kelvin > 0)) return 0;
    constexpr double c = 299792458.0, h = 6.62606957e-34, kb = 1.3806488e-23;  // SI
    const double l = 2.8977721e-3 / kelvin;
    return 1e-9 * (2 * h * c * c) / (std::pow(l, 5) * (std::exp((h * c) / (l * kb * kelvin)) - 1));
}

}  // namespace wmlt
