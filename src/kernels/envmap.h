// The environment map: an equirectangular (latitude-longitude) radiance map lighting every
// ray that leaves the scene (scene-format.md, "EnvMap").
// Orientation: +y up; the map's centre column (u = 0.5) looks along +z; u increasing
// turns towards -x (a viewer inside, looking along +z with +y up, has -x on his right in
// this right-handed world); v = 0 is the top row (+y), v = 1 the bottom row (-y):
//     u = 0.5 + atan2(-d.x, d.z) / (2 pi),   v = theta / pi,  theta = angle from +y,
//     d = (-sin(theta) sin(phi), cos(theta), sin(theta) cos(phi)),  phi = 2 pi (u - 0.5).
// Radiance is looked up at the NEAREST pixel (no filtering), so Le and the sampling pdf
// are both piecewise constant over the same pixels. Pixels are sampled in proportion to
// luminance(pixel) * sin(theta at the row's centre) with a Distribution2D;
// pdf(solid angle) = pdf(u, v) / (2 pi^2 sin(theta)), 0 where sin(theta) = 0.
#pragma once
#include <cmath>
#include <utility>

#include "kernels/distribution.h"
#include "wavemmlt/image.h"
#include "wavemmlt/math.h"

namespace wmlt {

// The unit direction at map coordinates (u, v) in [0, 1]^2.
inline Vec3 envDirection(float u, float v) {
    const float theta = kPi * v, phi = 2.0f * kPi * (u - 0.5f);
    const float sinTheta = std::sin(theta);
    return {-sinTheta * std::sin(phi), std::cos(theta), sinTheta * std::cos(phi)};
}

// Map coordinates of direction d (need not be normalised): u in [0, 1), v in [0, 1].
// theta is computed as atan2(|d.xz|, d.y), equal to acos(d.y) for unit d and accurate
// near the poles.
inline void envUv(Vec3 d, float& u, float& v) {
    u = 0.5f + std::atan2(-d.x, d.z) * kInv2Pi;
    if (!(u >= 0)) u = 0;  // also NaN
    if (u >= 1) u -= 1;    // atan2 = +pi (the seam) maps to u = 0
    v = std::atan2(std::sqrt(d.x * d.x + d.z * d.z), d.y) * kInvPi;
    if (!(v >= 0)) v = 0;
    if (v > 1) v = 1;
}

struct EnvMapSampler {
    Image image;              // linear RGB radiance, top row first
    Distribution2D dist;      // over (u, v)
    float meanLuminance = 0;  // (1 / 4 pi) * integral of luminance(Le) over the sphere

    bool valid() const { return image.width > 0 && image.height > 0; }

    void build(const Image& img) {
        image = img;
        prepare();
    }
    void build(Image&& img) {
        image = std::move(img);
        prepare();
    }

    // Radiance arriving along -d, i.e. seen looking in direction d: nearest pixel.
    Vec3 Le(Vec3 d) const {
        if (!valid()) return Vec3(0.0f);
        float u, v;
        envUv(d, u, v);
        int x, y;
        pixelOf(u, v, x, y);
        return image.at(x, y);
    }

    // A direction with density pdfSolidAngle (0 when the sample is unusable).
    Vec3 sample(float u1, float u2, float& pdfSolidAngle) const {
        pdfSolidAngle = 0;
        if (!valid()) return {0, 1, 0};
        float u, v, pdfUv;
        dist.sampleContinuous(u1, u2, u, v, &pdfUv);
        const float theta = kPi * v;
        const float sinTheta = std::sin(theta);
        Vec3 d = envDirection(u, v);
        if (!(sinTheta > 0) || !(pdfUv > 0)) return d;
        pdfSolidAngle = pdfUv / (2.0f * kPi * kPi * sinTheta);
        return d;
    }

    // Solid-angle density with which sample() produces d.
    float pdf(Vec3 d) const {
        if (!valid()) return 0.0f;
        float u, v;
        envUv(d, u, v);
        const float sinTheta = std::sin(kPi * v);
        if (!(sinTheta > 0)) return 0.0f;
        return dist.pdf(u, v) / (2.0f * kPi * kPi * sinTheta);
    }

    // The pixel (x, y) containing map coordinates (u, v).
    void pixelOf(float u, float v, int& x, int& y) const {
        x = std::min(std::max(int(u * float(image.width)), 0), image.width - 1);
        y = std::min(std::max(int(v * float(image.height)), 0), image.height - 1);
    }

private:
    void prepare();
};

}  // namespace wmlt
