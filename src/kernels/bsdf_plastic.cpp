// Smooth and rough plastic (bsdf_microfacet.h), after Mitsuba 3's `plastic` and
// `roughplastic` plugin descriptions: a dielectric coating over a diffuse base whose light
// bounces between base and coating (internal scattering) as a geometric series.
#include "kernels/bsdf.h"
#include "kernels/fresnel.h"

namespace wmlt {
namespace {

inline float flipUp(Vec3& wo, Vec3& wi) {  // two-sided: wo's hemisphere computed as the upper
    if (!(wo.z * wi.z > 0)) return 0.0f;
    if (wo.z < 0) {
        wo.z = -wo.z;
        wi.z = -wi.z;
    }
    return 1.0f;
}

// Kd seen through the coating: Kd / (1 - Fdr) sums the base's bounces under the coating
// (each returns a fraction Fdr); nonlinear: Kd / (1 - Kd Fdr) (the base's colour at every bounce).
inline Vec3 baseAlbedo(const BsdfParams& m) {
    const float f = m.x->fdrInt;
    if (!m.x->nonlinear) return m.diffuse / (1.0f - f);
    return {m.diffuse.x / (1 - m.diffuse.x * f), m.diffuse.y / (1 - m.diffuse.y * f), m.diffuse.z / (1 - m.diffuse.z * f)};
}

// Probability of the coating's lobe given its weight c = F_i or 1 - T_i.
inline float coatingProb(const BsdfParams& m, float c) {
    const float w = m.x->specularWeight, a = c * w, b = (1 - c) * (1 - w);
    return a + b > 0 ? a / (a + b) : 0.0f;
}

// The rough coating's transmittance at |cos| (linear in the table).
inline float transmittance(const BsdfExtra& x, float cosT) {
    const float t = std::min(1.0f, std::fabs(cosT)) * float(BsdfExtra::kRes - 1);
    const int i = std::min(int(t), BsdfExtra::kRes - 2);
    const float f = t - float(i);
    return x.transmittance[i] * (1 - f) + x.transmittance[i + 1] * f;
}

}  // namespace

// ---- Plastic ------------------------------------------------------------------------

Vec3 plasticF(const BsdfParams& m, Vec3 wo, Vec3 wi) {
    if (!flipUp(wo, wi)) return Vec3(0.0f);
    const float Fi = fresnelDielectric(wo.z, m.eta), Fo = fresnelDielectric(wi.z, m.eta);
    return baseAlbedo(m) * ((1 - Fi) * (1 - Fo) * kInvPi / (m.eta * m.eta));
}

float plasticPdf(const BsdfParams& m, Vec3 wo, Vec3 wi) {
    if (!flipUp(wo, wi)) return 0.0f;
    return (1 - coatingProb(m, fresnelDielectric(wo.z, m.eta))) * wi.z * kInvPi;
}

bool plasticSample(const BsdfParams& m, Vec3 wo, float uLobe, float u1, float u2, BsdfSample& s) {
    if (wo.z == 0) return false;
    const float Fi = fresnelDielectric(absCosTheta(wo), m.eta), pc = coatingProb(m, Fi);
    if (uLobe < pc) {  // the coating: a delta mirror of weight reflect * F_i
        s.wi = Vec3(-wo.x, -wo.y, wo.z);
        s.f = m.reflect * (Fi / absCosTheta(wo));
        s.pdf = pc;
        s.delta = true;
        return pc > 0;
    }
    Vec3 wi = sampleCosineHemisphere(u1, u2);
    if (wo.z < 0) wi.z = -wi.z;
    s.wi = wi;
    s.f = plasticF(m, wo, wi);
    s.pdf = plasticPdf(m, wo, wi);
    s.delta = false;
    return s.pdf > 0;
}

// ---- Rough plastic ------------------------------------------------------------------

Vec3 roughPlasticF(const BsdfParams& m, Vec3 wo, Vec3 wi) {
    if (!flipUp(wo, wi)) return Vec3(0.0f);
    const BsdfExtra& x = *m.x;
    Vec3 f = baseAlbedo(m) * (transmittance(x, wo.z) * transmittance(x, wi.z) * kInvPi / (m.eta * m.eta));
    Vec3 h = wo + wi;
    if (!(lengthSquared(h) > 0)) return f;
    h = normalize(h);
    const float DG = microfacetD(x.dist, h) * microfacetG(x.dist, wo, wi, h);
    if (DG > 0) f += m.reflect * (DG * fresnelDielectric(dot(wo, h), m.eta) / (4.0f * wo.z * wi.z));
    return f;
}

float roughPlasticPdf(const BsdfParams& m, Vec3 wo, Vec3 wi) {
    if (!flipUp(wo, wi)) return 0.0f;
    const float pc = coatingProb(m, 1 - transmittance(*m.x, wo.z));
    float pdf = (1 - pc) * wi.z * kInvPi;
    Vec3 h = wo + wi;
    if (lengthSquared(h) > 0) {
        h = normalize(h);
        const float woh = dot(wo, h);
        if (woh > 0) pdf += pc * visibleNormalPdf(m.x->dist, wo, h) / (4.0f * woh);
    }
    return pdf;
}

bool roughPlasticSample(const BsdfParams& m, Vec3 wo, float uLobe, float u1, float u2, BsdfSample& s) {
    if (wo.z == 0) return false;
    const bool below = wo.z < 0;
    const Vec3 w = below ? Vec3(wo.x, wo.y, -wo.z) : wo;
    const float pc = coatingProb(m, 1 - transmittance(*m.x, w.z));
    Vec3 wi;
    if (uLobe < pc) {
        wi = reflectAbout(w, sampleVisibleNormal(m.x->dist, w, u1, u2));
        if (!(wi.z > 0)) return false;
    } else {
        wi = sampleCosineHemisphere(u1, u2);
    }
    if (below) wi.z = -wi.z;
    s.wi = wi;
    s.f = roughPlasticF(m, wo, wi);
    s.pdf = roughPlasticPdf(m, wo, wi);
    s.delta = false;
    return s.pdf > 0;
}

// ---- Constants ----------------------------------------------------------------------

namespace {

constexpr int kQuad = 24;  // (u1, u2) midpoints per axis over the visible normals

// Energy through the rough interface from wo (above, relative index eta): the mean over
// visible normals of (1 - F) G1(wt) (a refracted sample's weight without the 1/eta^2 of
// radiance, which the plastic applies itself). below: from inside, the reflected energy
// F G1(wr) instead.
double roughInterface(const Microfacet& d, float mu, float eta, bool inside) {
    const float s = std::sqrt(std::max(0.0f, 1 - mu * mu));
    const Vec3 wo(s, 0.0f, inside ? -mu : mu);
    double sum = 0;
    for (int i = 0; i < kQuad; ++i)
        for (int j = 0; j < kQuad; ++j) {
            const Vec3 wm = sampleVisibleNormal(d, wo, (i + 0.5f) / kQuad, (j + 0.5f) / kQuad);
            const float c = dot(wo, wm), F = fresnelDielectric(c, eta);
            if (inside) {
                const Vec3 wr = reflectAbout(wo, wm);
                if (wr.z < 0) sum += F * microfacetG1(d, wr, wm);
                continue;
            }
            Vec3 wt;
            if (c > 0 && refractAbout(wo, wm, eta, wt) && wt.z < 0) sum += (1 - F) * microfacetG1(d, wt, wm);
        }
    return sum / (kQuad * kQuad);
}

}  // namespace

void preparePlastic(BsdfExtra& x, float eta, bool rough) {
    // Fdr_int = 2 int_0^1 R_inside(mu) mu dmu (the coating's hemispherical reflectance for
    // a diffuse (cosine) distribution from inside), by the midpoint rule.
    const int n = rough ? 64 : 4096;
    double fdr = 0;
    for (int i = 0; i < n; ++i) {
        const float mu = (i + 0.5f) / float(n);
        const double R = rough ? roughInterface(x.dist, mu, eta, true) : fresnelDielectric(-mu, eta);
        fdr += 2.0 * R * mu / n;
    }
    x.fdrInt = float(fdr);
    if (!rough) return;
    for (int i = 0; i < BsdfExtra::kRes; ++i) {
        const float mu = std::max(1e-4f, float(i) / float(BsdfExtra::kRes - 1));
        x.transmittance[i] = float(roughInterface(x.dist, mu, eta, false));
    }
}

}  // namespace wmlt
