// Delta lobes: the perfect mirror (Reflective) and smooth glass (Dielectric).
// f = weight / |cos wi| and pdf = the lobe's discrete probability (see bsdf.h).
#include "kernels/bsdf.h"
#include "kernels/fresnel.h"

namespace wmlt {

// Mirror scaled by Reflect, two-sided: wi = (-wo.x, -wo.y, wo.z).
bool mirrorSample(const BsdfParams& m, Vec3 wo, BsdfSample& s) {
    if (wo.z == 0) return false;
    s.wi = Vec3(-wo.x, -wo.y, wo.z);
    s.f = m.reflect / absCosTheta(s.wi);
    s.pdf = 1.0f;
    s.delta = true;
    return true;
}

// Smooth dielectric (pbrt-v4, section 9.5). eta = iorInside / iorOutside; the normal
// points outside, so wo.z > 0 means wo is in the outside medium.
bool dielectricSample(const BsdfParams& m, Vec3 wo, float uLobe, TransportMode mode, BsdfSample& s) {
    if (wo.z == 0) return false;
    float F = fresnelDielectric(wo.z, m.eta);  // 1 under total internal reflection
    s.delta = true;
    if (uLobe < F) {  // reflection, probability F
        s.wi = Vec3(-wo.x, -wo.y, wo.z);
        s.f = m.reflect * (F / absCosTheta(s.wi));
        s.pdf = F;
        return true;
    }
    // Refraction, probability 1 - F. etaRel = n(wi's medium) / n(wo's medium).
    // cos_t^2 = (etaRel^2 - 1 + cos_o^2) / etaRel^2, in double as in fresnelDielectric
    // (the float form 1 - sin_t^2 cancels near the critical angle).
    double e = m.eta, d = (e - 1.0) * (e + 1.0), c = absCosTheta(wo);
    if (wo.z < 0) {
        d = -d / (e * e);
        e = 1.0 / e;
    }
    double cos2T = (d + c * c) / (e * e);
    if (!(cos2T > 0)) return false;  // unreachable: F == 1 then
    float etaRel = float(e), cosT = float(std::sqrt(cos2T));
    // Snell's law (pbrt-v4 eq. 9.8): wi = -wo / etaRel + (cos_o / etaRel - cos_t) n, with n
    // on wo's side; so wi.xy = -wo.xy / etaRel and wi.z = -sign(wo.z) cos_t.
    s.wi = Vec3(-wo.x / etaRel, -wo.y / etaRel, wo.z > 0 ? -cosT : cosT);
    float T = 1.0f - F;
    s.f = m.refract * (T / cosT);
    // Radiance / n^2 is invariant across the interface (Veach 1997, section 5.2), so the
    // radiance carried from wi's medium into wo's is L_o = T (n_o / n_i)^2 L_i: camera
    // paths (Radiance) get the factor 1 / etaRel^2 (a camera in air sees the radiance
    // inside glass times T / eta^2). Light paths use the adjoint BSDF, which has no such
    // factor (pbrt-v4 section 9.5.2), so both subpaths of BDPT/MMLT estimate the same L.
    if (mode == TransportMode::Radiance) s.f *= 1.0f / (etaRel * etaRel);
    s.pdf = T;
    return s.pdf > 0;
}

}  // namespace wmlt
