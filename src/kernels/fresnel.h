// Fresnel reflectance of a smooth dielectric interface for unpolarised light.
//
// cosThetaI is the cosine of the incident direction with the normal, which points to
// the outside; eta = iorInside / iorOutside. cosThetaI < 0 means the light arrives from
// the inside: the relative index is then 1 / eta (pbrt-v4, section 9.3.1).
#pragma once
#include <complex>

#include "wavemmlt/math.h"

namespace wmlt {

// Exact Fresnel equations (Born and Wolf; pbrt-v4 eq. 9.4-9.6):
//   r_par  = (eta cos_i - cos_t) / (eta cos_i + cos_t)
//   r_perp = (cos_i - eta cos_t) / (cos_i + eta cos_t),   F = (r_par^2 + r_perp^2) / 2,
// with Snell's law cos_t^2 = 1 - (1 - cos_i^2) / eta^2 = (eta^2 - 1 + cos_i^2) / eta^2;
// returns 1 under total internal reflection. Evaluated in double with eta^2 - 1 formed as
// (eta - 1)(eta + 1): near the critical angle and for eta ~ 1 the float form cancels.
inline float fresnelDielectric(float cosThetaI, float etaF) {
    double c = std::min(1.0, std::max(-1.0, double(cosThetaI))), eta = etaF;
    double d = (eta - 1.0) * (eta + 1.0);  // eta^2 - 1
    if (c < 0) {
        d = -d / (eta * eta);
        eta = 1.0 / eta;
        c = -c;
    }
    double cos2T = (d + c * c) / (eta * eta);
    if (cos2T <= 0) return 1.0f;  // total internal reflection
    double cosT = std::sqrt(cos2T);
    double rPar = (eta * c - cosT) / (eta * c + cosT);
    double rPerp = (c - eta * cosT) / (c + eta * cosT);
    return float(0.5 * (rPar * rPar + rPerp * rPerp));
}

// Schlick's approximation F = R0 + (1 - R0) (1 - cos)^5, R0 = ((eta-1)/(eta+1))^2, with
// cos taken on the less dense side of the interface (so that it is symmetric and shows
// total internal reflection when leaving the denser medium).
inline float fresnelSchlick(float cosThetaI, float etaF) {
    double c = std::min(1.0, std::max(-1.0, double(cosThetaI))), eta = etaF;
    double d = (eta - 1.0) * (eta + 1.0);  // eta^2 - 1, as in fresnelDielectric
    if (c < 0) {
        d = -d / (eta * eta);
        eta = 1.0 / eta;
        c = -c;
    }
    double r0 = (eta - 1.0) / (eta + 1.0);
    r0 *= r0;
    if (eta < 1.0) {  // from the denser side: use the transmitted angle
        double cos2T = (d + c * c) / (eta * eta);
        if (cos2T <= 0) return 1.0f;
        c = std::sqrt(cos2T);
    }
    double m = 1.0 - c, m2 = m * m;
    return float(r0 + (1.0 - r0) * m2 * m2 * m);
}

// Conductor: the Fresnel equations with a complex relative index eta + i k (pbrt-v4,
// section 9.3.6, eq. 9.6 with complex cos_t), per RGB channel; cosThetaI = |cos| to the
// normal. eta = 0, k = 1 (a purely imaginary index) reflects everything.
inline float fresnelComplex(float cosThetaI, float etaRe, float etaIm) {
    using C = std::complex<double>;
    const double c = std::min(1.0, std::fabs(double(cosThetaI)));
    const C eta(etaRe, etaIm);
    const C sin2T = (1.0 - c * c) / (eta * eta);
    const C cosT = std::sqrt(1.0 - sin2T);
    const C rPar = (eta * c - cosT) / (eta * c + cosT);
    const C rPerp = (c - eta * cosT) / (c + eta * cosT);
    return float(0.5 * (std::norm(rPar) + std::norm(rPerp)));
}
inline Vec3 fresnelConductor(float cosThetaI, Vec3 eta, Vec3 k) {
    return {fresnelComplex(cosThetaI, eta.x, k.x), fresnelComplex(cosThetaI, eta.y, k.y), fresnelComplex(cosThetaI, eta.z, k.z)};
}

}  // namespace wmlt
