// The material kinds (WMLT_MATERIAL_KINDS, scene_desc.h) as pure per-element functions: the
// thesis' four here and in bsdf_glossy.cpp, bsdf_specular.cpp; the others in bsdf_*.cpp and
// bsdf_microfacet.h; the dispatch by kind at the end (BsdfOf<Kind>: bsdf_kinds.h).
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
// - f(wo, wi) is always the radiance-mode BSDF, wo towards the camera side and wi towards
//   the light side (the connections evaluate it so); in TransportMode::Importance the
//   sample's f is the adjoint, f(wi, wo) (bsdf_microfacet.h).
#pragma once
#include <algorithm>
#include <vector>

#include "kernels/medium.h"
#include "kernels/microfacet.h"
#include "kernels/sampling.h"
#include "wavemmlt/scene_desc.h"

namespace wmlt {

enum class TransportMode : uint8_t { Radiance, Importance };

// Per-material constants of the Mitsuba materials, built once with the scene (the table
// and the internal reflectance by bsdf_plastic.cpp's preparePlastic).
struct BsdfParams;
// A blend whose parts read textures: each part's description (null: a constant part) and
// the scene's textures, applied where the blend's kernel needs them (textureBlendPart).
struct BlendTextures {
    const std::vector<TextureDesc>* textures = nullptr;
    const MaterialDesc* part[2] = {nullptr, nullptr};
};
// Coated: the slab and the base as the description gives them (bsdf_coated.cpp; its albedo,
// the base's alphas and its Fresnel's scale, which textures or wavelengths may change, are
// read from the hit's BsdfParams).
struct CoatingExtra : MaterialDesc::Coating {};
struct BsdfExtra {
    Microfacet dist;                 // rough kinds (a textured roughness: the constants it scales)
    bool anisotropic = false;        // rough kinds: isAnisotropic (the frame follows dp/du)
    float specularWeight = 0.5f;     // plastics: mean(Ks) / (mean(Kd) + mean(Ks))
    float fdrInt = 0;                // plastics: diffuse reflectance of the coating from inside
    bool nonlinear = false;          // plastics: Mitsuba's `nonlinear`
    static constexpr int kRes = 64;  // roughplastic: T(cos) at cos = i / (kRes - 1)
    float transmittance[kRes] = {};
    const BsdfParams* blendParts = nullptr;        // Blend: its two parts (owned by the Scene)
    const BlendTextures* blendTextures = nullptr;  // Blend: its parts' textures (null: constant parts)
    // Principled: whether it transmits (spec_trans given: a back side of its own; else it
    // reflects only and is two-sided here, as the other reflecting kinds), and the sampling
    // rates of its diffuse, main specular and clearcoat lobes.
    bool transmits = false;
    float samplingRate[3] = {1, 1, 1};
    CoatingExtra coating;  // Coated
    // A material of the regularized table (scene/regularize.h): a textured roughness is
    // regularized at each hit after its texture (texturedParamsOf).
    bool regularized = false;
};

// A material at one hit, with its texture already applied to `diffuse`.
struct BsdfParams {
    MaterialKind kind = MaterialKind::Matte;
    Vec3 diffuse{0.0f};
    Vec3 specular{0.0f};
    float shininess = 0;
    Vec3 reflect{0.0f};
    Vec3 refract{0.0f};
    float eta = 1.5f;              // iorInside / iorOutside
    float blendWeight = 0;         // Blend: the weight of part 1 at this hit (x->blendParts)
    const BsdfExtra* x = nullptr;  // the Mitsuba kinds' constants (owned by the Scene)
    // Rough conductors and dielectrics with a textured roughness: the alphas at this hit
    // (0: x->dist's; materialAt writes them). Principled: always its GGX alphas here.
    float alphaX = 0, alphaY = 0;
};

// Conductors and a coated conductor's base: the complex index eta + i k relative to the
// outside at the hit, eta in `diffuse` and k in `specular` (slots these kinds have no other
// use for). Coated: the slab's albedo in `refract`, the conductor base's GGX alphas in
// `shininess` and `blendWeight`, the scale of its Fresnel in `reflect` (as a conductor's:
// MaterialDesc::reflect). Written by the scene (constants), the texture stage and the
// spectral stage.
inline Vec3 conductorEta(const BsdfParams& m) { return m.diffuse; }
inline Vec3 conductorK(const BsdfParams& m) { return m.specular; }
inline void setConductorIndex(BsdfParams& m, Vec3 eta, Vec3 k) {
    m.diffuse = eta;
    m.specular = k;
}
inline Vec3 coatingAlbedo(const BsdfParams& m) { return m.refract; }
inline void setCoatingAlbedo(BsdfParams& m, Vec3 a) { m.refract = a; }
inline Vec3 coatBaseScale(const BsdfParams& m) { return m.reflect; }
inline float coatBaseAlphaU(const BsdfParams& m) { return m.shininess; }
inline float coatBaseAlphaV(const BsdfParams& m) { return m.blendWeight; }
inline void setCoatBaseAlphas(BsdfParams& m, float au, float av) {
    m.shininess = au;
    m.blendWeight = av;
}

// A blend with textured parts keeps its hit's (u, v), point and geometric normal, for its
// parts' textures, in slots it has no other use for (diffuse, specular, reflect). Written by
// the texture stage.
inline void setBlendPoint(BsdfParams& m, float u, float v, Vec3 p, Vec3 n) {
    m.diffuse = Vec3(u, v, 0.0f);
    m.specular = p;
    m.reflect = n;
}
inline void blendPoint(const BsdfParams& m, float& u, float& v, Vec3& p, Vec3& n) {
    u = m.diffuse.x;
    v = m.diffuse.y;
    p = m.specular;
    n = m.reflect;
}

// Principled (Mitsuba's `principled`): base_color is `diffuse`, eta `eta`, the GGX alphas
// (from roughness and anisotropic) alphaX, alphaY; its other weights at the hit are kept in
// slots the kind has no other use for (shininess, specular, reflect, refract), so that
// BsdfParams stays 80 bytes for every kind. Read and written only through these functions.
// The tints' normaliser (refract.z, 0 unless set): the base colour's luminance, which the
// kernel computes from `diffuse` unless the spectral stage gave the RGB colour's (`diffuse`
// then holds the base at the path's wavelengths, not RGB).
struct PrincipledLobes {
    float roughness = 0.5f, metallic = 0, specTrans = 0, specTint = 0, sheen = 0, sheenTint = 0, flatness = 0, clearcoat = 0, clearcoatGloss = 0;
};
inline PrincipledLobes principledLobes(const BsdfParams& m) {
    return {m.shininess, m.specular.x, m.specular.y, m.specular.z, m.reflect.x, m.reflect.y, m.reflect.z, m.refract.x, m.refract.y};
}
// Writes the parameters v (indexed by PrincipledParam) into m: the weights, and the main
// lobes' GGX alphas from roughness r and anisotropic a (Burley 2012, as Mitsuba 3:
// r^2 / aspect and r^2 aspect, aspect = sqrt(1 - 0.9 a), each at least 0.001).
inline void setPrincipled(BsdfParams& m, const float v[kPrincipledParams]) {
    auto at = [&](PrincipledParam q) { return v[int(q)]; };
    using P = PrincipledParam;
    m.shininess = at(P::Roughness);
    m.specular = Vec3(at(P::Metallic), at(P::SpecTrans), at(P::SpecTint));
    m.reflect = Vec3(at(P::Sheen), at(P::SheenTint), at(P::Flatness));
    m.refract = Vec3(at(P::Clearcoat), at(P::ClearcoatGloss), 0.0f);
    const float r2 = at(P::Roughness) * at(P::Roughness), aspect = std::sqrt(1.0f - 0.9f * at(P::Anisotropic));
    m.alphaX = std::max(0.001f, r2 / aspect);
    m.alphaY = std::max(0.001f, r2 * aspect);
}

// Mitsuba's luminance of linear RGB (the principled tints are normalised by it).
inline float principledLuminance(Vec3 c) { return 0.212671f * c.x + 0.715160f * c.y + 0.072169f * c.z; }
// The base colour's luminance for the tints: the spectral stage's (its RGB's), else `diffuse`'s.
inline void setPrincipledTintLuminance(BsdfParams& m, float l) { m.refract.z = l; }
inline float principledTintLuminance(const BsdfParams& m) { return m.refract.z > 0 ? m.refract.z : principledLuminance(m.diffuse); }

// The microfacet distribution at a hit: the material's, or its textured roughness'.
inline Microfacet distributionAt(const BsdfParams& m) { return m.alphaX > 0 ? Microfacet(m.x->dist.type, m.alphaX, m.alphaY) : m.x->dist; }

struct BsdfSample {
    Vec3 wi;
    Vec3 f;
    float pdf = 0;
    bool delta = false;
};

// Every lobe is a delta (Plastic mixes a delta coating with a diffuse base: not delta).
inline bool isDeltaMaterial(MaterialKind k) {
    return k == MaterialKind::Reflective || k == MaterialKind::Dielectric || k == MaterialKind::Conductor || k == MaterialKind::ThinDielectric;
}

inline float absCosTheta(Vec3 w) { return std::fabs(w.z); }

// ---- Phase: a medium vertex's Henyey-Greenstein phase function (kernels/medium.h) ----
// In a frame whose z is the vertex's wo (towards the previous vertex), so one of the two
// directions is the frame's z and the other's z is c = dot(wo, wi); g in `eta`. As a BSDF
// the stages multiply f by |cos| of that other direction (PT: f(wo, wi) |wi.z|; the light
// tracer: f(wi, wo) |wi.z| with wo its z): f = p(c) / |c| makes that product p (0 on the
// measure-zero circle c = 0); pdf = p(c). Both symmetric in their arguments.
inline float phaseG(const BsdfParams& m) { return m.eta; }
inline Vec3 phaseF(const BsdfParams& m, Vec3 wo, Vec3 wi) {
    const float c = dot(wo, wi);
    return c != 0 ? Vec3(henyeyGreenstein(c, phaseG(m)) / std::fabs(c)) : Vec3(0.0f);
}
inline float phasePdf(const BsdfParams& m, Vec3 wo, Vec3 wi) { return henyeyGreenstein(dot(wo, wi), phaseG(m)); }
inline bool phaseSample(const BsdfParams& m, float u1, float u2, BsdfSample& s) {
    const float c = sampleHenyeyGreensteinCos(phaseG(m), u1);
    const float sn = std::sqrt(std::max(0.0f, 1.0f - c * c)), phi = 2.0f * kPi * u2;
    s.wi = Vec3(sn * std::cos(phi), sn * std::sin(phi), c);
    s.pdf = henyeyGreenstein(c, phaseG(m));
    s.f = c != 0 ? Vec3(s.pdf / std::fabs(c)) : Vec3(0.0f);
    s.delta = false;
    return c != 0 && s.pdf > 0;
}
inline bool sameHemisphere(Vec3 a, Vec3 b) { return a.z * b.z > 0; }

// ---- Matte: f = Kd / pi --------------------------------------------------------
inline Vec3 matteF(const BsdfParams& m, Vec3 wo, Vec3 wi) { return sameHemisphere(wo, wi) ? m.diffuse * kInvPi : Vec3(0.0f); }
inline float mattePdf(const BsdfParams&, Vec3 wo, Vec3 wi) { return sameHemisphere(wo, wi) ? absCosTheta(wi) * kInvPi : 0.0f; }
// The matte sample from a cosine-weighted direction wi about +z (sampleCosineHemisphere).
inline bool matteSampleFrom(const BsdfParams& m, Vec3 wo, Vec3 wi, BsdfSample& s) {
    if (wo.z < 0) wi.z = -wi.z;
    s.wi = wi;
    s.pdf = absCosTheta(wi) * kInvPi;
    s.f = m.diffuse * kInvPi;
    s.delta = false;
    return s.pdf > 0;
}
inline bool matteSample(const BsdfParams& m, Vec3 wo, float, float u1, float u2, BsdfSample& s) {
    return matteSampleFrom(m, wo, sampleCosineHemisphere(u1, u2), s);
}

// ---- DiffuseTransmission (pbrt-v4's diffusetransmission) ----
// f = R / pi on wo's side, T / pi on the other (R = diffuse, T = refract); a side chosen in
// proportion to max(R) and max(T), then a cosine-weighted direction there. Symmetric: no
// adjoint correction.
inline Vec3 diffuseTransmissionF(const BsdfParams& m, Vec3 wo, Vec3 wi) { return (sameHemisphere(wo, wi) ? m.diffuse : m.refract) * kInvPi; }
inline float diffuseTransmissionPdf(const BsdfParams& m, Vec3 wo, Vec3 wi) {
    const float pr = std::max(m.diffuse.x, std::max(m.diffuse.y, m.diffuse.z));
    const float pt = std::max(m.refract.x, std::max(m.refract.y, m.refract.z));
    if (!(pr + pt > 0)) return 0.0f;
    return absCosTheta(wi) * kInvPi * (sameHemisphere(wo, wi) ? pr : pt) / (pr + pt);
}
inline bool diffuseTransmissionSample(const BsdfParams& m, Vec3 wo, float uLobe, float u1, float u2, BsdfSample& s) {
    const float pr = std::max(m.diffuse.x, std::max(m.diffuse.y, m.diffuse.z));
    const float pt = std::max(m.refract.x, std::max(m.refract.y, m.refract.z));
    if (!(pr + pt > 0)) return false;
    const bool reflect = uLobe < pr / (pr + pt);
    s.wi = sampleCosineHemisphere(u1, u2);
    if ((wo.z < 0) == reflect) s.wi.z = -s.wi.z;  // reflection: wo's side; transmission: the other
    s.f = (reflect ? m.diffuse : m.refract) * kInvPi;
    s.pdf = absCosTheta(s.wi) * kInvPi * (reflect ? pr : pt) / (pr + pt);
    s.delta = false;
    return s.pdf > 0;
}

// ---- Glossy, Reflective, Dielectric: bsdf_glossy.cpp, bsdf_specular.cpp -------
Vec3 glossyF(const BsdfParams& m, Vec3 wo, Vec3 wi);
float glossyPdf(const BsdfParams& m, Vec3 wo, Vec3 wi);
bool glossySample(const BsdfParams& m, Vec3 wo, float uLobe, float u1, float u2, BsdfSample& s);
bool mirrorSample(const BsdfParams& m, Vec3 wo, BsdfSample& s);
bool dielectricSample(const BsdfParams& m, Vec3 wo, float uLobe, TransportMode mode, BsdfSample& s);
}  // namespace wmlt

