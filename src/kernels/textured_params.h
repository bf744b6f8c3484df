// A material's textured parameters at one point: kind K's constants (a hit's BsdfParams,
// written by materialAt) finished with its textures there. The texture stage runs it kind by
// kind over a round's hits (stages/core/textures.h); a blend with textured parts runs it on its
// parts where its kernel needs them (textureBlendParts). Pure: no allocation, no state.
#pragma once
#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <vector>

#include "kernels/bsdf.h"
#include "kernels/texture.h"

namespace wmlt {

namespace textured_detail {
constexpr bool isAny(MaterialKind k, std::initializer_list<MaterialKind> ks) {
    for (MaterialKind x : ks)
        if (x == k) return true;
    return false;
}

}  // namespace textured_detail

// Kind K's textured parameters at (u, v, p, n) on material m, into out (which holds the
// constants): a colour parameter's texture scales its constant (MaterialDesc::colourTexture),
// a roughness texture's luminance (or its square root: MaterialDesc::alphaRemap) scales
// alpha (at least 1e-4; a coated material's interface too; then regularized for a material
// of the regularized table, BsdfExtra::regularized), a blend's weight is its
// texture's luminance in [0, 1] (and a blend with textured parts keeps (u, v) and p for
// them: BsdfExtra::blendTextures), a principled's weights each their constant times a
// texture's luminance in [0, 1] (the alphas made again from them).

template <MaterialKind K>
void texturedParamsOf(const std::vector<TextureDesc>& tex, const MaterialDesc& m, float u, float v, Vec3 p, Vec3 n, BsdfParams& out) {
    using M = MaterialKind;
    using textured_detail::isAny;
    const int* t = m.colourTexture;
    auto scale = [&](ColourParam c, Vec3& x) {
        if (t[int(c)] >= 0) x = x * evalTextureOf(tex, size_t(t[int(c)]), u, v, p, n);
    };
    if constexpr (isAny(K, {M::Matte, M::Glossy, M::Plastic, M::RoughPlastic, M::Principled, M::Coated, M::DiffuseTransmission}))
        scale(ColourParam::Diffuse, out.diffuse);
    if constexpr (K == M::Glossy) scale(ColourParam::Specular, out.specular);
    if constexpr (isAny(K, {M::Reflective, M::Dielectric, M::Conductor, M::RoughConductor, M::RoughDielectric,
                            M::ThinDielectric, M::Plastic, M::RoughPlastic}))
        scale(ColourParam::Reflect, out.reflect);
    if constexpr (isAny(K, {M::Dielectric, M::RoughDielectric, M::ThinDielectric, M::DiffuseTransmission}))
        scale(ColourParam::Refract, out.refract);
    if constexpr (isAny(K, {M::RoughConductor, M::RoughDielectric, M::Coated})) {
        if (m.alphaTexture >= 0 || m.alphaVTexture >= 0) {
            auto alpha = [&](int i, float a) {
                if (i < 0) return a;
                const float r = luminance(evalTextureOf(tex, size_t(i), u, v, p, n));
                return std::max(a * (m.alphaRemap ? std::sqrt(std::max(r, 0.0f)) : r), 1e-4f);
            };
            // (a coated interface's constants ride in out itself; a rough kind's in x->dist)
            const float ax = K == M::Coated ? out.alphaX : out.x->dist.alphaX, ay = K == M::Coated ? out.alphaY : out.x->dist.alphaY;
            out.alphaX = alpha(m.alphaTexture, ax);
            out.alphaY = alpha(m.alphaVTexture, ay);
            if (out.x->regularized) {  // pbrt's regularize: the rule on the alphas at this hit
                out.alphaX = regularizedAlpha(out.alphaX);
                out.alphaY = regularizedAlpha(out.alphaY);
            }
        }
    }
    if constexpr (K == M::Blend) {
        if (m.blendWeightTexture >= 0)
            out.blendWeight = std::clamp(luminance(evalTextureOf(tex, size_t(m.blendWeightTexture), u, v, p, n)), 0.0f, 1.0f);
        if (out.x->blendTextures) setBlendPoint(out, u, v, p, n);
    }
    if constexpr (K == M::Principled) {
        float value[kPrincipledParams];
        bool any = false;
        for (int i = 0; i < kPrincipledParams; ++i) {
            const int ti = m.principledTexture[i];
            value[i] = m.principled[i];
            if (ti < 0) continue;
            any = true;
            value[i] = std::clamp(value[i] * luminance(evalTextureOf(tex, size_t(ti), u, v, p, n)), 0.0f, 1.0f);
        }
        if (any) setPrincipled(out, value);
    }
}


// The same for any kind (a switch: for a blend's parts, not for a stage's loop).
void texturedParams(const std::vector<TextureDesc>& tex, const MaterialDesc& m, float u, float v, Vec3 p, Vec3 n, BsdfParams& out);

}  // namespace wmlt
