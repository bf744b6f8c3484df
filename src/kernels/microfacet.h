// Microfacet distributions (Walter et al. 2007, "Microfacet models for refraction
// through rough surfaces"; Heitz 2014, "Understanding the masking-shadowing function"):
// GGX and Beckmann, isotropic or anisotropic (roughness alphaX along the local frame's x,
// the shading tangent, alphaY along y), with the exact Smith Lambda of each, the separable
// shadowing-masking G = G1(wo, m) G1(wi, m) (as Mitsuba 3 uses), and sampling of the
// visible normals D_wo(m) = G1(wo, m) max(0, wo.m) D(m) / wo.z (Heitz 2018 for GGX; Heitz
// and d'Eon 2014 for Beckmann, inverting the slope CDF numerically); and pbrt-v4's path
// regularisation of a roughness (regularizedAlpha).
// Directions are in the local frame, z = the macro-surface normal; m.z > 0.
// An isotropic distribution (alphaX == alphaY) computes D and Lambda with the isotropic
// arithmetic, chosen per call: the same bits as before anisotropy existed.
#pragma once
#include <cmath>
#include <cstdint>

#include "wavemmlt/math.h"
#include "wavemmlt/scene_desc.h"

namespace wmlt {

struct Microfacet {
    MicrofacetType type = MicrofacetType::Beckmann;
    // RMS slope (Beckmann) / width (GGX) along the frame's x (Mitsuba's alpha_u) and y (alpha_v)
    float alphaX = 0.1f, alphaY = 0.1f;
    Microfacet() = default;
    Microfacet(MicrofacetType t, float alpha) : type(t), alphaX(alpha), alphaY(alpha) {}
    Microfacet(MicrofacetType t, float ax, float ay) : type(t), alphaX(ax), alphaY(ay) {}
    bool isotropic() const { return alphaX == alphaY; }
};

// Path regularisation (pbrt-v4's "bool regularize", TrowbridgeReitzDistribution::Regularize):
// a roughness below 0.3 is doubled into [0.1, 0.3], so a smooth surface (alpha 0) becomes
// one of alpha 0.1; 0.3 and above are kept.
inline float regularizedAlpha(float alpha) { return alpha < 0.3f ? std::fmin(std::fmax(2.0f * alpha, 0.1f), 0.3f) : alpha; }

// D(m), normalised so that the projected area int D(m) m.z dm = 1 (Walter 2007, eqs. 25, 33;
// anisotropic: Heitz 2014's anisotropic forms, pbrt-v4 9.6: tan^2 / alpha^2 ->
// (m.x^2 / ax^2 + m.y^2 / ay^2) / m.z^2 and alpha^2 -> ax ay).
inline float microfacetD(const Microfacet& d, Vec3 m) {
    if (!(m.z > 0)) return 0.0f;
    if (!d.isotropic()) {
        const double c2 = double(m.z) * m.z, ax = d.alphaX, ay = d.alphaY;
        const double e = (double(m.x) * m.x / (ax * ax) + double(m.y) * m.y / (ay * ay)) / c2, axy = ax * ay;
        if (d.type == MicrofacetType::Beckmann) return float(std::exp(-e) / (M_PI * axy * c2 * c2));
        return float(1.0 / (M_PI * axy * c2 * c2 * (1.0 + e) * (1.0 + e)));
    }
    const double c2 = double(m.z) * m.z, a2 = double(d.alphaX) * d.alphaX;
    const double s2 = std::max(0.0, double(m.x) * m.x + double(m.y) * m.y);
    const double tan2 = s2 / c2, c4 = c2 * c2;
    if (d.type == MicrofacetType::Beckmann) return float(std::exp(-tan2 / a2) / (M_PI * a2 * c4));
    const double k = 1.0 + tan2 / a2;
    return float(1.0 / (M_PI * a2 * c4 * k * k));
}

// Smith's Lambda(w) (Heitz 2014, eqs. 72 and 86): GGX (-1 + sqrt(1 + alpha^2 tan^2)) / 2;
// Beckmann (exp(-a^2) / (a sqrt(pi)) - erfc(a)) / 2 with a = 1 / (alpha tan). Anisotropic:
// alpha is the projected roughness alpha(phi) = sqrt(cos^2 phi ax^2 + sin^2 phi ay^2) of
// w's azimuth (Heitz 2014, anisotropic Smith), alpha^2 tan^2 = (w.x^2 ax^2 + w.y^2 ay^2) / w.z^2.
inline double microfacetLambda(const Microfacet& d, Vec3 w) {
    const double s2 = std::max(0.0, double(w.x) * w.x + double(w.y) * w.y), c = std::fabs(double(w.z));
    if (s2 == 0) return 0.0;
    if (c == 0) return INFINITY;
    if (!d.isotropic()) {
        const double ax = d.alphaX, ay = d.alphaY;
        const double at2 = (double(w.x) * w.x * ax * ax + double(w.y) * w.y * ay * ay) / (c * c);  // alpha^2 tan^2
        if (d.type == MicrofacetType::GGX) return 0.5 * at2 / (1.0 + std::sqrt(1.0 + at2));
        const double a = 1.0 / std::sqrt(at2);
        if (a > 26) return 0.0;
        return 0.5 * (std::exp(-a * a) / (a * std::sqrt(M_PI)) - std::erfc(a));
    }
    const double alpha = d.alphaX;
    if (d.type == MicrofacetType::GGX) {
        const double t2 = alpha * alpha * s2 / (c * c);
        return 0.5 * t2 / (1.0 + std::sqrt(1.0 + t2));  // = (-1 + sqrt(1 + t2)) / 2, no cancellation
    }
    const double a = c / (alpha * std::sqrt(s2));
    if (a > 26) return 0.0;  // exp(-a^2) underflows: Lambda < 1e-300
    return 0.5 * (std::exp(-a * a) / (a * std::sqrt(M_PI)) - std::erfc(a));
}

// G1(w, m): masking of microfacet m seen from w; 0 when w sees m's back (Walter 2007, eq. 7).
inline float microfacetG1(const Microfacet& d, Vec3 w, Vec3 m) {
    if (!(dot(w, m) * w.z > 0)) return 0.0f;
    return float(1.0 / (1.0 + microfacetLambda(d, w)));
}

// The separable shadowing-masking term.
inline float microfacetG(const Microfacet& d, Vec3 wo, Vec3 wi, Vec3 m) { return microfacetG1(d, wo, m) * microfacetG1(d, wi, m); }

// Density of the visible normal m seen from wo (solid angle of m), D_wo(m) (Heitz 2018,
// eq. 2); wo on either side: the distribution of -wo's upper-side mirror is used.
inline float visibleNormalPdf(const Microfacet& d, Vec3 wo, Vec3 m) {
    if (wo.z < 0) wo = -wo;
    const float cosO = wo.z, wm = dot(wo, m);
    if (!(cosO > 0) || !(wm > 0)) return 0.0f;
    return microfacetG1(d, wo, m) * wm * microfacetD(d, m) / cosO;
}

// A microfacet normal (m.z > 0) distributed as D_wo; wo below the surface is mirrored
// first (as visibleNormalPdf does). microfacet.cpp.
Vec3 sampleVisibleNormal(const Microfacet& d, Vec3 wo, float u1, float u2);

// Mirror reflection of w about m (unit): 2 (w.m) m - w.
inline Vec3 reflectAbout(Vec3 w, Vec3 m) { return m * (2.0f * dot(w, m)) - w; }

// Refraction of w about m (pbrt-v4 eq. 9.8). etaRel = n(transmitted side) / n(w's side);
// m on w's side. False under total internal reflection.
inline bool refractAbout(Vec3 w, Vec3 m, float etaRel, Vec3& wt) {
    const double c = dot(w, m), s2 = std::max(0.0, 1.0 - c * c);
    const double t2 = 1.0 - s2 / (double(etaRel) * etaRel);
    if (!(t2 > 0)) return false;
    const double ct = std::sqrt(t2);
    wt = normalize(-w / etaRel + m * float(c / etaRel - ct));
    return true;
}

// The direction leaving microfacet m (m.z > 0) for wo: its mirror (reflect) or its
// refraction through an interface of relative index eta (inside / outside, m on either
// side of wo); false when that leaves on the wrong side of the macro-surface or under
// total internal reflection.
inline bool scatterAbout(Vec3 wo, Vec3 m, float eta, bool reflect, Vec3& wi) {
    if (reflect) {
        wi = reflectAbout(wo, m);
        return wi.z * wo.z > 0;
    }
    const float cosM = dot(wo, m);
    if (!refractAbout(wo, cosM > 0 ? m : -m, cosM > 0 ? eta : 1.0f / eta, wi)) return false;
    return wi.z * wo.z < 0;
}

// The generalised half vector of (wo, wi) at an interface of relative index eta (inside /
// outside, z pointing outside; Walter 2007, eq. 16), facing +z, and eta' = n(wi side) /
// n(wo side) (1 for reflection). False for a degenerate pair or one that sees a facet's back.
inline bool generalizedHalfVector(float eta, Vec3 wo, Vec3 wi, Vec3& wm, float& etap) {
    if (wo.z == 0 || wi.z == 0) return false;
    const bool reflect = wo.z * wi.z > 0;
    etap = reflect ? 1.0f : (wo.z > 0 ? eta : 1.0f / eta);
    wm = wi * etap + wo;
    if (!(lengthSquared(wm) > 0)) return false;
    wm = normalize(wm);
    if (wm.z < 0) wm = -wm;
    // Discard back-facing microfacets (Walter 2007: wo and wi each on their facet's side).
    return dot(wm, wi) * wi.z > 0 && dot(wm, wo) * wo.z > 0;
}

}  // namespace wmlt
