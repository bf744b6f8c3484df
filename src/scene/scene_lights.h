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

// Starts a light subpath on light li (pbrt-v4 12.5; scene-format.md, "Lights"): u[0..3].
// The environment: direction d from its importance sampling (light travels along -d),
// origin uniform on the disc of radius R (the scene's bounding sphere) perpendicular to
// d, centred at center + R d, outside the bounds: pdfPos = 1 / (pi R^2), n = -d.
inline bool sampleLightEmission(const Scene& s, int li, float u0, float u1, float u2, float u3,
                                LightEmission& e) {
    const Light& l = s.lights[li];
    switch (l.type) {
        case LightType::Rect: return sampleRectEmission(l, u0, u1, u2, u3, e);
        case LightType::Sphere: return sampleSphereEmission(l, u0, u1, u2, u3, e);
        case LightType::Env: {
            Vec3 d = s.env.sample(u0, u1, e.pdfDir);
            if (!(e.pdfDir > 0)) return false;
            float dx, dy;
            sampleConcentricDisk(u2, u3, dx, dy);
            Frame f = Frame::fromNormal(d);
            const float R = s.radius;
            e.p = s.center + (d + f.s * dx + f.t * dy) * R;
            e.n = -d;
            e.dir = -d;
            e.pdfPos = 1.0f / (kPi * R * R);
            e.Le = s.env.Le(d);
            return true;
        }
    }
    return false;
}

}  // namespace wmlt