#include "kernels/bsdf_microfacet.h"  // the Mitsuba kinds

namespace wmlt {

// Shading-normal correction of the adjoint BSDF (Veach 1997, eq. 5.19; pbrt-v3 16.1):
// |wo.ns| |wi.ng| / (|wo.ng| |wi.ns|), wo towards the light side, wi onwards.
inline float shadingCorrection(Vec3 wo, Vec3 wi, Vec3 ns, Vec3 ng) {
    if (ng.x == 0 && ng.y == 0 && ng.z == 0) return 1.0f;  // a medium vertex: no surface to correct for
    float den = std::fabs(dot(wo, ng)) * std::fabs(dot(wi, ns));
    return den > 0 ? std::fabs(dot(wo, ns)) * std::fabs(dot(wi, ng)) / den : 0.0f;
}

// ---- Principled (bsdf_principled.cpp) -------------------------------------------------
Vec3 principledF(const BsdfParams& m, Vec3 wo, Vec3 wi);
float principledPdf(const BsdfParams& m, Vec3 wo, Vec3 wi);
bool principledSample(const BsdfParams& m, Vec3 wo, float uLobe, float u1, float u2, TransportMode mode, BsdfSample& s);

// ---- Coated (bsdf_coated.cpp): pbrt-v4's layered BSDF, estimated by random walks ----
// The interface: eta, alphaX/alphaY; the diffuse base `diffuse`; the rest in x->coating.
Vec3 coatedF(const BsdfParams& m, Vec3 wo, Vec3 wi, TransportMode mode = TransportMode::Radiance);
float coatedPdf(const BsdfParams& m, Vec3 wo, Vec3 wi, TransportMode mode = TransportMode::Radiance);
bool coatedSample(const BsdfParams& m, Vec3 wo, float uLobe, float u1, float u2, TransportMode mode, BsdfSample& s);

// ---- Blend (blendbsdf): f = (1 - w) f_0 + w f_1, the parts by the dispatch below ----
inline Vec3 blendF(const BsdfParams& m, Vec3 wo, Vec3 wi);
inline float blendPdf(const BsdfParams& m, Vec3 wo, Vec3 wi);
inline bool blendSample(const BsdfParams& m, Vec3 wo, float uLobe, float u1, float u2, TransportMode mode, BsdfSample& s);

}  // namespace wmlt

