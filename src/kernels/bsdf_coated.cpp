// Coated (pbrt-v4's coateddiffuse and coatedconductor: its LayeredBxDF, two-sided): a
// dielectric interface (eta, GGX alphas; smooth below alpha 1e-3) over a diffuse or
// conductor base, a slab of `thickness` between them with an optional scattering medium
// (albedo, Henyey-Greenstein g). f, the pdf and sampling are pbrt-v4's stochastic
// estimates (Guo et al. 2018's position-free random walk, pbrt-v4 section 14.3):
//   f(wo, wi): the entrance's reflection plus nSamples random walks between the layers,
//     with next-event estimation through the exit (MIS between the exit's sample and the
//     walk's direction); Russian roulette after 3 bounces, at most maxDepth;
//   pdf(wo, wi): 0.1 / 4 pi + 0.9 times an estimate of the transmission-reflection-
//     transmission density;
//   sample: a walk from the entrance; its f / pdf is the path's weight. The sample returned
//     carries the weight as f / pdf with pdf = the pdf estimate above (pbrt's
//     pdfIsProportional: MIS uses that estimate; the throughput the walk's weight).
// Every random number of a walk comes from a generator seeded by a hash of its arguments
// (wo and wi for f and the pdf, wo and the sample's u for sampling): the functions are
// deterministic, as every kernel is, so MMLT's replay of a path sees the same values.
// One deliberate difference: where a direction w sampled inside the slab (by the base or the
// phase function) meets next-event estimation through the exit, pbrt-v4's code weighs it
// against the exit strategy with the exit's density of wi given -w; the strategy that
// sampled such a direction sampled it from wi (wis), so its density is that of -w given wi.
// With pbrt's weights f is 6-19% above its own walk's albedo (rough coats, tests/
// test_bsdf_coated.cpp); with these, f integrates to the walk's albedo. pbrt-v4's renders
// carry that bias: with pbrt's weights (MaterialDesc::Coating::pbrtExitWeight, off) the
// coated gold killeroo and the caustic glass's floor render what pbrt-v4 renders; with
// these, the killeroo's highlights are 4-8% darker and the caustic glass 1.9% (docs/pbrt.md).
// pbrt's weights also make f non-reciprocal, and pbrt evaluates a light subpath's vertex from
// the light's side: pbrtWalkFromLight plants that (f(wo, wi) = pbrt's f(wi, wo) in Importance
// mode; bench/bench_pbrt_blocks.cpp renders the caustic glass as pbrt's BDPT does with it).
// The interfaces are pbrt-v4's dielectric, diffuse and conductor BxDFs with its
// reflection-only / transmission-only sampling restrictions; the bottom one is seen upside
// down (pbrt's TopOrBottomBxDF).
#include <cstring>

#include "kernels/bsdf.h"
#include "kernels/fresnel.h"

namespace wmlt {
namespace {

enum Restrict : int { kReflect = 1, kTransmit = 2, kAll = 3 };

struct Sample {
    Vec3 f{0.0f}, wi{0.0f};
    float pdf = 0;
    bool reflect = false, specular = false;
    explicit operator bool() const { return pdf > 0 && (f.x > 0 || f.y > 0 || f.z > 0) && wi.z != 0; }
};

inline float maxOf(Vec3 v) { return std::max(v.x, std::max(v.y, v.z)); }
inline bool sameSide(Vec3 a, Vec3 b) { return a.z * b.z > 0; }
inline float power2(float a, float b) { return a * a / (a * a + b * b); }  // power heuristic, one sample each

// ---- the interfaces -------------------------------------------------------------------

// A dielectric interface of relative index eta (below / above), pbrt-v4's DielectricBxDF.
struct Dielectric {
    float eta;
    Microfacet d;
    bool smooth() const { return std::max(d.alphaX, d.alphaY) < 1e-3f; }

