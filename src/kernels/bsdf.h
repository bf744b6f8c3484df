// The four materials of the scene format as pure per-element functions.
//
// Conventions (pbrt-v4, chapter 9):
// - wo, wi are unit vectors in the local shading frame, z = the shading normal. The
//   normal points to the object's outside: for a Dielectric, wo.z > 0 means wo lies in
//   the oIOR medium. Matte, Glossy and Reflective are two-sided: they scatter into the
//   hemisphere of wo, whichever it is.
// - f excludes the cosine factor. For delta lobes (mirror, glass) `f` in BsdfSample is
//   the lobe's weight divided by |cos wi|, and `pdf` the discrete probability of the
//   lobe, so f * |cos wi| / pdf is the throughput weight in both cases.
// - Radiance crossing a dielectric interface is scaled by 1/eta^2 in
//   TransportMode::Radiance (camera paths) only (Veach 1997, section 5.2).
#pragma once
#include "kernels/sampling.h"
#include "wavemmlt/scene_desc.h"

namespace wmlt {

enum class TransportMode : uint8_t { Radiance, Importance };

// A material at one hit, with its texture already applied to `diffuse`.
struct BsdfParams {
    MaterialKind kind = MaterialKind::Matte;
    Vec3 diffuse{0.0f};
    Vec3 specular{0.0f};
    float shininess = 0;
    Vec3 reflect{0.0f};
    Vec3 refract{0.0f};
    float eta = 1.5f;  // iorInside / iorOutside
};

struct BsdfSample {
    Vec3 wi;
    Vec3 f;
    float pdf = 0;
    bool delta = false;
};

inline bool isDeltaMaterial(MaterialKind k) {
    return k == MaterialKind::Reflective || k == MaterialKind::Dielectric;
}

inline float absCosTheta(Vec3 w) { return std::fabs(w.z); }
inline bool sameHemisphere(Vec3 a, Vec3 b) { return a.z * b.z > 0; }

// ---- Matte: f = Kd / pi --------------------------------------------------------
inline Vec3 matteF(const BsdfParams& m, Vec3 wo, Vec3 wi) {
    return sameHemisphere(wo, wi) ? m.diffuse * kInvPi : Vec3(0.0f);
}
inline float mattePdf(const BsdfParams&, Vec3 wo, Vec3 wi) {
    return sameHemisphere(wo, wi) ? absCosTheta(wi) * kInvPi : 0.0f;
}
inline bool matteSample(const BsdfParams& m, Vec3 wo, float, float u1, float u2, BsdfSample& s) {
    Vec3 wi = sampleCosineHemisphere(u1, u2);
    if (wo.z < 0) wi.z = -wi.z;
    s.wi = wi;
    s.pdf = absCosTheta(wi) * kInvPi;
    s.f = m.diffuse * kInvPi;
    s.delta = false;
    return s.pdf > 0;
}

// ---- Glossy, Reflective, Dielectric: bsdf_glossy.cpp, bsdf_specular.cpp -------
Vec3 glossyF(const BsdfParams& m, Vec3 wo, Vec3 wi);
float glossyPdf(const BsdfParams& m, Vec3 wo, Vec3 wi);
bool glossySample(const BsdfParams& m, Vec3 wo, float uLobe, float u1, float u2, BsdfSample& s);
bool mirrorSample(const BsdfParams& m, Vec3 wo, BsdfSample& s);
bool dielectricSample(const BsdfParams& m, Vec3 wo, float uLobe, TransportMode mode, BsdfSample& s);

// Shading-normal correction of the adjoint BSDF (Veach 1997, eq. 5.19; pbrt-v3 16.1):
// |wo.ns| |wi.ng| / (|wo.ng| |wi.ns|), wo towards the light side, wi onwards.
inline float shadingCorrection(Vec3 wo, Vec3 wi, Vec3 ns, Vec3 ng) {
    float den = std::fabs(dot(wo, ng)) * std::fabs(dot(wi, ns));
    return den > 0 ? std::fabs(dot(wo, ns)) * std::fabs(dot(wi, ng)) / den : 0.0f;
}

// ---- Dispatch by kind (tests and rare paths; stages call the kind's function) ----
inline Vec3 bsdfF(const BsdfParams& m, Vec3 wo, Vec3 wi) {
    switch (m.kind) {
        case MaterialKind::Matte: return matteF(m, wo, wi);
        case MaterialKind::Glossy: return glossyF(m, wo, wi);
        default: return Vec3(0.0f);  // delta lobes
    }
}
inline float bsdfPdf(const BsdfParams& m, Vec3 wo, Vec3 wi) {
    switch (m.kind) {
        case MaterialKind::Matte: return mattePdf(m, wo, wi);
        case MaterialKind::Glossy: return glossyPdf(m, wo, wi);
        default: return 0.0f;
    }
}
inline bool bsdfSample(const BsdfParams& m, Vec3 wo, float uLobe, float u1, float u2,
                       TransportMode mode, BsdfSample& s) {
    switch (m.kind) {
        case MaterialKind::Matte: return matteSample(m, wo, uLobe, u1, u2, s);
        case MaterialKind::Glossy: return glossySample(m, wo, uLobe, u1, u2, s);
        case MaterialKind::Reflective: return mirrorSample(m, wo, s);
        case MaterialKind::Dielectric: return dielectricSample(m, wo, uLobe, mode, s);
    }
    return false;
}

}  // namespace wmlt
