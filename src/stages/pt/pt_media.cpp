// The path tracer's media stages (docs/media.md), run only for a scene with media or
// pass-through boundaries (SceneFeatures::media): traverseMedia after each intersect,
// traceShadowsThroughMedia instead of traceShadows (the shared parts: media.{h,cpp}).
#include "stages/core/media.h"
#include "stages/pt/pt_stages.h"

namespace wmlt {

void traverseMedia(const Scene& scene, PtBatch& b, int depth, int minLength, int maxLength, RayCounters& c) {
    if (!scene.features.emissiveMedia) {
        traverseMediaOf(scene, b, depth, c);
        return;
    }
    // Emitting media: what they send back along each ray is a contribution of length depth
    // (only the path's own walk can find it: no other strategy to weigh it against).
    const bool count = depth >= minLength && depth <= maxLength;
    SegmentDensities unused;
    for (size_t i = 0; i < b.numPaths; ++i) {
        int m = b.medium[i];
        const uint32_t slot = b.pathSlot[i];
        Vec3 emitted(0.0f);
        traverseMediumOf<false, true>(
            scene, pathMedia(scene, b, slot), b.ray[i], m,
            [&](uint32_t k, float& u, uint64_t& seed) { hashedFreePathNumber(b.key[slot], mediumDim(depth, k), u, seed); }, b.beta[i],
            b.mediumEvent[i], b.mediumT[i], false, unused, emitted, c);
        b.medium[i] = m;
        if (count && !isBlack(emitted)) addRadiance(b, slot, emitted, depth);
    }
}

void traceShadowsThroughMedia(const Scene& scene, PtBatch& b, int length, RayCounters& c) {
    const bool passThrough = scene.features.passThrough;
    SegmentDensities unused;
    for (size_t i = 0; i < b.numShadow; ++i) {
        // a grid's ratio tracking: a stream per shadow ray and segment, apart from the paths'
        const uint64_t seed = mix64(b.key[b.shadowSlot[i]] ^ 0x5348414430ull ^ (uint64_t(length) << 40));
        const PathMedia media = pathMedia(scene, b, b.shadowSlot[i]);
        if (!passThrough) {  // the transmittance here, visibility by the batched occlusion rays below
            const Vec3 T = transmittanceUnblocked<false>(media, b.shadow[i], b.shadowMedium[i], seed, false, false, unused);
            b.shadowL[i] = b.shadowL[i] * T;
            if (isBlack(T)) b.shadow[i].tfar = -1.0f;  // (a ray with tfar < tnear is not traced)
            continue;
        }
        const Vec3 T = transmittanceAlong(scene, media, b.shadow[i], b.shadowMedium[i], seed, c);
        if (!isBlack(T)) addRadiance(b, b.shadowSlot[i], b.shadowL[i] * T, length);
    }
    if (!passThrough) traceShadows(scene, b, length, c);
}

}  // namespace wmlt
