// Spectral kernels (kernels/spectral.h, issue 45): the visible-wavelength density and its
// sampling, the XYZ estimate of sampled radiance, the RGB-to-spectrum table fitted at build
// time (round trips of reflectances, unbounded colours and illuminants through their spectra
// and the CIE observer), blackbody spectra.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "kernels/spectral.h"
#include "scene/spectrum.h"

extern "C" {
extern const float wmlt_rgb_sigmoid_srgb[];
extern const float wmlt_rgb_sigmoid_srgb_end[];
}

using namespace wmlt;

namespace {

// The linear sRGB of a spectral radiance s(lambda) (as the film sees it: XYZ = integral of
// s cmf / integral of y-bar), by the midpoint rule on a 0.1 nm grid.
template <typename F>
Vec3 srgbOfRadiance(F s) {
    double xyz[3] = {0, 0, 0};
    const double h = 0.1;
    for (double l = kLambdaMin + h / 2; l < kLambdaMax; l += h) {
        const Vec3 m = cieMatching(float(l));
        const double v = s(float(l));
        for (int k = 0; k < 3; ++k) xyz[k] += v * m[k] * h;
    }
    const double y = cieYIntegral();
    return xyzToSrgb(Vec3(float(xyz[0] / y), float(xyz[1] / y), float(xyz[2] / y)));
}

// A reflectance's colour under the colour space's illuminant.
Vec3 srgbOfReflectance(SigmoidPoly c) {
    return srgbOfRadiance([c](float l) { return double(sigmoidPolyAt(c, l)) * srgbIlluminant(l); });
}

double maxAbs(Vec3 a, Vec3 b) { return std::max({std::abs(a.x - b.x), std::abs(a.y - b.y), std::abs(a.z - b.z)}); }

}  // namespace

TEST_CASE("Visible wavelengths: the density integrates to 1 and sampling inverts its CDF", "[spectral]") {
    double sum = 0;
    const double h = 0.01;
    for (double l = kLambdaMin + h / 2; l < kLambdaMax; l += h) sum += visibleWavelengthPdf(float(l)) * h;
    CHECK(sum == Approx(1.0).epsilon(1e-5));
    CHECK(visibleWavelengthPdf(359.0f) == 0.0f);
    CHECK(visibleWavelengthPdf(831.0f) == 0.0f);
    // CDF(lambda(u)) = u: integrate the density up to each sample.
    for (double u : {0.0, 0.05, 0.25, 0.5, 0.75, 0.95, 0.999}) {
        const float l = sampleVisibleWavelength(float(u));
        double cdf = 0;
        const int n = 20000;
        for (int i = 0; i < n; ++i) cdf += visibleWavelengthPdf(float(kLambdaMin + (l - kLambdaMin) * (i + 0.5) / n)) * (l - kLambdaMin) / n;
        CHECK(cdf == Approx(u).margin(2e-5));
    }
    CHECK(sampleVisibleWavelength(0.0f) == Approx(kLambdaMin).margin(1e-3));
    CHECK(sampleVisibleWavelength(1.0f) == Approx(kLambdaMax).margin(1e-2));
}

TEST_CASE("Visible wavelengths: a path's wavelengths are stratified in the CDF", "[spectral]") {
    for (float u : {0.0f, 0.3f, 0.74f, 0.9999f}) {
        const Wavelengths w = sampleWavelengths(u);
        for (int i = 0; i < kWavelengths; ++i) {
            CHECK(w.lambda[i] >= kLambdaMin);
            CHECK(w.lambda[i] <= kLambdaMax);
            CHECK(w.pdf[i] == Approx(visibleWavelengthPdf(w.lambda[i])).epsilon(1e-5));
            float ui = u + float(i) / kWavelengths;
            if (ui >= 1) ui -= 1;
            CHECK(w.lambda[i] == Approx(sampleVisibleWavelength(ui)).margin(1e-3));
        }
    }
}

