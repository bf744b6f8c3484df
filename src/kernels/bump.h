// Bump mapping (Blinn 1978, as in pbrt-v4 10.5.2): a texture's luminance is a height
// field along the shading normal; the perturbed normal is the normal of the displaced
// surface, from finite differences of the height in u and v.
// The format gives no bump scale: wavemmlt displaces by kBumpScale * luminance in units
// of the surface's own (u, v) patch size, sqrt(|dp/du x dp/dv|), so the look does not
// change when a scene is scaled (docs/scene-format-choices.md).
#pragma once
#include "kernels/texture.h"

namespace wmlt {

constexpr float kBumpScale = 0.01f;
constexpr float kBumpDelta = 1.0f / 1024.0f;  // finite-difference step in (u, v)

inline Vec3 bumpedNormal(const TextureDesc& tex, Vec3 p, float u, float v, Vec3 ns, Vec3 dpdu, Vec3 dpdv) {
    float patch = std::sqrt(length(cross(dpdu, dpdv)));
    if (!(patch > 0)) return ns;
    float scale = kBumpScale * patch;
    float h0 = textureHeight(tex, u, v, p);
    float hu = textureHeight(tex, u + kBumpDelta, v, p + dpdu * kBumpDelta);
    float hv = textureHeight(tex, u, v + kBumpDelta, p + dpdv * kBumpDelta);
    Vec3 dpu = dpdu + ns * ((hu - h0) / kBumpDelta * scale);
    Vec3 dpv = dpdv + ns * ((hv - h0) / kBumpDelta * scale);
    Vec3 n = cross(dpu, dpv);
    float len = length(n);
    if (!(len > 0) || !std::isfinite(len)) return ns;
    n = n / len;
    return dot(n, ns) < 0 ? -n : n;
}

}  // namespace wmlt
