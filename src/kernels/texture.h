// Textures (scene-format.md, "Textures"): pure, deterministic functions of (u, v) and the
// world position p. Checker and image lookups are inline; the marble is in texture.cpp.
//  - Checker: colour1 where floor(2 u') + floor(2 v') is even, colour2 elsewhere, with
//    (u', v') = (u * repeatU, v * repeatV): a 2 x 2 grid per unit of scaled (u, v).
//  - ImageFile: bilinear lookup, wrapping (repeat) in both directions; (u', v') mod 1,
//    v = 0 is the image's BOTTOM row (pbrt's convention), pixel centres at half-integers.
//  - Bitmap (Mitsuba's): (u, v) through to_uv, then nearest or bilinear lookup with
//    Mitsuba's conventions: v = 0 is the image's TOP row, pixel centres at half-integers,
//    the wrap mode (repeat, mirror, clamp) applied to the pixel indices.
//  - Checkerboard (Mitsuba's): (u, v) through to_uv; colour1 (color0) where the
//    fractional parts of u and v are both above 0.5 or both not, colour2 (color1) elsewhere.
//  - Marble: a solid texture of p (Repeat is not used): Perlin's improved gradient noise
//    (Perlin 2002) with a permutation table made here by a seeded Fisher-Yates shuffle,
//    turbulence(q) = sum_{i<6} |noise(2^i q)| / 2^i, and
//    t = 0.5 + 0.5 sin(kMarbleStripes * p.x + kMarbleTurbulence * turbulence(kMarbleFrequency * p)),
//    colour1 -> colour2 over t in [0, 0.5], colour2 -> colour3 over [0.5, 1]
//    (Shirley and Morley 2000, "Realistic Ray Tracing", 2nd ed.).
//  - pbrt-v4's (texture.cpp; docs/pbrt.md): a mapping first turns the hit into (s, t)
//    (TextureMapping: uv, or spherical, cylindrical, planar of the point in the texture's
//    space), then Dots (a dot of radius 0.35 in the cells of (s, t) where noise says so),
//    Bilerp, and the solid Fbm, Wrinkled (turbulence), Windy and PbrtMarble of
//    q = textureFromWorld p, with pbrt's sums of octaves (frequency x 1.99 per octave). There
//    are no ray differentials here: every octave is summed (pbrt's limit of a zero footprint),
//    and the noise is the marble's (its own permutation: pbrt's patterns, not its exact dots
//    and veins).
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "wavemmlt/math.h"
#include "wavemmlt/scene_desc.h"

namespace wmlt {

// Marble: bands across x with a period of 2 pi / 8 = 0.79 units, bent by turbulence
// whose coarsest octave has features ~0.7 units across: visible, wavy veins on objects
// about 1 unit wide.
constexpr float kMarbleStripes = 8.0f;
constexpr float kMarbleFrequency = 1.5f;
constexpr float kMarbleTurbulence = 3.0f;
constexpr int kMarbleOctaves = 6;

namespace texture_detail {

// A permutation of 0..255 (repeated twice), from a Fisher-Yates shuffle driven by
// SplitMix64 (Steele et al. 2014) at a fixed seed: deterministic on every platform.
constexpr std::array<uint8_t, 512> makePermutation() {
    std::array<uint8_t, 512> p{};
    for (int i = 0; i < 256; ++i) p[i] = uint8_t(i);
    uint64_t s = 0x9e3779b97f4a7c15ULL * 2024u;
    for (int i = 255; i > 0; --i) {
        s += 0x9e3779b97f4a7c15ULL;
        uint64_t z = s;
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
        z ^= z >> 31;
        int j = int(z % uint64_t(i + 1));
        uint8_t t = p[i];
        p[i] = p[j];
        p[j] = t;
    }
    for (int i = 0; i < 256; ++i) p[256 + i] = p[i];
    return p;
}
inline constexpr std::array<uint8_t, 512> kPerm = makePermutation();

}  // namespace texture_detail

// Perlin's improved noise, in about [-1, 1]; 0 on integer lattice points and for
// non-finite input. (Out of line, in texture.cpp, like the rest of the marble: one
// compiled copy, so every call site gets bit-identical results.)
float perlinNoise(Vec3 p);
// sum_{i < octaves} |noise(2^i p)| / 2^i.
float turbulence(Vec3 p, int octaves = kMarbleOctaves);
// The marble's blend parameter t in [0, 1] at world position p.
float marbleParameter(Vec3 p);
// colour1 -> colour2 -> colour3, piecewise linearly in marbleParameter(p).
Vec3 marbleColour(const TextureDesc& t, Vec3 p);

// pbrt-v4's fractional Brownian motion and turbulence at a zero footprint:
// FBm = sum_{i < octaves} omega^i noise(1.99^i q); Turbulence = sum omega^i |noise(1.99^i q)|
// + 0.2 omega^octaves (pbrt's allowance for the octaves beyond the footprint, all of it here).
float fbm(Vec3 q, float omega, int octaves);
float turbulencePbrt(Vec3 q, float omega, int octaves);
// pbrt's polka dots: in the cell round(s), round(t), a dot of radius 0.35 when the noise at
// the cell's centre is positive, its centre shifted by up to 0.15 by two more noises.
bool insidePolkaDot(float s, float t);
// pbrt's marble: t = 0.5 + 0.5 sin(q'.y + variation FBm(q')), q' = scale q, through its
// cubic Bezier spline of nine greys and blues, times 1.5.
Vec3 pbrtMarbleColour(const TextureDesc& t, Vec3 q);

// The point p in the texture's space (TextureDesc::textureFromWorld).
inline Vec3 textureSpacePoint(const TextureDesc& t, Vec3 p) {
    const float* m = t.textureFromWorld;
    return Vec3(m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3], m[4] * p.x + m[5] * p.y + m[6] * p.z + m[7],
                m[8] * p.x + m[9] * p.y + m[10] * p.z + m[11]);
}

