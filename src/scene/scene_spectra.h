// A scene's colours as spectra, for spectral rendering (docs/spectral.md; --spectral): made
// once per render from the scene model, read by the spectral stage (a hit's colour parameters
// at its path's wavelengths) and where emission is read. Every colour the file gave as a
// spectrum (SceneDesc::spectra) is tabulated every nm; every RGB colour is uplifted by the
// sigmoid table (kernels/spectral.h) at the hit. What cannot be rendered spectrally yet makes
// the whole render RGB (`unsupported` says why; the tracer warns).
#pragma once
#include <array>
#include <string>
#include <vector>

#include "kernels/bsdf.h"
#include "kernels/spectral.h"
#include "scene/scene.h"

namespace wmlt {

// An RGB colour and its spectrum (scale times the sigmoid), made once for a material's constant.
struct UpliftedColour {
    Vec3 rgb{-1.0f};  // (-1: none)
    SigmoidPoly poly;
    float scale = 1;
};

struct SpectralScene {
    std::string unsupported;             // "" or why this scene renders in RGB
    std::vector<DenseSpectrum> dense;    // SceneDesc::spectra, times their scales
    std::vector<ParamSpectra> params;    // per material (SceneDesc::materials): index into dense, -1: its RGB
    std::vector<int> light;              // per Scene::lights: index into dense (Y = 1), -1: its RGB
    std::vector<UpliftedColour> lightL;  // per Scene::lights: its L's unbounded spectrum (scale 0: textured, or black)
    // Per material, its constants' spectra (a hit whose slot still holds the constant, i.e.
    // untextured, reads these instead of looking the table up): Diffuse, Specular, Reflect,
    // Refract (a coat's albedo), a conductor's eta and k.
    static constexpr int kSlots = 6;
    std::vector<std::array<UpliftedColour, kSlots>> constants;
    // Per medium (Scene::media): sigma_a and sigma_s as unbounded spectra, Le as an
    // illuminant (pbrt-v4's RGBUnboundedSpectrum and RGBIlluminantSpectrum); its RGB grids
    // voxel by voxel alike (the albedo's bounded, as a reflectance), and RGB coefficient
    // grids' majorant grid for the spectra (each voxel's largest sigma_t at any wavelength).
    // A Mitsuba medium's constant albedo (byAlbedo): sigma_t unbounded and the albedo bounded,
    // sigma_s their product at each wavelength, as Mitsuba 3's scalar_spectral.
    struct MediumSpectra {
        UpliftedColour sigmaA, sigmaS, Le;
        UpliftedColour sigmaT, albedo;
        bool byAlbedo = false;
        std::vector<UnboundedSpectrum> gridSigmaA, gridSigmaS, gridAlbedo, gridLe;
        std::vector<float> majorants;
        float majorant = 0;
    };
    std::vector<MediumSpectra> media;

    // Hit h's material m (SceneDesc::materials) at the wavelengths w: every colour parameter its
    // kind reads, in out (a hit's BsdfParams, its texture applied), from RGB or from its spectrum.
    // Returns true for a dispersive dielectric (an index given as a spectrum): its index is then
    // the hero wavelength's, and the path must keep only that wavelength (terminateSecondary).
    bool colours(int m, const MaterialDesc& desc, BsdfParams& out, const Wavelengths& w) const;
    // Light l's emission at w, from the RGB radiance the RGB code computed for it (its
    // geometry and texture applied): its spectrum times that radiance's luminance, or the RGB's
    // illuminant spectrum.
    // (An untextured light's LeRgb is its L times a number: its L's spectrum, made once, times
    // that number.)
    Vec3 emission(int l, Vec3 LeRgb, const Wavelengths& w) const {
        if (l >= 0 && light[size_t(l)] >= 0) return denseAt(dense[size_t(light[size_t(l)])], w) * luminance(LeRgb);
        if (l >= 0 && lightL[size_t(l)].scale > 0) {
            const UpliftedColour& c = lightL[size_t(l)];
            const float g = luminance(LeRgb) / luminance(c.rgb);
            return sigmoidPolyAt(c.poly, w) * (c.scale * g) *
                   Vec3(srgbIlluminant(w.lambda[0]), srgbIlluminant(w.lambda[1]), srgbIlluminant(w.lambda[2]));
        }
        return rgbIlluminantAt(LeRgb, w);
    }
    // Medium m (rgb: its RGB form, Scene::media) at w: sigma_t, sigma_s and Le there; a
    // density grid's majorants scaled to bound sigma_t at w (Medium::majorantScale). A copy,
    // made per segment: the stages read the media through PathMedia (stages/core/media.h).
    Medium medium(int m, const Medium& rgb, const Wavelengths& w) const;
};

// A render's mode, chosen once per render: spectral when asked (RenderOptions::spectral) and the
// scene can be (`scene` then holds its spectra), else RGB, with the reason when it was asked.
struct SpectralMode {
    SpectralScene scene;  // (built only when asked)
    bool spectral = false;
    const SpectralScene* spectra() const { return spectral ? &scene : nullptr; }
    // --stats' spectral_reason: "" unless asked and rendered in RGB.
    std::string reason(bool asked) const {
        return asked && !spectral ? "the scene has " + scene.unsupported + " (not spectral yet): rendered in RGB" : std::string();
    }
};
SpectralMode chooseSpectralMode(const Scene& scene, bool asked);

// A spectral render's description (render() and the interactive session apply it before
// Scene::build): every linear blend (Mitsuba's blendbsdf) resolved to one part per hit
// (blendPerHit: part 1 with probability its weight, as pbrt-v4's mix), which has the linear
// blend's mean and whose parts the spectral stage colours; an RGB render keeps the linear
// blend bit for bit (docs/spectral.md).
void resolveBlendsForSpectral(SceneDesc& d);

// The scene's spectra, or `unsupported` set (what the spectral stage cannot colour: a linear
// blend, in a scene built without resolveBlendsForSpectral).
SpectralScene buildSpectralScene(const Scene& scene);
// The same reason from the description alone, for a render that resolves its blends ("" when
// the scene can render spectrally): --describe's.
std::string spectralUnsupported(const SceneDesc& d);

}  // namespace wmlt