TEST_CASE("XYZ estimate: a constant spectrum of 1 has Y = 1 and E's chromaticity", "[spectral]") {
    // Stratified u: the estimate's mean over the strata converges to the integral.
    const int n = 4096;
    double xyz[3] = {0, 0, 0};
    for (int j = 0; j < n; ++j) {
        const Wavelengths w = sampleWavelengths((float(j) + 0.5f) / n);
        float L[kWavelengths];
        for (float& v : L) v = 1;
        const Vec3 v = xyzOfSample(L, w);
        for (int k = 0; k < 3; ++k) xyz[k] += v[k] / n;
    }
    CHECK(xyz[1] == Approx(1.0).epsilon(1e-3));
    // Illuminant E: X and Z are the integrals of x-bar and z-bar over y-bar's, 1 to 1%.
    CHECK(xyz[0] == Approx(1.0).epsilon(0.01));
    CHECK(xyz[2] == Approx(1.0).epsilon(0.01));
    // A terminated wavelength (pdf 0) contributes nothing.
    Wavelengths w = sampleWavelengths(0.5f);
    float L[kWavelengths];
    for (float& v : L) v = 1;
    const Vec3 all = xyzOfSample(L, w);
    for (int i = 1; i < kWavelengths; ++i) w.pdf[i] = 0;
    const Vec3 hero = xyzOfSample(L, w);
    CHECK(hero.y < all.y);
    CHECK(hero.y == Approx(cieMatching(w.lambda[0]).y / visibleWavelengthPdf(w.lambda[0]) / (kWavelengths * cieYIntegral())).epsilon(1e-5));
}

TEST_CASE("sRGB for spectra: the illuminant's own spectrum is white", "[spectral]") {
    const Vec3 white = srgbOfRadiance([](float l) { return double(srgbIlluminant(l)); });
    CHECK(maxAbs(white, Vec3(1, 1, 1)) < 2e-4);
    CHECK(srgbWhiteXyz().y == Approx(1.0f));
}

TEST_CASE("RGB to spectrum: the table is the size the fit wrote", "[spectral]") {
    CHECK(size_t(wmlt_rgb_sigmoid_srgb_end - wmlt_rgb_sigmoid_srgb) == size_t(3) * kSigmoidTableRes * kSigmoidTableRes * kSigmoidTableRes * 3);
    size_t nonfinite = 0;
    for (const float* p = wmlt_rgb_sigmoid_srgb; p < wmlt_rgb_sigmoid_srgb_end; ++p) nonfinite += std::isfinite(*p) ? 0 : 1;
    CHECK(nonfinite == 0);
}

TEST_CASE("RGB to spectrum: greys are constant spectra", "[spectral]") {
    for (float v : {0.0f, 0.18f, 0.5f, 0.9f, 1.0f}) {
        const SigmoidPoly c = sigmoidPolyOfRgb(Vec3(v, v, v));
        for (float l : {360.0f, 500.0f, 700.0f, 830.0f}) CHECK(sigmoidPolyAt(c, l) == Approx(v).margin(1e-6));
    }
}

TEST_CASE("RGB to spectrum: reflectances round-trip through their spectra", "[spectral]") {
    // At the table's nodes (no interpolation) the fit's own accuracy: 1.3e-5 in CIELAB.
    constexpr int res = kSigmoidTableRes;
    for (int l = 0; l < 3; ++l)
        for (int i : {8, 20, 40, 63})
            for (int j : {0, 21, 50})
                for (int k : {3, 33, 63}) {
                    const float z = float(sigmoidTableZ(i)), x = float(k) / (res - 1), y = float(j) / (res - 1);
                    Vec3 rgb;
                    rgb[l] = z;
                    rgb[(l + 1) % 3] = x * z;
                    rgb[(l + 2) % 3] = y * z;
                    CHECK(maxAbs(srgbOfReflectance(sigmoidPolyOfRgb(rgb)), rgb) < 2e-4);
                }
    // Anywhere in [0,1]^3 (trilinear interpolation of the coefficients between nodes).
    std::mt19937 rng(45);
    std::uniform_real_distribution<float> U(0.0f, 1.0f);
    double worst = 0, sum = 0;
    const int n = 400;
    for (int t = 0; t < n; ++t) {
        const Vec3 rgb(U(rng), U(rng), U(rng));
        const double e = maxAbs(srgbOfReflectance(sigmoidPolyOfRgb(rgb)), rgb);
        worst = std::max(worst, e);
        sum += e;
    }
    INFO("worst " << worst << ", mean " << sum / n);
    CHECK(worst < 2e-3);
    // Saturated colours: the primaries and secondaries.
    for (Vec3 rgb : {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(1, 1, 0), Vec3(0, 1, 1), Vec3(1, 0, 1), Vec3(0.8f, 0.1f, 0.05f)}) {
        INFO(rgb.x << " " << rgb.y << " " << rgb.z);
        CHECK(maxAbs(srgbOfReflectance(sigmoidPolyOfRgb(rgb)), rgb) < 2e-3);
    }
}