// The texture's (s, t) at a hit where its mapping is not UV (TextureMapping), into u, v.
inline void mapTexturePoint(const TextureDesc& t, Vec3 p, float& u, float& v) {
    const Vec3 q = textureSpacePoint(t, p);
    switch (t.mapping) {
        case TextureMapping::UV: return;
        case TextureMapping::Spherical: {
            const float r = length(q);
            const float z = r > 0 ? std::clamp(q.z / r, -1.0f, 1.0f) : 1.0f;
            float phi = std::atan2(q.y, q.x);
            if (phi < 0) phi += 2.0f * kPi;
            u = std::acos(z) * kInvPi;
            v = phi * kInv2Pi;
            break;
        }
        case TextureMapping::Cylindrical:
            u = (kPi + std::atan2(q.y, q.x)) * kInv2Pi;
            v = q.z;
            break;
        case TextureMapping::Planar:
            u = dot(q, t.planarS);
            v = dot(q, t.planarT);
            break;
    }
    if (!std::isfinite(u)) u = 0;
    if (!std::isfinite(v)) v = 0;
}

// Bilinear lookup with wrapping in both directions; v = 0 is the bottom row.
inline Vec3 lookupBilinearWrap(const Image& img, float u, float v) {
    if (img.width <= 0 || img.height <= 0) return Vec3(0.0f);
    if (!std::isfinite(u)) u = 0;
    if (!std::isfinite(v)) v = 0;
    u -= std::floor(u);
    v -= std::floor(v);
    const float fx = u * float(img.width) - 0.5f;
    const float fy = (1.0f - v) * float(img.height) - 0.5f;
    const float x0f = std::floor(fx), y0f = std::floor(fy);
    const float tx = fx - x0f, ty = fy - y0f;
    auto wrap = [](int i, int n) {
        i %= n;
        return i < 0 ? i + n : i;
    };
    const int x0 = wrap(int(x0f), img.width), x1 = wrap(int(x0f) + 1, img.width);
    const int y0 = wrap(int(y0f), img.height), y1 = wrap(int(y0f) + 1, img.height);
    return img.at(x0, y0) * ((1 - tx) * (1 - ty)) + img.at(x1, y0) * (tx * (1 - ty)) + img.at(x0, y1) * ((1 - tx) * ty) + img.at(x1, y1) * (tx * ty);
}

inline int wrapTexel(int i, int n, TextureWrap w) {
    switch (w) {
        case TextureWrap::Repeat: i %= n; return i < 0 ? i + n : i;
        case TextureWrap::Clamp: return i < 0 ? 0 : i >= n ? n - 1 : i;
        case TextureWrap::Mirror: {
            const int p = 2 * n;
            i %= p;
            if (i < 0) i += p;
            return i < n ? i : p - 1 - i;
        }
    }
    return 0;
}

// Mitsuba's to_uv.
inline void mitsubaUv(const TextureDesc& t, float& u, float& v) {
    const float* a = t.uvTransform;
    const float x = a[0] * u + a[1] * v + a[2], y = a[3] * u + a[4] * v + a[5];
    u = std::isfinite(x) ? x : 0.0f;
    v = std::isfinite(y) ? y : 0.0f;
}

