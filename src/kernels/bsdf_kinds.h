// Each material kind's kernels by kind, BsdfOf<Kind> (f, pdf, sample; `delta`: every lobe
// a delta; `reads`: which of a sample's numbers it reads), one specialisation per kind of
// WMLT_MATERIAL_KINDS (include/wavemmlt/scene_desc.h). The dispatch by a kind known at run
// time (bsdf.h: bsdfF, bsdfPdf, bsdfSample) and the stages' per-kind loops
// (stages/core/bsdf_dispatch.h) are made from the list and these. Included by bsdf.h.
#pragma once

namespace wmlt {

// BsdfOf<K>::reads: which of sample's numbers the kind reads (the others are ignored, and
// the stages do not load them: MMLT proposes only numbers that are read).
constexpr uint8_t kReadsLobe = 1, kReadsDirection = 2;

template <MaterialKind K>
struct BsdfOf;

// The kinds whose every lobe is a delta: f and the densities of any given pair of
// directions are 0 (only their own samples find them).
struct DeltaBsdf {
    static constexpr bool delta = true;
    static Vec3 f(const BsdfParams&, Vec3, Vec3) { return Vec3(0.0f); }
    static float pdf(const BsdfParams&, Vec3, Vec3) { return 0.0f; }
};

template <>
struct BsdfOf<MaterialKind::Matte> {
    static constexpr uint8_t reads = kReadsDirection;
    static constexpr bool delta = false;
    static Vec3 f(const BsdfParams& m, Vec3 wo, Vec3 wi) { return matteF(m, wo, wi); }
    static float pdf(const BsdfParams& m, Vec3 wo, Vec3 wi) { return mattePdf(m, wo, wi); }
    static bool sample(const BsdfParams& m, Vec3 wo, float ul, float u1, float u2, TransportMode, BsdfSample& s) {
        return matteSample(m, wo, ul, u1, u2, s);
    }
};
template <>
struct BsdfOf<MaterialKind::Glossy> {
    static constexpr uint8_t reads = kReadsLobe | kReadsDirection;
    static constexpr bool delta = false;
    static Vec3 f(const BsdfParams& m, Vec3 wo, Vec3 wi) { return glossyF(m, wo, wi); }
    static float pdf(const BsdfParams& m, Vec3 wo, Vec3 wi) { return glossyPdf(m, wo, wi); }
    static bool sample(const BsdfParams& m, Vec3 wo, float ul, float u1, float u2, TransportMode, BsdfSample& s) {
        return glossySample(m, wo, ul, u1, u2, s);
    }
};
template <>
struct BsdfOf<MaterialKind::Reflective> : DeltaBsdf {
    static constexpr uint8_t reads = 0;
    static bool sample(const BsdfParams& m, Vec3 wo, float, float, float, TransportMode, BsdfSample& s) { return mirrorSample(m, wo, s); }
};
template <>
struct BsdfOf<MaterialKind::Dielectric> : DeltaBsdf {
    static constexpr uint8_t reads = kReadsLobe;
    static bool sample(const BsdfParams& m, Vec3 wo, float ul, float, float, TransportMode mode, BsdfSample& s) {
        return dielectricSample(m, wo, ul, mode, s);
    }
};

// The Mitsuba kinds (bsdf_microfacet.h). `delta`: every lobe is a delta, so no light
// sampling or connection is tried there; Plastic mixes a delta coating with a diffuse base
// and is not (its sample reports which lobe it took).
template <>
struct BsdfOf<MaterialKind::Conductor> : DeltaBsdf {
    static constexpr uint8_t reads = 0;
    static bool sample(const BsdfParams& m, Vec3 wo, float, float, float, TransportMode, BsdfSample& s) { return conductorSample(m, wo, s); }
};
template <>
struct BsdfOf<MaterialKind::RoughConductor> {
    static constexpr uint8_t reads = kReadsDirection;
    static constexpr bool delta = false;
    static Vec3 f(const BsdfParams& m, Vec3 wo, Vec3 wi) { return roughConductorF(m, wo, wi); }
    static float pdf(const BsdfParams& m, Vec3 wo, Vec3 wi) { return roughConductorPdf(m, wo, wi); }
    static bool sample(const BsdfParams& m, Vec3 wo, float, float u1, float u2, TransportMode, BsdfSample& s) {
        return roughConductorSample(m, wo, u1, u2, s);
    }
};
template <>
struct BsdfOf<MaterialKind::RoughDielectric> {
    static constexpr uint8_t reads = kReadsLobe | kReadsDirection;
    static constexpr bool delta = false;
    static Vec3 f(const BsdfParams& m, Vec3 wo, Vec3 wi) { return roughDielectricF(m, wo, wi); }
    static float pdf(const BsdfParams& m, Vec3 wo, Vec3 wi) { return roughDielectricPdf(m, wo, wi); }
    static bool sample(const BsdfParams& m, Vec3 wo, float ul, float u1, float u2, TransportMode mode, BsdfSample& s) {
        return roughDielectricSample(m, wo, ul, u1, u2, mode, s);
    }
};
template <>
struct BsdfOf<MaterialKind::ThinDielectric> : DeltaBsdf {
    static constexpr uint8_t reads = kReadsLobe;
    static bool sample(const BsdfParams& m, Vec3 wo, float ul, float, float, TransportMode, BsdfSample& s) {
        return thinDielectricSample(m, wo, ul, s);
    }
};
template <>
struct BsdfOf<MaterialKind::Plastic> {
    static constexpr uint8_t reads = kReadsLobe | kReadsDirection;
    static constexpr bool delta = false;
    static Vec3 f(const BsdfParams& m, Vec3 wo, Vec3 wi) { return plasticF(m, wo, wi); }
    static float pdf(const BsdfParams& m, Vec3 wo, Vec3 wi) { return plasticPdf(m, wo, wi); }
    static bool sample(const BsdfParams& m, Vec3 wo, float ul, float u1, float u2, TransportMode, BsdfSample& s) {
        return plasticSample(m, wo, ul, u1, u2, s);
    }
};
template <>
struct BsdfOf<MaterialKind::RoughPlastic> {
    static constexpr uint8_t reads = kReadsLobe | kReadsDirection;
    static constexpr bool delta = false;
    static Vec3 f(const BsdfParams& m, Vec3 wo, Vec3 wi) { return roughPlasticF(m, wo, wi); }
    static float pdf(const BsdfParams& m, Vec3 wo, Vec3 wi) { return roughPlasticPdf(m, wo, wi); }
    static bool sample(const BsdfParams& m, Vec3 wo, float ul, float u1, float u2, TransportMode, BsdfSample& s) {
        return roughPlasticSample(m, wo, ul, u1, u2, s);
    }
};

template <>
struct BsdfOf<MaterialKind::Blend> {
    static constexpr uint8_t reads = kReadsLobe | kReadsDirection;
    static constexpr bool delta = false;
    static Vec3 f(const BsdfParams& m, Vec3 wo, Vec3 wi) { return blendF(m, wo, wi); }
    static float pdf(const BsdfParams& m, Vec3 wo, Vec3 wi) { return blendPdf(m, wo, wi); }
    static bool sample(const BsdfParams& m, Vec3 wo, float ul, float u1, float u2, TransportMode mode, BsdfSample& s) {
        return blendSample(m, wo, ul, u1, u2, mode, s);
    }
};

template <>
struct BsdfOf<MaterialKind::Principled> {
    static constexpr uint8_t reads = kReadsLobe | kReadsDirection;
    static constexpr bool delta = false;
    static Vec3 f(const BsdfParams& m, Vec3 wo, Vec3 wi) { return principledF(m, wo, wi); }
    static float pdf(const BsdfParams& m, Vec3 wo, Vec3 wi) { return principledPdf(m, wo, wi); }
    static bool sample(const BsdfParams& m, Vec3 wo, float ul, float u1, float u2, TransportMode mode, BsdfSample& s) {
        return principledSample(m, wo, ul, u1, u2, mode, s);
    }
};

template <>
struct BsdfOf<MaterialKind::Coated> {
    static constexpr uint8_t reads = kReadsLobe | kReadsDirection;
    static constexpr bool delta = false;
    static Vec3 f(const BsdfParams& m, Vec3 wo, Vec3 wi) { return coatedF(m, wo, wi); }
    static float pdf(const BsdfParams& m, Vec3 wo, Vec3 wi) { return coatedPdf(m, wo, wi); }
    static bool sample(const BsdfParams& m, Vec3 wo, float ul, float u1, float u2, TransportMode mode, BsdfSample& s) {
        return coatedSample(m, wo, ul, u1, u2, mode, s);
    }
};

template <>
struct BsdfOf<MaterialKind::DiffuseTransmission> {
    static constexpr uint8_t reads = kReadsLobe | kReadsDirection;
    static constexpr bool delta = false;
    static Vec3 f(const BsdfParams& m, Vec3 wo, Vec3 wi) { return diffuseTransmissionF(m, wo, wi); }
    static float pdf(const BsdfParams& m, Vec3 wo, Vec3 wi) { return diffuseTransmissionPdf(m, wo, wi); }
    static bool sample(const BsdfParams& m, Vec3 wo, float ul, float u1, float u2, TransportMode, BsdfSample& s) {
        return diffuseTransmissionSample(m, wo, ul, u1, u2, s);
    }
};

template <>
struct BsdfOf<MaterialKind::Phase> {
    static constexpr uint8_t reads = kReadsDirection;
    static constexpr bool delta = false;
    static Vec3 f(const BsdfParams& m, Vec3 wo, Vec3 wi) { return phaseF(m, wo, wi); }
    static float pdf(const BsdfParams& m, Vec3 wo, Vec3 wi) { return phasePdf(m, wo, wi); }
    static bool sample(const BsdfParams& m, Vec3, float, float u1, float u2, TransportMode, BsdfSample& s) { return phaseSample(m, u1, u2, s); }
};

}  // namespace wmlt
