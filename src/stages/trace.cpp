#include "stages/trace.h"

namespace wmlt {

// Camera rays: one COHERENT stream (Embree's frustum traversal pays for tile order).
// Incoherent rays: a loop of rtcIntersect1; bench/bench_pt.cpp measures it against
// rtcIntersect1M INCOHERENT on the same rays (which falls back to 8-wide packets that
// degenerate to single rays; the loop measured 5-10% faster here).
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