    Vec3 f(Vec3 wo, Vec3 wi, TransportMode mode) const {
        if (eta == 1 || smooth()) return Vec3(0.0f);
        Vec3 wm;
        float etap;
        if (!generalizedHalfVector(eta, wo, wi, wm, etap)) return Vec3(0.0f);
        const float F = fresnelDielectric(dot(wo, wm), eta);
        const float G = float(1.0 / (1.0 + microfacetLambda(d, wo) + microfacetLambda(d, wi)));
        if (sameSide(wo, wi)) return Vec3(microfacetD(d, wm) * G * F / std::fabs(4 * wi.z * wo.z));
        const float denom = (dot(wi, wm) + dot(wo, wm) / etap) * (dot(wi, wm) + dot(wo, wm) / etap) * wi.z * wo.z;
        float ft = microfacetD(d, wm) * (1 - F) * G * std::fabs(dot(wi, wm) * dot(wo, wm) / denom);
        if (mode == TransportMode::Radiance) ft /= etap * etap;
        return Vec3(ft);
    }
    float pdf(Vec3 wo, Vec3 wi, int restrict) const {
        if (eta == 1 || smooth()) return 0;
        Vec3 wm;
        float etap;
        if (!generalizedHalfVector(eta, wo, wi, wm, etap)) return 0;
        const float R = fresnelDielectric(dot(wo, wm), eta), T = 1 - R;
        const float pr = restrict & kReflect ? R : 0, pt = restrict & kTransmit ? T : 0;
        if (pr + pt <= 0) return 0;
        if (sameSide(wo, wi)) return visibleNormalPdf(d, wo, wm) / (4 * std::fabs(dot(wo, wm))) * pr / (pr + pt);
        const float denom = (dot(wi, wm) + dot(wo, wm) / etap) * (dot(wi, wm) + dot(wo, wm) / etap);
        return visibleNormalPdf(d, wo, wm) * std::fabs(dot(wi, wm)) / denom * pt / (pr + pt);
    }
    Sample sample(Vec3 wo, float uc, float u1, float u2, TransportMode mode, int restrict) const {
        Sample s;
        if (eta == 1 || smooth()) {
            const float R = fresnelDielectric(wo.z, eta), T = 1 - R;
            const float pr = restrict & kReflect ? R : 0, pt = restrict & kTransmit ? T : 0;
            if (pr + pt <= 0) return s;
            s.specular = true;
            if (uc < pr / (pr + pt)) {
                s.wi = Vec3(-wo.x, -wo.y, wo.z);
                s.f = Vec3(R / std::fabs(s.wi.z));
                s.pdf = pr / (pr + pt);
                s.reflect = true;
                return s;
            }
            const bool entering = wo.z > 0;
            const float etap = entering ? eta : 1 / eta;
            if (!refractAbout(wo, Vec3(0, 0, entering ? 1.0f : -1.0f), etap, s.wi)) return Sample{};
            float ft = T / std::fabs(s.wi.z);
            if (mode == TransportMode::Radiance) ft /= etap * etap;
            s.f = Vec3(ft);
            s.pdf = pt / (pr + pt);
            return s;
        }
        const Vec3 wm = sampleVisibleNormal(d, wo, u1, u2);
        const float R = fresnelDielectric(dot(wo, wm), eta), T = 1 - R;
        const float pr = restrict & kReflect ? R : 0, pt = restrict & kTransmit ? T : 0;
        if (pr + pt <= 0) return s;
        const bool reflect = uc < pr / (pr + pt);
        if (!scatterAbout(wo, wm, eta, reflect, s.wi)) return Sample{};
        s.reflect = reflect;
        s.f = f(wo, s.wi, mode);
        s.pdf = pdf(wo, s.wi, restrict);
        return s;
    }
};

// A Lambertian base, pbrt-v4's DiffuseBxDF: reflection only.
struct Diffuse {
    Vec3 R;
    Vec3 f(Vec3 wo, Vec3 wi) const { return sameSide(wo, wi) ? R * kInvPi : Vec3(0.0f); }
    float pdf(Vec3 wo, Vec3 wi, int restrict) const { return restrict & kReflect && sameSide(wo, wi) ? std::fabs(wi.z) * kInvPi : 0.0f; }
    Sample sample(Vec3 wo, float u1, float u2, int restrict) const {
        Sample s;
        if (!(restrict & kReflect)) return s;
        s.wi = sampleCosineHemisphere(u1, u2);
        if (wo.z < 0) s.wi.z = -s.wi.z;
        s.f = f(wo, s.wi);
        s.pdf = std::fabs(s.wi.z) * kInvPi;
        s.reflect = true;
        return s;
    }
};

// A conductor base (complex index eta + i k per channel, GGX; smooth below alpha 1e-3),
// pbrt-v4's ConductorBxDF, times `scale` (the importer's spectral albedo match).
struct Conductor {
    Vec3 eta, k, scale;
    Microfacet d;
    bool smooth() const { return std::max(d.alphaX, d.alphaY) < 1e-3f; }
    Vec3 f(Vec3 wo, Vec3 wi) const {
        if (!sameSide(wo, wi) || smooth()) return Vec3(0.0f);
        Vec3 wm = wi + wo;
        if (!(lengthSquared(wm) > 0)) return Vec3(0.0f);
        wm = normalize(wm);
        if (wm.z < 0) wm = -wm;
        const float G = float(1.0 / (1.0 + microfacetLambda(d, wo) + microfacetLambda(d, wi)));
        return fresnelConductor(std::fabs(dot(wo, wm)), eta, k) * scale * (microfacetD(d, wm) * G / std::fabs(4 * wi.z * wo.z));
    }
    float pdf(Vec3 wo, Vec3 wi, int restrict) const {
        if (!(restrict & kReflect) || !sameSide(wo, wi) || smooth()) return 0;
        Vec3 wm = wo + wi;
        if (!(lengthSquared(wm) > 0)) return 0;
        wm = normalize(wm);
        if (wm.z < 0) wm = -wm;
        return visibleNormalPdf(d, wo, wm) / (4 * std::fabs(dot(wo, wm)));
    }
    Sample sample(Vec3 wo, float u1, float u2, int restrict) const {
        Sample s;
        if (!(restrict & kReflect)) return s;
        s.reflect = true;
        if (smooth()) {
            s.wi = Vec3(-wo.x, -wo.y, wo.z);
            s.f = fresnelConductor(std::fabs(s.wi.z), eta, k) * scale / std::fabs(s.wi.z);
            s.pdf = 1;
            s.specular = true;
            return s;
        }
        const Vec3 wm = sampleVisibleNormal(d, wo, u1, u2);
        s.wi = reflectAbout(wo, wm);
        if (!sameSide(wo, s.wi)) return Sample{};
        s.f = f(wo, s.wi);
        s.pdf = pdf(wo, s.wi, kAll);
        return s;
    }
};

// The slab: the top interface, the base below (seen upside down: pbrt's TopOrBottomBxDF),
// and the slab's constants (from CoatingExtra).
struct Layers {
    Dielectric top;
    Diffuse diffuse;
    Conductor conductor;
    bool conductorBase;
    float thickness, g;
    Vec3 albedo;
    int maxDepth, nSamples;
    bool pbrtExitWeight;

