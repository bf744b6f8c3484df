#include "stages/trace.h"

namespace wmlt {

void traceClosest(RTCScene scene, RTCRayHit* rays, size_t n, bool coherent) {
    if (n == 0) return;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags = coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    rtcIntersect1M(scene, &ctx, rays, unsigned(n), sizeof(RTCRayHit));
}

void traceOccluded(RTCScene scene, RTCRay* rays, size_t n) {
    if (n == 0) return;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    rtcOccluded1M(scene, &ctx, rays, unsigned(n), sizeof(RTCRay));
}

}  // namespace wmlt
