// pbrt-v4's path regularisation (Integrator "bool regularize"; pbrt-v4's BxDF::Regularize):
// a material's roughened version, which PT and BPT use at a path's hits after its first
// non-specular bounce (Scene::regularizedOffset). Every microfacet roughness goes through
// regularizedAlpha (kernels/microfacet.h); a smooth dielectric or conductor becomes a rough
// one of GGX alpha 0.1; a coating its interface and conductor base. Pure.
#pragma once
#include "kernels/microfacet.h"
#include "wavemmlt/scene_desc.h"

namespace wmlt {

// m's regularized version. A textured roughness (the interface's or the base's) keeps its
// constants (the texture's scale): the texture stage applies the rule to the alphas at each
// hit (BsdfExtra::regularized, regularizeTexturedAlphas).
// Unchanged: the kinds without a microfacet lobe (diffuse, diffuse transmission); a blend,
// whose parts are regularized each (Scene::build takes them from the regularized table);
// thin dielectrics (pbrt-v4 leaves them specular); and the kinds no pbrt file makes
// (the thesis' glossy and mirror, Mitsuba's smooth plastic and principled).
inline MaterialDesc regularizedMaterial(const MaterialDesc& m) {
    MaterialDesc r = m;
    const bool textured = m.texture[MaterialParam::AlphaU] >= 0 || m.texture[MaterialParam::AlphaV] >= 0;
    const bool baseTextured = m.texture[MaterialParam::BaseAlphaU] >= 0 || m.texture[MaterialParam::BaseAlphaV] >= 0;
    auto roughen = [&] {
        if (textured) return;
        r.alpha = regularizedAlpha(m.alpha);
        r.alphaV = regularizedAlpha(alphaVOf(m));
    };
    switch (m.kind) {
        case MaterialKind::Dielectric:
        case MaterialKind::Conductor:  // alpha 0: effectively smooth
            r.kind = m.kind == MaterialKind::Dielectric ? MaterialKind::RoughDielectric : MaterialKind::RoughConductor;
            r.distribution = MicrofacetType::GGX;
            r.alpha = r.alphaV = regularizedAlpha(0.0f);
            r.texture[MaterialParam::AlphaU] = r.texture[MaterialParam::AlphaV] = -1;
            break;
        case MaterialKind::RoughConductor:
        case MaterialKind::RoughDielectric:
        case MaterialKind::RoughPlastic: roughen(); break;
        case MaterialKind::Coated:
            roughen();
            if (m.coating.conductorBase && !baseTextured) {
                r.coating.baseAlpha = regularizedAlpha(m.coating.baseAlpha);
                r.coating.baseAlphaV = regularizedAlpha(m.coating.baseAlphaV);
            }
            break;
        default: break;
    }
    return r;
}

}  // namespace wmlt
