// Principled (Mitsuba 3's `principled`: Burley 2012 and 2015's Disney BSDF without
// subsurface), f as Mitsuba 3 defines it (docs/mitsuba.md, "principled"), in bsdf.h's
// conventions: wo towards the camera, wi towards the light, f without the cosine.
//   front (wo.z > 0), reflection:
//     f = Fp D G / (4 |cos_o cos_i|)                          main specular (GGX, alphas)
//       + cc/4 F_cc D_cc G_cc                                 clearcoat (GTR1; Mitsuba's: no 1/(4 cos cos))
//       + w_brdf base/pi ((1 - fl)(f_d + f_r) + fl f_ss)     diffuse, retro-reflection, fake subsurface
//       + sheen (1 - metallic) F_d(wi.h) c_sheen              sheen (w_brdf > 0; no 1/pi, as Burley's)
//     Fp = (1 - metallic)(1 - spec_tint) F + metallic S(base) + (1 - metallic) spec_tint S(c_tint R0)
//   back (wo.z < 0, transmitting only): reflection w_bsdf F D G / (4 |cos_o cos_i|);
//   refraction (either side): sqrt(base) w_bsdf (1 - F) D G |wo.h wi.h| / (|cos_o cos_i| (wo.h + eta' wi.h)^2)
// with w_brdf = (1 - metallic)(1 - spec_trans), w_bsdf = (1 - metallic) spec_trans, F the
// dielectric Fresnel at wo.h and S Schlick's with Mitsuba's choice of angle.
//
// Sampling is ours (Mitsuba's pdf mixes in F of a microfacet drawn for another lobe, so it
// is not its sampler's density): a lobe by wo alone -- diffuse w_brdf r_d, clearcoat
// cc/4 r_c, specular r_s (normalised; from the back the specular only) -- then for the
// specular a visible normal h and reflection with probability R(h) = 1 - w_bsdf (1 - F(h))
// (front) or F(h) (back), refraction otherwise. The pdf below is that density exactly.
#include "kernels/bsdf.h"
#include "kernels/fresnel.h"

