// Rough dielectric (bsdf_microfacet.h): Walter et al. 2007 with the generalised half
// vector, in pbrt-v4's form (section 9.7). eta = iorInside / iorOutside, z points outside.
#include "kernels/bsdf.h"
#include "kernels/fresnel.h"

namespace wmlt {

Vec3 roughDielectricF(const BsdfParams& m, Vec3 wo, Vec3 wi) {
    Vec3 wm;
    float etap;
    if (!generalizedHalfVector(m.eta, wo, wi, wm, etap)) return Vec3(0.0f);
    const Microfacet d = distributionAt(m);
    const float DG = microfacetD(d, wm) * microfacetG(d, wo, wi, wm);
    // F from the direction in the less dense medium (for a refraction pair it is the same
    // from both, but the denser side's cosine near the critical angle amplifies rounding):
    // so f stays reciprocal.
    const bool useWo = wo.z * wi.z > 0 || (wo.z > 0) == (m.eta >= 1);
    const float F = fresnelDielectric(useWo ? dot(wo, wm) : dot(wi, wm), m.eta);
    const float cosCos = std::fabs(wo.z * wi.z);
    if (wo.z * wi.z > 0) return m.reflect * (DG * F / (4.0f * cosCos));
    const float a = dot(wi, wm), b = dot(wo, wm) / etap, denom = (a + b) * (a + b) * cosCos;
    if (!(denom > 0)) return Vec3(0.0f);
    // Radiance mode: 1 / eta'^2 (Veach 1997, 5.2), as the smooth dielectric.
    return m.refract * (DG * (1.0f - F) * std::fabs(a * dot(wo, wm)) / denom / (etap * etap));
}

float roughDielectricPdf(const BsdfParams& m, Vec3 wo, Vec3 wi) {
    Vec3 wm;
    float etap;
    if (!generalizedHalfVector(m.eta, wo, wi, wm, etap)) return 0.0f;
    const float F = fresnelDielectric(dot(wo, wm), m.eta);
    const float pdfM = visibleNormalPdf(distributionAt(m), wo, wm);
    if (wo.z * wi.z > 0) return F * pdfM / (4.0f * std::fabs(dot(wo, wm)));
    const float a = dot(wi, wm), b = dot(wo, wm) / etap;
    const float denom = (a + b) * (a + b);
    return denom > 0 ? (1.0f - F) * pdfM * std::fabs(a) / denom : 0.0f;  // dwm/dwi (Walter eq. 17)
}

bool roughDielectricSample(const BsdfParams& m, Vec3 wo, float uLobe, float u1, float u2, TransportMode mode, BsdfSample& s) {
    if (wo.z == 0) return false;
    const Vec3 wm = sampleVisibleNormal(distributionAt(m), wo, u1, u2);  // wm.z > 0
    const float cosM = dot(wo, wm);
    const float F = fresnelDielectric(cosM, m.eta);
    Vec3 wi;
    if (!scatterAbout(wo, wm, m.eta, uLobe < F, wi)) return false;
    s.wi = wi;
    s.f = mode == TransportMode::Radiance ? roughDielectricF(m, wo, wi) : roughDielectricF(m, wi, wo);
    s.pdf = roughDielectricPdf(m, wo, wi);
    s.delta = false;
    return s.pdf > 0;
}

}  // namespace wmlt
