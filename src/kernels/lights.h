// Emitters: one-sided rectangles, spheres emitting outward (scene-format.md, "Lights").
// Emitted radiance is uniform over the surface and over directions. Sampling functions
// return solid-angle pdfs as seen from a reference point (next-event estimation);
// the environment map is sampled by EnvMapSampler (envmap.h).
#pragma once
#include "kernels/sampling.h"

namespace wmlt {

enum class LightType : uint8_t { Rect, Sphere, Env };

struct Light {
    LightType type = LightType::Rect;
    Vec3 L{0.0f};            // emitted radiance
    Vec3 corner, e1, e2, n;  // Rect: corner + s e1 + t e2, unit normal on the emitting side
    Vec3 center;             // Sphere
    float radius = 0;
    float area = 0;
};

struct LightSample {
    Vec3 p;         // point on the light
    Vec3 wi;        // unit direction from the reference point to p
    float dist = 0; // distance to p (infinite lights: +inf)
    Vec3 Le;        // radiance arriving along -wi
    float pdf = 0;  // solid angle
};

// Emitted radiance leaving a rect light's point in direction w (towards the viewer).
inline Vec3 rectLe(const Light& l, Vec3 w) { return dot(w, l.n) > 0 ? l.L : Vec3(0.0f); }

// Area-uniform point on the rectangle; pdf_w = dist^2 / (cos_l * area) (pbrt-v4 eq. 4.9).
inline bool sampleRectLight(const Light& l, Vec3 ref, float u1, float u2, LightSample& s) {
    s.p = l.corner + l.e1 * u1 + l.e2 * u2;
    Vec3 d = s.p - ref;
    float dist2 = lengthSquared(d);
    if (!(dist2 > 0)) return false;
    s.dist = std::sqrt(dist2);
    s.wi = d / s.dist;
    float cosL = -dot(s.wi, l.n);
    if (cosL <= 0) return false;  // the back of a one-sided light
    s.Le = l.L;
    s.pdf = dist2 / (cosL * l.area);
    return std::isfinite(s.pdf);
}
inline float rectLightPdf(const Light& l, Vec3 ref, Vec3 pLight) {
    Vec3 d = pLight - ref;
    float dist2 = lengthSquared(d);
    float cosL = -dot(d, l.n) / std::sqrt(dist2);
    return cosL > 0 ? dist2 / (cosL * l.area) : 0.0f;
}

// Spheres are sampled uniformly in the cone they subtend (pbrt-v3 14.2.2): a better
// estimator than area sampling, whose back half never reaches the reference point.
// 1 - cos(theta_max) is computed as sin^2 / (1 + cos) to stay exact for far spheres.
inline float sphereConeSolidAngle(const Light& l, Vec3 ref) {
    float d2 = lengthSquared(l.center - ref);
    float r2 = l.radius * l.radius;
    if (d2 <= r2) return 0.0f;  // inside: the outward emission never reaches ref
    float sin2 = r2 / d2;
    float cosMax = std::sqrt(std::max(0.0f, 1.0f - sin2));
    return 2.0f * kPi * (sin2 / (1.0f + cosMax));
}
inline float sphereLightPdf(const Light& l, Vec3 ref) {
    float omega = sphereConeSolidAngle(l, ref);
    return omega > 0 ? 1.0f / omega : 0.0f;
}
inline bool sampleSphereLight(const Light& l, Vec3 ref, float u1, float u2, LightSample& s) {
    float omega = sphereConeSolidAngle(l, ref);
    if (!(omega > 0)) return false;
    Vec3 toC = l.center - ref;
    float dc = length(toC);
    Frame f = Frame::fromNormal(toC / dc);
    // 1 - cos(theta) = u1 (1 - cos(theta_max)) and sin^2 = (1 - cos)(1 + cos), both from
    // 1 - cos, never from a cos rounded near 1 (for a far sphere, cos in float would take
    // only a few thousand values over the cone: rings, not a uniform cone).
    float oneMinusCos = u1 * (omega / (2.0f * kPi));
    float cosTheta = 1.0f - oneMinusCos;
    float sinTheta = std::sqrt(std::max(0.0f, oneMinusCos * (2.0f - oneMinusCos)));
    float phi = 2.0f * kPi * u2;
    s.wi = f.toWorld({sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta});
    // Nearest intersection with the sphere along wi. The squared distance of the line from
    // the centre is |toC - b wi|^2, not dc^2 - b^2: that difference of two nearly equal
    // numbers loses the digits a small far sphere needs (Haines et al. 2019, "Precision
    // improvements for ray/sphere intersection"), and a point computed inside the sphere
    // makes the shadow ray towards it hit the light itself.
    float b = dot(s.wi, toC);
    float rho = length(toC - s.wi * b);
    float h2 = (l.radius - rho) * (l.radius + rho);
    s.dist = b - std::sqrt(std::max(0.0f, h2));
    s.p = ref + s.wi * s.dist;
    s.Le = l.L;
    s.pdf = 1.0f / omega;
    return s.dist > 0;
}

// Power (flux) of a light, used to choose lights in proportion to it.
inline float lightPower(const Light& l) { return kPi * l.area * luminance(l.L); }

// ---- Emission sampling: the start of a light subpath (scene-format.md, "Lights") ----
// A point (area density pdfPos) and a direction (solid-angle density pdfDir about the
// normal n); Le leaves p along dir. Infinite lights: see sampleLightEmission.
struct LightEmission {
    Vec3 p, n, dir;
    Vec3 Le;
    float pdfPos = 0, pdfDir = 0;
};

// Cosine-weighted direction about n: pdfDir = cos / pi (pbrt-v4 12.5 SampleLe).
inline void sampleCosineAbout(Vec3 n, float u1, float u2, LightEmission& e) {
    Vec3 w = sampleCosineHemisphere(u1, u2);
    e.dir = normalize(Frame::fromNormal(n).toWorld(w));
    e.pdfDir = cosineHemispherePdf(w.z);
}

// Rect: area-uniform point (pdfPos = 1 / area), cosine-weighted direction about n.
inline bool sampleRectEmission(const Light& l, float u1, float u2, float u3, float u4, LightEmission& e) {
    e.p = l.corner + l.e1 * u1 + l.e2 * u2;
    e.n = l.n;
    e.pdfPos = 1.0f / l.area;
    sampleCosineAbout(e.n, u3, u4, e);
    e.Le = l.L;
    return e.pdfDir > 0;
}

// Sphere: area-uniform point on the sphere, cosine-weighted outward direction.
inline bool sampleSphereEmission(const Light& l, float u1, float u2, float u3, float u4, LightEmission& e) {
    e.n = sampleUniformSphere(u1, u2);
    e.p = l.center + e.n * l.radius;
    e.pdfPos = 1.0f / l.area;
    sampleCosineAbout(e.n, u3, u4, e);
    e.Le = l.L;
    return e.pdfDir > 0;
}

// Radiance an area light's surface point with outward normal n emits in direction w.
inline Vec3 areaLe(const Light& l, Vec3 n, Vec3 w) { return dot(w, n) > 0 ? l.L : Vec3(0.0f); }

}  // namespace wmlt
