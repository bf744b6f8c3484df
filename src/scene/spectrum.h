// Spectra in scene files, for an RGB renderer: wavelength-value pairs (inline, or an .spd
// file of "lambda value" lines) projected once, at load time, onto linear sRGB by
// integration against the CIE 1931 2-degree observer (Debian colord-data's 5 nm tables,
// cmake/embed_cie.cmake). docs/mitsuba.md "Spectra" says which parameter uses which weighting.
#pragma once
#include <string>
#include <vector>

#include "kernels/spectral.h"
#include "wavemmlt/math.h"
#include "wavemmlt/scene_desc.h"

namespace wmlt {

struct SampledSpectrum {
    std::vector<double> lambda, value;  // nm, strictly increasing; at least two pairs
};

// "400:0.5, 500:0.7 ..." (commas or white space between pairs). Returns "" or the problem.
std::string parseSpectrumPairs(const std::string& text, SampledSpectrum& out);
// An .spd file: one "lambda value" pair per line, '#' comments and blank lines skipped.
// Returns "" or the problem, naming the line ("line 7: ...").
std::string readSpectrumFile(const std::string& path, SampledSpectrum& out);

// The CIE 1931 colour matching functions (x-bar, y-bar, z-bar) at lambda nm, linearly
// interpolated between the 5 nm samples, zero outside 360-830 nm.
Vec3 cieXyz(double lambda);
// The CIE D65 illuminant (1 at 560 nm), linear between its 5 nm samples, 300-830 nm.
double cieD65(double lambda);
// XYZ to linear sRGB (IEC 61966-2-1, D65 white).
Vec3 xyzToLinearSrgb(Vec3 xyz);

// Mitsuba 3's projection in its RGB variants (spectrum_list_to_srgb): a Riemann sum of 1000
// samples over 360-830 nm of s(lambda) times the matching functions, s linear between its
// pairs and zero outside them, then XYZ -> linear sRGB.
//   illuminantD65 = false: XYZ / integral(y-bar): the spectrum of an emitter or an index
//     of refraction (a constant 1 gives E white, (1.205, 0.948, 0.909) in sRGB);
//   illuminantD65 = true:  XYZ of s times D65 / integral(D65 y-bar): a reflectance seen
//     under D65 (a constant 1 gives white, (1, 1, 1) to 1e-3).
// Negative results are clamped to 0 (out of gamut), and `clamped` says so.
Vec3 spectrumToRgb(const SampledSpectrum& s, bool illuminantD65, bool* clamped = nullptr);

// A conductor given as spectra eta(lambda) + i k(lambda), rendered in RGB with the
// projected indices etaRgb, kRgb (the Fresnel term per channel): the factor per channel that
// makes the RGB conductor's albedo -- its Fresnel reflectance averaged over the hemisphere,
// cosine-weighted -- equal to the spectral conductor's (the spectral reflectance projected
// under D65 at each angle). Gold's red, out of sRGB's gamut, needs 1.05: the projected
// indices alone reflect 4.6% too little at normal incidence.
Vec3 conductorAlbedoScale(const SampledSpectrum& eta, const SampledSpectrum& k, Vec3 etaRgb, Vec3 kRgb);

// s kept in the scene model for spectral renders (SceneDesc::spectra) times scale, by its
// source's name ("spds/Au.eta.spd", "blackbody 5500 K"; kelvin > 0: a blackbody, normalised
// to 1 at its peak, s unused): its index, an equal entry's when there is one (an area light's
// spectrum on many shapes).
int keepSpectrum(SceneDesc& d, const SampledSpectrum& s, float scale, const std::string& source, float kelvin = 0);

// pbrt-v4's named glasses ("glass-BK7", "-BAF10", "-FK51A", "-LASF9", and "-F5", "-F10",
// "-F11": Schott's SF5, N-SF10 and SF11) by their catalogue Sellmeier coefficients
// (Schott's data sheets); nullptr for any other name.
const Sellmeier* namedGlass(const std::string& name);

}  // namespace wmlt