// The bitmap's bilinear cell at (u, v) (after to_uv): texel indices and weights; fx, fy
// in texels, so d(value)/du = width * d(value)/dfx.
struct BitmapCell {
    int x0, x1, y0, y1;
    float tx, ty;
};
inline BitmapCell bitmapCell(const TextureDesc& t, float u, float v) {
    const Image& img = t.image;
    // Far outside [0, 1] the float position loses its fraction; wrap it first (exact for
    // repeat and mirror with an even period; clamp needs no more than [-1, 2]).
    if (t.wrap == TextureWrap::Clamp) {
        u = std::clamp(u, -1.0f, 2.0f);
        v = std::clamp(v, -1.0f, 2.0f);
    } else {
        u -= 2.0f * std::floor(0.5f * u);
        v -= 2.0f * std::floor(0.5f * v);
    }
    const float fx = u * float(img.width) - 0.5f, fy = v * float(img.height) - 0.5f;
    const float x0f = std::floor(fx), y0f = std::floor(fy);
    BitmapCell c;
    c.tx = fx - x0f;
    c.ty = fy - y0f;
    c.x0 = wrapTexel(int(x0f), img.width, t.wrap);
    c.x1 = wrapTexel(int(x0f) + 1, img.width, t.wrap);
    c.y0 = wrapTexel(int(y0f), img.height, t.wrap);
    c.y1 = wrapTexel(int(y0f) + 1, img.height, t.wrap);
    return c;
}

inline Vec3 lookupBitmap(const TextureDesc& t, float u, float v) {
    const Image& img = t.image;
    if (img.width <= 0 || img.height <= 0) return Vec3(0.0f);
    mitsubaUv(t, u, v);
    if (t.nearest) {
        if (t.wrap != TextureWrap::Clamp) {
            u -= 2.0f * std::floor(0.5f * u);
            v -= 2.0f * std::floor(0.5f * v);
        } else {
            u = std::clamp(u, -1.0f, 2.0f);
            v = std::clamp(v, -1.0f, 2.0f);
        }
        return img.at(wrapTexel(int(std::floor(u * float(img.width))), img.width, t.wrap),
                      wrapTexel(int(std::floor(v * float(img.height))), img.height, t.wrap));
    }
    const BitmapCell c = bitmapCell(t, u, v);
    return img.at(c.x0, c.y0) * ((1 - c.tx) * (1 - c.ty)) + img.at(c.x1, c.y0) * (c.tx * (1 - c.ty)) + img.at(c.x0, c.y1) * ((1 - c.tx) * c.ty) +
           img.at(c.x1, c.y1) * (c.tx * c.ty);
}

// The gradient (d/du, d/dv, in the shape's (u, v)) of the bilinear bitmap's luminance,
// as Mitsuba's bumpmap reads it (eval_1_grad): exact inside a texel cell.
inline void bitmapLuminanceGradient(const TextureDesc& t, float u, float v, float& du, float& dv) {
    const Image& img = t.image;
    du = dv = 0;
    if (img.width <= 0 || img.height <= 0) return;
    mitsubaUv(t, u, v);
    const BitmapCell c = bitmapCell(t, u, v);
    const float h00 = luminance(img.at(c.x0, c.y0)), h10 = luminance(img.at(c.x1, c.y0));
    const float h01 = luminance(img.at(c.x0, c.y1)), h11 = luminance(img.at(c.x1, c.y1));
    const float dfx = ((1 - c.ty) * (h10 - h00) + c.ty * (h11 - h01)) * float(img.width);   // per unit of u'
    const float dfy = ((1 - c.tx) * (h01 - h00) + c.tx * (h11 - h10)) * float(img.height);  // per unit of v'
    // Chain rule through to_uv: u' = a u + b v + c, v' = d u + e v + f.
    const float* a = t.uvTransform;
    du = dfx * a[0] + dfy * a[3];
    dv = dfx * a[1] + dfy * a[4];
}

