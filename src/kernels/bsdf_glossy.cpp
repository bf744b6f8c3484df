// Glossy: normalised modified Phong (Lafortune and Willems 1994), two-sided.
//   f = Kd / pi + Ks (n + 2) / (2 pi) max(0, cos a)^n,  a = angle(wi, mirror(wo)),
// zero outside the hemisphere of wo. Sampled as a mixture of a cosine lobe and a
// power-cosine lobe around the mirror direction (pdf (n + 1) / (2 pi) cos^n a).
#include "kernels/bsdf.h"

namespace wmlt {
namespace {

// max(0, cos a)^n, a = angle(wi, mirror(wo)), with 0^0 := 0 (for n = 0 the lobe is the
// indicator of cos a > 0). Symmetric in wo, wi, so f(wo, wi) == f(wi, wo) bitwise.
// In double, divided by |wo| |wi|: cos^n amplifies any relative error of cos by n, and
// float "unit" vectors are off by ~1e-7 in length (2e-4 of bias at n = 1e4). The
// products of floats are exact in double, so this is accurate to ~1e-16 for any n.
inline float phongTerm(Vec3 wo, Vec3 wi, float n) {
    double dotR = double(wo.z) * wi.z - (double(wo.x) * wi.x + double(wo.y) * wi.y);
    if (!(dotR > 0)) return 0.0f;
    double lo = double(wo.x) * wo.x + double(wo.y) * wo.y + double(wo.z) * wo.z;
    double li = double(wi.x) * wi.x + double(wi.y) * wi.y + double(wi.z) * wi.z;
    double c = std::min(1.0, dotR / std::sqrt(lo * li));
    return float(std::pow(c, double(n)));
}

// Probability of picking the diffuse lobe: lum(Kd) / (lum(Kd) + lum(Ks)); false if both are 0.
inline bool lobeProbs(const BsdfParams& m, float& pd, float& ps) {
    float ld = std::max(0.0f, luminance(m.diffuse)), ls = std::max(0.0f, luminance(m.specular));
    if (!(ld + ls > 0)) {
        pd = ps = 0;
        return false;
    }
    pd = ld / (ld + ls);
    ps = 1.0f - pd;
    return true;
}

}  // namespace

Vec3 glossyF(const BsdfParams& m, Vec3 wo, Vec3 wi) {
    if (!sameHemisphere(wo, wi)) return Vec3(0.0f);
    float n = std::max(0.0f, m.shininess);
    float phong = (n + 2.0f) * kInv2Pi * phongTerm(wo, wi, n);
    return m.diffuse * kInvPi + m.specular * phong;
}

float glossyPdf(const BsdfParams& m, Vec3 wo, Vec3 wi) {
    float pd, ps;
    if (!sameHemisphere(wo, wi) || !lobeProbs(m, pd, ps)) return 0.0f;
    float n = std::max(0.0f, m.shininess);
    return pd * absCosTheta(wi) * kInvPi + ps * (n + 1.0f) * kInv2Pi * phongTerm(wo, wi, n);
}

bool glossySample(const BsdfParams& m, Vec3 wo, float uLobe, float u1, float u2, BsdfSample& s) {
    float pd, ps;
    if (wo.z == 0 || !lobeProbs(m, pd, ps)) return false;
    Vec3 wi;
    if (uLobe < pd) {
        wi = sampleCosineHemisphere(u1, u2);
        if (wo.z < 0) wi.z = -wi.z;
    } else {
        Vec3 r(-wo.x, -wo.y, wo.z);  // mirror direction, the lobe's axis
        wi = Frame::fromNormal(r).toWorld(samplePowerCosine(std::max(0.0f, m.shininess), u1, u2));
        // Part of the lobe lies below the surface: f = 0 there, the sample is rejected.
        // glossyPdf is then zero there too, and the lost mass makes the mixture integrate
        // to 1 - ps * (lobe mass below the horizon).
        if (!sameHemisphere(wo, wi)) return false;
    }
    // The full mixture pdf and f of the direction, so that sampling and evaluation agree.
    s.wi = wi;
    s.f = glossyF(m, wo, wi);
    s.pdf = glossyPdf(m, wo, wi);
    s.delta = false;
    return s.pdf > 0;
}

}  // namespace wmlt
