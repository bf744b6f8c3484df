#include "scene/pbrt/subsurface_albedo.h"

#include <algorithm>
#include <cmath>

#include "kernels/fresnel.h"

namespace wmlt::pbrt {

namespace {

constexpr double kInv4Pi = 1 / (4 * M_PI);

// The first two moments of the dielectric Fresnel reflectance (polynomial fits in eta, pbrt).
double fresnelMoment1(double eta) {
    const double e2 = eta * eta, e3 = e2 * eta, e4 = e3 * eta, e5 = e4 * eta;
    if (eta < 1) return 0.45966 - 1.73965 * eta + 3.37668 * e2 - 3.904945 * e3 + 2.49277 * e4 - 0.68441 * e5;
    return -4.61686 + 11.1136 * eta - 10.4646 * e2 + 5.11455 * e3 - 1.27198 * e4 + 0.12746 * e5;
}
double fresnelMoment2(double eta) {
    const double e2 = eta * eta, e3 = e2 * eta, e4 = e3 * eta, e5 = e4 * eta;
    if (eta < 1) return 0.27614 - 0.87350 * eta + 1.12077 * e2 - 0.65095 * e3 + 0.07883 * e4 + 0.04860 * e5;
    const double r = 1 / eta, r2 = r * r, r3 = r2 * r;
    return -547.033 + 45.3087 * r3 - 218.725 * r2 + 458.843 * r + 404.557 * eta - 189.519 * e2 + 54.9327 * e3 - 9.00603 * e4 + 0.63942 * e5;
}

// Multiple scattering at distance r from the beam's entry: the dipole's exitance (the
// fluence and the vector irradiance, Grosjean's D_G, the extrapolated boundary) summed over
// 100 real sources along the refracted beam, at depths sampled by the reduced extinction.
double beamDiffusionMS(double sigmaS, double sigmaA, double g, double eta, double r) {
    const double sps = sigmaS * (1 - g), spt = sigmaA + sps, rhop = sps / spt;
    const double D = (2 * sigmaA + sps) / (3 * spt * spt);
    const double sigmaTr = std::sqrt(sigmaA / D);
    const double fm1 = fresnelMoment1(eta), fm2 = fresnelMoment2(eta);
    const double ze = -2 * D * (1 + 3 * fm2) / (1 - 2 * fm1);
    const double cPhi = 0.25 * (1 - 2 * fm1), cE = 0.5 * (1 - 3 * fm2);
    const int n = 100;
    double sum = 0;
    for (int i = 0; i < n; ++i) {
        const double zr = -std::log(1 - (i + 0.5) / n) / spt, zv = -zr + 2 * ze;
        const double dr = std::sqrt(r * r + zr * zr), dv = std::sqrt(r * r + zv * zv);
        const double er = std::exp(-sigmaTr * dr), ev = std::exp(-sigmaTr * dv);
        const double phi = kInv4Pi / D * (er / dr - ev / dv);
        const double En = kInv4Pi * (zr * (1 + sigmaTr * dr) * er / (dr * dr * dr) - zv * (1 + sigmaTr * dv) * ev / (dv * dv * dv));
        const double kappa = 1 - std::exp(-2 * spt * (dr + zr));
        sum += kappa * rhop * rhop * (phi * cPhi + En * cE);
    }
    return sum / n;
}

// Single scattering along the refracted beam, seen at distance r, from depths past the
// critical angle's (100 depths sampled by the extinction).
double beamDiffusionSS(double sigmaS, double sigmaA, double g, double eta, double r) {
    const double sigmaT = sigmaA + sigmaS, rho = sigmaS / sigmaT;
    const double tCrit = r * std::sqrt(eta * eta - 1);
    const int n = 100;
    double sum = 0;
    for (int i = 0; i < n; ++i) {
        const double t = tCrit - std::log(1 - (i + 0.5) / n) / sigmaT;
        const double d = std::sqrt(r * r + t * t), cosO = t / d;
        const double hg = kInv4Pi * (1 - g * g) / std::pow(1 + g * g + 2 * g * cosO, 1.5);
        sum += rho * std::exp(-sigmaT * (d + tCrit)) / (d * d) * hg * (1 - fresnelDielectric(float(-cosO), float(eta))) * std::fabs(cosO);
    }
    return sum / n;
}

// The spline's end slopes: from one side at the ends, centred elsewhere (pbrt's).
void slopes(const std::vector<double>& x, const std::vector<double>& f, size_t i, double& d0, double& d1) {
    const double w = x[i + 1] - x[i];
    d0 = i > 0 ? w * (f[i + 1] - f[i - 1]) / (x[i + 1] - x[i - 1]) : f[i + 1] - f[i];
    d1 = i + 2 < x.size() ? w * (f[i + 2] - f[i]) / (x[i + 2] - x[i]) : f[i + 1] - f[i];
}

}  // namespace

double integrateCatmullRom(const std::vector<double>& x, const std::vector<double>& f) {
    double sum = 0;
    for (size_t i = 0; i + 1 < x.size(); ++i) {
        double d0, d1;
        slopes(x, f, i, d0, d1);
        sum += ((d0 - d1) / 12 + (f[i] + f[i + 1]) / 2) * (x[i + 1] - x[i]);  // the Hermite cubic's integral
    }
    return sum;
}

double invertCatmullRom(const std::vector<double>& x, const std::vector<double>& f, double u) {
    if (!(u > f.front())) return x.front();
    if (!(u < f.back())) return x.back();
    const size_t i = size_t(std::upper_bound(f.begin(), f.end(), u) - f.begin()) - 1;
    double d0, d1;
    slopes(x, f, i, d0, d1);
    // Newton's method on the Hermite cubic F(t) = u, t in [0, 1], kept in a shrinking bracket
    double a = 0, b = 1, t = 0.5;
    for (int it = 0; it < 100; ++it) {
        if (!(t >= a && t <= b)) t = 0.5 * (a + b);
        const double t2 = t * t, t3 = t2 * t;
        const double F = (2 * t3 - 3 * t2 + 1) * f[i] + (-2 * t3 + 3 * t2) * f[i + 1] + (t3 - 2 * t2 + t) * d0 + (t3 - t2) * d1;
        const double dF = (6 * t2 - 6 * t) * f[i] + (-6 * t2 + 6 * t) * f[i + 1] + (3 * t2 - 4 * t + 1) * d0 + (3 * t2 - 2 * t) * d1;
        if (std::fabs(F - u) < 1e-9 || b - a < 1e-9) break;
        (F - u < 0 ? a : b) = t;
        t -= (F - u) / dF;
    }
    return x[i] + t * (x[i + 1] - x[i]);
}

DiffusionAlbedo diffusionAlbedo(double g, double eta) {
    const int nRho = 100, nR = 64;
    std::vector<double> radius(nR);
    radius[0] = 0;
    radius[1] = 2.5e-3;
    for (int j = 2; j < nR; ++j) radius[j] = radius[j - 1] * 1.2;
    DiffusionAlbedo t;
    std::vector<double> profile(nR);
    for (int i = 0; i < nRho; ++i) {
        const double rho = (1 - std::exp(-8.0 * i / (nRho - 1))) / (1 - std::exp(-8.0));
        for (int j = 0; j < nR; ++j) {
            const double r = radius[size_t(j)];
            profile[size_t(j)] = r == 0 ? 0 : 2 * M_PI * r * (beamDiffusionSS(rho, 1 - rho, g, eta, r) + beamDiffusionMS(rho, 1 - rho, g, eta, r));
        }
        t.rho.push_back(rho);
        t.rhoEff.push_back(integrateCatmullRom(radius, profile));
    }
    return t;
}

double albedoOf(const DiffusionAlbedo& table, double reflectance) { return invertCatmullRom(table.rho, table.rhoEff, reflectance); }

}  // namespace wmlt::pbrt
