// Per-kind BSDF calls chosen at compile time: a stage loops over the hits of one
// material kind and calls that kind's kernel, with no per-hit switch.
#pragma once
#include "kernels/bsdf.h"

namespace wmlt {

// BsdfOf<K>::reads: which of sample's numbers the kind reads (the others are ignored, and
// the stages do not load them: MMLT proposes only numbers that are read).
constexpr uint8_t kReadsLobe = 1, kReadsDirection = 2;

template <MaterialKind K> struct BsdfOf;

// The kinds whose every lobe is a delta: f and the densities of any given pair of
// directions are 0 (only their own samples find them).
struct DeltaBsdf {
    static constexpr bool delta = true;
    static Vec3 f(const BsdfParams&, Vec3, Vec3) { return Vec3(0.0f); }
    static float pdf(const BsdfParams&, Vec3, Vec3) { return 0.0f; }
};

template <> struct BsdfOf<MaterialKind::Matte> {
    static constexpr uint8_t reads = kReadsDirection;
    static constexpr bool delta = false;
    static Vec3 f(const BsdfParams& m, Vec3 wo, Vec3 wi) { return matteF(m, wo, wi); }
    static float pdf(const BsdfParams& m, Vec3 wo, Vec3 wi) { return mattePdf(m, wo, wi); }
    static bool sample(const BsdfParams& m, Vec3 wo, float ul, float u1, float u2, TransportMode, BsdfSample& s) {
        return matteSample(m, wo, ul, u1, u2, s);
    }
};
template <> struct BsdfOf<MaterialKind::Glossy> {
    static constexpr uint8_t reads = kReadsLobe | kReadsDirection;
    static constexpr bool delta = false;
    static Vec3 f(const BsdfParams& m, Vec3 wo, Vec3 wi) { return glossyF(m, wo, wi); }
    static float pdf(const BsdfParams& m, Vec3 wo, Vec3 wi) { return glossyPdf(m, wo, wi); }
    static bool sample(const BsdfParams& m, Vec3 wo, float ul, float u1, float u2, TransportMode, BsdfSample& s) {
        return glossySample(m, wo, ul, u1, u2, s);
    }
};
template <> struct BsdfOf<MaterialKind::Reflective> : DeltaBsdf {
    static constexpr uint8_t reads = 0;
    static bool sample(const BsdfParams& m, Vec3 wo, float, float, float, TransportMode, BsdfSample& s) {
        return mirrorSample(m, wo, s);
    }
};
template <> struct BsdfOf<MaterialKind::Dielectric> : DeltaBsdf {
    static constexpr uint8_t reads = kReadsLobe;
    static bool sample(const BsdfParams& m, Vec3 wo, float ul, float, float, TransportMode mode, BsdfSample& s) {
        return dielectricSample(m, wo, ul, mode, s);
    }
};

// The Mitsuba kinds (bsdf_microfacet.h). `delta`: every lobe is a delta, so no light
// sampling or connection is tried there; Plastic mixes a delta coating with a diffuse base
// and is not (its sample reports which lobe it took).
template <> struct BsdfOf<MaterialKind::Conductor> : DeltaBsdf {
    static constexpr uint8_t reads = 0;
    static bool sample(const BsdfParams& m, Vec3 wo, float, float, float, TransportMode, BsdfSample& s) {
        return conductorSample(m, wo, s);
    }
};
template <> struct BsdfOf<MaterialKind::RoughConductor> {
    static constexpr uint8_t reads = kReadsDirection;
    static constexpr bool delta = false;
    static Vec3 f(const BsdfParams& m, Vec3 wo, Vec3 wi) { return roughConductorF(m, wo, wi); }
    static float pdf(const BsdfParams& m, Vec3 wo, Vec3 wi) { return roughConductorPdf(m, wo, wi); }
    static bool sample(const BsdfParams& m, Vec3 wo, float, float u1, float u2, TransportMode, BsdfSample& s) {
        return roughConductorSample(m, wo, u1, u2, s);
    }
};
template <> struct BsdfOf<MaterialKind::RoughDielectric> {
    static constexpr uint8_t reads = kReadsLobe | kReadsDirection;
    static constexpr bool delta = false;
    static Vec3 f(const BsdfParams& m, Vec3 wo, Vec3 wi) { return roughDielectricF(m, wo, wi); }
    static float pdf(const BsdfParams& m, Vec3 wo, Vec3 wi) { return roughDielectricPdf(m, wo, wi); }
    static bool sample(const BsdfParams& m, Vec3 wo, float ul, float u1, float u2, TransportMode mode, BsdfSample& s) {
        return roughDielectricSample(m, wo, ul, u1, u2, mode, s);
    }
};
template <> struct BsdfOf<MaterialKind::ThinDielectric> : DeltaBsdf {
    static constexpr uint8_t reads = kReadsLobe;
    static bool sample(const BsdfParams& m, Vec3 wo, float ul, float, float, TransportMode, BsdfSample& s) {
        return thinDielectricSample(m, wo, ul, s);
    }
};
template <> struct BsdfOf<MaterialKind::Plastic> {
    static constexpr uint8_t reads = kReadsLobe | kReadsDirection;
    static constexpr bool delta = false;
    static Vec3 f(const BsdfParams& m, Vec3 wo, Vec3 wi) { return plasticF(m, wo, wi); }
    static float pdf(const BsdfParams& m, Vec3 wo, Vec3 wi) { return plasticPdf(m, wo, wi); }
    static bool sample(const BsdfParams& m, Vec3 wo, float ul, float u1, float u2, TransportMode, BsdfSample& s) {
        return plasticSample(m, wo, ul, u1, u2, s);
    }
};
template <> struct BsdfOf<MaterialKind::RoughPlastic> {
    static constexpr uint8_t reads = kReadsLobe | kReadsDirection;
    static constexpr bool delta = false;
    static Vec3 f(const BsdfParams& m, Vec3 wo, Vec3 wi) { return roughPlasticF(m, wo, wi); }
    static float pdf(const BsdfParams& m, Vec3 wo, Vec3 wi) { return roughPlasticPdf(m, wo, wi); }
    static bool sample(const BsdfParams& m, Vec3 wo, float ul, float u1, float u2, TransportMode, BsdfSample& s) {
        return roughPlasticSample(m, wo, ul, u1, u2, s);
    }
};

template <> struct BsdfOf<MaterialKind::Blend> {
    static constexpr uint8_t reads = kReadsLobe | kReadsDirection;
    static constexpr bool delta = false;
    static Vec3 f(const BsdfParams& m, Vec3 wo, Vec3 wi) { return blendF(m, wo, wi); }
    static float pdf(const BsdfParams& m, Vec3 wo, Vec3 wi) { return blendPdf(m, wo, wi); }
    static bool sample(const BsdfParams& m, Vec3 wo, float ul, float u1, float u2, TransportMode mode, BsdfSample& s) {
        return blendSample(m, wo, ul, u1, u2, mode, s);
    }
};

template <> struct BsdfOf<MaterialKind::Principled> {
    static constexpr uint8_t reads = kReadsLobe | kReadsDirection;
    static constexpr bool delta = false;
    static Vec3 f(const BsdfParams& m, Vec3 wo, Vec3 wi) { return principledF(m, wo, wi); }
    static float pdf(const BsdfParams& m, Vec3 wo, Vec3 wi) { return principledPdf(m, wo, wi); }
    static bool sample(const BsdfParams& m, Vec3 wo, float ul, float u1, float u2, TransportMode mode, BsdfSample& s) {
        return principledSample(m, wo, ul, u1, u2, mode, s);
    }
};

template <> struct BsdfOf<MaterialKind::Coated> {
    static constexpr uint8_t reads = kReadsLobe | kReadsDirection;
    static constexpr bool delta = false;
    static Vec3 f(const BsdfParams& m, Vec3 wo, Vec3 wi) { return coatedF(m, wo, wi); }
    static float pdf(const BsdfParams& m, Vec3 wo, Vec3 wi) { return coatedPdf(m, wo, wi); }
    static bool sample(const BsdfParams& m, Vec3 wo, float ul, float u1, float u2, TransportMode mode, BsdfSample& s) {
        return coatedSample(m, wo, ul, u1, u2, mode, s);
    }
};

template <> struct BsdfOf<MaterialKind::DiffuseTransmission> {
    static constexpr uint8_t reads = kReadsLobe | kReadsDirection;
    static constexpr bool delta = false;
    static Vec3 f(const BsdfParams& m, Vec3 wo, Vec3 wi) { return diffuseTransmissionF(m, wo, wi); }
    static float pdf(const BsdfParams& m, Vec3 wo, Vec3 wi) { return diffuseTransmissionPdf(m, wo, wi); }
    static bool sample(const BsdfParams& m, Vec3 wo, float ul, float u1, float u2, TransportMode, BsdfSample& s) {
        return diffuseTransmissionSample(m, wo, ul, u1, u2, s);
    }
};

template <> struct BsdfOf<MaterialKind::Phase> {
    static constexpr uint8_t reads = kReadsDirection;
    static constexpr bool delta = false;
    static Vec3 f(const BsdfParams& m, Vec3 wo, Vec3 wi) { return phaseF(m, wo, wi); }
    static float pdf(const BsdfParams& m, Vec3 wo, Vec3 wi) { return phasePdf(m, wo, wi); }
    static bool sample(const BsdfParams& m, Vec3, float, float u1, float u2, TransportMode, BsdfSample& s) {
        return phaseSample(m, u1, u2, s);
    }
};

// Kind B's BSDF sample with its numbers from number(m) (m = 0: lobe, 1-2: direction), asked
// for only those the kind reads.
template <class B, class Number>
inline bool sampleBsdfOf(const BsdfParams& m, Vec3 wo, Number&& number, TransportMode mode, BsdfSample& s) {
    const float ul = B::reads & kReadsLobe ? number(0) : 0.0f;
    const float u1 = B::reads & kReadsDirection ? number(1) : 0.0f;
    const float u2 = B::reads & kReadsDirection ? number(2) : 0.0f;
    return B::sample(m, wo, ul, u1, u2, mode, s);
}

// A stable counting sort of n hits by material kind (kindOf(h): hit h's kind): kind k's
// hits are order[kindStart[k] .. kindStart[k + 1]), in their original order.
template <class KindOf>
inline void groupByMaterialKind(KindOf&& kindOf, size_t n, uint32_t* order, uint32_t kindStart[kMaterialKinds + 1]) {
    uint32_t count[kMaterialKinds] = {};
    for (size_t h = 0; h < n; ++h) ++count[int(kindOf(h))];
    kindStart[0] = 0;
    for (int k = 0; k < kMaterialKinds; ++k) kindStart[k + 1] = kindStart[k] + count[k];
    uint32_t next[kMaterialKinds];
    for (int k = 0; k < kMaterialKinds; ++k) next[k] = kindStart[k];
    for (size_t h = 0; h < n; ++h) order[next[int(kindOf(h))]++] = uint32_t(h);
}

// Calls fn(std::integral_constant<MaterialKind, K>{}) for each kind (a kind with no hits
// costs one empty loop).
template <class Fn> void forEachMaterialKind(Fn&& fn) {
    fn(std::integral_constant<MaterialKind, MaterialKind::Matte>{});
    fn(std::integral_constant<MaterialKind, MaterialKind::Glossy>{});
    fn(std::integral_constant<MaterialKind, MaterialKind::Reflective>{});
    fn(std::integral_constant<MaterialKind, MaterialKind::Dielectric>{});
    fn(std::integral_constant<MaterialKind, MaterialKind::Conductor>{});
    fn(std::integral_constant<MaterialKind, MaterialKind::RoughConductor>{});
    fn(std::integral_constant<MaterialKind, MaterialKind::RoughDielectric>{});
    fn(std::integral_constant<MaterialKind, MaterialKind::ThinDielectric>{});
    fn(std::integral_constant<MaterialKind, MaterialKind::Plastic>{});
    fn(std::integral_constant<MaterialKind, MaterialKind::RoughPlastic>{});
    fn(std::integral_constant<MaterialKind, MaterialKind::Blend>{});
    fn(std::integral_constant<MaterialKind, MaterialKind::Principled>{});
    fn(std::integral_constant<MaterialKind, MaterialKind::Coated>{});
    fn(std::integral_constant<MaterialKind, MaterialKind::DiffuseTransmission>{});
    fn(std::integral_constant<MaterialKind, MaterialKind::Phase>{});
}
static_assert(kMaterialKinds == 15, "forEachMaterialKind lists every kind");

}  // namespace wmlt
