// Light sampling over the scene's lights, chosen in proportion to power: the kind
// dispatch for next-event estimation and for MIS of emitters found by BSDF sampling.
#pragma once
#include "scene/scene.h"

namespace wmlt {

// Samples light `li` from reference point ref (solid-angle pdf, without the choice pmf).
inline bool sampleLightFrom(const Scene& s, int li, Vec3 ref, float u1, float u2, LightSample& ls) {
    const Light& l = s.lights[li];
    switch (l.type) {
        case LightType::Rect: return sampleRectLight(l, ref, u1, u2, ls);
        case LightType::Sphere: return sampleSphereLight(l, ref, u1, u2, ls);
        case LightType::Env: {
            ls.wi = s.env.sample(u1, u2, ls.pdf);
            ls.dist = INFINITY;
            ls.Le = s.env.Le(ls.wi);
            ls.p = ref + ls.wi * (2.0f * s.radius);
            return ls.pdf > 0;
        }
    }
    return false;
}

// Solid-angle pdf (times the choice pmf) with which next-event estimation from ref
// would have produced the emitter point pLight of light li, in direction dir.
inline float lightPdfFrom(const Scene& s, int li, Vec3 ref, Vec3 pLight, Vec3 dir) {
    const Light& l = s.lights[li];
    float pdf = 0;
    switch (l.type) {
        case LightType::Rect: pdf = rectLightPdf(l, ref, pLight); break;
        case LightType::Sphere: pdf = sphereLightPdf(l, ref); break;
        case LightType::Env: pdf = s.env.pdf(dir); break;
    }
    return pdf * s.lightPmf[li];
}

}  // namespace wmlt