    explicit Layers(const BsdfParams& m)
        : top{m.eta, Microfacet(MicrofacetType::GGX, m.alphaX, m.alphaY)},
          diffuse{m.diffuse},
          conductor{conductorEta(m), conductorK(m), coatBaseScale(m), Microfacet(MicrofacetType::GGX, coatBaseAlphaU(m), coatBaseAlphaV(m))},
          conductorBase(m.x->coating.conductorBase),
          thickness(m.x->coating.thickness),
          g(m.x->coating.g),
          albedo(coatingAlbedo(m)),
          maxDepth(m.x->coating.maxDepth),
          nSamples(m.x->coating.nSamples),
          pbrtExitWeight(m.x->coating.pbrtExitWeight) {}

    // which = 0: the top; 1: the base (directions turned over)
    Vec3 f(int which, Vec3 wo, Vec3 wi, TransportMode mode) const {
        if (which == 0) return top.f(wo, wi, mode);
        return conductorBase ? conductor.f(-wo, -wi) : diffuse.f(-wo, -wi);
    }
    float pdf(int which, Vec3 wo, Vec3 wi, TransportMode, int restrict = kAll) const {
        if (which == 0) return top.pdf(wo, wi, restrict);
        return conductorBase ? conductor.pdf(-wo, -wi, restrict) : diffuse.pdf(-wo, -wi, restrict);
    }
    Sample sample(int which, Vec3 wo, float uc, float u1, float u2, TransportMode mode, int restrict = kAll) const {
        if (which == 0) return top.sample(wo, uc, u1, u2, mode, restrict);
        Sample s = conductorBase ? conductor.sample(-wo, u1, u2, restrict) : diffuse.sample(-wo, u1, u2, restrict);
        s.wi = -s.wi;
        return s;
    }
    bool specular(int which) const { return which == 0 ? top.smooth() : conductorBase && conductor.smooth(); }
    // The density with which next-event estimation through the exit samples the direction w
    // inside the slab (travelling towards the exit): the exit's transmission density of -w
    // given wi. pbrtExitWeight: pbrt-v4's, the density of wi given -w (biased: see above).
    float exitPdf(int exitI, Vec3 wi, Vec3 w, TransportMode mode, TransportMode other) const {
        return pbrtExitWeight ? pdf(exitI, -w, wi, mode, kTransmit) : pdf(exitI, wi, -w, other, kTransmit);
    }
};

// Transmittance through the slab's medium (extinction 1 per unit thickness) along w over dz.
inline float Tr(float dz, Vec3 w) { return std::fabs(dz) <= 1e-30f ? 1.0f : std::exp(-std::fabs(dz / w.z)); }

// Henyey-Greenstein with pbrt's convention: p(wo, wi) from cos(wo, wi) (wo pointing away).
inline float hg(float cosTheta, float g) {
    const float denom = 1 + g * g + 2 * g * cosTheta;
    return (1 - g * g) / (4 * kPi * denom * std::sqrt(std::max(denom, 1e-12f)));
}
inline Vec3 sampleHg(Vec3 wo, float g, float u1, float u2, float& pdf) {
    float cosTheta;
    if (std::fabs(g) < 1e-3f) cosTheta = 1 - 2 * u1;
    else cosTheta = -1 / (2 * g) * (1 + g * g - ((1 - g * g) / (1 + g - 2 * g * u1)) * ((1 - g * g) / (1 + g - 2 * g * u1)));
    const float sinTheta = std::sqrt(std::max(0.0f, 1 - cosTheta * cosTheta)), phi = 2 * kPi * u2;
    const Frame fr = Frame::fromNormal(wo);
    const Vec3 wi = fr.toWorld(Vec3(sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta));
    pdf = hg(cosTheta, g);
    return wi;
}

// The walks' random numbers: SplitMix64 seeded by a hash of the arguments' bits.
struct Rng {
    uint64_t s;
    static uint64_t mix(uint64_t z) {
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
        return z ^ (z >> 31);
    }
    Rng(std::initializer_list<float> xs) : s(0x9e3779b97f4a7c15ULL) {
        for (float x : xs) {
            uint32_t b;
            std::memcpy(&b, &x, 4);
            s = mix(s ^ (b + 0x9e3779b97f4a7c15ULL + (s << 6) + (s >> 2)));
        }
    }
    float operator()() {
        s += 0x9e3779b97f4a7c15ULL;
        return std::min(float(mix(s) >> 40) * 0x1p-24f, 0x1.fffffep-1f);
    }
};

}  // namespace

Vec3 coatedF(const BsdfParams& m, Vec3 wo, Vec3 wi, TransportMode mode) {
    const Layers L(m);
    // pbrt-v4 at a light subpath's vertex (planted; off)
    if (L.pbrtExitWeight && m.x->coating.pbrtWalkFromLight && mode == TransportMode::Radiance) return coatedF(m, wi, wo, TransportMode::Importance);
    if (wo.z < 0) {  // two-sided
        wo = -wo;
        wi = -wi;
    }
    // entered at the top; exits at the top (reflection, z = 0 is the base) or the base
    const bool reflect = sameSide(wo, wi);
    const int exitI = reflect ? 0 : 1, nonExitI = reflect ? 1 : 0;
    const float exitZ = reflect ? L.thickness : 0;
    Vec3 f(0.0f);
    if (reflect) f = L.f(0, wo, wi, mode) * float(L.nSamples);
    Rng r{wo.x, wo.y, wo.z, wi.x, wi.y, wi.z};
    const TransportMode other = mode == TransportMode::Radiance ? TransportMode::Importance : TransportMode::Radiance;
    for (int k = 0; k < L.nSamples; ++k) {
        float uc = r(), u1 = r(), u2 = r();
        const Sample wos = L.sample(0, wo, uc, u1, u2, mode, kTransmit);
        if (!wos) continue;
        uc = r(), u1 = r(), u2 = r();
        const Sample wis = L.sample(exitI, wi, uc, u1, u2, other, kTransmit);
        if (!wis) continue;
        Vec3 beta = wos.f * std::fabs(wos.wi.z) / wos.pdf;
        float z = L.thickness;
        Vec3 w = wos.wi;
        for (int depth = 0; depth < L.maxDepth; ++depth) {
            if (depth > 3 && maxOf(beta) < 0.25f) {  // Russian roulette
                const float q = std::max(0.0f, 1 - maxOf(beta));
                if (r() < q) break;
                beta = beta / (1 - q);
            }
            if (maxOf(L.albedo) <= 0) {
                z = z == L.thickness ? 0 : L.thickness;
                beta = beta * Tr(L.thickness, w);
            } else {
                const float dz = -std::log(1 - r()) * std::fabs(w.z);  // exponential, extinction 1 along w
                const float zp = w.z > 0 ? z + dz : z - dz;
                if (zp == z) continue;
                if (0 < zp && zp < L.thickness) {  // scattering in the medium
                    float wt = 1;
                    if (!L.specular(exitI)) wt = power2(wis.pdf, hg(dot(-w, -wis.wi), L.g));
                    f = f + beta * L.albedo * hg(dot(-w, -wis.wi), L.g) * wt * Tr(zp - exitZ, wis.wi) * wis.f / wis.pdf;
                    float phasePdf;
                    u1 = r(), u2 = r();
                    const Vec3 wn = sampleHg(-w, L.g, u1, u2, phasePdf);
                    if (!(phasePdf > 0) || wn.z == 0) continue;
                    beta = beta * L.albedo;  // p / pdf = 1 for HG's exact sampling
                    w = wn;
                    z = zp;
                    if (((z < exitZ && w.z > 0) || (z > exitZ && w.z < 0)) && !L.specular(exitI)) {
                        const Vec3 fExit = L.f(exitI, -w, wi, mode);
                        if (maxOf(fExit) > 0) {
                            const float exitPdf = L.exitPdf(exitI, wi, w, mode, other);
                            f = f + beta * Tr(zp - exitZ, w) * fExit * power2(phasePdf, exitPdf);
                        }
                    }
                    continue;
                }
                z = std::clamp(zp, 0.0f, L.thickness);
            }
            if (z == exitZ) {  // reflection off the exit interface back into the slab
                uc = r(), u1 = r(), u2 = r();
                const Sample bs = L.sample(exitI, -w, uc, u1, u2, mode, kReflect);
                if (!bs) break;
                beta = beta * bs.f * std::fabs(bs.wi.z) / bs.pdf;
                w = bs.wi;
            } else {  // scattering at the other interface, with next-event estimation through the exit
                if (!L.specular(nonExitI)) {
                    float wt = 1;
                    if (!L.specular(exitI)) wt = power2(wis.pdf, L.pdf(nonExitI, -w, -wis.wi, mode));
                    f = f + beta * L.f(nonExitI, -w, -wis.wi, mode) * std::fabs(wis.wi.z) * wt * Tr(L.thickness, wis.wi) * wis.f / wis.pdf;
                }
                uc = r(), u1 = r(), u2 = r();
                const Sample bs = L.sample(nonExitI, -w, uc, u1, u2, mode, kReflect);
                if (!bs) break;
                beta = beta * bs.f * std::fabs(bs.wi.z) / bs.pdf;
                w = bs.wi;
                if (!L.specular(exitI)) {
                    const Vec3 fExit = L.f(exitI, -w, wi, mode);
                    if (maxOf(fExit) > 0) {
                        float wt = 1;
                        if (!L.specular(nonExitI)) wt = power2(bs.pdf, L.exitPdf(exitI, wi, w, mode, other));
                        f = f + beta * Tr(L.thickness, bs.wi) * fExit * wt;
                    }
                }
            }
        }
    }
    return f / float(L.nSamples);
}

float coatedPdf(const BsdfParams& m, Vec3 wo, Vec3 wi, TransportMode mode) {
    const Layers L(m);
    if (wo.z < 0) {
        wo = -wo;
        wi = -wi;
    }
    Rng r{wi.x, wi.y, wi.z, wo.x, wo.y, wo.z, 1.0f};
    float sum = 0;
    const TransportMode other = mode == TransportMode::Radiance ? TransportMode::Importance : TransportMode::Radiance;
    if (sameSide(wo, wi)) {
        sum = float(L.nSamples) * L.pdf(0, wo, wi, mode, kReflect);
        for (int k = 0; k < L.nSamples; ++k) {  // transmission, reflection at the base, transmission
            float uc = r(), u1 = r(), u2 = r();
            const Sample wos = L.sample(0, wo, uc, u1, u2, mode, kTransmit);
            uc = r(), u1 = r(), u2 = r();
            const Sample wis = L.sample(0, wi, uc, u1, u2, other, kTransmit);
            if (!wos || !wis) continue;
            if (L.specular(0)) {
                sum += L.pdf(1, -wos.wi, -wis.wi, mode);
            } else {
                uc = r(), u1 = r(), u2 = r();
                const Sample rs = L.sample(1, -wos.wi, uc, u1, u2, mode);
                if (!rs) continue;
                if (L.specular(1)) {
                    sum += L.pdf(0, -rs.wi, wi, mode);
                } else {
                    const float rPdf = L.pdf(1, -wos.wi, -wis.wi, mode);
                    sum += power2(wis.pdf, rPdf) * rPdf;
                    const float tPdf = L.pdf(0, -rs.wi, wi, mode);
                    sum += power2(rs.pdf, tPdf) * tPdf;
                }
            }
        }
    }
    // (opaque bases: no transmission through the slab)
    return 0.1f / (4 * kPi) + 0.9f * sum / float(L.nSamples);
}

bool coatedSample(const BsdfParams& m, Vec3 wo, float uLobe, float u1, float u2, TransportMode mode, BsdfSample& out) {
    const Layers L(m);
    const bool flip = wo.z < 0;
    if (flip) wo = -wo;
    const Sample bs = L.sample(0, wo, uLobe, u1, u2, mode);
    if (!bs) return false;
    Vec3 weight;  // f |cos| / pdf of the whole walk
    Vec3 wi;
    bool specular = bs.specular;
    if (bs.reflect) {
        wi = bs.wi;
        weight = bs.f * std::fabs(bs.wi.z) / bs.pdf;
    } else {
        Rng r{wo.x, wo.y, wo.z, uLobe, u1, u2};
        Vec3 f = bs.f * std::fabs(bs.wi.z);
        float pdf = bs.pdf, z = L.thickness;
        Vec3 w = bs.wi;
        bool out_ = false;
        for (int depth = 0; depth < L.maxDepth; ++depth) {
            const float rrBeta = maxOf(f) / pdf;
            if (depth > 3 && rrBeta < 0.25f) {
                const float q = std::max(0.0f, 1 - rrBeta);
                if (r() < q) return false;
                pdf *= 1 - q;
            }
            if (w.z == 0) return false;
            if (maxOf(L.albedo) > 0) {
                const float dz = -std::log(1 - r()) * std::fabs(w.z);
                const float zp = w.z > 0 ? z + dz : z - dz;
                if (zp == z) return false;
                if (0 < zp && zp < L.thickness) {
                    float phasePdf;
                    const float a = r(), b = r();
                    const Vec3 wn = sampleHg(-w, L.g, a, b, phasePdf);
                    if (!(phasePdf > 0) || wn.z == 0) return false;
                    f = f * L.albedo * phasePdf;  // p = pdf
                    pdf *= phasePdf;
                    specular = false;
                    w = wn;
                    z = zp;
                    continue;
                }
                z = std::clamp(zp, 0.0f, L.thickness);
            } else {
                z = z == L.thickness ? 0 : L.thickness;
                f = f * Tr(L.thickness, w);
            }
            const int which = z == 0 ? 1 : 0;
            const float uc = r(), a = r(), b = r();
            const Sample s = L.sample(which, -w, uc, a, b, mode);
            if (!s) return false;
            f = f * s.f;
            pdf *= s.pdf;
            specular = specular && s.specular;
            w = s.wi;
            if (!s.reflect) {  // left the slab (through the top: the base is opaque)
                out_ = true;
                break;
            }
            f = f * std::fabs(s.wi.z);
        }
        if (!out_) return false;
        wi = w;
        weight = f * std::fabs(w.z) / pdf;  // the exit's cosine: f |cos wi| / pdf
    }
    if (flip) wi = -wi;
    out.wi = wi;
    out.delta = specular;
    // MIS reads the pdf estimate; the throughput the walk's weight (pbrt's pdfIsProportional)
    const float cosI = std::fabs(wi.z);
    if (!(cosI > 0)) return false;
    if (specular) {  // a delta path (the smooth coat's mirror): its own probability
        out.pdf = bs.reflect ? bs.pdf : 1.0f;
        out.f = weight * out.pdf / cosI;
    } else {
        out.pdf = coatedPdf(m, flip ? -wo : wo, out.wi, mode);
        out.f = weight * out.pdf / cosI;
    }
    return out.pdf > 0 && maxOf(out.f) > 0;
}

}  // namespace wmlt
