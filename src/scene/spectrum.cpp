// Spectra to linear sRGB (spectrum.h).
#include "scene/spectrum.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "kernels/fresnel.h"
#include "scene/number.h"
#include "scene/read_file.h"

namespace wmlt {

namespace {

// (the CIE tables: kernels/spectral.h)
double tableAt(const double* t, int n, double lambda0, double lambda) { return cieTableAt(t, n, lambda0, lambda); }

constexpr double kMin = 360, kMax = 830;
constexpr int kSteps = 1000;
double riemannLambda(int i) { return kMin + i / double(kSteps - 1) * (kMax - kMin); }

// integral of f over 360-830 nm by the projection's own Riemann sum, so that the
// normalisations below are exact for that sum.
template <typename F>
double integrate(F f) {
    double sum = 0;
    for (int i = 0; i < kSteps; ++i) sum += f(riemannLambda(i));
    return sum * (kMax - kMin) / kSteps;
}

std::string parsePair(const std::string& token, double& l, double& v) {
    const size_t colon = token.find(':');
    if (colon == std::string::npos || !parseNumber(token.substr(0, colon), false, l) || !parseNumber(token.substr(colon + 1), false, v))
        return "\"" + token + "\" is not a wavelength:value pair";
    return "";
}

std::string checkIncreasing(const SampledSpectrum& s) {
    if (s.lambda.size() < 2) return "a spectrum needs at least two wavelength-value pairs";
    for (size_t i = 1; i < s.lambda.size(); ++i)
        if (!(s.lambda[i] > s.lambda[i - 1])) return "the wavelengths must increase";
    return "";
}

}  // namespace

std::string parseSpectrumPairs(const std::string& text, SampledSpectrum& out) {
    out = {};
    std::string t = text;
    for (char& c : t)
        if (c == ',') c = ' ';
    std::istringstream in(t);
    std::string token;
    while (in >> token) {
        double l = 0, v = 0;
        const std::string e = parsePair(token, l, v);
        if (!e.empty()) return e;
        out.lambda.push_back(l);
        out.value.push_back(v);
    }
    return checkIncreasing(out);
}

std::string readSpectrumFile(const std::string& path, SampledSpectrum& out) {
    out = {};
    if (std::string why = regularFileProblem(path, "the spectrum file"); !why.empty()) return why;  // /dev/zero would be read for ever
    std::ifstream in(path);
    if (!in) return "cannot open the spectrum file";
    std::string line;
    for (int n = 1; std::getline(in, line); ++n) {
        const size_t b = line.find_first_not_of(" \t\r");
        if (b == std::string::npos || line[b] == '#') continue;
        std::istringstream fields(line);
        std::string a, v, extra;
        double l = 0, x = 0;
        if (!(fields >> a >> v) || (fields >> extra) || !parseNumber(a, false, l) || !parseNumber(v, false, x))
            return "line " + std::to_string(n) + ": expected a wavelength and a value";
        out.lambda.push_back(l);
        out.value.push_back(x);
    }
    return checkIncreasing(out);
}

Vec3 cieXyz(double lambda) {
    return Vec3(float(tableAt(cie::kXyz[0], 95, 360, lambda)), float(tableAt(cie::kXyz[1], 95, 360, lambda)),
                float(tableAt(cie::kXyz[2], 95, 360, lambda)));
}

double cieD65(double lambda) { return tableAt(cie::kD65[0], 107, 300, lambda); }

Vec3 xyzToLinearSrgb(Vec3 c) {
    return Vec3(3.240479f * c.x - 1.537150f * c.y - 0.498535f * c.z, -0.969256f * c.x + 1.875991f * c.y + 0.041556f * c.z,
                0.055648f * c.x - 0.204043f * c.y + 1.057311f * c.z);
}

Vec3 spectrumToRgb(const SampledSpectrum& s, bool illuminantD65, bool* clamped) {
    static const double yE = integrate([](double l) { return tableAt(cie::kXyz[1], 95, 360, l); });
    static const double yD65 = integrate([](double l) { return tableAt(cie::kXyz[1], 95, 360, l) * cieD65(l); });
    double xyz[3] = {0, 0, 0};
    size_t j = 0;
    for (int i = 0; i < kSteps; ++i) {
        const double l = riemannLambda(i);
        if (l < s.lambda.front() || l > s.lambda.back()) continue;
        while (j + 2 < s.lambda.size() && s.lambda[j + 1] <= l) ++j;
        const double f = (l - s.lambda[j]) / (s.lambda[j + 1] - s.lambda[j]);
        double v = s.value[j] * (1 - f) + s.value[j + 1] * f;  // linear between pairs
        if (illuminantD65) v *= cieD65(l);
        for (int k = 0; k < 3; ++k) xyz[k] += v * tableAt(cie::kXyz[k], 95, 360, l);
    }
    const double norm = (kMax - kMin) / kSteps / (illuminantD65 ? yD65 : yE);
    Vec3 rgb = xyzToLinearSrgb(Vec3(float(xyz[0] * norm), float(xyz[1] * norm), float(xyz[2] * norm)));
    const bool neg = rgb.x < 0 || rgb.y < 0 || rgb.z < 0;
    if (clamped) *clamped = neg;
    return Vec3(std::max(rgb.x, 0.0f), std::max(rgb.y, 0.0f), std::max(rgb.z, 0.0f));
}

namespace {
double valueAt(const SampledSpectrum& s, double l) {  // linear, constant beyond the ends
    if (l <= s.lambda.front()) return s.value.front();
    if (l >= s.lambda.back()) return s.value.back();
    size_t i = 0;
    while (i + 2 < s.lambda.size() && s.lambda[i + 1] < l) ++i;
    const double t = (l - s.lambda[i]) / (s.lambda[i + 1] - s.lambda[i]);
    return s.value[i] * (1 - t) + s.value[i + 1] * t;
}
}  // namespace

Vec3 conductorAlbedoScale(const SampledSpectrum& eta, const SampledSpectrum& k, Vec3 etaRgb, Vec3 kRgb) {
    constexpr int kAngles = 64;  // midpoints in cos theta, each weighted by cos theta
    SampledSpectrum R;
    for (int l = 360; l <= 830; ++l) R.lambda.push_back(l);
    R.value.resize(R.lambda.size());
    double spectral[3] = {0, 0, 0}, rgb[3] = {0, 0, 0};
    for (int a = 0; a < kAngles; ++a) {
        const float mu = (a + 0.5f) / kAngles;
        for (size_t i = 0; i < R.lambda.size(); ++i)
            R.value[i] = fresnelComplex(mu, float(valueAt(eta, R.lambda[i])), float(valueAt(k, R.lambda[i])));
        const Vec3 s = spectrumToRgb(R, true), f = fresnelConductor(mu, etaRgb, kRgb);
        for (int c = 0; c < 3; ++c) {
            spectral[c] += mu * s[c];
            rgb[c] += mu * f[c];
        }
    }
    return Vec3(float(rgb[0] > 0 ? spectral[0] / rgb[0] : 1), float(rgb[1] > 0 ? spectral[1] / rgb[1] : 1),
                float(rgb[2] > 0 ? spectral[2] / rgb[2] : 1));
}

const Sellmeier* namedGlass(const std::string& name) {
    // B1 B2 B3, C1 C2 C3 (um^2), from Schott's catalogue.
    static const struct {
        const char* name;
        Sellmeier g;
    } kGlasses[] = {
        {"glass-BK7", {{1.03961212f, 0.231792344f, 1.01046945f}, {0.00600069867f, 0.0200179144f, 103.560653f}}},
        {"glass-BAF10", {{1.5851495f, 0.143559385f, 1.08521269f}, {0.00926681282f, 0.0424489805f, 105.613573f}}},
        {"glass-FK51A", {{0.971247817f, 0.216901417f, 0.904651666f}, {0.00472301995f, 0.0153575612f, 168.68133f}}},
        {"glass-LASF9", {{2.00029547f, 0.298926886f, 1.80691843f}, {0.0121426017f, 0.0538736236f, 156.530829f}}},
        {"glass-F5", {{1.52481889f, 0.187085527f, 1.42729015f}, {0.011254756f, 0.0588995392f, 129.141675f}}},
        {"glass-F10", {{1.62153902f, 0.256287842f, 1.64447552f}, {0.0122241457f, 0.0595736775f, 147.468793f}}},
        {"glass-F11", {{1.73759695f, 0.313747346f, 1.89878101f}, {0.013188707f, 0.0623068142f, 155.23629f}}},
    };
    for (const auto& g : kGlasses)
        if (name == g.name) return &g.g;
    return nullptr;
}

int keepSpectrum(SceneDesc& desc, const SampledSpectrum& s, float scale, const std::string& source, float kelvin) {
    SpectrumDesc d;
    d.kind = kelvin > 0 ? SpectrumDesc::Kind::Blackbody : SpectrumDesc::Kind::Tabulated;
    d.kelvin = kelvin;
    if (!(kelvin > 0))
        for (size_t i = 0; i < s.lambda.size(); ++i) {
            d.lambda.push_back(float(s.lambda[i]));
            d.value.push_back(float(s.value[i]));
        }
    d.scale = scale;
    d.source = source;
    // the same spectrum again (an area light's directive on many shapes): the same entry
    for (size_t i = 0; i < desc.spectra.size(); ++i) {
        const SpectrumDesc& e = desc.spectra[i];
        if (e.kind == d.kind && e.kelvin == d.kelvin && e.scale == d.scale && e.lambda == d.lambda && e.value == d.value && e.source == d.source)
            return int(i);
    }
    desc.spectra.push_back(std::move(d));
    return int(desc.spectra.size()) - 1;
}

}  // namespace wmlt
