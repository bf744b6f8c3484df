// A scene's colours as spectra (scene_spectra.h).
#include "scene/scene_spectra.h"

namespace wmlt {

namespace {

DenseSpectrum densify(const SpectrumDesc& s) {
    DenseSpectrum d;
    for (int i = 0; i < DenseSpectrum::kSamples; ++i) {
        const double l = double(kLambdaMin) + i;
        double v = 0;
        if (s.kind == SpectrumDesc::Kind::Blackbody) {
            v = blackbodyNormalized(l, s.kelvin);
        } else if (s.kind == SpectrumDesc::Kind::Sellmeier) {
            Sellmeier g;
            for (int k = 0; k < 3; ++k) {
                g.B[k] = s.sellmeierB[k];
                g.C[k] = s.sellmeierC[k];
            }
            v = sellmeierEta(g, float(l));
        } else if (!s.lambda.empty() && l >= s.lambda.front() && l <= s.lambda.back()) {  // linear between pairs, 0 outside
            size_t j = 0;
            while (j + 2 < s.lambda.size() && s.lambda[j + 1] < l) ++j;
            const double t = s.lambda[j + 1] > s.lambda[j] ? (l - s.lambda[j]) / (s.lambda[j + 1] - s.lambda[j]) : 0.0;
            v = s.value[j] * (1 - t) + s.value[j + 1] * t;
        }
        d.v[i] = float(v * s.scale);
    }
    return d;
}

UpliftedColour uplift(Vec3 rgb, bool unbounded) {
    UpliftedColour c;
    c.rgb = rgb;
    if (unbounded || std::max({rgb.x, rgb.y, rgb.z}) > 1.0f) {
        const UnboundedSpectrum s = unboundedSpectrumOfRgb(rgb);
        c.poly = s.poly;
        c.scale = s.scale;
    } else {
        c.poly = sigmoidPolyOfRgb(rgb);
    }
    return c;
}

// rgb's spectrum at w: the constant's when rgb is it, else looked up.
Vec3 upliftedAt(const UpliftedColour& c, Vec3 rgb, bool unbounded, const Wavelengths& w) {
    if (!(rgb.x == c.rgb.x && rgb.y == c.rgb.y && rgb.z == c.rgb.z)) {
        const UpliftedColour u = uplift(rgb, unbounded);
        return sigmoidPolyAt(u.poly, w) * u.scale;
    }
    return sigmoidPolyAt(c.poly, w) * c.scale;
}

// A voxel's RGB as a spectrum, unbounded (coefficients, emission) or bounded (an albedo).
UnboundedSpectrum voxelSpectrum(Vec3 rgb, bool unbounded) {
    const UpliftedColour c = uplift(rgb, unbounded);
    return {c.scale, c.poly};
}

// The largest value of v at any wavelength in [360, 830] nm: the sigmoid is increasing, so
// where its quadratic in t = (lambda - 360) / 470 is largest on [0, 1] (an end, or the vertex).
float voxelMax(const UnboundedSpectrum& v) {
    float x = std::max(sigmoidPolyAtT(v.poly, 0.0f), sigmoidPolyAtT(v.poly, 1.0f));
    if (v.poly.c0 < 0) {
        const float t = -v.poly.c1 / (2 * v.poly.c0);
        if (t > 0 && t < 1) x = std::max(x, sigmoidPolyAtT(v.poly, t));
    }
    return v.scale * x;
}

// Medium desc (built as rgb) as spectra: its constants, and its RGB grids voxel by voxel.
SpectralScene::MediumSpectra mediumSpectra(const MediumDesc& desc, const Medium& rgb) {
    SpectralScene::MediumSpectra s;
    s.sigmaA = uplift(desc.sigmaA, true);
    s.sigmaS = uplift(desc.sigmaS, true);
    s.Le = uplift(desc.Le, true);
    if (desc.albedo.x >= 0 && desc.albedoGrid.empty()) {  // Mitsuba's constant albedo: sigma_s = albedo(l) sigma_t(l)
        s.byAlbedo = true;
        s.sigmaT = uplift(desc.sigmaA + desc.sigmaS, true);
        s.albedo = uplift(desc.albedo, false);
    }
    auto grid = [](const std::vector<Vec3>& values, bool unbounded, std::vector<UnboundedSpectrum>& out) {
        out.reserve(values.size());
        for (Vec3 v : values) out.push_back(voxelSpectrum(v, unbounded));
    };
    grid(desc.sigmaAGrid, true, s.gridSigmaA);
    grid(desc.sigmaSGrid, true, s.gridSigmaS);
    grid(desc.albedoGrid, false, s.gridAlbedo);
    grid(desc.LeGrid, true, s.gridLe);
    if (!s.gridSigmaS.empty()) {  // sigma_t's majorants at any wavelength
        majorantCells(
            rgb, [&](size_t i) { return voxelMax(s.gridSigmaA[i]) + voxelMax(s.gridSigmaS[i]); }, s.majorants);
        for (float c : s.majorants) s.majorant = std::max(s.majorant, c);
    }
    return s;
}

// Why material m of d cannot be rendered spectrally yet ("" if it can), blends resolved or
// not (perHit): a linear blend, whose parts are constants the spectral stage never sees (a
// blend resolved per hit is its parts there). (A plastic's and a principled material's
// sampling weights are made from RGB, but they are sampling choices only.)
std::string unsupportedMaterial(const SceneDesc& d, const MaterialDesc& m, bool perHit) {
    if (m.kind == MaterialKind::Blend && !perHit && !blendChoosesPart(d.materials, m)) return "a linear blend material";
    if (m.kind == MaterialKind::Phase) return "a phase material";
    return "";
}

}  // namespace

void resolveBlendsForSpectral(SceneDesc& d) {
    for (MaterialDesc& m : d.materials)
        if (m.kind == MaterialKind::Blend) m.blendPerHit = true;
}

std::string spectralUnsupported(const SceneDesc& d) {
    for (const MaterialDesc& m : d.materials)
        if (std::string why = unsupportedMaterial(d, m, true); !why.empty()) return why;
    return "";
}

SpectralScene buildSpectralScene(const Scene& scene) {
    SpectralScene s;
    const SceneDesc& d = scene.desc;
    for (const MaterialDesc& m : d.materials)
        if (s.unsupported.empty()) s.unsupported = unsupportedMaterial(d, m, false);
    if (!s.unsupported.empty()) return s;
    for (const SpectrumDesc& sd : d.spectra) s.dense.push_back(densify(sd));
    for (const MaterialDesc& m : d.materials) {
        const Vec3 eta = m.conductorEta, k = m.conductorK;
        s.constants.push_back({uplift(m.diffuse, false), uplift(m.specular, false), uplift(m.reflect, false),
                               uplift(m.kind == MaterialKind::Coated ? m.coating.albedo : m.refract, false), uplift(eta, true), uplift(k, true)});
        s.params.push_back(m.spectra);
    }
    for (size_t i = 0; i < d.media.size(); ++i) s.media.push_back(mediumSpectra(d.media[i], scene.media[i]));
    s.light.assign(scene.lights.size(), -1);
    for (size_t i = 0; i < d.lights.size() && i < scene.lights.size(); ++i) s.light[i] = d.lights[i].spectrum;
    s.lightL.assign(scene.lights.size(), UpliftedColour{});
    for (size_t i = 0; i < d.lights.size() && i < scene.lights.size(); ++i)
        if (d.lights[i].texture < 0 && luminance(scene.lights[i].L) > 0) s.lightL[i] = uplift(scene.lights[i].L, true);
    for (UpliftedColour& c : s.lightL)
        if (c.rgb.x < 0) c.scale = 0;  // (none)
    return s;
}

SpectralMode chooseSpectralMode(const Scene& scene, bool asked) {
    SpectralMode m;
    if (asked) m.scene = buildSpectralScene(scene);
    m.spectral = asked && m.scene.unsupported.empty();
    return m;
}

Medium SpectralScene::medium(int m, const Medium& rgb, const Wavelengths& w) const {
    const MediumSpectra& s = media[size_t(m)];
    auto at = [&](const UpliftedColour& c) { return sigmoidPolyAt(c.poly, w) * c.scale; };  // (black: scale 0)
    Medium r = rgb;
    if (s.byAlbedo) {
        r.sigmaT = at(s.sigmaT);
        r.sigmaS = r.sigmaT * at(s.albedo);
    } else {
        r.sigmaS = at(s.sigmaS);
        r.sigmaT = at(s.sigmaA) + r.sigmaS;
    }
    if (r.emissive) r.Le = at(s.Le) * Vec3(srgbIlluminant(w.lambda[0]), srgbIlluminant(w.lambda[1]), srgbIlluminant(w.lambda[2]));
    if (r.density) {  // a density grid: its majorants were made for the largest channel of the RGB sigma_t
        const float before = maxComponent(rgb.sigmaT), now = maxComponent(r.sigmaT);
        r.majorantScale = before > 0 ? now / before : 0.0f;
        r.majorant = rgb.majorant * r.majorantScale;
    }
    // RGB grids: their voxels' spectra at w (kernels/medium.h, spectralGridLookup)
    for (int i = 0; i < kWavelengths; ++i) r.lambdaT[i] = (w.lambda[i] - kLambdaMin) / (kLambdaMax - kLambdaMin);
    if (!s.gridSigmaS.empty()) {
        r.specSigmaA = s.gridSigmaA.data();
        r.specSigmaS = s.gridSigmaS.data();
        r.majorants = s.majorants.data();  // (the same cells as the RGB grid's)
        r.majorant = s.majorant;
        r.majorantScale = 1;
    }
    if (!s.gridAlbedo.empty()) r.specAlbedo = s.gridAlbedo.data();
    if (!s.gridLe.empty()) {
        r.specLe = s.gridLe.data();
        r.illuminant = Vec3(srgbIlluminant(w.lambda[0]), srgbIlluminant(w.lambda[1]), srgbIlluminant(w.lambda[2]));
    }
    return r;
}

bool SpectralScene::colours(int m, const MaterialDesc& desc, BsdfParams& out, const Wavelengths& w) const {
    using K = MaterialKind;
    using P = MaterialParam;
    const ParamSpectra& ps = params[size_t(m)];
    const auto& k = constants[size_t(m)];
    // A colour parameter (its constant's slot: k's index): its file spectrum (untextured),
    // else its RGB at the hit uplifted.
    auto colour = [&](P q, int slot, Vec3 rgb) {
        if (ps[q] >= 0 && desc.texture[q] < 0) return denseAt(dense[size_t(ps[q])], w);
        return upliftedAt(k[size_t(slot)], rgb, false, w);
    };
    auto index = [&](P q, int slot, Vec3 rgb) {
        if (ps[q] >= 0 && desc.texture[q] < 0) return denseAt(dense[size_t(ps[q])], w);
        return upliftedAt(k[size_t(slot)], rgb, true, w);
    };
    // A conductor's (or a coated conductor's base's) index; a conductor given by spectra keeps
    // in reflect its RGB albedo correction (conductorAlbedoScale): 1 here.
    auto conductor = [&]() {
        setConductorIndex(out, index(P::ConductorEta, 4, conductorEta(out)), index(P::ConductorK, 5, conductorK(out)));
        out.reflect = ps[P::ConductorEta] >= 0 && ps[P::ConductorK] >= 0 ? Vec3(1.0f) : colour(P::Reflect, 2, out.reflect);
    };
    switch (desc.kind) {
        case K::Matte: out.diffuse = colour(P::Diffuse, 0, out.diffuse); break;
        case K::Glossy:
            out.diffuse = colour(P::Diffuse, 0, out.diffuse);
            out.specular = colour(P::Specular, 1, out.specular);
            break;
        case K::Reflective: out.reflect = colour(P::Reflect, 2, out.reflect); break;
        case K::Dielectric:
        case K::RoughDielectric:
        case K::ThinDielectric:
            out.reflect = colour(P::Reflect, 2, out.reflect);
            out.refract = colour(P::Refract, 3, out.refract);
            if (desc.etaSpectrum >= 0) {  // dispersion: the hero wavelength's index (pbrt-v4's TerminateSecondary)
                out.eta = dense[size_t(desc.etaSpectrum)].at(w.lambda[0]) / desc.iorOutside;
                return true;
            }
            break;
        case K::Conductor:
        case K::RoughConductor: conductor(); break;
        case K::Plastic:
        case K::RoughPlastic:
            out.diffuse = colour(P::Diffuse, 0, out.diffuse);
            out.reflect = colour(P::Reflect, 2, out.reflect);
            break;
        case K::Coated:  // a diffuse or a conductor base (its index and Fresnel scale as a conductor's)
            if (desc.coating.conductorBase) conductor();
            else out.diffuse = colour(P::Diffuse, 0, out.diffuse);
            setCoatingAlbedo(out, colour(P::Albedo, 3, coatingAlbedo(out)));
            break;
        case K::Principled: {  // the base at w; the tints normalised by the RGB base's luminance (docs/spectral.md)
            const Vec3 rgb = out.diffuse;
            out.diffuse = colour(P::Diffuse, 0, rgb);
            setPrincipledTintLuminance(out, principledLuminance(rgb));
            break;
        }
        case K::DiffuseTransmission:
            out.diffuse = colour(P::Diffuse, 0, out.diffuse);
            out.refract = colour(P::Refract, 3, out.refract);
            break;
        default: break;
    }
    return false;
}

}  // namespace wmlt