namespace wmlt {
namespace {

inline float schlickWeight(float c) {
    const float m = std::clamp(1.0f - c, 0.0f, 1.0f), m2 = m * m;
    return m2 * m2 * m;
}

// Schlick's weight at cos (to the microfacet normal, from wo's side) as Mitsuba takes it:
// |cos| when entering the denser medium, else the transmitted cosine (0 past the critical
// angle: weight 1).
inline float schlickWeightAt(float cos, float eta) {
    const float etaIt = cos >= 0 ? eta : 1.0f / eta;
    if (etaIt > 1.0f) return schlickWeight(std::fabs(cos));
    const float etaTi = 1.0f / etaIt, cos2T = 1.0f - (1.0f - cos * cos) * etaTi * etaTi;
    return schlickWeight(std::sqrt(std::max(0.0f, cos2T)));
}

inline Vec3 schlick(Vec3 R0, float w) { return R0 + (Vec3(1.0f) - R0) * w; }

// Burley's GTR1 (gamma = 1) of the clearcoat, alpha from clearcoat_gloss: D(h) =
// (a^2 - 1) / (pi ln(a^2) (1 + (a^2 - 1) cos^2)), int D cos dh = 1.
inline float clearcoatAlpha(float gloss) { return 0.1f + (0.001f - 0.1f) * gloss; }
inline float gtr1D(float a, Vec3 h) {
    if (!(h.z > 0)) return 0.0f;
    const float a2 = a * a, d = (a2 - 1.0f) / (kPi * std::log(a2) * (1.0f + (a2 - 1.0f) * h.z * h.z));
    return d * h.z > 1e-20f ? d : 0.0f;
}
// h distributed as D(h) h.z: cos^2 = (1 - a^(2 (1 - u2))) / (1 - a^2).
inline Vec3 sampleGtr1(float a, float u1, float u2) {
    const float a2 = a * a, cos2 = (1.0f - std::pow(a2, 1.0f - u2)) / (1.0f - a2);
    const float c = std::sqrt(std::max(0.0f, cos2)), s = std::sqrt(std::max(0.0f, 1.0f - cos2)), phi = 2.0f * kPi * u1;
    return Vec3(s * std::cos(phi), s * std::sin(phi), c);
}

// Both lobe weights of the base.
struct Weights {
    float brdf, bsdf;
};
inline Weights weightsOf(const PrincipledLobes& p) { return {(1.0f - p.metallic) * (1.0f - p.specTrans), (1.0f - p.metallic) * p.specTrans}; }

// A reflecting-only principled is two-sided here (one-sided in Mitsuba: materialAt makes
// its back black unless twosided): wo's hemisphere is computed as the upper.
inline bool flipUp(const BsdfParams& m, Vec3& wo, Vec3& wi) {
    if (m.x->transmits) return true;
    if (!(wo.z * wi.z > 0)) return false;
    if (wo.z < 0) {
        wo.z = -wo.z;
        wi.z = -wi.z;
    }
    return true;
}

// Probabilities of the diffuse, clearcoat and specular lobes from wo's side.
struct LobeChoice {
    float diffuse = 0, clearcoat = 0, specular = 1;
};
inline LobeChoice lobeChoice(const BsdfParams& m, const PrincipledLobes& p, Weights w, bool front) {
    LobeChoice c;
    if (!front) return c;
    const float* r = m.x->samplingRate;
    const float d = w.brdf * r[0], cc = 0.25f * p.clearcoat * r[2], s = r[1], sum = d + cc + s;
    c.diffuse = d / sum;
    c.clearcoat = cc / sum;
    c.specular = s / sum;
    return c;
}

// Probability of reflection at the main lobe's microfacet of Fresnel F.
inline float reflectProb(Weights w, float F, bool front) { return front ? 1.0f - w.bsdf * (1.0f - F) : F; }

}  // namespace

Vec3 principledF(const BsdfParams& m, Vec3 wo, Vec3 wi) {
    if (wo.z == 0 || wi.z == 0 || !flipUp(m, wo, wi)) return Vec3(0.0f);
    const PrincipledLobes p = principledLobes(m);
    const Weights w = weightsOf(p);
    const bool front = wo.z > 0, reflect = wo.z * wi.z > 0;
    if (!front && !(w.bsdf > 0)) return Vec3(0.0f);
    Vec3 h;
    float etap;
    if (!generalizedHalfVector(m.eta, wo, wi, h, etap)) return Vec3(0.0f);
    const Microfacet d = distributionAt(m);
    const float DG = microfacetD(d, h) * microfacetG(d, wo, wi, h);
    // F at wo.h; for a refraction pair from the less dense side's cosine (equal to it, but
    // the denser side's near the critical angle amplifies rounding), as roughDielectricF.
    const float cosOH = dot(wo, h), cosCos = std::fabs(wo.z * wi.z);
    const bool useWo = reflect || (wo.z > 0) == (m.eta >= 1);
    const float F = fresnelDielectric(useWo ? cosOH : dot(wi, h), m.eta);
    const Vec3 base = m.diffuse;
    if (!reflect) {  // refraction
        if (!(w.bsdf > 0) || !(F < 1)) return Vec3(0.0f);
        const float a = cosOH + etap * dot(wi, h), denom = a * a * cosCos;
        if (!(denom > 0)) return Vec3(0.0f);
        const Vec3 tint(std::sqrt(base.x), std::sqrt(base.y), std::sqrt(base.z));
        return tint * (w.bsdf * (1.0f - F) * DG * std::fabs(cosOH * dot(wi, h)) / denom);
    }
    // the base colour's hue (normalised by its luminance): the spec and sheen tints'
    const float l = principledTintLuminance(m);
    const Vec3 cTint = l > 0 ? base / l : Vec3(1.0f);
    Vec3 f(0.0f);
    if (F > 0) {
        Vec3 Fp(w.bsdf * F);
        if (front) {
            const float sw = schlickWeightAt(cosOH, m.eta);
            const float etaIt = cosOH >= 0 ? m.eta : 1.0f / m.eta, r0 = (etaIt - 1.0f) * (etaIt - 1.0f) / ((etaIt + 1.0f) * (etaIt + 1.0f));
            Fp = Vec3((1.0f - p.metallic) * (1.0f - p.specTint) * F) + schlick(base, sw) * p.metallic +
                 schlick(cTint * r0, sw) * ((1.0f - p.metallic) * p.specTint);
        }
        f += Fp * (DG / (4.0f * cosCos));
    }
    if (!front) return f;
    if (p.clearcoat > 0) {
        const Microfacet g(MicrofacetType::GGX, 0.25f);
        const float Fcc = 0.04f + 0.96f * schlickWeightAt(cosOH, m.eta);
        f += Vec3(0.25f * p.clearcoat * Fcc * gtr1D(clearcoatAlpha(p.clearcoatGloss), h) * microfacetG(g, wo, wi, h));
    }
    if (w.brdf > 0) {
        const float Fo = schlickWeight(std::fabs(wi.z)), Fi = schlickWeight(std::fabs(wo.z)), cosD = dot(h, wi);
        const float Rr = 2.0f * p.roughness * cosD * cosD;
        float diffuse = (1.0f - 0.5f * Fi) * (1.0f - 0.5f * Fo) + Rr * (Fo + Fi + Fo * Fi * (Rr - 1.0f));
        if (p.flatness > 0) {  // Hanrahan-Krueger's fake subsurface, lerped in
            const float Fss90 = 0.5f * Rr, Fss = (1.0f + (Fss90 - 1.0f) * Fo) * (1.0f + (Fss90 - 1.0f) * Fi);
            const float ss = 1.25f * (Fss * (1.0f / (std::fabs(wo.z) + std::fabs(wi.z)) - 0.5f) + 0.5f);
            diffuse += (ss - diffuse) * p.flatness;
        }
        f += base * (w.brdf * kInvPi * diffuse);
        if (p.sheen > 0 && p.metallic < 1) {
            const Vec3 cSheen = Vec3(1.0f) + (cTint - Vec3(1.0f)) * p.sheenTint;
            f += cSheen * (p.sheen * (1.0f - p.metallic) * schlickWeight(std::fabs(cosD)));
        }
    }
    return f;
}

float principledPdf(const BsdfParams& m, Vec3 wo, Vec3 wi) {
    if (wo.z == 0 || wi.z == 0 || !flipUp(m, wo, wi)) return 0.0f;
    const PrincipledLobes p = principledLobes(m);
    const Weights w = weightsOf(p);
    const bool front = wo.z > 0, reflect = wo.z * wi.z > 0;
    if (!front && !(w.bsdf > 0)) return 0.0f;
    const LobeChoice c = lobeChoice(m, p, w, front);
    float pdf = reflect && front ? c.diffuse * wi.z * kInvPi : 0.0f;
    Vec3 h;
    float etap;
    if (!generalizedHalfVector(m.eta, wo, wi, h, etap)) return pdf;
    const float cosOH = dot(wo, h), R = reflectProb(w, fresnelDielectric(cosOH, m.eta), front);
    const float pdfH = visibleNormalPdf(distributionAt(m), wo, h);
    if (reflect) {
        pdf += c.specular * R * pdfH / (4.0f * std::fabs(cosOH));  // dh/dwi = 1 / (4 |wo.h|)
        if (front && c.clearcoat > 0) pdf += c.clearcoat * gtr1D(clearcoatAlpha(p.clearcoatGloss), h) * h.z / (4.0f * std::fabs(cosOH));
        return pdf;
    }
    const float cosIH = dot(wi, h), a = cosOH + etap * cosIH;
    // dh/dwi = eta'^2 |wi.h| / (wo.h + eta' wi.h)^2 (Walter 2007, eq. 17)
    return a * a > 0 ? pdf + c.specular * (1.0f - R) * pdfH * etap * etap * std::fabs(cosIH) / (a * a) : pdf;
}

bool principledSample(const BsdfParams& m, Vec3 wo, float uLobe, float u1, float u2, TransportMode mode, BsdfSample& s) {
    if (wo.z == 0) return false;
    const bool flipped = !m.x->transmits && wo.z < 0;
    const Vec3 v = flipped ? Vec3(wo.x, wo.y, -wo.z) : wo;
    const PrincipledLobes p = principledLobes(m);
    const Weights w = weightsOf(p);
    const bool front = v.z > 0;
    if (!front && !(w.bsdf > 0)) return false;
    const LobeChoice c = lobeChoice(m, p, w, front);
    Vec3 wi;
    if (uLobe < c.diffuse) {
        wi = sampleCosineHemisphere(u1, u2);
    } else if (uLobe < c.diffuse + c.clearcoat) {
        wi = reflectAbout(v, sampleGtr1(clearcoatAlpha(p.clearcoatGloss), u1, u2));
        if (!(wi.z > 0)) return false;
    } else {
        const float u = std::min((uLobe - c.diffuse - c.clearcoat) / c.specular, 0x1.fffffep-1f);
        const Vec3 h = sampleVisibleNormal(distributionAt(m), v, u1, u2);  // h.z > 0
        if (!scatterAbout(v, h, m.eta, u < reflectProb(w, fresnelDielectric(dot(v, h), m.eta), front), wi)) return false;
    }
    if (flipped) wi.z = -wi.z;
    s.wi = wi;
    s.f = mode == TransportMode::Radiance ? principledF(m, wo, wi) : principledF(m, wi, wo);
    s.pdf = principledPdf(m, wo, wi);
    s.delta = false;
    return s.pdf > 0;
}

}  // namespace wmlt
