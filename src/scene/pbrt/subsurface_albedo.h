// pbrt-v4's subsurface material given by a diffuse reflectance (`reflectance`, and `mfp`):
// the single-scattering albedo rho of the homogeneous medium whose photon-beam-diffusion
// profile (pbrt's BSSRDF: the multiple-scattering dipole integrated along the refracted beam,
// plus single scattering below the critical angle; pbrt-v3 section 15.5) has the effective
// albedo rho_eff (the profile's integral over the plane) equal to that reflectance. Found as
// pbrt-v4 finds it: the profile tabulated at 100 albedos and 64 radii, integrated by
// Catmull-Rom splines, and the albedo curve inverted by a Catmull-Rom spline, so that
// sigma_s = rho / mfp and sigma_a = (1 - rho) / mfp are pbrt's coefficients. The medium is
// then rendered exactly by the media code's random walk, where pbrt uses the diffusion
// approximation itself.
#pragma once
#include <vector>

namespace wmlt::pbrt {

struct DiffusionAlbedo {
    std::vector<double> rho, rhoEff;  // the albedos sampled and their effective albedos (increasing)
};

// The table for a medium of Henyey-Greenstein g under a boundary of relative index eta.
DiffusionAlbedo diffusionAlbedo(double g, double eta);

// The albedo rho whose effective albedo is `reflectance` (clamped to the table's range).
double albedoOf(const DiffusionAlbedo& table, double reflectance);

// The Catmull-Rom spline through (x[i], f[i]) (pbrt's: end slopes from one side): its
// integral over [x.front(), x.back()], and x where it takes the value u (f increasing).
double integrateCatmullRom(const std::vector<double>& x, const std::vector<double>& f);
double invertCatmullRom(const std::vector<double>& x, const std::vector<double>& f, double u);

}  // namespace wmlt::pbrt
