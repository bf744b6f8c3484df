// Emitters: one-sided rectangles, spheres emitting outward (scene-format.md, "Lights"),
// and for Mitsuba scenes one-sided triangle meshes (emitting on their winding's side;
// sampled in scene_lights.h, which holds the triangles) and point lights (a delta in
// position: intensity I in every direction, never hit by a ray, invisible to the camera).
// Area emitters' radiance is uniform over the surface and over directions. Sampling
// functions return solid-angle pdfs as seen from a reference point (next-event
// estimation; a point light: the discrete pdf 1 with delta set); the environment map is
// sampled by EnvMapSampler (envmap.h).
#pragma once
#include "kernels/sampling.h"

namespace wmlt {

enum class LightType : uint8_t { Rect, Sphere, Env, Mesh, Point, Directional };

struct Light {
    LightType type = LightType::Rect;
    Vec3 L{0.0f};            // emitted radiance (Point: intensity, W / sr)
    Vec3 corner, e1, e2, n;  // Rect: corner + s e1 + t e2, unit normal on the emitting side
    Vec3 center;             // Sphere; Point: the position
    float radius = 0;
    float area = 0;  // Rect, Sphere, Mesh: the emitting area; Point: 0
    int mesh = -1;   // Mesh: index into Scene::meshLights
    // Point as a spot (Mitsuba's `spot`): L is the intensity on the unit axis, scaled by
    // spotFalloff; cosCutoff < -1: a point light, emitting alike in every direction.
    // Directional (Mitsuba's `directional`, a delta in direction at infinity): L is the
    // irradiance on a plane facing it, axis the direction its light travels, area the
    // emission disc's pi R^2 (R the scene's bounding radius).
    Vec3 axis{0, 0, 1};
    Frame axisFrame = Frame::fromNormal(Vec3(0, 0, 1));  // spot: about axis, made once with the scene
    float cosCutoff = -2, cosBeam = -2, cutoff = 0, invTransition = 0;
    bool smoothstep = false;  // spot: pbrt-v4's falloff, smoothstep in the cosine
    bool twoSided = false;    // Mesh: emits from both faces (LightDesc::twoSided)
};

// Delta lights are found by next-event estimation only: a point (or spot) in position, a
// directional light in direction.
inline bool isDeltaLight(const Light& l) { return l.type == LightType::Point || l.type == LightType::Directional; }
// Lights at infinity: light subpaths start on a disc outside the scene's bounds.
inline bool isInfiniteLight(const Light& l) { return l.type == LightType::Env || l.type == LightType::Directional; }
inline bool isSpot(const Light& l) { return l.cosCutoff >= -1; }

// A spot's intensity factor in the unit direction w from it (Mitsuba's falloff curve): 1
// within beam_width of the axis, falling linearly in the angle to 0 at cutoff_angle, 0
// beyond (pbrt-v4's: smoothstep(cos cutoff, cos beam, cos theta)); 1 for a point light.
inline float spotFalloff(const Light& l, Vec3 w) {
    if (!isSpot(l)) return 1.0f;
    const float c = dot(w, l.axis);
    if (!(c > l.cosCutoff)) return 0.0f;
    if (c >= l.cosBeam) return 1.0f;
    if (l.smoothstep) {
        const float t = (c - l.cosCutoff) / (l.cosBeam - l.cosCutoff);
        return t * t * (3.0f - 2.0f * t);
    }
    return std::max(0.0f, (l.cutoff - std::acos(std::min(c, 1.0f))) * l.invTransition);
}

// The solid-angle density with which a point light's emission (samplePointEmission)
// leaves in the unit direction w: uniform over the sphere, a spot's uniform over its cone.
inline float pointEmissionPdf(const Light& l, Vec3 w) {
    if (!isSpot(l)) return kUniformSpherePdf;
    return dot(w, l.axis) > l.cosCutoff ? 1.0f / (2.0f * kPi * (1.0f - l.cosCutoff)) : 0.0f;
}

struct LightSample {
    Vec3 p;              // point on the light
    Vec3 n;              // the light's normal at p (the emitting side; Env: -wi; Point: -wi)
    Vec3 wi;             // unit direction from the reference point to p
    float dist = 0;      // distance to p (infinite lights: +inf)
    Vec3 Le;             // radiance arriving along -wi (Point: I / dist^2, the irradiance's factor)
    float pdf = 0;       // solid angle (Point: 1, a discrete choice)
    bool delta = false;  // a point light: no other strategy finds it (MIS weight 1)
    float pdfA = -1;     // a textured emitter: the area density of p (else < 0: 1 / area)
};

// Emitted radiance leaving a rect light's point in direction w (towards the viewer).
inline Vec3 rectLe(const Light& l, Vec3 w) { return dot(w, l.n) > 0 ? l.L : Vec3(0.0f); }

// A rectangle light's geometry as floats, made once for many samples: the per-element
// samplers below take it by value, so that their loops read no Light through a reference
// (which the compiler must assume the loops' stores may change; they did not vectorise).
struct RectFloats {
    float cx, cy, cz, ax, ay, az, bx, by, bz, nx, ny, nz, area;
};
inline RectFloats rectFloats(const Light& l) {
    return {l.corner.x, l.corner.y, l.corner.z, l.e1.x, l.e1.y, l.e1.z, l.e2.x, l.e2.y, l.e2.z, l.n.x, l.n.y, l.n.z, l.area};
}

// The point corner + e1 u1 + e2 u2 (rounded left to right, as Vec3's operators do).
inline void rectPoint(const RectFloats& g, float u1, float u2, float& px, float& py, float& pz) {
    px = (g.cx + g.ax * u1) + g.bx * u2;
    py = (g.cy + g.ay * u1) + g.by * u2;
    pz = (g.cz + g.az * u1) + g.bz * u2;
}

// Area-uniform point on the rectangle seen from r; pdf_w = dist^2 / (cos_l * area) (pbrt-v4
// eq. 4.9). In floats (a / s as a * (1 / s), as Vec3's operators round), so that loops of it
// vectorise (rectLightSamples); false at the back of the one-sided light or at its plane
// (the outputs are then unspecified).
inline bool rectLightSampleAt(const RectFloats& g, float u1, float u2, float rx, float ry, float rz, float& px, float& py, float& pz, float& wx,
                              float& wy, float& wz, float& dist, float& pdf) {
    rectPoint(g, u1, u2, px, py, pz);
    const float dx = px - rx, dy = py - ry, dz = pz - rz;
    const float dist2 = dx * dx + dy * dy + dz * dz;
    dist = std::sqrt(dist2);
    const float r = 1.0f / dist;
    wx = dx * r;
    wy = dy * r;
    wz = dz * r;
    const float cosL = -(wx * g.nx + wy * g.ny + wz * g.nz);
    pdf = dist2 / (cosL * g.area);
    return dist2 > 0 && cosL > 0 && std::isfinite(pdf);
}
inline bool sampleRectLight(const Light& l, Vec3 ref, float u1, float u2, LightSample& s) {
    s.n = l.n;
    s.Le = l.L;
    return rectLightSampleAt(rectFloats(l), u1, u2, ref.x, ref.y, ref.z, s.p.x, s.p.y, s.p.z, s.wi.x, s.wi.y, s.wi.z, s.dist, s.pdf);
}
// sampleRectLight for h < n (reference point ref[3h .. 3h + 2]): s.p into p (three floats
// each), s.wi into (wx, wy, wz), s.dist, s.pdf, and ok[h] what it returned. Restrict
// parameters: the loop vectorises.
__attribute__((noinline)) inline void rectLightSamples(const RectFloats g, const float* __restrict u1, const float* __restrict u2,
                                                       const float* __restrict ref, size_t n, float* __restrict p, float* __restrict wx,
                                                       float* __restrict wy, float* __restrict wz, float* __restrict dist, float* __restrict pdf,
                                                       uint8_t* __restrict ok) {
    for (size_t h = 0; h < n; ++h)
        ok[h] = rectLightSampleAt(g, u1[h], u2[h], ref[3 * h], ref[3 * h + 1], ref[3 * h + 2], p[3 * h], p[3 * h + 1], p[3 * h + 2], wx[h], wy[h],
                                  wz[h], dist[h], pdf[h]);
}

// rectLightSamples with each hit's own light: rects[light[h]] (a light that is no
// rectangle has all zeros there, which no sample passes: ok[h] = 0).
__attribute__((noinline)) inline void rectLightSamplesOf(const RectFloats* __restrict rects, const uint32_t* __restrict light,
                                                         const float* __restrict u1, const float* __restrict u2, const float* __restrict ref,
                                                         size_t n, float* __restrict p, float* __restrict wx, float* __restrict wy,
                                                         float* __restrict wz, float* __restrict dist, float* __restrict pdf,
                                                         uint8_t* __restrict ok) {
    for (size_t h = 0; h < n; ++h)
        ok[h] = rectLightSampleAt(rects[light[h]], u1[h], u2[h], ref[3 * h], ref[3 * h + 1], ref[3 * h + 2], p[3 * h], p[3 * h + 1], p[3 * h + 2],
                                  wx[h], wy[h], wz[h], dist[h], pdf[h]);
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
    float sinPhi, cosPhi;
    sinCos2Pi(u2, sinPhi, cosPhi);
    s.wi = f.toWorld({sinTheta * cosPhi, sinTheta * sinPhi, cosTheta});
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
    s.n = normalize(s.p - l.center);
    s.Le = l.L;
    s.pdf = 1.0f / omega;
    return s.dist > 0;
}

// A point light from ref: the one direction to it, Le = I / dist^2, discrete pdf 1.
inline bool samplePointLight(const Light& l, Vec3 ref, LightSample& s) {
    const Vec3 d = l.center - ref;
    const float dist2 = lengthSquared(d);
    if (!(dist2 > 0) || !std::isfinite(dist2)) return false;
    s.dist = std::sqrt(dist2);
    s.wi = d / s.dist;
    s.p = l.center;
    s.n = -s.wi;
    s.Le = l.L / dist2;
    if (isSpot(l)) s.Le = s.Le * spotFalloff(l, -s.wi);
    s.pdf = 1.0f;
    s.delta = true;
    return true;
}

// Power (flux) of a light, used to choose lights in proportion to it: pi A L for area
// lights (cosine-weighted; twice that from both faces), 4 pi I for a point light.
inline float lightPower(const Light& l) {
    if (l.type == LightType::Directional) return l.area * luminance(l.L);  // E through the disc pi R^2
    if (l.type == LightType::Point && isSpot(l))                           // the cone to mid-falloff (pbrt-v4's SpotLight::Phi)
        return 2.0f * kPi * (1.0f - 0.5f * (l.cosCutoff + l.cosBeam)) * luminance(l.L);
    if (l.type == LightType::Point) return 4.0f * kPi * luminance(l.L);
    return (l.twoSided ? 2.0f : 1.0f) * kPi * l.area * luminance(l.L);
}

// ---- Emission sampling: the start of a light subpath (scene-format.md, "Lights") ----
// A point (area density pdfPos) and a direction (solid-angle density pdfDir about the
// normal n); Le leaves p along dir. Infinite lights: see sampleLightEmission.
struct LightEmission {
    Vec3 p, n, dir;
    Vec3 Le;
    float pdfPos = 0, pdfDir = 0;
    Vec3 tex{1.0f};  // a textured emitter: the texture's value at p (Le includes it)
};

// Cosine-weighted direction about frame f's normal, normalised: (dx, dy, dz); returns its
// density cos / pi (pbrt-v4 12.5 SampleLe). In floats (toWorldUnit), so that loops of it
// vectorise.
inline float cosineAboutAt(const FrameFloats& f, float u1, float u2, float& dx, float& dy, float& dz) {
    float wx, wy, wz;
    sampleCosineHemisphere(u1, u2, wx, wy, wz);
    toWorldUnit(f, wx, wy, wz, dx, dy, dz);
    return cosineHemispherePdf(wz);
}
inline void sampleCosineAbout(Vec3 n, float u1, float u2, LightEmission& e) {
    e.pdfDir = cosineAboutAt(frameFromNormal(n.x, n.y, n.z), u1, u2, e.dir.x, e.dir.y, e.dir.z);
}

// Rect: area-uniform point (pdfPos = 1 / area), cosine-weighted direction about n.
inline bool sampleRectEmission(const Light& l, float u1, float u2, float u3, float u4, LightEmission& e) {
    rectPoint(rectFloats(l), u1, u2, e.p.x, e.p.y, e.p.z);
    e.n = l.n;
    e.pdfPos = 1.0f / l.area;
    sampleCosineAbout(e.n, u3, u4, e);
    e.Le = l.L;
    return e.pdfDir > 0;
}

// sampleRectEmission for i < n (frame: frameFromNormal of l.n, made once): e.p into p
// (three floats each), e.dir into (dx, dy, dz), e.pdfDir, and in ok[i] what it returned
// (e.n is l.n, e.pdfPos 1 / l.area, e.Le l.L). Restrict parameters: the loop vectorises.
__attribute__((noinline)) inline void rectEmissionSamples(const RectFloats g, const FrameFloats frame, const float* __restrict u1,
                                                          const float* __restrict u2, const float* __restrict u3, const float* __restrict u4,
                                                          size_t n, float* __restrict p, float* __restrict dx, float* __restrict dy,
                                                          float* __restrict dz, float* __restrict pdfDir, uint8_t* __restrict ok) {
    for (size_t i = 0; i < n; ++i) {
        rectPoint(g, u1[i], u2[i], p[3 * i], p[3 * i + 1], p[3 * i + 2]);
        pdfDir[i] = cosineAboutAt(frame, u3[i], u4[i], dx[i], dy[i], dz[i]);
        ok[i] = pdfDir[i] > 0;
    }
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

// Point light: the point, a uniform direction (pdfDir = 1 / 4 pi), the discrete position
// pdf 1; n = dir, so that the caller's |n.dir| / (pdfPos pdfDir) is 4 pi; Le = I.
// A spot: a uniform direction in its cone (cos theta = 1 - u (1 - cos cutoff)), Le = I
// times the falloff.
inline bool samplePointEmission(const Light& l, float u2, float u3, LightEmission& e) {
    e.p = l.center;
    e.pdfPos = 1.0f;
    if (isSpot(l)) {
        const float c = 1.0f - u2 * (1.0f - l.cosCutoff), sn = std::sqrt(std::max(0.0f, 1.0f - c * c));
        const float phi = 2.0f * kPi * u3;
        e.dir = normalize(l.axisFrame.toWorld(Vec3(sn * std::cos(phi), sn * std::sin(phi), c)));
        e.n = e.dir;
        e.pdfDir = pointEmissionPdf(l, e.dir);
        e.Le = l.L * spotFalloff(l, e.dir);
        return e.pdfDir > 0;
    }
    e.dir = sampleUniformSphere(u2, u3);
    e.n = e.dir;
    e.pdfDir = kUniformSpherePdf;
    e.Le = l.L;
    return true;
}

// Whether an area light's surface with normal n emits towards w (its front face's side; a
// two-sided one either side).
inline bool emitsTowards(const Light& l, Vec3 n, Vec3 w) {
    const float c = dot(w, n);
    return c > 0 || (l.twoSided && c < 0);
}
// Radiance an area light's surface point with outward normal n emits in direction w.
inline Vec3 areaLe(const Light& l, Vec3 n, Vec3 w) { return emitsTowards(l, n, w) ? l.L : Vec3(0.0f); }

}  // namespace wmlt
