// pbrt-v4 materials, textures and spectra (docs/pbrt.md): the materials onto the scene
// model's kinds, with their normal maps and displacement; the textures (imagemap,
// checkerboard, scale, mix, directionmix, constant, bilerp, dots, the noises, marble) with
// their mappings; rgb, spectrum (pairs, a named spectrum, an .spd file) and blackbody
// parameters as linear sRGB (scene/spectrum.h).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>

#include "kernels/texture.h"
#include "kernels/textured_params.h"
#include "scene/number.h"
#include "scene/pbrt/pbrt_importer.h"
#include "scene/pbrt/subsurface_albedo.h"
#include "scene/read_file.h"
#include "scene/spectrum.h"
#include "wavemmlt/error.h"
#include "wavemmlt/image.h"
#include "wavemmlt/quote.h"

namespace wmlt::pbrt {

namespace {
// Whether readImage decodes the file's values from sRGB (its 8- and 16-bit formats), so
// that a texture pbrt reads linearly must be encoded back.
bool decodedAsSrgb(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".tga";
}

// pbrt-v4's named metal spectra (metal-X-eta, metal-X-k) projected as every other
// unbounded spectrum is (scene/spectrum.h, under D65): computed once from the measured
// indices pbrt-v4 and Mitsuba ship (the same data; its projection against E reproduces
// Mitsuba's named conductors to five digits, tests/test_spectrum.cpp).
struct NamedRgb {
    const char* name;
    Vec3 rgb;
};
const NamedRgb kNamed[] = {{"metal-Ag-eta", {0.1284897f, 0.1235323f, 0.1508811f}},
                           {"metal-Ag-k", {4.0651789f, 3.2861540f, 2.3915668f}},
                           {"metal-Al-eta", {1.4075118f, 0.9266390f, 0.5840235f}},
                           {"metal-Al-k", {7.7409348f, 6.6023483f, 5.3599148f}},
                           {"metal-Au-eta", {0.0799591f, 0.4051012f, 1.5606973f}},
                           {"metal-Au-k", {3.3905025f, 2.5034795f, 1.7708745f}},
                           {"metal-Cu-eta", {0.1051726f, 0.9779023f, 1.2045629f}},
                           {"metal-Cu-k", {3.2737899f, 2.5924754f, 2.3689678f}},
                           {"stdillum-D65", {1.0f, 1.0f, 1.0f}}};
// Each metal's conductorAlbedoScale (scene/spectrum.h) from the same data.
const NamedRgb kAlbedoScale[] = {{"metal-Ag", {1.0004823f, 1.0007459f, 1.0007850f}},
                                 {"metal-Al", {0.9986361f, 0.9997986f, 0.9989799f}},
                                 {"metal-Au", {1.0395629f, 0.9782439f, 0.9715044f}},
                                 {"metal-Cu", {0.9875440f, 1.0074508f, 0.9967776f}}};

}  // namespace

bool namedSpectrumRgb(const std::string& name, Vec3& rgb) {
    for (const NamedRgb& n : kNamed)
        if (name == n.name) {
            rgb = n.rgb;
            return true;
        }
    return false;
}

int Importer::keepSpectrum(const SampledSpectrum& s, float scale, const std::string& source, float kelvin) {
    return wmlt::keepSpectrum(s_, s, scale, source, kelvin);
}

void Importer::keepParamSpectrum(MaterialDesc& m, MaterialParam q, float scale) {
    m.spectra[q] = lastSpectrum_;
    if (lastSpectrum_ >= 0) s_.spectra[size_t(lastSpectrum_)].scale *= scale;
}

Vec3 Importer::spectrum(Params& p, const std::string& name, Vec3 def, SpectrumUse use, SampledSpectrum* sampled) {
    const Param* q = p.find(name);
    lastSpectrum_ = -1;
    if (sampled) *sampled = SampledSpectrum{};
    if (!q) return def;
    const std::string decl = "\"" + q->type + " " + name + "\"";
    if (q->type == "rgb" || q->type == "color") {
        if (q->numbers.size() != 3) fail(q->at, decl + ": expected three values");
        const Vec3 c(float(q->numbers[0]), float(q->numbers[1]), float(q->numbers[2]));
        if (!(c.x >= 0 && c.y >= 0 && c.z >= 0)) fail(q->at, decl + ": components must be >= 0");
        if (use == SpectrumUse::Albedo && (c.x > 1 || c.y > 1 || c.z > 1))
            fail(q->at, decl + ": an RGB reflectance above 1 (pbrt-v4 refuses it too)");
        return c;
    }
    if (q->type == "float") {
        if (q->numbers.size() != 1) fail(q->at, decl + ": expected one value");
        return Vec3(float(q->numbers[0]));
    }
    SampledSpectrum s;
    if (q->type == "blackbody") {
        if (q->numbers.size() != 1 || !(q->numbers[0] > 0)) fail(q->at, decl + ": expected one temperature > 0 (kelvin)");
        const double T = q->numbers[0];  // Planck's law over its peak, as pbrt-v4's BlackbodySpectrum
        for (int l = 360; l <= 830; ++l) {
            s.lambda.push_back(l);
            s.value.push_back(blackbodyNormalized(l, T));
        }
    } else if (q->type == "spectrum") {
        if (!q->strings.empty()) {
            if (q->strings.size() != 1) fail(q->at, decl + ": expected one name or file");
            Vec3 rgb;
            if (namedSpectrumRgb(q->strings[0], rgb)) return rgb;
            const std::string f = q->strings[0];
            if (f.rfind("metal-", 0) == 0 || f.rfind("glass-", 0) == 0 || f.rfind("stdillum-", 0) == 0 || f.rfind("canon_", 0) == 0)
                fail(q->at, decl + ": the named spectrum \"" + f + "\" is not in wavemmlt's table (docs/pbrt.md): give it as an .spd file");
            const std::string why = readSpectrumFile(resolve(f), s);
            if (!why.empty()) fail(q->at, resolve(f) + ": " + why);
        } else {
            if (q->numbers.size() < 4 || q->numbers.size() % 2) fail(q->at, decl + ": expected wavelength-value pairs");
            for (size_t i = 0; i < q->numbers.size(); i += 2) {
                if (i > 0 && !(q->numbers[i] > s.lambda.back())) fail(q->at, decl + ": the wavelengths must increase");
                s.lambda.push_back(q->numbers[i]);
                s.value.push_back(q->numbers[i + 1]);
            }
        }
    } else {
        fail(q->at, decl + ": expected an rgb, spectrum or blackbody value");
    }
    if (sampled) *sampled = s;
    const std::string source = q->type == "blackbody" ? "blackbody " + std::to_string(int(std::lround(q->numbers[0]))) + " K"
                               : !q->strings.empty()  ? q->strings[0]
                                                      : "pairs (line " + std::to_string(q->at.line) + ")";
    const float kelvin = q->type == "blackbody" ? float(q->numbers[0]) : 0.0f;
    if (use != SpectrumUse::Illuminant) {
        lastSpectrum_ = keepSpectrum(s, 1.0f, source, kelvin);
        return spectrumToRgb(s, true);
    }
    // pbrt-v4 scales an emitter's spectrum to a luminance of 1 (times its scale)
    const Vec3 c = spectrumToRgb(s, false);
    const float y = luminance(c);
    if (!(y > 0)) fail(q->at, decl + ": the spectrum has no luminance");
    lastSpectrum_ = keepSpectrum(s, 1.0f / y, source, kelvin);
    return c / y;
}

Vec3 Importer::colourParam(Params& p, const std::string& name, Vec3 def, int& texture, bool floatParam) {
    lastSpectrum_ = -1;
    const Param* q = p.find(name);
    if (q && q->type == "texture") {
        if (q->strings.size() != 1) fail(q->at, "\"texture " + name + "\": expected one texture name");
        const std::string& t = q->strings[0];
        auto c = constTextures_.find(t);
        auto it = textures_.find(t);
        if (c == constTextures_.end() && it == textures_.end()) fail(q->at, "\"texture " + name + "\": no texture named \"" + t + "\"");
        if (floatTexture_[t] != floatParam)
            fail(q->at, "\"texture " + name + "\": \"" + t + "\" is a " + (floatParam ? "spectrum" : "float") + " texture, the parameter takes a " +
                            (floatParam ? "float" : "spectrum") + " one");
        if (c != constTextures_.end()) return c->second;
        texture = it->second;
        return Vec3(1.0f);
    }
    return floatParam ? Vec3(float(p.getFloat(name, def.x))) : spectrum(p, name, def, SpectrumUse::Albedo);
}

float Importer::floatParam(Params& p, const std::string& name, float def, int& texture) { return colourParam(p, name, Vec3(def), texture, true).x; }

int Importer::currentMaterial() {
    if (g_.material >= 0 || g_.material == kInterfaceMaterial) return g_.material;
    if (defaultMaterial_ < 0) {  // pbrt's default: diffuse, reflectance 0.5
        MaterialDesc m;
        m.kind = MaterialKind::Matte;
        m.diffuse = Vec3(0.5f);
        m.id = defaultMaterial_ = int(s_.materials.size());
        s_.materials.push_back(m);
    }
    return defaultMaterial_;
}

// A conductor's eta and k (prefix "" or "conductor."), relative to a medium of index
// `outside` (a coated conductor's coating, as pbrt-v4 divides them): rgb, spectra, .spd files or pbrt's
// named metals (default copper), projected under D65; spectral ones with the albedo per
// channel made the spectral conductor's in m.reflect (conductorAlbedoScale: the projected
// indices alone miss gold's red by 4.6%; a named metal's table value is for vacuum).
void Importer::conductorIndices(Params& p, const std::string& prefix, MaterialDesc& m, float outside) {
    Vec3 eta, kk;
    namedSpectrumRgb("metal-Cu-eta", eta);
    namedSpectrumRgb("metal-Cu-k", kk);
    SampledSpectrum se, sk;
    // a spectrum, or a texture whose value at a hit is the index there (MaterialParam::ConductorEta, K)
    auto index = [&](const std::string& n, Vec3 def, MaterialParam q, SampledSpectrum& s) {
        if (const Param* x = p.find(n); x && x->type == "texture") return colourParam(p, n, def, m.texture[q]) / outside;
        return spectrum(p, n, def, SpectrumUse::Unbounded, &s) / outside;
    };
    m.conductorEta = index(prefix + "eta", eta, MaterialParam::ConductorEta, se);
    keepParamSpectrum(m, MaterialParam::ConductorEta, 1 / outside);
    m.conductorK = index(prefix + "k", kk, MaterialParam::ConductorK, sk);
    keepParamSpectrum(m, MaterialParam::ConductorK, 1 / outside);
    m.reflect = Vec3(1.0f);
    if (!se.lambda.empty() && !sk.lambda.empty()) {  // both sampled (pairs, files)
        for (double& v : se.value) v /= outside;
        for (double& v : sk.value) v /= outside;
        m.reflect = conductorAlbedoScale(se, sk, m.conductorEta, m.conductorK);
        return;
    }
    auto named = [&](const std::string& n, const char* def) {  // the metal's name, or ""
        const Param* q = p.find(n);
        return !q ? std::string(def) : q->type == "spectrum" && q->strings.size() == 1 ? q->strings[0] : std::string();
    };
    const std::string ne = named(prefix + "eta", "metal-Cu-eta"), nk = named(prefix + "k", "metal-Cu-k");
    for (const NamedRgb& a : kAlbedoScale)
        if (ne == std::string(a.name) + "-eta" && nk == std::string(a.name) + "-k") m.reflect = a.rgb;
}

int Importer::material(const std::string& type, Directive& d) {
    Params& p = d.params;
    MaterialDesc m;
    m.twoSided = true;
    // pbrt's roughness (Trowbridge-Reitz = GGX): roughness or u/vroughness, remapped to
    // alpha = sqrt(r) unless remaproughness is false; effectively smooth below 1e-3.
    const bool remap = p.getBool("remaproughness", true);
    // A roughness pair (prefix "": roughness, uroughness, vroughness) as alphas: constants, or
    // textures (tu, tv >= 0) whose value at a hit is the roughness there (remapped or not:
    // MaterialDesc::alphaRemap); the constant of a textured one is 1.
    auto alphas = [&](const std::string& prefix, float& au, float& av, int& tu, int& tv) {
        int tr = -1;
        tu = tv = -1;
        const float r = floatParam(p, prefix + "roughness", 0, tr);
        const float ur = p.has(prefix + "uroughness") ? floatParam(p, prefix + "uroughness", r, tu) : (tu = tr, r);
        const float vr = p.has(prefix + "vroughness") ? floatParam(p, prefix + "vroughness", r, tv) : (tv = tr, r);
        if (!(ur >= 0 && vr >= 0)) fail(d.at, "roughness must be >= 0");
        au = tu >= 0 ? 1.0f : remap ? std::sqrt(ur) : ur;
        av = tv >= 0 ? 1.0f : remap ? std::sqrt(vr) : vr;
    };
    // The material's own roughness (m.alpha, alphaV and their textures); whether it is rough.
    auto rough = [&]() {
        float au, av;
        alphas("", au, av, m.texture[MaterialParam::AlphaU], m.texture[MaterialParam::AlphaV]);
        m.distribution = MicrofacetType::GGX;
        m.alpha = au;
        m.alphaV = av;
        m.alphaRemap = remap;
        const bool textured = m.texture[MaterialParam::AlphaU] >= 0 || m.texture[MaterialParam::AlphaV] >= 0;
        return textured || std::max(au, av) >= 1e-3f;
    };
    // A dielectric's eta: a float, or a spectrum whose value at 550 nm is used (no dispersion).
    auto dielectricEta = [&](double def) {
        double eta = def;
        if (const Param* q = p.find("eta")) {
            if (q->type == "float") {
                eta = p.getFloat("eta", 1.5);
            } else if (q->type == "spectrum") {  // its value at 550 nm in RGB; dispersion in spectral PT
                if (!q->strings.empty() && q->strings[0].rfind("glass-", 0) == 0) {
                    const Sellmeier* g = namedGlass(q->strings[0]);
                    if (!g)
                        fail(q->at, "the named spectrum \"" + q->strings[0] +
                                        "\" is not one of pbrt-v4's glasses (glass-BK7, -BAF10, -FK51A, -LASF9, -F5, -F10, -F11)");
                    SpectrumDesc sd;
                    sd.kind = SpectrumDesc::Kind::Sellmeier;
                    std::copy(g->B, g->B + 3, sd.sellmeierB);
                    std::copy(g->C, g->C + 3, sd.sellmeierC);
                    sd.source = q->strings[0];
                    s_.spectra.push_back(sd);
                    m.etaSpectrum = int(s_.spectra.size()) - 1;
                    return double(sellmeierEta(*g, 550.0f));  // (an RGB render's index: renderWarnings says so)
                }
                SampledSpectrum s;
                if (!q->strings.empty()) {
                    const std::string why = readSpectrumFile(resolve(q->strings[0]), s);
                    if (!why.empty()) fail(q->at, resolve(q->strings[0]) + ": " + why);
                } else {
                    for (size_t i = 0; i + 1 < q->numbers.size(); i += 2) {
                        s.lambda.push_back(q->numbers[i]);
                        s.value.push_back(q->numbers[i + 1]);
                    }
                }
                if (s.lambda.empty() || s.lambda.front() > 550 || s.lambda.back() < 550) fail(q->at, "\"spectrum eta\": no value at 550 nm");
                size_t i = 0;
                while (i + 2 < s.lambda.size() && s.lambda[i + 1] < 550) ++i;
                const double t = s.lambda[i + 1] > s.lambda[i] ? (550 - s.lambda[i]) / (s.lambda[i + 1] - s.lambda[i]) : 0;
                eta = s.value[i] * (1 - t) + s.value[i + 1] * t;
                m.etaSpectrum = keepSpectrum(s, 1.0f, !q->strings.empty() ? q->strings[0] : "pairs (line " + std::to_string(q->at.line) + ")");
                warn(q->at, "a spectral eta: --tracer pt --spectral renders its dispersion; otherwise its value at 550 nm, " + std::to_string(eta));
            } else {
                fail(q->at, "\"" + q->type + " eta\": expected a float or a spectrum");
            }
        }
        return eta;
    };
    // pbrt-v4's conductor by reflectance r: eta 1, k = 2 sqrt(r) / sqrt(1 - r), relative to a
    // medium of index `outside`; a textured r per hit (MaterialParam::ConductorReflectance).
    auto reflectanceConductor = [&](float outside) {
        int t = -1;
        const Vec3 r = colourParam(p, "reflectance", Vec3(0.0f), t);
        keepParamSpectrum(m, MaterialParam::ConductorReflectance);
        m.texture[MaterialParam::ConductorReflectance] = t;
        m.conductorEta = Vec3(1.0f / outside);
        m.conductorK = (t >= 0 ? Vec3(1.0f) : conductorKOfReflectance(r)) / outside;
    };
    if (type == "diffuse") {
        m.kind = MaterialKind::Matte;
        m.diffuse = colourParam(p, "reflectance", Vec3(0.5f), m.texture[MaterialParam::Diffuse]);
        keepParamSpectrum(m, MaterialParam::Diffuse);
    } else if (type == "conductor") {
        m.kind = rough() ? MaterialKind::RoughConductor : MaterialKind::Conductor;
        m.reflect = Vec3(1.0f);
        if (p.has("reflectance")) {
            if (p.has("eta") || p.has("k")) fail(d.at, "give either eta and k or reflectance, not both");
            reflectanceConductor(1);
        } else {
            conductorIndices(p, "", m);
        }
    } else if (type == "dielectric" || type == "thindielectric") {
        const double eta = dielectricEta(1.5);
        if (!(eta > 0) || eta == 1) fail(d.at, type + ": eta must be > 0 and not 1");
        m.iorInside = float(eta);
        m.iorOutside = 1;
        m.reflect = m.refract = Vec3(1.0f);
        if (type == "thindielectric") m.kind = MaterialKind::ThinDielectric;
        else m.kind = rough() ? MaterialKind::RoughDielectric : MaterialKind::Dielectric;
    } else if (type == "coateddiffuse" || type == "coatedconductor") {
        // pbrt-v4's LayeredBxDF: a dielectric interface over a diffuse or conductor base
        m.kind = MaterialKind::Coated;
        MaterialDesc::Coating& c = m.coating;
        const bool conductor = type == "coatedconductor";
        const std::string ip = conductor ? "interface." : "";
        float au, av;
        alphas(ip, au, av, m.texture[MaterialParam::AlphaU], m.texture[MaterialParam::AlphaV]);  // the interface's: per hit, textured or not
        m.distribution = MicrofacetType::GGX;
        m.alpha = au;
        m.alphaV = av;
        m.alphaRemap = remap;
        double eta = 1.5;
        if (const Param* q = p.find(ip + "eta")) {
            if (q->type != "float") fail(q->at, "\"" + q->type + " " + q->name + "\": give the coating's index as a float");
            eta = p.getFloat(ip + "eta", 1.5);
        }
        if (!(eta > 0)) fail(d.at, type + ": eta must be > 0");
        m.iorInside = float(eta);
        m.iorOutside = 1;
        c.thickness = float(p.getFloat("thickness", 0.01));
        c.g = float(p.getFloat("g", 0));
        c.maxDepth = p.getInt("maxdepth", 10);
        c.nSamples = p.getInt("nsamples", 1);
        if (!(c.thickness > 0) || !(c.g > -1 && c.g < 1) || c.maxDepth < 1 || c.maxDepth > 1000 || c.nSamples < 1 || c.nSamples > 1000)
            fail(d.at, type + ": thickness must be > 0, g in (-1, 1), maxdepth and nsamples 1 to 1000");
        c.albedo = colourParam(p, "albedo", Vec3(0.0f), m.texture[MaterialParam::Albedo]);
        keepParamSpectrum(m, MaterialParam::Albedo);
        m.reflect = Vec3(1.0f);
        if (!conductor) {
            m.diffuse = colourParam(p, "reflectance", Vec3(0.5f), m.texture[MaterialParam::Diffuse]);
            keepParamSpectrum(m, MaterialParam::Diffuse);
        } else {
            c.conductorBase = true;
            alphas("conductor.", c.baseAlpha, c.baseAlphaV, m.texture[MaterialParam::BaseAlphaU], m.texture[MaterialParam::BaseAlphaV]);
            if (p.has("reflectance")) {
                if (p.has("conductor.eta") || p.has("conductor.k")) fail(d.at, "give either conductor.eta and conductor.k or reflectance, not both");
                reflectanceConductor(m.iorInside);
            } else {  // pbrt-v4: the base's index relative to the coating's
                conductorIndices(p, "conductor.", m, m.iorInside);
            }
        }
    } else if (type == "mix") {
        const Param* q = p.find("materials");
        if (!q || q->type != "string" || q->strings.size() != 2) fail(d.at, "mix needs \"string materials\" with two names");
        m.kind = MaterialKind::Blend;
        m.blendPerHit = true;  // one part per hit, as pbrt-v4 (so each part's colours render spectrally)
        for (int k = 0; k < 2; ++k) {
            auto it = namedMaterials_.find(q->strings[size_t(k)]);
            if (it == namedMaterials_.end()) fail(q->at, "mix: no material named \"" + q->strings[size_t(k)] + "\"");
            if (it->second == kInterfaceMaterial) fail(q->at, "mix: the interface material cannot be a part");
            const MaterialDesc& part = s_.materials[size_t(it->second)];
            if (part.kind == MaterialKind::Blend) fail(q->at, "a mix inside a mix is not supported");
            m.blendPart[k] = it->second;
        }
        // pbrt chooses material 1 with probability amount per hit: blendPerHit
        m.blendWeight = floatParam(p, "amount", 0.5f, m.texture[MaterialParam::BlendWeight]);
        if (m.texture[MaterialParam::BlendWeight] >= 0) m.blendWeight = 1;
        if (!(m.blendWeight >= 0 && m.blendWeight <= 1)) fail(d.at, "mix: amount must be in [0, 1]");
    } else if (type == "diffusetransmission") {  // R / pi on the side of wo, T / pi through
        m.kind = MaterialKind::DiffuseTransmission;
        const float scale = floatParam(p, "scale", 1, m.texture[MaterialParam::Scale]);
        m.diffuse = colourParam(p, "reflectance", Vec3(0.25f), m.texture[MaterialParam::Diffuse]) * scale;
        keepParamSpectrum(m, MaterialParam::Diffuse, scale);
        m.refract = colourParam(p, "transmittance", Vec3(0.25f), m.texture[MaterialParam::Refract]) * scale;
        keepParamSpectrum(m, MaterialParam::Refract, scale);
    } else if (type == "interface") {  // no surface: rays cross it (ShapeDesc::passThrough)
        return kInterfaceMaterial;
    } else if (type == "subsurface") {
        // pbrt-v4's subsurface as what it describes: a dielectric boundary (eta 1.33, rough
        // as a dielectric's) over a homogeneous scattering interior, rendered by a volumetric
        // random walk (the media code: exact for that medium, where pbrt's diffusion BSSRDF
        // is an approximation). sigma_a and sigma_s (pbrt's defaults, per mm) times scale, g;
        // or a diffuse `reflectance` and mean free path `mfp` (1) times scale, from which pbrt's
        // diffusion table gives them (subsurface_albedo.h).
        if (const Param* q = p.find("name"))
            fail(q->at, "subsurface: \"name\" (pbrt's measured media) is not supported yet: give sigma_a and sigma_s, or reflectance");
        if (p.has("reflectance") && (p.has("sigma_a") || p.has("sigma_s")))
            fail(p.find("reflectance")->at, "subsurface: give reflectance (and mfp) or sigma_a and sigma_s, not both");
        const double eta = dielectricEta(1.33);
        if (!(eta > 0) || eta == 1) fail(p.has("eta") ? p.find("eta")->at : d.at, "subsurface: eta must be > 0 and not 1");
        m.iorInside = float(eta);
        m.iorOutside = 1;
        m.reflect = m.refract = Vec3(1.0f);
        m.kind = rough() ? MaterialKind::RoughDielectric : MaterialKind::Dielectric;
        MediumDesc md;
        md.line = d.at.line;
        md.name = "the subsurface material of " + *d.at.file + ":" + std::to_string(d.at.line);
        const float scale = float(p.getFloat("scale", 1));
        md.g = float(p.getFloat("g", 0));
        if (!(md.g > -1 && md.g < 1)) fail(p.has("g") ? p.find("g")->at : d.at, "subsurface: g must be in (-1, 1)");
        if (p.has("reflectance")) {
            int t = -1;
            const Vec3 r = colourParam(p, "reflectance", Vec3(1.0f), t);
            if (t >= 0) fail(p.find("reflectance")->at, "subsurface: a textured reflectance is not supported (a medium has one albedo)");
            const Vec3 mfp = spectrum(p, "mfp", Vec3(1.0f), SpectrumUse::Unbounded) * scale;
            if (!(mfp.x > 0 && mfp.y > 0 && mfp.z > 0) || !isFinite(mfp))
                fail(p.has("mfp") ? p.find("mfp")->at : d.at, "subsurface: mfp times scale must be > 0");
            const DiffusionAlbedo table = diffusionAlbedo(md.g, eta);
            for (int c = 0; c < 3; ++c) {
                const double rho = albedoOf(table, std::clamp(double(r[c]), 0.0, 1.0));
                md.sigmaS[c] = float(rho / mfp[c]);
                md.sigmaA[c] = float((1 - rho) / mfp[c]);
            }
        } else {
            md.sigmaA = spectrum(p, "sigma_a", Vec3(0.0011f, 0.0024f, 0.014f), SpectrumUse::Unbounded) * scale;
            md.sigmaS = spectrum(p, "sigma_s", Vec3(2.55f, 3.21f, 3.77f), SpectrumUse::Unbounded) * scale;
        }
        auto bad = [](Vec3 v) { return !isFinite(v) || v.x < 0 || v.y < 0 || v.z < 0; };
        if (bad(md.sigmaA) || bad(md.sigmaS)) fail(d.at, "subsurface: sigma_a and sigma_s (times scale) must be finite and >= 0");
        namedMedia_[md.name] = int(s_.media.size());
        subsurfaceMedium_[int(s_.materials.size())] = md.name;  // (this material's index, below)
        s_.media.push_back(std::move(md));
    } else if (type == "measured" || type == "hair") {
        fail(d.at, "Material \"" + type + "\" is not supported yet (docs/pbrt.md)");
    } else {
        fail(d.at, "unknown Material \"" + type + "\"");
    }
    // pbrt-v4's normal map (a tangent-space image, read linearly, at (u, 1 - v), repeating)
    // before its bump map (a float texture `displacement`): MaterialDesc::normalMap, bump.
    if (const Param* q = p.find("normalmap")) {
        TextureDesc t;
        t.kind = TextureKind::Bitmap;
        const std::string path = resolve(p.getString("normalmap", ""));
        try {
            t.image = readSceneImage(path);
        } catch (const InputError& e) {
            fail(q->at, e.what());
        }
        if (decodedAsSrgb(path))
            for (float& v : t.image.rgb) v = linearToSrgb(v);  // readImage decoded sRGB: pbrt reads normal maps linearly
        const float flip[6] = {1, 0, 0, 0, -1, 1};
        std::copy(flip, flip + 6, t.uvTransform);
        t.id = m.normalMap = int(s_.textures.size());
        s_.textures.push_back(std::move(t));
    }
    if (const Param* q = p.find("displacement")) {
        int tex = -1;
        const float d = floatParam(p, "displacement", 0, tex);
        if (tex < 0 && d != 0) warn(q->at, "a constant displacement does not bump the surface: ignored");
        if (tex >= 0 && m.normalMap < 0) {
            m.bump = tex;
            m.bumpPbrt = true;
        }
    }
    m.id = int(s_.materials.size());
    s_.materials.push_back(m);
    return m.id;
}

namespace {

// An upper bound of the magnitude a texture's value can take: an image's largest texel, its
// constants, the product of a scale's operands, the larger of a mix's or checkerboard's. A
// texture whose bound passes a float's range (an imagemap of texels up to 10 with scale 1e38)
// would make infinities wherever it is read: finite parameters whose product is not.
double textureBound(const std::vector<TextureDesc>& tex, const TextureDesc& t) {
    auto maxOf = [](Vec3 c) { return double(std::max({std::fabs(c.x), std::fabs(c.y), std::fabs(c.z)})); };
    auto operand = [&](int k, Vec3 c) { return t.operand[k] >= 0 ? textureBound(tex, tex[size_t(t.operand[k])]) : maxOf(c); };
    switch (t.kind) {
        case TextureKind::Bitmap: {
            double m = 0;
            for (float v : t.image.rgb) m = std::max(m, double(std::fabs(v)));  // (a non-finite texel: infinite)
            return m;
        }
        case TextureKind::Scale: return operand(0, t.colour1) * operand(1, t.colour2);
        case TextureKind::Mix:
        case TextureKind::DirectionMix:
        case TextureKind::Checkerboard: return std::max(operand(0, t.colour1), operand(1, t.colour2));
        default: return std::max({1.0, maxOf(t.colour1), maxOf(t.colour2)});  // the procedurals: their colours, values near [0, 1]
    }
}

}  // namespace

void Importer::texture(Directive& d) {
    Params& p = d.params;
    const std::string& name = d.strings[0];
    const std::string& kind = d.strings[1];
    const std::string& cls = d.strings[2];
    if (kind != "spectrum" && kind != "float") fail(d.at, "Texture \"" + name + "\": \"" + kind + "\" is not spectrum or float");
    const bool isFloat = kind == "float";
    if (textures_.count(name) || constTextures_.count(name)) fail(d.at, "Texture \"" + name + "\" defined twice");
    TextureDesc t;
    // The texture's space: the CTM here, inverted (pbrt's textureFromRender), for the
    // mappings other than uv and for the solid textures.
    if (g_.ctm.det3() == 0) fail(d.at, "Texture \"" + name + "\": the current transformation is singular");
    const Matrix fromWorld = g_.ctm.inverse();
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) t.textureFromWorld[4 * r + c] = float(fromWorld.m[r][c]);
    // The 2D mapping (s, t): uv's (su u + du, sv v + dv), or spherical, cylindrical, planar
    // (TextureMapping), planar's offsets udelta, vdelta; su, sv, du, dv go to uvTransform.
    const std::string mapping = p.getString("mapping", "uv");
    float su = 1, sv = 1, du = 0, dv = 0;
    if (mapping == "uv") {
        su = float(p.getFloat("uscale", 1)), sv = float(p.getFloat("vscale", 1));
        du = float(p.getFloat("udelta", 0)), dv = float(p.getFloat("vdelta", 0));
    } else if (mapping == "spherical") {
        t.mapping = TextureMapping::Spherical;
    } else if (mapping == "cylindrical") {
        t.mapping = TextureMapping::Cylindrical;
    } else if (mapping == "planar") {
        t.mapping = TextureMapping::Planar;
        t.planarS = p.getPoint3("v1", Vec3(1, 0, 0));
        t.planarT = p.getPoint3("v2", Vec3(0, 1, 0));
        du = float(p.getFloat("udelta", 0)), dv = float(p.getFloat("vdelta", 0));
    } else {
        fail(p.find("mapping")->at, "mapping \"" + mapping + "\" is not uv, spherical, cylindrical or planar");
    }
    const float uvScale[6] = {su, 0, du, 0, sv, dv};  // (s, t) as pbrt maps them
    // a texture or constant operand k of scale and mix: colour1 / colour2 hold constants
    auto operand = [&](const char* pname, Vec3 def, int k) {
        int tex = -1;
        const Vec3 v = colourParam(p, pname, def, tex, isFloat);
        t.operand[k] = tex;
        if (k == 0) t.colour1 = tex >= 0 ? Vec3(1.0f) : v;
        if (k == 1) t.colour2 = tex >= 0 ? Vec3(1.0f) : v;
        return v;
    };
    if (cls == "constant") {
        int tex = -1;
        const Vec3 v = colourParam(p, "value", Vec3(1.0f), tex, isFloat);
        constTextures_[name] = v;
        floatTexture_[name] = isFloat;
        return;
    } else if (cls == "imagemap") {
        t.kind = TextureKind::Bitmap;
        const std::string f = p.getString("filename", "");
        if (f.empty()) fail(d.at, "imagemap needs \"string filename\"");
        const std::string path = resolve(f);
        try {
            t.image = readSceneImage(path);
        } catch (const InputError& e) {
            fail(d.at, e.what());
        }
        const std::string filter = p.getString("filter", "bilinear");
        if (filter == "point") t.nearest = true;
        else if (filter == "trilinear" || filter == "ewa")
            warn(p.find("filter")->at, "filter \"" + filter + "\" is evaluated bilinearly (no MIP maps)");
        else if (filter != "bilinear") fail(p.find("filter")->at, "filter \"" + filter + "\" is not point, bilinear, trilinear or ewa");
        p.getFloat("maxanisotropy", 8);
        const std::string wrap = p.getString("wrap", "repeat");
        if (wrap == "repeat") t.wrap = TextureWrap::Repeat;
        else if (wrap == "clamp") t.wrap = TextureWrap::Clamp;
        else fail(p.find("wrap")->at, "wrap \"" + wrap + "\" is not supported (repeat and clamp are)");
        const bool encoded = decodedAsSrgb(path);
        const std::string enc = p.getString("encoding", encoded ? "sRGB" : "linear");
        if (enc == "linear" && encoded) {
            for (float& v : t.image.rgb) v = linearToSrgb(v);  // readImage decoded sRGB
        } else if (enc.rfind("gamma ", 0) == 0 && encoded) {
            double g = 0;
            if (!parseNumber(enc.substr(6), false, g) || !(g > 0)) fail(p.find("encoding")->at, "encoding \"" + enc + "\": bad gamma");
            for (float& v : t.image.rgb) v = float(std::pow(double(linearToSrgb(v)), g));
        } else if (enc != "sRGB" && enc != "linear") {
            fail(p.find("encoding")->at, "encoding \"" + enc + "\" is not sRGB, linear or gamma g");
        }
        // pbrt looks images up at (s, 1 - t), row 0 on top: wavemmlt's v = 0 is the top row
        const float uv[6] = {su, 0, du, 0, -sv, 1 - dv};
        std::copy(uv, uv + 6, t.uvTransform);
        const float scale = float(p.getFloat("scale", 1));
        if (p.getBool("invert", false)) {  // pbrt: max(0, 1 - scale texel), made here once
            for (float& v : t.image.rgb) v = std::max(0.0f, 1.0f - scale * v);
        } else if (scale != 1) {  // the image times its scale: a Scale texture over it
            t.id = int(s_.textures.size());
            s_.textures.push_back(std::move(t));
            TextureDesc sc;
            sc.kind = TextureKind::Scale;
            sc.operand[0] = int(s_.textures.size()) - 1;
            sc.colour2 = Vec3(scale);
            t = std::move(sc);
        }
    } else if (cls == "checkerboard") {
        if (p.getInt("dimension", 2) != 2) fail(d.at, "a 3D checkerboard is not supported");
        t.kind = TextureKind::Checkerboard;
        int a = -1, b = -1;
        t.colour1 = colourParam(p, "tex1", Vec3(1.0f), a, isFloat);
        t.colour2 = colourParam(p, "tex2", Vec3(0.0f), b, isFloat);
        if (a >= 0 || b >= 0) fail(d.at, "checkerboard: tex1 and tex2 must be constants");
        // pbrt: tex1 where floor(s) + floor(t) is even; Mitsuba's checkerboard on (s, t) / 2
        const float uv[6] = {su / 2, 0, du / 2, 0, sv / 2, dv / 2};
        std::copy(uv, uv + 6, t.uvTransform);
    } else if (cls == "dots") {
        t.kind = TextureKind::Dots;
        operand("inside", Vec3(1.0f), 0);
        operand("outside", Vec3(0.0f), 1);
        std::copy(uvScale, uvScale + 6, t.uvTransform);
    } else if (cls == "directionmix") {
        t.kind = TextureKind::DirectionMix;
        operand("tex1", Vec3(0.0f), 0);
        operand("tex2", Vec3(1.0f), 1);
        // pbrt: dir in the texture's space, normalised in world space
        const Vec3 dir = g_.ctm.vector(p.getPoint3("dir", Vec3(0, 1, 0)));
        if (!(length(dir) > 0) || !isFinite(dir)) fail(p.find("dir")->at, "directionmix: dir must be a nonzero vector");
        t.direction = normalize(dir);
    } else if (cls == "bilerp") {
        t.kind = TextureKind::Bilerp;
        auto corner = [&](const char* n, Vec3 def) {
            const Param* q = p.find(n);
            if (q && q->type == "texture") fail(q->at, std::string("bilerp: ") + n + " must be a constant");
            return isFloat ? Vec3(float(p.getFloat(n, def.x))) : spectrum(p, n, def, SpectrumUse::Albedo);
        };
        t.colour1 = corner("v00", Vec3(0.0f));
        t.colour2 = corner("v01", Vec3(1.0f));
        t.colour3 = corner("v10", Vec3(0.0f));
        t.colour4 = corner("v11", Vec3(1.0f));
        std::copy(uvScale, uvScale + 6, t.uvTransform);
    } else if (cls == "fbm" || cls == "wrinkled" || cls == "windy" || cls == "marble") {
        if (cls == "marble" ? isFloat : !isFloat) fail(d.at, "\"" + cls + "\" is a " + (isFloat ? "spectrum" : "float") + " texture in pbrt-v4");
        t.kind = cls == "fbm"        ? TextureKind::Fbm
                 : cls == "wrinkled" ? TextureKind::Wrinkled
                 : cls == "windy"    ? TextureKind::Windy
                                     : TextureKind::PbrtMarble;
        if (cls != "windy") {
            t.octaves = p.getInt("octaves", 8);
            t.roughness = float(p.getFloat("roughness", 0.5));
            if (t.octaves < 0 || t.octaves > 32) fail(p.find("octaves")->at, "octaves must be in [0, 32]");
            if (!std::isfinite(t.roughness)) fail(p.find("roughness")->at, "roughness must be finite");
        }
        if (cls == "marble") {
            t.noiseScale = float(p.getFloat("scale", 1));
            t.variation = float(p.getFloat("variation", 0.2));
            if (!std::isfinite(t.noiseScale) || !std::isfinite(t.variation)) fail(d.at, "marble: scale and variation must be finite");
        }
    } else if (cls == "scale") {
        t.kind = TextureKind::Scale;
        operand("tex", Vec3(1.0f), 0);
        int tex = -1;
        const float s = floatParam(p, "scale", 1, tex);
        t.operand[1] = tex;
        t.colour2 = Vec3(tex >= 0 ? 1.0f : s);
    } else if (cls == "mix") {
        t.kind = TextureKind::Mix;
        operand("tex1", Vec3(0.0f), 0);
        operand("tex2", Vec3(1.0f), 1);
        int tex = -1;
        t.amount = floatParam(p, "amount", 0.5f, tex);
        t.operand[2] = tex;
    } else {
        fail(d.at, "Texture class \"" + cls + "\" is not supported yet (docs/pbrt.md)");
    }
    if (const double bound = textureBound(s_.textures, t); !fitsFloat(bound))
        fail(d.at, "Texture " + quoteToken(name) + ": its values times its scale reach " + numberText(bound) + ", beyond a float's range");
    t.id = int(s_.textures.size());
    textures_[name] = t.id;
    floatTexture_[name] = isFloat;
    s_.textures.push_back(std::move(t));
}

}  // namespace wmlt::pbrt
