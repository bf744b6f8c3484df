// Per-kind BSDF calls chosen at compile time: a stage loops over the hits of one
// material kind and calls that kind's kernel, with no per-hit switch.
#pragma once
#include "kernels/bsdf.h"

namespace wmlt {

template <MaterialKind K> struct BsdfOf;

template <> struct BsdfOf<MaterialKind::Matte> {
    static constexpr bool delta = false;
    static Vec3 f(const BsdfParams& m, Vec3 wo, Vec3 wi) { return matteF(m, wo, wi); }
    static float pdf(const BsdfParams& m, Vec3 wo, Vec3 wi) { return mattePdf(m, wo, wi); }
    static bool sample(const BsdfParams& m, Vec3 wo, float ul, float u1, float u2, TransportMode, BsdfSample& s) {
        return matteSample(m, wo, ul, u1, u2, s);
    }
};
template <> struct BsdfOf<MaterialKind::Glossy> {
    static constexpr bool delta = false;
    static Vec3 f(const BsdfParams& m, Vec3 wo, Vec3 wi) { return glossyF(m, wo, wi); }
    static float pdf(const BsdfParams& m, Vec3 wo, Vec3 wi) { return glossyPdf(m, wo, wi); }
    static bool sample(const BsdfParams& m, Vec3 wo, float ul, float u1, float u2, TransportMode, BsdfSample& s) {
        return glossySample(m, wo, ul, u1, u2, s);
    }
};
template <> struct BsdfOf<MaterialKind::Reflective> {
    static constexpr bool delta = true;
    static Vec3 f(const BsdfParams&, Vec3, Vec3) { return Vec3(0.0f); }
    static float pdf(const BsdfParams&, Vec3, Vec3) { return 0.0f; }
    static bool sample(const BsdfParams& m, Vec3 wo, float, float, float, TransportMode, BsdfSample& s) {
        return mirrorSample(m, wo, s);
    }
};
template <> struct BsdfOf<MaterialKind::Dielectric> {
    static constexpr bool delta = true;
    static Vec3 f(const BsdfParams&, Vec3, Vec3) { return Vec3(0.0f); }
    static float pdf(const BsdfParams&, Vec3, Vec3) { return 0.0f; }
    static bool sample(const BsdfParams& m, Vec3 wo, float ul, float, float, TransportMode mode, BsdfSample& s) {
        return dielectricSample(m, wo, ul, mode, s);
    }
};

// A stable counting sort of n hits by material kind: kind k's hits are
// order[kindStart[k] .. kindStart[k + 1]), in their original order.
inline void groupByMaterialKind(const BsdfParams* bsdf, size_t n, uint32_t* order, uint32_t kindStart[5]) {
    uint32_t count[4] = {0, 0, 0, 0};
    for (size_t h = 0; h < n; ++h) ++count[int(bsdf[h].kind)];
    kindStart[0] = 0;
    for (int k = 0; k < 4; ++k) kindStart[k + 1] = kindStart[k] + count[k];
    uint32_t next[4] = {kindStart[0], kindStart[1], kindStart[2], kindStart[3]};
    for (size_t h = 0; h < n; ++h) order[next[int(bsdf[h].kind)]++] = uint32_t(h);
}

// Calls fn(std::integral_constant<MaterialKind, K>{}) for each of the four kinds.
template <class Fn> void forEachMaterialKind(Fn&& fn) {
    fn(std::integral_constant<MaterialKind, MaterialKind::Matte>{});
    fn(std::integral_constant<MaterialKind, MaterialKind::Glossy>{});
    fn(std::integral_constant<MaterialKind, MaterialKind::Reflective>{});
    fn(std::integral_constant<MaterialKind, MaterialKind::Dielectric>{});
}

}  // namespace wmlt
