// Light sampling over the scene's lights, chosen in proportion to power: the kind
// dispatch for next-event estimation and for MIS of emitters found by BSDF sampling.
#pragma once
#include "scene/scene.h"

namespace wmlt {

// Light li's mesh light when it is a textured one (mesh_light.h), else nullptr.
inline const MeshLight* texturedMeshLight(const Scene& s, int li) {
    const Light& l = s.lights[size_t(li)];
    if (l.type != LightType::Mesh) return nullptr;
    const MeshLight& m = s.meshLights[size_t(l.mesh)];
    return m.texture ? &m : nullptr;
}

// A triangle mesh emitter (mesh_light.h); a textured one: Le = L T at the point, its
// density pdfA.
inline bool sampleMeshLight(const Scene& s, const Light& l, Vec3 ref, float u1, float u2, LightSample& ls) {
    const MeshLight& m = s.meshLights[size_t(l.mesh)];
    Vec3 tex(1.0f);
    if (m.texture) sampleTexturedMeshPoint(m, u1, u2, ls.p, ls.n, tex, ls.pdfA);
    else sampleMeshPoint(m, u1, u2, ls.p, ls.n);
    const Vec3 d = ls.p - ref;
    const float dist2 = lengthSquared(d);
    if (!(dist2 > 0)) return false;
    ls.dist = std::sqrt(dist2);
    ls.wi = d / ls.dist;
    float cosL = -dot(ls.wi, ls.n);
    if (l.twoSided && cosL < 0) {  // the back face, towards ref
        ls.n = -ls.n;
        cosL = -cosL;
    }
    if (!(cosL > 0)) return false;  // the back of a one-sided emitter
    if (m.texture) {
        ls.Le = l.L * tex;
        ls.pdf = dist2 * ls.pdfA / cosL;
    } else {
        ls.Le = l.L;
        ls.pdf = dist2 / (cosL * l.area);
    }
    return std::isfinite(ls.pdf);
}

// The emitter hit rh found (light li): whether it is a textured mesh light, and then T at
// the hit and its area density under light sampling (texturedEmitterAt).
inline bool texturedEmitterHit(const Scene& s, int li, const RTCRayHit& rh, Vec3 p, Vec3& tex, float& pdfA) {
    const MeshLight* m = texturedMeshLight(s, li);
    if (m) texturedEmitterAt(*m, int(rh.hit.primID), rh.hit.u, rh.hit.v, p, tex, pdfA);
    return m != nullptr;
}

// The scene's light when it has exactly one and that is a rectangle, else nullptr: the
// stages then sample it in flat loops (sampleLights, generateBptLightPaths), and the
// choice among lights is certain (pmf lightDistribution.discretePmf(0), no number read).
inline const Light* soleRectLight(const Scene& s) { return s.lights.size() == 1 && s.lights[0].type == LightType::Rect ? &s.lights[0] : nullptr; }

// Samples light `li` from reference point ref (solid-angle pdf, without the choice pmf;
// delta lights: 1).
inline bool sampleLightFrom(const Scene& s, int li, Vec3 ref, float u1, float u2, LightSample& ls) {
    const Light& l = s.lights[li];
    switch (l.type) {
        case LightType::Rect: return sampleRectLight(l, ref, u1, u2, ls);
        case LightType::Sphere: return sampleSphereLight(l, ref, u1, u2, ls);
        case LightType::Mesh: return sampleMeshLight(s, l, ref, u1, u2, ls);
        case LightType::Point: return samplePointLight(l, ref, ls);
        case LightType::Directional: {  // the one direction: a delta (pdf 1), at infinity
            ls.wi = -l.axis;
            ls.pdf = 1.0f;
            ls.delta = true;
            ls.dist = INFINITY;
            ls.Le = l.L;
            ls.p = ref + ls.wi * (2.0f * s.radius);
            ls.n = -ls.wi;
            return true;
        }
        case LightType::Env: {
            ls.wi = s.env.sample(u1, u2, ls.pdf);
            ls.dist = INFINITY;
            ls.Le = s.env.Le(ls.wi);
            ls.p = ref + ls.wi * (2.0f * s.radius);
            ls.n = -ls.wi;
            return ls.pdf > 0;
        }
    }
    return false;
}

// Solid-angle pdf (times the choice pmf) with which next-event estimation from ref
// would have produced the emitter point pLight (normal nLight) of light li, in
// direction dir. Point lights: the discrete pmf (their only strategy is this one).
// pdfA: a textured mesh light's area density at pLight (emitterAt; < 0: 1 / area).
inline float lightPdfFrom(const Scene& s, int li, Vec3 ref, Vec3 pLight, Vec3 dir, Vec3 nLight, float pdfA = -1) {
    const Light& l = s.lights[li];
    float pdf = 0;
    switch (l.type) {
        case LightType::Rect: pdf = rectLightPdf(l, ref, pLight); break;
        case LightType::Sphere: pdf = sphereLightPdf(l, ref); break;
        case LightType::Env: pdf = s.env.pdf(dir); break;
        case LightType::Point:
        case LightType::Directional: pdf = 1.0f; break;
        case LightType::Mesh: {
            const Vec3 d = pLight - ref;
            const float dist2 = lengthSquared(d);
            const float cosL = std::fabs(dot(d, nLight)) / std::sqrt(dist2);
            if (pdfA >= 0) pdf = cosL > 0 ? dist2 * pdfA / cosL : 0.0f;
            else pdf = cosL > 0 ? dist2 / (cosL * l.area) : 0.0f;
            break;
        }
    }
    return pdf * s.lightPmf[li];
}

// Starts a light subpath on light li (pbrt-v4 12.5; scene-format.md, "Lights"): u[0..3].
// The environment: direction d from its importance sampling (light travels along -d),
// origin uniform on the disc of radius R (the scene's bounding sphere) perpendicular to
// d, centred at center + R d, outside the bounds: pdfPos = 1 / (pi R^2), n = -d.
inline bool sampleLightEmission(const Scene& s, int li, float u0, float u1, float u2, float u3, LightEmission& e) {
    const Light& l = s.lights[li];
    switch (l.type) {
        case LightType::Rect: return sampleRectEmission(l, u0, u1, u2, u3, e);
        case LightType::Sphere: return sampleSphereEmission(l, u0, u1, u2, u3, e);
        case LightType::Point: return samplePointEmission(l, u2, u3, e);
        case LightType::Mesh: {  // area-uniform point (textured: by T), cosine-weighted direction about its normal
            // (two-sided: a face each with probability 1/2, u2's halves, e.n that face's normal)
            const MeshLight& m = s.meshLights[size_t(l.mesh)];
            if (m.texture) {
                sampleTexturedMeshPoint(m, u0, u1, e.p, e.n, e.tex, e.pdfPos);
                e.Le = l.L * e.tex;
            } else {
                sampleMeshPoint(m, u0, u1, e.p, e.n);
                e.pdfPos = 1.0f / l.area;
                e.Le = l.L;
            }
            if (l.twoSided) {
                const bool back = u2 >= 0.5f;
                u2 = back ? 2.0f * u2 - 1.0f : 2.0f * u2;
                if (back) e.n = -e.n;
            }
            sampleCosineAbout(e.n, u2, u3, e);
            if (l.twoSided) e.pdfDir *= 0.5f;
            return e.pdfDir > 0;
        }
        case LightType::Env:
        case LightType::Directional: {  // directional: its one direction (pdfDir 1, a delta)
            Vec3 d;
            if (l.type == LightType::Directional) {
                d = -l.axis;
                e.pdfDir = 1.0f;
            } else {
                d = s.env.sample(u0, u1, e.pdfDir);
            }
            if (!(e.pdfDir > 0)) return false;
            float dx, dy;
            sampleConcentricDisk(u2, u3, dx, dy);
            Frame f = Frame::fromNormal(d);
            const float R = s.radius;
            e.p = s.center + (d + f.s * dx + f.t * dy) * R;
            e.n = -d;
            e.dir = -d;
            e.pdfPos = 1.0f / (kPi * R * R);
            e.Le = l.type == LightType::Directional ? l.L : s.env.Le(d);
            return true;
        }
    }
    return false;
}

}  // namespace wmlt
