// Conductors (smooth and rough) and the thin dielectric (bsdf_microfacet.h).
#include "kernels/bsdf.h"
#include "kernels/fresnel.h"

namespace wmlt {

bool conductorSample(const BsdfParams& m, Vec3 wo, BsdfSample& s) {
    if (wo.z == 0) return false;
    s.wi = Vec3(-wo.x, -wo.y, wo.z);
    s.f = m.reflect * fresnelConductor(wo.z, conductorEta(m), conductorK(m)) / absCosTheta(wo);
    s.pdf = 1.0f;
    s.delta = true;
    return true;
}

namespace {
// Both directions mirrored into the upper hemisphere (two-sided); false if they are not
// on the same side.
inline bool upper(Vec3& wo, Vec3& wi) {
    if (!(wo.z * wi.z > 0)) return false;
    if (wo.z < 0) {
        wo.z = -wo.z;
        wi.z = -wi.z;
    }
    return true;
}
}  // namespace

Vec3 roughConductorF(const BsdfParams& m, Vec3 wo, Vec3 wi) {
    if (!upper(wo, wi)) return Vec3(0.0f);
    Vec3 h = wo + wi;
    if (!(lengthSquared(h) > 0)) return Vec3(0.0f);
    h = normalize(h);
    const Microfacet d = distributionAt(m);
    const float DG = microfacetD(d, h) * microfacetG(d, wo, wi, h);
    if (!(DG > 0)) return Vec3(0.0f);
    return m.reflect * fresnelConductor(dot(wo, h), conductorEta(m), conductorK(m)) * (DG / (4.0f * wo.z * wi.z));
}

float roughConductorPdf(const BsdfParams& m, Vec3 wo, Vec3 wi) {
    if (!upper(wo, wi)) return 0.0f;
    Vec3 h = wo + wi;
    if (!(lengthSquared(h) > 0)) return 0.0f;
    h = normalize(h);
    const float woh = dot(wo, h);
    return woh > 0 ? visibleNormalPdf(distributionAt(m), wo, h) / (4.0f * woh) : 0.0f;
}

bool roughConductorSample(const BsdfParams& m, Vec3 wo, float u1, float u2, BsdfSample& s) {
    if (wo.z == 0) return false;
    const bool below = wo.z < 0;
    Vec3 w = below ? Vec3(wo.x, wo.y, -wo.z) : wo;
    Vec3 h = sampleVisibleNormal(distributionAt(m), w, u1, u2);
    Vec3 wi = reflectAbout(w, h);
    if (!(wi.z > 0)) return false;  // reflected below the surface: shadowed, no sample
    if (below) wi.z = -wi.z;
    s.wi = wi;
    s.f = roughConductorF(m, wo, wi);
    s.pdf = roughConductorPdf(m, wo, wi);
    s.delta = false;
    return s.pdf > 0;
}

bool thinDielectricSample(const BsdfParams& m, Vec3 wo, float uLobe, BsdfSample& s) {
    if (wo.z == 0) return false;
    float R = fresnelDielectric(absCosTheta(wo), m.eta);
    if (R < 1) R += (1 - R) * (1 - R) * R / (1 - R * R);  // inter-reflections in the slab
    const float T = 1 - R;
    s.delta = true;
    if (uLobe < R) {
        s.wi = Vec3(-wo.x, -wo.y, wo.z);
        s.f = m.reflect * (R / absCosTheta(wo));
        s.pdf = R;
    } else {
        s.wi = -wo;
        s.f = m.refract * (T / absCosTheta(wo));
        s.pdf = T;
    }
    return s.pdf > 0;
}

}  // namespace wmlt
