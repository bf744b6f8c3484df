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

// (height(u, v, p): the texture's luminance there; a texture of the scene's table, combined
// ones too, by heightOf)
template <class Height>
inline Vec3 bumpedNormalBy(Height&& height, Vec3 p, float u, float v, Vec3 ns, Vec3 dpdu, Vec3 dpdv) {
    float patch = std::sqrt(length(cross(dpdu, dpdv)));
    if (!(patch > 0)) return ns;
    float scale = kBumpScale * patch;
    float h0 = height(u, v, p);
    float hu = height(u + kBumpDelta, v, p + dpdu * kBumpDelta);
    float hv = height(u, v + kBumpDelta, p + dpdv * kBumpDelta);
    Vec3 dpu = dpdu + ns * ((hu - h0) / kBumpDelta * scale);
    Vec3 dpv = dpdv + ns * ((hv - h0) / kBumpDelta * scale);
    Vec3 n = cross(dpu, dpv);
    float len = length(n);
    if (!(len > 0) || !std::isfinite(len)) return ns;
    n = n / len;
    return dot(n, ns) < 0 ? -n : n;
}

inline Vec3 bumpedNormal(const TextureDesc& tex, Vec3 p, float u, float v, Vec3 ns, Vec3 dpdu, Vec3 dpdv) {
    return bumpedNormalBy([&](float su, float sv, Vec3 sp) { return textureHeight(tex, su, sv, sp); }, p, u, v, ns, dpdu, dpdv);
}
// The height field of texture i of the scene's table (a scale, mix or directionmix of
// others too: evalTextureOf, with the hit's geometric normal n).
inline auto heightOf(const std::vector<TextureDesc>& all, size_t i, Vec3 n) {
    return [&all, i, n](float u, float v, Vec3 p) { return luminance(evalTextureOf(all, i, u, v, p, n)); };
}

// Mitsuba's bumpmap: height h = scale * the bitmap's luminance, its exact gradient in
// (u, v); the tangents lose their normal component and gain the height's slope,
// dp/du' = dp/du + n (scale dh/du - n.dp/du), and the normal is theirs, on ng's side.
inline Vec3 bumpedNormalMitsuba(const TextureDesc& tex, float scale, float u, float v, Vec3 ns, Vec3 ng, Vec3 dpdu, Vec3 dpdv) {
    float gu, gv;
    bitmapLuminanceGradient(tex, u, v, gu, gv);
    const Vec3 dpu = dpdu + ns * (scale * gu - dot(ns, dpdu));
    const Vec3 dpv = dpdv + ns * (scale * gv - dot(ns, dpdv));
    Vec3 n = cross(dpu, dpv);
    const float len = length(n);
    if (!(len > 0) || !std::isfinite(len)) return ns;
    n = n / len;
    return dot(n, ng) < 0 ? -n : n;
}

// pbrt-v4's displacement (BumpMap): the height d = the texture's luminance in world units
// along ns, by forward differences of step 0.0005 in u and v (pbrt's without ray
// differentials), dp/du' = dp/du + ns (d(u + du) - d) / du (pbrt adds d dn/du: left out,
// second order for small displacements), the normal theirs, on ng's side.
constexpr float kPbrtBumpDelta = 0.0005f;
template <class Height>
inline Vec3 bumpedNormalPbrt(Height&& height, Vec3 p, float u, float v, Vec3 ns, Vec3 ng, Vec3 dpdu, Vec3 dpdv) {
    const float d = kPbrtBumpDelta;
    const float h0 = height(u, v, p);
    const float hu = height(u + d, v, p + dpdu * d);
    const float hv = height(u, v + d, p + dpdv * d);
    Vec3 n = cross(dpdu + ns * ((hu - h0) / d), dpdv + ns * ((hv - h0) / d));
    const float len = length(n);
    if (!(len > 0) || !std::isfinite(len)) return ns;
    n = n / len;
    return dot(n, ng) < 0 ? -n : n;
}

// Mitsuba's normalmap: n = 2 rgb - 1 in the frame (s, t, ns), s = dp/du made orthogonal to
// ns and t = ns x s (Mitsuba 3's shading frame); the normal is n normalised, on ng's side.
// Without a usable dp/du (degenerate uv), ns is kept.
// (texture i of the scene's table, combined ones too: evalTextureOf with ng)
inline Vec3 normalMapped(const std::vector<TextureDesc>& all, size_t i, float u, float v, Vec3 p, Vec3 ns, Vec3 ng, Vec3 dpdu) {
    Vec3 s = dpdu - ns * dot(ns, dpdu);
    const float ls = length(s);
    if (!(ls > 0) || !std::isfinite(ls)) return ns;
    s = s / ls;
    const Vec3 t = cross(ns, s);
    const Vec3 c = evalTextureOf(all, i, u, v, p, ng) * 2.0f - Vec3(1.0f);
    Vec3 n = s * c.x + t * c.y + ns * c.z;
    const float len = length(n);
    if (!(len > 0) || !std::isfinite(len)) return ns;
    n = n / len;
    return dot(n, ng) < 0 ? -n : n;
}

}  // namespace wmlt
