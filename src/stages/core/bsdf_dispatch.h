// Per-kind BSDF calls chosen at compile time: a stage loops over the hits of one
// material kind and calls that kind's kernel (BsdfOf<Kind>, kernels/bsdf_kinds.h), with no
// per-hit switch.
#pragma once
#include "kernels/bsdf.h"

namespace wmlt {

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
template <class Fn>
void forEachMaterialKind(Fn&& fn) {
#define WMLT_KIND_CALL(K, name) fn(std::integral_constant<MaterialKind, MaterialKind::K>{});
    WMLT_MATERIAL_KINDS(WMLT_KIND_CALL)
#undef WMLT_KIND_CALL
}

}  // namespace wmlt
