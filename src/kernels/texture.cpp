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
    const float t = 0.5f + 0.5f * std::sin(kMarbleStripes * p.x + kMarbleTurbulence * turbulence(kMarbleFrequency * p));
    return std::isfinite(t) ? std::min(1.0f, std::max(0.0f, t)) : 0.5f;
}

float fbm(Vec3 q, float omega, int octaves) {
    float sum = 0, lambda = 1, o = 1;
    for (int i = 0; i < octaves; ++i) {
        sum += o * perlinNoise(q * lambda);
        lambda *= 1.99f;
        o *= omega;
    }
    return sum;
}

float turbulencePbrt(Vec3 q, float omega, int octaves) {
    float sum = 0, lambda = 1, o = 1;
    for (int i = 0; i < octaves; ++i) {
        sum += o * std::fabs(perlinNoise(q * lambda));
        lambda *= 1.99f;
        o *= omega;
    }
    return sum + 0.2f * o;
}

bool insidePolkaDot(float s, float t) {
    if (!std::isfinite(s) || !std::isfinite(t)) return false;
    const float sCell = std::floor(s + 0.5f), tCell = std::floor(t + 0.5f);
    if (perlinNoise(Vec3(sCell + 0.5f, tCell + 0.5f, 0.5f)) <= 0) return false;
    constexpr float radius = 0.35f, maxShift = 0.5f - radius;
    const float sCentre = sCell + maxShift * perlinNoise(Vec3(sCell + 1.5f, tCell + 2.8f, 0.5f));
    const float tCentre = tCell + maxShift * perlinNoise(Vec3(sCell + 4.5f, tCell + 9.8f, 0.5f));
    const float ds = s - sCentre, dt = t - tCentre;
    return ds * ds + dt * dt < radius * radius;
}

Vec3 pbrtMarbleColour(const TextureDesc& tex, Vec3 q) {
    // pbrt's spline: nine control points, six cubic Bezier segments over t in [0, 1]
    static const Vec3 c[9] = {{0.58f, 0.58f, 0.6f}, {0.58f, 0.58f, 0.6f}, {0.58f, 0.58f, 0.6f}, {0.5f, 0.5f, 0.5f},  {0.6f, 0.59f, 0.58f},
                              {0.58f, 0.58f, 0.6f}, {0.58f, 0.58f, 0.6f}, {0.2f, 0.2f, 0.33f},  {0.58f, 0.58f, 0.6f}};
    const Vec3 p = q * tex.noiseScale;
    float t = 0.5f + 0.5f * std::sin(p.y + tex.variation * fbm(p, tex.roughness, tex.octaves));
    if (!std::isfinite(t)) t = 0.5f;
    constexpr int kSegments = 9 - 3;
    const int first = std::clamp(int(std::floor(t * kSegments)), 0, kSegments - 1);
    t = t * kSegments - float(first);
    auto lerp3 = [](float x, Vec3 a, Vec3 b) { return a * (1 - x) + b * x; };
    // de Casteljau
    const Vec3 s0 = lerp3(t, c[first], c[first + 1]), s1 = lerp3(t, c[first + 1], c[first + 2]), s2 = lerp3(t, c[first + 2], c[first + 3]);
    return lerp3(t, lerp3(t, s0, s1), lerp3(t, s1, s2)) * 1.5f;
}

namespace {
// A procedural texture's mean, estimated at 512 fixed points: (u, v) over [0, 1)^2 and p
// over [0, 4)^3 (the R3 sequence, Roberts 2018), for sampling weights only.
Vec3 estimatedMean(const TextureDesc& t) {
    constexpr double a1 = 0.8191725133961645, a2 = 0.6710436067037893, a3 = 0.5497004779019703;
    Vec3 sum(0.0f);
    constexpr int n = 512;
    for (int i = 1; i <= n; ++i) {
        const double x = std::fmod(0.5 + a1 * i, 1.0), y = std::fmod(0.5 + a2 * i, 1.0), z = std::fmod(0.5 + a3 * i, 1.0);
        sum = sum + evalTexture(t, float(x), float(y), Vec3(float(4 * x), float(4 * y), float(4 * z)));
    }
    return sum * (1.0f / n);
}
}  // namespace

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
        case TextureKind::Dots:
        case TextureKind::Bilerp:
        case TextureKind::Fbm:
        case TextureKind::Wrinkled:
        case TextureKind::Windy:
        case TextureKind::PbrtMarble: return estimatedMean(t);
        case TextureKind::Scale:
        case TextureKind::Mix:
        case TextureKind::DirectionMix: break;  // textureMeanOf
    }
    return Vec3(0.0f);
}

Vec3 textureMeanOf(const std::vector<TextureDesc>& all, size_t i) {
    const TextureDesc& t = all[i];
    if (!combinesTextures(t)) return textureMean(t);
    auto operand = [&](int k, Vec3 c) { return t.operand[k] < 0 ? c : textureMeanOf(all, size_t(t.operand[k])); };
    const Vec3 a = operand(0, t.colour1), b = operand(1, t.colour2);
    if (t.kind == TextureKind::Dots) {  // the share of (s, t) inside a dot, estimated
        TextureDesc share = t;
        share.colour1 = Vec3(1.0f);
        share.colour2 = Vec3(0.0f);
        const float w = textureMean(share).x;
        return a * w + b * (1.0f - w);
    }
    if (t.kind == TextureKind::Scale) return a * b;
    if (t.kind == TextureKind::DirectionMix) return (a + b) * 0.5f;  // |cos| uniform over directions
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
