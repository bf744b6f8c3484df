// The path tracer's media stages (docs/media.md), run only for a scene with media or
// pass-through boundaries (SceneFeatures::media): traverseMedia after each intersect,
// traceShadowsThroughMedia instead of traceShadows (the shared parts: media.{h,cpp}).
#include "stages/core/media.h"
#include "stages/pt/pt_stages.h"

namespace wmlt {

void traverseMedia(const Scene& scene, PtBatch& b, int depth, RayCounters& c) { traverseMediaOf(scene, b, depth, c); }

void traceShadowsThroughMedia(const Scene& scene, PtBatch& b, int length, RayCounters& c) {
    const bool passThrough = scene.features.passThrough;
    SegmentDensities unused;
    for (size_t i = 0; i < b.numShadow; ++i) {
        // a grid's ratio tracking: a stream per shadow ray and segment, apart from the paths'
        const uint64_t seed = mix64(b.key[b.shadowSlot[i]] ^ 0x5348414430ull ^ (uint64_t(length) << 40));
        if (!passThrough) {  // the transmittance here, visibility by the batched occlusion rays below
            const Vec3 T = transmittanceUnblocked<false>(scene, b.shadow[i], b.shadowMedium[i], seed, false, false, unused);
            b.shadowL[i] = b.shadowL[i] * T;
            if (isBlack(T)) b.shadow[i].tfar = -1.0f;  // (a ray with tfar < tnear is not traced)
            continue;
        }
        const Vec3 T = transmittanceAlong(scene, b.shadow[i], b.shadowMedium[i], seed, c);
        if (!isBlack(T)) addRadiance(b, b.shadowSlot[i], b.shadowL[i] * T, length);
    }
    if (!passThrough) traceShadows(scene, b, length, c);
}

}  // namespace wmlt
