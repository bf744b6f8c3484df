// A material's textured parameters at one point: its constants (a hit's BsdfParams, written
// by materialAt) finished with its textures there, one rule per parameter (MaterialParam),
// the same for every kind: a kind reads the parameters readsParam lists, each where
// BsdfParams keeps it for that kind (bsdf.h: conductorEta, coatingAlbedo, ...). The texture
// stage runs it over a round's hits (stages/core/textures.h); a blend with textured parts
// runs it on its parts where its kernel needs them (textureBlendPart). Pure: no allocation,
// no state.
#pragma once
#include <algorithm>
#include <cmath>
#include <vector>

#include "kernels/bsdf.h"
#include "kernels/texture.h"

namespace wmlt {

// Whether kind k reads parameter q: a texture on a parameter the kind does not read costs
// nothing (roughplastic's alpha is not among them: its tables are made for one alpha, and
// Mitsuba 3 reads a number there too).
constexpr bool readsParam(MaterialKind k, MaterialParam q) {
    using M = MaterialKind;
    using P = MaterialParam;
    if (int(q) >= int(P::Principled)) return k == M::Principled;
    switch (q) {
        case P::Diffuse:
            return k == M::Matte || k == M::Glossy || k == M::Plastic || k == M::RoughPlastic || k == M::Principled || k == M::Coated ||
                   k == M::DiffuseTransmission;
        case P::Specular: return k == M::Glossy;
        case P::Reflect:
            return k == M::Reflective || k == M::Dielectric || k == M::Conductor || k == M::RoughConductor || k == M::RoughDielectric ||
                   k == M::ThinDielectric || k == M::Plastic || k == M::RoughPlastic;
        case P::Refract: return k == M::Dielectric || k == M::RoughDielectric || k == M::ThinDielectric || k == M::DiffuseTransmission;
        case P::AlphaU:
        case P::AlphaV: return k == M::RoughConductor || k == M::RoughDielectric || k == M::Coated;
        case P::ConductorEta:
        case P::ConductorK:
        case P::ConductorReflectance: return k == M::Conductor || k == M::RoughConductor || k == M::Coated;
        case P::BaseAlphaU:
        case P::BaseAlphaV:
        case P::Albedo: return k == M::Coated;
        case P::Scale: return k == M::DiffuseTransmission;
        case P::BlendWeight: return k == M::Blend;  // (its parts' own: the blend's kernel)
        case P::Principled: break;
    }
    return false;
}

// pbrt-v4's conductor from a reflectance r (eta 1): k = 2 sqrt(r) / sqrt(1 - r), per channel
// (r >= 1: a large k, a perfect mirror).
inline Vec3 conductorKOfReflectance(Vec3 r) {
    auto k = [](float x) { return x >= 1 ? 1e4f : 2 * std::sqrt(std::max(x, 0.0f)) / std::sqrt(1 - x); };
    return Vec3(k(r.x), k(r.y), k(r.z));
}

// Parameter q's texture value t at a hit applied to its constant in out (MaterialParam's
// rules); a principled parameter goes to principled[] (setPrincipled makes the lobes).
inline void applyParamTexture(const MaterialDesc& m, MaterialParam q, Vec3 t, BsdfParams& out, float* principled) {
    using P = MaterialParam;
    // a roughness: luminance r, or sqrt(r) for pbrt's remapped roughness, times alpha (>= 1e-4)
    auto alpha = [&](float a) {
        const float r = luminance(t);
        return std::max(a * (m.alphaRemap ? std::sqrt(std::max(r, 0.0f)) : r), 1e-4f);
    };
    // a rough kind's constant alphas are x->dist's (0 in out: distributionAt), a coat's ride in
    // out: both into out before either is textured
    auto alphas = [&]() {
        if (!(out.alphaX > 0) && out.x) {
            out.alphaX = out.x->dist.alphaX;
            out.alphaY = out.x->dist.alphaY;
        }
    };
    if (int(q) >= int(P::Principled)) {
        const int i = int(q) - int(P::Principled);
        principled[i] = std::clamp(principled[i] * luminance(t), 0.0f, 1.0f);
        return;
    }
    switch (q) {
        case P::Diffuse: out.diffuse = out.diffuse * t; break;
        case P::Specular: out.specular = out.specular * t; break;
        case P::Reflect: out.reflect = out.reflect * t; break;
        case P::Refract: out.refract = out.refract * t; break;
        case P::AlphaU: alphas(), out.alphaX = alpha(out.alphaX); break;
        case P::AlphaV: alphas(), out.alphaY = alpha(out.alphaY); break;
        case P::BaseAlphaU: setCoatBaseAlphas(out, alpha(coatBaseAlphaU(out)), coatBaseAlphaV(out)); break;
        case P::BaseAlphaV: setCoatBaseAlphas(out, coatBaseAlphaU(out), alpha(coatBaseAlphaV(out))); break;
        case P::ConductorEta: setConductorIndex(out, conductorEta(out) * t, conductorK(out)); break;
        case P::ConductorK: setConductorIndex(out, conductorEta(out), conductorK(out) * t); break;
        case P::ConductorReflectance: setConductorIndex(out, conductorEta(out), conductorK(out) * conductorKOfReflectance(t)); break;
        case P::Albedo: setCoatingAlbedo(out, coatingAlbedo(out) * t); break;
        case P::Scale: {
            const float s = luminance(t);
            out.diffuse = out.diffuse * s;
            out.refract = out.refract * s;
            break;
        }
        case P::BlendWeight: out.blendWeight = std::clamp(out.blendWeight * luminance(t), 0.0f, 1.0f); break;
        case P::Principled: break;
    }
}

// pbrt's regularize on a material of the regularized table (BsdfExtra::regularized,
// scene/regularize.h): a textured roughness keeps its constants there, and the rule
// (regularizedAlpha) applies to the alphas at the hit once the texture has scaled them.
inline void regularizeTexturedAlphas(const MaterialDesc& m, BsdfParams& out) {
    using P = MaterialParam;
    auto textured = [&](P q) { return m.texture[q] >= 0 && readsParam(m.kind, q); };
    if (textured(P::AlphaU) || textured(P::AlphaV)) {
        out.alphaX = regularizedAlpha(out.alphaX);
        out.alphaY = regularizedAlpha(out.alphaY);
    }
    if (textured(P::BaseAlphaU) || textured(P::BaseAlphaV))
        setCoatBaseAlphas(out, regularizedAlpha(coatBaseAlphaU(out)), regularizedAlpha(coatBaseAlphaV(out)));
}

// m's textured parameters at (u, v, p, n) into out (which holds the constants); a blend with
// textured parts keeps (u, v) and p for them (BsdfExtra::blendTextures).
inline void texturedParams(const std::vector<TextureDesc>& tex, const MaterialDesc& m, float u, float v, Vec3 p, Vec3 n, BsdfParams& out) {
    float principled[kPrincipledParams];
    std::copy(m.principled, m.principled + kPrincipledParams, principled);
    bool anyPrincipled = false;
    for (int i = 0; i < kMaterialParams; ++i) {
        const MaterialParam q = MaterialParam(i);
        const int t = m.texture.index[i];
        if (t < 0 || !readsParam(m.kind, q)) continue;
        applyParamTexture(m, q, evalTextureOf(tex, size_t(t), u, v, p, n), out, principled);
        anyPrincipled = anyPrincipled || i >= int(MaterialParam::Principled);
    }
    if (anyPrincipled) setPrincipled(out, principled);
    if (out.x && out.x->regularized) regularizeTexturedAlphas(m, out);
    if (m.kind == MaterialKind::Blend && out.x->blendTextures) setBlendPoint(out, u, v, p, n);
}

}  // namespace wmlt