inline Vec3 evalTexture(const TextureDesc& t, float u, float v, Vec3 p) {
    if (t.mapping != TextureMapping::UV) mapTexturePoint(t, p, u, v);
    switch (t.kind) {
        case TextureKind::Checker: {
            const float cu = std::floor(2.0f * u * t.repeatU), cv = std::floor(2.0f * v * t.repeatV);
            const bool oddU = std::fmod(cu, 2.0f) != 0, oddV = std::fmod(cv, 2.0f) != 0;
            return oddU == oddV ? t.colour1 : t.colour2;
        }
        case TextureKind::ImageFile: return lookupBilinearWrap(t.image, u * t.repeatU, v * t.repeatV);
        case TextureKind::Marble: return marbleColour(t, p);
        case TextureKind::Bitmap: return lookupBitmap(t, u, v);
        case TextureKind::Checkerboard: {
            mitsubaUv(t, u, v);
            const bool hu = u - std::floor(u) > 0.5f, hv = v - std::floor(v) > 0.5f;
            return hu == hv ? t.colour1 : t.colour2;
        }
        case TextureKind::Dots:  // colour1 inside, colour2 outside (operands: evalTextureOf)
            mitsubaUv(t, u, v);
            return insidePolkaDot(u, v) ? t.colour1 : t.colour2;
        case TextureKind::Bilerp:
            mitsubaUv(t, u, v);
            return t.colour1 * ((1 - u) * (1 - v)) + t.colour3 * (u * (1 - v)) + t.colour2 * ((1 - u) * v) + t.colour4 * (u * v);
        case TextureKind::Fbm: return Vec3(fbm(textureSpacePoint(t, p), t.roughness, t.octaves));
        case TextureKind::Wrinkled: return Vec3(turbulencePbrt(textureSpacePoint(t, p), t.roughness, t.octaves));
        case TextureKind::Windy: {  // pbrt: |FBm(0.1 q, 0.5, 3)| FBm(q, 0.5, 6)
            const Vec3 q = textureSpacePoint(t, p);
            return Vec3(std::fabs(fbm(q * 0.1f, 0.5f, 3)) * fbm(q, 0.5f, 6));
        }
        case TextureKind::PbrtMarble: return pbrtMarbleColour(t, textureSpacePoint(t, p));
        case TextureKind::Scale:
        case TextureKind::Mix:
        case TextureKind::DirectionMix: break;  // they need their operands: evalTextureOf
    }
    return Vec3(0.0f);
}

// Whether texture t combines others (operands): Scale, Mix, DirectionMix, and Dots with a
// textured side.
inline bool combinesTextures(const TextureDesc& t) {
    return t.kind == TextureKind::Scale || t.kind == TextureKind::Mix || t.kind == TextureKind::DirectionMix ||
           (t.kind == TextureKind::Dots && (t.operand[0] >= 0 || t.operand[1] >= 0));
}

// Texture i of all at (u, v, p) with geometric normal n, combining the operands of Scale,
// Mix, DirectionMix and Dots (their indices are below i, so the recursion ends).
inline Vec3 evalTextureOf(const std::vector<TextureDesc>& all, size_t i, float u, float v, Vec3 p, Vec3 n) {
    const TextureDesc& t = all[i];
    if (!combinesTextures(t)) return evalTexture(t, u, v, p);
    auto operand = [&](int k, Vec3 c) { return t.operand[k] < 0 ? c : evalTextureOf(all, size_t(t.operand[k]), u, v, p, n); };
    if (t.kind == TextureKind::DirectionMix) {  // pbrt: |n . dir| tex1 + (1 - |n . dir|) tex2
        const float l = length(n);
        const float a = l > 0 ? std::min(1.0f, std::fabs(dot(n, t.direction)) / l) : 0.0f;
        return operand(0, t.colour1) * a + operand(1, t.colour2) * (1.0f - a);
    }
    if (t.kind == TextureKind::Dots) {  // the operands see the hit, not the dots' (s, t)
        float s = u, tt = v;
        if (t.mapping != TextureMapping::UV) mapTexturePoint(t, p, s, tt);
        mitsubaUv(t, s, tt);
        return insidePolkaDot(s, tt) ? operand(0, t.colour1) : operand(1, t.colour2);
    }
    const Vec3 a = operand(0, t.colour1), b = operand(1, t.colour2);
    if (t.kind == TextureKind::Scale) return a * b;
    const float w = t.operand[2] < 0 ? t.amount : luminance(operand(2, Vec3(0.0f)));
    return a * (1.0f - w) + b * w;
}

// The texture's mean over its domain: the checkers' two colours alike, an image's texels;
// the marble's is approximate ((colour1 + 2 colour2 + colour3) / 4, its parameter taken as
// uniform). For sampling weights (texture.cpp).
Vec3 textureMean(const TextureDesc& t);
// The same for texture i of all: a Scale's the product of its operands' means, a Mix's
// their blend by the mean amount (approximations: for sampling weights).
Vec3 textureMeanOf(const std::vector<TextureDesc>& all, size_t i);

// Height for bump mapping: the Rec. 709 luminance of the texture.
inline float textureHeight(const TextureDesc& t, float u, float v, Vec3 p) { return luminance(evalTexture(t, u, v, p)); }

}  // namespace wmlt