TEST_CASE("RGB to spectrum: unbounded colours and illuminants", "[spectral]") {
    for (Vec3 rgb : {Vec3(3.0f, 1.5f, 0.3f), Vec3(0.2f, 0.4f, 0.1f), Vec3(17.0f, 12.0f, 10.0f)}) {
        const UnboundedSpectrum s = unboundedSpectrumOfRgb(rgb);
        CHECK(s.scale == Approx(2 * std::max({rgb.x, rgb.y, rgb.z})));
        // As a reflectance-like quantity (seen under the illuminant): its RGB.
        const Vec3 refl = srgbOfRadiance([&](float l) { return double(unboundedAt(s, l)) * srgbIlluminant(l); });
        // As an illuminant (times the colour space's illuminant): the same RGB, as light.
        CHECK(maxAbs(refl, rgb) < 2e-3 * s.scale);
    }
    const UnboundedSpectrum black = unboundedSpectrumOfRgb(Vec3(0, 0, 0));
    CHECK(unboundedAt(black, 550.0f) == 0.0f);
}

TEST_CASE("Blackbody: 1 at Wien's peak and below it elsewhere", "[spectral]") {
    for (double T : {2700.0, 5500.0, 6500.0}) {
        const double peak = 2.8977721e6 / T;  // nm
        CHECK(blackbodyNormalized(peak, T) == Approx(1.0).epsilon(1e-9));
        CHECK(blackbodyNormalized(peak * 0.9, T) < 1.0);
        CHECK(blackbodyNormalized(peak * 1.1, T) < 1.0);
    }
    // Planck's law's ratio at two wavelengths, written out: B(450) / B(650) at 3000 K.
    const double c2 = 6.62606957e-34 * 299792458.0 / 1.3806488e-23;  // h c / k, m K
    auto planck = [&](double l) { return 1.0 / (std::pow(l, 5) * (std::exp(c2 / (l * 3000.0)) - 1)); };
    CHECK(blackbodyNormalized(450, 3000) / blackbodyNormalized(650, 3000) == Approx(planck(450e-9) / planck(650e-9)).epsilon(1e-9));
    CHECK(blackbodyNormalized(500, 0) == 0.0);
}

TEST_CASE("Named glasses: catalogue indices and Abbe numbers", "[spectral]") {
    // Schott's n_d (587.56 nm) and v_d = (n_d - 1) / (n_F - n_C) (486.13, 656.27 nm).
    const struct {
        const char* name;
        double nd, vd;
    } kCatalogue[] = {{"glass-BK7", 1.51680, 64.17},   {"glass-BAF10", 1.67003, 47.11}, {"glass-FK51A", 1.48656, 84.47},
                      {"glass-LASF9", 1.85025, 32.17}, {"glass-F5", 1.67270, 32.21},    {"glass-F10", 1.72828, 28.53},
                      {"glass-F11", 1.78472, 25.68}};
    for (const auto& c : kCatalogue) {
        INFO(c.name);
        const Sellmeier* g = namedGlass(c.name);
        REQUIRE(g);
        const double nd = sellmeierEta(*g, 587.56f), nF = sellmeierEta(*g, 486.13f), nC = sellmeierEta(*g, 656.27f);
        CHECK(nd == Approx(c.nd).margin(2e-5));
        CHECK((nd - 1) / (nF - nC) == Approx(c.vd).margin(0.05));
    }
    CHECK(namedGlass("glass-Fake") == nullptr);
    CHECK(namedGlass("metal-Ag-eta") == nullptr);
}
