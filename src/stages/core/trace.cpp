#include "stages/core/trace.h"

namespace wmlt {

// Camera rays: one COHERENT stream (Embree's frustum traversal pays for tile order).
// Incoherent rays: a loop of rtcIntersect1. bench/bench_pt.cpp measures it against
// rtcIntersect1M INCOHERENT on the same 2^20 bounce rays (which falls back to 8-wide
// packets that degenerate to single rays): on the dragon the two were within 5% of each
// other (7.8 vs 7.7 and 7.0 vs 6.8 Mrays/s on 1 thread, 14.0 vs 14.9 and 14.1 vs 13.8 on
// 2), the loop ahead on 1 thread, as in ../shared/spec/embree-streams.md.
void traceClosest(RTCScene scene, RTCRayHit* rays, size_t n, bool coherent) {
    if (n == 0) return;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    if (coherent) {
        ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        rtcIntersect1M(scene, &ctx, rays, unsigned(n), sizeof(RTCRayHit));
        return;
    }
    for (size_t i = 0; i < n; ++i) rtcIntersect1(scene, &ctx, &rays[i]);
}

void traceOccluded(RTCScene scene, RTCRay* rays, size_t n) {
    if (n == 0) return;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    rtcOccluded1M(scene, &ctx, rays, unsigned(n), sizeof(RTCRay));
}

}  // namespace wmlt