#include "kernels/bsdf_kinds.h"  // BsdfOf<Kind>: each kind's kernels

namespace wmlt {

// ---- Dispatch by kind (tests, rare paths and a blend's parts; stages call the kind's function) ----
// clang-format off
#define WMLT_KIND_F(K, name) \
    case MaterialKind::K: return BsdfOf<MaterialKind::K>::f(m, wo, wi);
// clang-format on
// clang-format off
#define WMLT_KIND_PDF(K, name) \
    case MaterialKind::K: return BsdfOf<MaterialKind::K>::pdf(m, wo, wi);
// clang-format on
// clang-format off
#define WMLT_KIND_SAMPLE(K, name) \
    case MaterialKind::K: return BsdfOf<MaterialKind::K>::sample(m, wo, uLobe, u1, u2, mode, s);
// clang-format on
inline Vec3 bsdfF(const BsdfParams& m, Vec3 wo, Vec3 wi) {
    switch (m.kind) { WMLT_MATERIAL_KINDS(WMLT_KIND_F) }
    return Vec3(0.0f);
}
inline float bsdfPdf(const BsdfParams& m, Vec3 wo, Vec3 wi) {
    switch (m.kind) { WMLT_MATERIAL_KINDS(WMLT_KIND_PDF) }
    return 0.0f;
}
inline bool bsdfSample(const BsdfParams& m, Vec3 wo, float uLobe, float u1, float u2, TransportMode mode, BsdfSample& s) {
    switch (m.kind) { WMLT_MATERIAL_KINDS(WMLT_KIND_SAMPLE) }
    return false;
}
#undef WMLT_KIND_F
#undef WMLT_KIND_PDF
#undef WMLT_KIND_SAMPLE

// The parts are never blends (the importer refuses that), so these recurse one level.
inline Vec3 blendFOf(const BsdfParams* part, float w, Vec3 wo, Vec3 wi) { return bsdfF(part[0], wo, wi) * (1.0f - w) + bsdfF(part[1], wo, wi) * w; }
inline float blendPdfOf(const BsdfParams* part, float w, Vec3 wo, Vec3 wi) {
    return bsdfPdf(part[0], wo, wi) * (1.0f - w) + bsdfPdf(part[1], wo, wi) * w;
}
// A blend with textured parts: its parts' constants with their textures applied at the
// hit's point, into part[2] (textured_params.cpp).
void textureBlendPart(const BsdfParams& blend, int k, BsdfParams& part);
inline void texturedBlendParts(const BsdfParams& m, BsdfParams* part) {
    for (int k = 0; k < 2; ++k) {
        part[k] = m.x->blendParts[k];
        textureBlendPart(m, k, part[k]);
    }
}
inline Vec3 blendF(const BsdfParams& m, Vec3 wo, Vec3 wi) {
    if (m.x->blendTextures) {
        BsdfParams part[2];
        texturedBlendParts(m, part);
        return blendFOf(part, m.blendWeight, wo, wi);
    }
    return blendFOf(m.x->blendParts, m.blendWeight, wo, wi);
}
inline float blendPdf(const BsdfParams& m, Vec3 wo, Vec3 wi) {
    if (m.x->blendTextures) {
        BsdfParams part[2];
        texturedBlendParts(m, part);
        return blendPdfOf(part, m.blendWeight, wo, wi);
    }
    return blendPdfOf(m.x->blendParts, m.blendWeight, wo, wi);
}
// Part k with probability its weight (uLobe chooses and is reused, rescaled, by the part);
// a delta lobe of it: f and pdf times that weight (their ratio the part's); any other
// direction: the mixture's f (its adjoint f(wi, wo) in importance mode, as every kind's
// sample gives) and pdf, as both parts could have sampled it.
inline bool blendSampleOf(const BsdfParams* part, float w1, Vec3 wo, float uLobe, float u1, float u2, TransportMode mode, BsdfSample& s) {
    const float w0 = 1.0f - w1;
    const int k = uLobe < w0 ? 0 : 1;
    const float wk = k ? w1 : w0;
    if (!(wk > 0)) return false;
    const float u = std::min((k ? uLobe - w0 : uLobe) / wk, 0x1.fffffep-1f);
    if (!bsdfSample(part[k], wo, u, u1, u2, mode, s)) return false;
    if (s.delta) {
        s.f = s.f * wk;
        s.pdf *= wk;
        return true;
    }
    s.f = mode == TransportMode::Radiance ? blendFOf(part, w1, wo, s.wi) : blendFOf(part, w1, s.wi, wo);
    s.pdf = blendPdfOf(part, w1, wo, s.wi);
    return s.pdf > 0;
}
inline bool blendSample(const BsdfParams& m, Vec3 wo, float uLobe, float u1, float u2, TransportMode mode, BsdfSample& s) {
    if (m.x->blendTextures) {
        BsdfParams part[2];
        texturedBlendParts(m, part);
        return blendSampleOf(part, m.blendWeight, wo, uLobe, u1, u2, mode, s);
    }
    return blendSampleOf(m.x->blendParts, m.blendWeight, wo, uLobe, u1, u2, mode, s);
}

}  // namespace wmlt
