// The marble texture's noise (texture.h): Perlin's improved noise (Perlin 2002, "Improving
// Noise"), turbulence, and the colour blend.
#include "kernels/texture.h"

namespace wmlt {

namespace {

using texture_detail::kPerm;

inline float fade(float t) { return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f); }
inline float lerp(float t, float a, float b) { return a + t * (b - a); }
// One of the 12 cube-edge gradients (4 of them twice), dotted with (x, y, z).
inline float grad(int hash, float x, float y, float z) {
    const int h = hash & 15;
    const float u = h < 8 ? x : y;
    const float v = h < 4 ? y : (h == 12 || h == 14 ? x : z);
    return ((h & 1) ? -u : u) + ((h & 2) ? -v : v);
}
// The integer lattice cell of f (already floored), modulo 256; safe for any finite f.
inline int cell(float f) {
    float m = std::fmod(f, 256.0f);
    if (m < 0) m += 256.0f;
    return int(m) & 255;
}

}  // namespace

float perlinNoise(Vec3 p) {
    if (!isFinite(p)) return 0.0f;
    const float fx = std::floor(p.x), fy = std::floor(p.y), fz = std::floor(p.z);
    const int X = cell(fx), Y = cell(fy), Z = cell(fz);
    const float x = p.x - fx, y = p.y - fy, z = p.z - fz;
    const float u = fade(x), v = fade(y), w = fade(z);
    const int A = kPerm[X] + Y, AA = kPerm[A] + Z, AB = kPerm[A + 1] + Z;
    const int B = kPerm[X + 1] + Y, BA = kPerm[B] + Z, BB = kPerm[B + 1] + Z;
    return lerp(w,
                lerp(v, lerp(u, grad(kPerm[AA], x, y, z), grad(kPerm[BA], x - 1, y, z)),
                     lerp(u, grad(kPerm[AB], x, y - 1, z), grad(kPerm[BB], x - 1, y - 1, z))),
                lerp(v, lerp(u, grad(kPerm[AA + 1], x, y, z - 1), grad(kPerm[BA + 1], x - 1, y, z - 1)),
                     lerp(u, grad(kPerm[AB + 1], x, y - 1, z - 1), grad(kPerm[BB + 1], x - 1, y - 1, z - 1))));
}

float turbulence(Vec3 p, int octaves) {
    float sum = 0, scale = 1;
    for (int i = 0; i < octaves; ++i) {
        sum += std::fabs(perlinNoise(p * scale)) / scale;
        scale *= 2.0f;
    }
    return sum;
}

float marbleParameter(Vec3 p) {
    const float t =
        0.5f + 0.5f * std::sin(kMarbleStripes * p.x + kMarbleTurbulence * turbulence(kMarbleFrequency * p));
    return std::isfinite(t) ? std::min(1.0f, std::max(0.0f, t)) : 0.5f;
}

Vec3 textureMean(const TextureDesc& t) {
    switch (t.kind) {
        case TextureKind::Checker:
        case TextureKind::Checkerboard: return (t.colour1 + t.colour2) * 0.5f;
        case TextureKind::Marble: return (t.colour1 + t.colour2 * 2.0f + t.colour3) * 0.25f;
        case TextureKind::ImageFile:
        case TextureKind::Bitmap: {
            double sum[3] = {0, 0, 0};
            for (size_t i = 0; i < t.image.rgb.size(); ++i) sum[i % 3] += t.image.rgb[i];
            const double n = std::max<double>(1, double(t.image.rgb.size() / 3));
            return Vec3(float(sum[0] / n), float(sum[1] / n), float(sum[2] / n));
        }
        case TextureKind::Scale:
        case TextureKind::Mix: break;  // textureMeanOf
    }
    return Vec3(0.0f);
}

Vec3 textureMeanOf(const std::vector<TextureDesc>& all, size_t i) {
    const TextureDesc& t = all[i];
    if (t.kind != TextureKind::Scale && t.kind != TextureKind::Mix) return textureMean(t);
    auto operand = [&](int k, Vec3 c) { return t.operand[k] < 0 ? c : textureMeanOf(all, size_t(t.operand[k])); };
    const Vec3 a = operand(0, t.colour1), b = operand(1, t.colour2);
    if (t.kind == TextureKind::Scale) return a * b;
    const float w = t.operand[2] < 0 ? t.amount : luminance(operand(2, Vec3(0.0f)));
    return a * (1.0f - w) + b * w;
}

Vec3 marbleColour(const TextureDesc& t, Vec3 p) {
    const float m = marbleParameter(p);
    if (m < 0.5f) {
        const float s = 2.0f * m;
        return t.colour1 * (1 - s) + t.colour2 * s;
    }
    const float s = 2.0f * m - 1.0f;
    return t.colour2 * (1 - s) + t.colour3 * s;
}

}  // namespace wmlt
