// The thin-lens camera of the scene format: FOV is the full angle across the shorter
// image side; image right = normalize(forward x up), so a camera looking along +z
// with +y up sees +x on its left (scene-format.md, "Camera").
#pragma once
#include <algorithm>

#include "kernels/rng.h"
#include "kernels/sampling.h"
#include "wavemmlt/scene_desc.h"

namespace wmlt {

struct Camera {
    Vec3 position, forward, right, up;  // orthonormal basis
    float scaleX = 1, scaleY = 1;       // half extent of the image plane at distance 1
    float shiftX = 0, shiftY = 0;       // its centre's offset along right and up (a crop window)
    int width = 1, height = 1;
    bool thinLens = false;
    float lensRadius = 0, focusDistance = 1;
    // Orthographic (a delta in direction): rays along `forward` from the film rectangle
    // through `position`, of half extents scaleX, scaleY (world units), nearClip ahead.
    bool ortho = false;
    float nearClip = 0;
};

inline Camera makeCamera(const CameraDesc& d, int width, int height) {
    Camera c;
    c.position = d.position;
    c.forward = normalize(d.lookAt - d.position);
    c.right = normalize(cross(c.forward, d.up));
    c.up = cross(c.right, c.forward);
    if (d.flipX) c.right = -c.right;  // a mirror image: right turns over, up stays
    float tanHalf = std::tan(0.5f * d.fovDegrees * kPi / 180.0f);
    // The whole film (this image its window [x0, x1] x [y0, y1]): its half extents S, then
    // the window's: sx = (2 px / width - 1) S (x1 - x0) + S (x0 + x1 - 1), and in y (down)
    // sy = (1 - 2 py / height) S (y1 - y0) + S (1 - y0 - y1). No window: S and 0 exactly.
    const float* win = d.window;
    const float wx = win[1] - win[0], wy = win[3] - win[2];
    const float fullW = float(width) / wx, fullH = float(height) / wy;
    float shorter = std::min(fullW, fullH);
    c.scaleX = tanHalf * fullW / shorter;
    c.scaleY = tanHalf * fullH / shorter;
    c.width = width;
    c.height = height;
    c.thinLens = d.dof;
    c.lensRadius = d.dof ? d.focalLength / (2.0f * d.fStop) : 0.0f;
    c.focusDistance = d.focalLength;
    if (d.orthographic) {
        c.ortho = true;
        c.thinLens = false;
        c.lensRadius = 0;
        c.scaleX = d.orthoHalfWidth;
        c.scaleY = d.orthoHalfHeight;
        c.nearClip = d.nearClip;
    }
    c.shiftX = c.scaleX * (win[0] + win[1] - 1.0f);
    c.shiftY = c.scaleY * (1.0f - win[2] - win[3]);
    c.scaleX *= wx;
    c.scaleY *= wy;
    return c;
}

// A pinhole: the one camera whose rays all start at its position (the flat loops').
inline bool isPinhole(const Camera& c) { return !c.thinLens && !c.ortho; }

// The camera's frame and image as floats, made once for many rays: the per-element
// functions below take it by value, so that loops of them read no Camera through a
// reference (which the compiler must assume their stores may change) and vectorise.
struct CameraFloats {
    float fx, fy, fz, rx, ry, rz, ux, uy, uz, width, height, scaleX, scaleY;
    float ox, oy, oz, focusDistance, planeArea, lensArea;  // position; cameraPlaneArea, cameraLensArea
    float shiftX, shiftY;
};
inline float cameraPlaneArea(const Camera& c);
inline float cameraLensArea(const Camera& c);
inline CameraFloats cameraFloats(const Camera& c) {
    return {c.forward.x,  c.forward.y,  c.forward.z,     c.right.x,          c.right.y,         c.right.z, c.up.x,
            c.up.y,       c.up.z,       float(c.width),  float(c.height),    c.scaleX,          c.scaleY,  c.position.x,
            c.position.y, c.position.z, c.focusDistance, cameraPlaneArea(c), cameraLensArea(c), c.shiftX,  c.shiftY};
}

// Direction (unnormalised, forward component 1) through the raster point (px, py),
// raster y pointing down, (0, 0) the image's top-left corner.
inline void cameraPlaneDirectionAt(const CameraFloats c, float px, float py, float& dx, float& dy, float& dz) {
    const float sx = (2.0f * px / c.width - 1.0f) * c.scaleX + c.shiftX;  // + 0: the same bits
    const float sy = (1.0f - 2.0f * py / c.height) * c.scaleY + c.shiftY;
    dx = (c.fx + c.rx * sx) + c.ux * sy;
    dy = (c.fy + c.ry * sx) + c.uy * sy;
    dz = (c.fz + c.rz * sx) + c.uz * sy;
}
inline Vec3 cameraPlaneDirection(const Camera& c, float px, float py) {
    Vec3 d;
    cameraPlaneDirectionAt(cameraFloats(c), px, py, d.x, d.y, d.z);
    return d;
}

// The pixel holding raster point (px, py) of the image (clamped at the far edges).
inline uint32_t rasterPixel(const Camera& cam, float px, float py) {
    int x = std::min(int(px), cam.width - 1), y = std::min(int(py), cam.height - 1);
    return uint32_t(y) * uint32_t(cam.width) + uint32_t(x);
}

// Raster position of sample s of pixel (x, y) in the pixel's n x n grid of strata,
// jittered by (u1, u2). Round r = s / n^2 visits the strata in a random order (a
// permutation keyed by the pixel's key and r): a complete round covers every stratum once,
// and any prefix of a round (a render stopped early) is a uniform sample of the pixel, so
// it stays unbiased. (A fixed order would cover the top rows of every pixel first.) Per
// axis the point is stratumPoint: x + (stratum + u) / n.
inline float stratumPoint(float x, float stratum, float u, float n) { return x + (stratum + u) / n; }
inline void stratifiedRasterPoint(int x, int y, uint32_t s, int n, uint64_t pixelKey, float u1, float u2, float& px, float& py) {
    const uint32_t nn = uint32_t(n) * uint32_t(n);
    const uint32_t stratum = permuteIndex(s % nn, nn, mix64(pixelKey + s / nn));
    px = stratumPoint(float(x), float(stratum % uint32_t(n)), u1, float(n));
    py = stratumPoint(float(y), float(stratum / uint32_t(n)), u2, float(n));
}

// generateCameraRay's direction without a lens, bit for bit, for m rays through the
// raster points (stratumPoint(x[i], sx[i], sampleDimension(key[i], dimX), n), the same in
// y): into d[3 i .. 3 i + 2], in one loop the compiler vectorises (the hashes, the
// divisions, the square root).
__attribute__((noinline)) inline void pinholeCameraDirections(const CameraFloats c, const uint64_t* __restrict key, const float* __restrict x,
                                                              const float* __restrict y, const float* __restrict sx, const float* __restrict sy,
                                                              size_t m, float n, uint32_t dimX, uint32_t dimY, float* __restrict d) {
    for (size_t i = 0; i < m; ++i) {
        const float px = stratumPoint(x[i], sx[i], sampleDimension(key[i], dimX), n);
        const float py = stratumPoint(y[i], sy[i], sampleDimension(key[i], dimY), n);
        float ux, uy, uz;
        cameraPlaneDirectionAt(c, px, py, ux, uy, uz);
        const float r = 1.0f / std::sqrt((ux * ux + uy * uy) + uz * uz);  // normalize: a * (1 / |a|)
        d[3 * i] = ux * r;
        d[3 * i + 1] = uy * r;
        d[3 * i + 2] = uz * r;
    }
}

// Primary ray through raster point (px, py); (u1, u2) pick the lens point when the
// camera has a thin lens (pbrt-v4 5.2.3): rays through a lens point converge on the
// plane of focus at distance focusDistance along the view direction.
inline void generateCameraRay(const Camera& c, float px, float py, float u1, float u2, Vec3& origin, Vec3& dir) {
    if (c.ortho) {  // the film point (the unit plane's offsets, in world units), along forward
        const Vec3 d = cameraPlaneDirection(c, px, py) - c.forward;
        origin = c.position + d + c.forward * c.nearClip;
        dir = c.forward;
        return;
    }
    Vec3 d = cameraPlaneDirection(c, px, py);
    if (!c.thinLens) {
        origin = c.position;
        dir = normalize(d);
        return;
    }
    float lx, ly;
    sampleConcentricDisk(u1, u2, lx, ly);
    Vec3 lens = c.right * (lx * c.lensRadius) + c.up * (ly * c.lensRadius);
    Vec3 focus = d * c.focusDistance;
    origin = c.position + lens;
    dir = normalize(focus - lens);
}

// Inverse: the raster point a world direction from the camera's centre passes through;
// false when it is behind the camera or outside the image.
inline bool cameraRasterOf(const Camera& c, Vec3 w, float& px, float& py) {
    float z = dot(w, c.forward);
    if (z <= 0) return false;
    float sx = (dot(w, c.right) / z - c.shiftX) / c.scaleX, sy = (dot(w, c.up) / z - c.shiftY) / c.scaleY;
    px = (sx + 1.0f) * 0.5f * float(c.width);
    py = (1.0f - sy) * 0.5f * float(c.height);
    return px >= 0 && px < float(c.width) && py >= 0 && py < float(c.height);
}

// ---- Importance (pbrt-v4 5.4.1, 16.1.1; Veach 1997, 8.1) ---------------------------
// The path tracer's pixel j is the box-filtered mean over its raster square and over the
// lens:  I_j = (1 / A_lens) int_lens int_pixel L d(raster) dA_lens.  The image plane at
// distance 1 has area A = (2 scaleX)(2 scaleY) and a pixel covers A / (W H) of it, so
// d(raster) = (W H / A) dA_plane; a direction through the plane point at angle theta to
// `forward` has d(omega) = cos^3(theta) dA_plane (also through a thin lens: the focus
// plane is the unit plane scaled by focusDistance). Hence
//   I_j = W H * int int We(p, w) L(p, w) cos(theta) dA_lens d(omega)  over pixel j's rays,
//   We = 1 / (A * A_lens * cos^4(theta)),   A_lens = pi r^2 (pinhole: 1, a delta point).
// The light tracer estimates the double integral with N = W H spp light paths; summing
// their splats on pixel j and dividing by spp gives W H times their mean: I_j.
inline float cameraPlaneArea(const Camera& c) { return 4.0f * c.scaleX * c.scaleY; }
inline float cameraLensArea(const Camera& c) { return c.thinLens && c.lensRadius > 0 ? kPi * c.lensRadius * c.lensRadius : 1.0f; }

// Raster point of a ray leaving lens point `lens` in unit direction w (towards the scene):
// through the focus plane for a thin lens (pbrt-v4 PerspectiveCamera::We). False when
// behind the camera or outside the image. cosTheta = dot(w, forward).
inline bool cameraRasterOfRay(const Camera& c, Vec3 lens, Vec3 w, float& px, float& py, float& cosTheta) {
    cosTheta = dot(w, c.forward);
    if (!(cosTheta > 0)) return false;
    if (!c.thinLens) return cameraRasterOf(c, w, px, py);
    Vec3 pFocus = lens + w * (c.focusDistance / cosTheta);
    return cameraRasterOf(c, pFocus - c.position, px, py);
}

// We(lens, w): zero outside the image.
inline float cameraWe(const Camera& c, Vec3 lens, Vec3 w) {
    float px, py, cosTheta;
    if (!cameraRasterOfRay(c, lens, w, px, py, cosTheta)) return 0.0f;
    float cos2 = cosTheta * cosTheta;
    return 1.0f / (cameraPlaneArea(c) * cameraLensArea(c) * cos2 * cos2);
}

// The camera seen from ref through lens point l (pbrt-v4 PerspectiveCamera::SampleWi, as
// sampleCameraFrom below, in floats so that loops of it vectorise): the unit direction w
// from ref to l, dist2 = |l - ref|^2, the raster point (px, py) of the ray from l along -w
// (through the focus plane for a thin lens: cameraRasterOfRay), cosTheta = dot(-w,
// forward), We and the solid-angle density at ref, pdf = dist2 / (cos(theta) A_lens).
// False when ref is at l, behind the camera or outside the image, or pdf is not finite and
// positive (the outputs are then unspecified).
template <bool ThinLens>
inline bool cameraSampleAt(const CameraFloats c, float lx, float ly, float lz, float refX, float refY, float refZ, float& wx, float& wy, float& wz,
                           float& dist2, float& px, float& py, float& cosTheta, float& We, float& pdf) {
    const float dx = lx - refX, dy = ly - refY, dz = lz - refZ;
    dist2 = dx * dx + dy * dy + dz * dz;
    const float r = 1.0f / std::sqrt(dist2);  // d / |d| as d * (1 / |d|)
    wx = dx * r;
    wy = dy * r;
    wz = dz * r;
    const float ux = -wx, uy = -wy, uz = -wz;
    cosTheta = ux * c.fx + uy * c.fy + uz * c.fz;
    float qx = ux, qy = uy, qz = uz;  // cameraRasterOf's direction
    if constexpr (ThinLens) {
        const float t = c.focusDistance / cosTheta;
        qx = (lx + ux * t) - c.ox;
        qy = (ly + uy * t) - c.oy;
        qz = (lz + uz * t) - c.oz;
    }
    const float z = qx * c.fx + qy * c.fy + qz * c.fz;
    const float sx = ((qx * c.rx + qy * c.ry + qz * c.rz) / z - c.shiftX) / c.scaleX;
    const float sy = ((qx * c.ux + qy * c.uy + qz * c.uz) / z - c.shiftY) / c.scaleY;
    px = (sx + 1.0f) * 0.5f * c.width;
    py = (1.0f - sy) * 0.5f * c.height;
    const float cos2 = cosTheta * cosTheta;
    We = 1.0f / (c.planeArea * c.lensArea * cos2 * cos2);
    pdf = dist2 / (cosTheta * c.lensArea);
    return dist2 > 0 && cosTheta > 0 && z > 0 && px >= 0 && px < c.width && py >= 0 && py < c.height && std::isfinite(pdf) && pdf > 0;
}

struct CameraSample {
    Vec3 lens;             // point on the lens (pinhole: the position)
    Vec3 wi;               // unit, from ref to lens
    float dist = 0;        // |lens - ref|
    float px = 0, py = 0;  // raster position
    float We = 0;
    float pdf = 0;       // solid angle at ref: dist^2 / (cos(theta) A_lens)
    bool valid = false;  // (else the other fields are unspecified)
};

// A lens point seen from ref (uniform on the lens disc) and the importance it receives
// (pbrt-v4 PerspectiveCamera::SampleWi). (u1, u2) are used only by a thin lens.
inline Vec3 cameraLensPoint(const Camera& c, float u1, float u2) {
    if (!(c.thinLens && c.lensRadius > 0)) return c.position;
    float lx, ly;
    sampleConcentricDisk(u1, u2, lx, ly);
    return c.position + c.right * (lx * c.lensRadius) + c.up * (ly * c.lensRadius);
}
// Orthographic: the film point ref projects to along -forward, reached from ref along wi =
// -forward (a delta: pdf 1), We = 1 / A (the film's area: I_j = (W H / A) int_pixel L dA).
inline CameraSample sampleOrthographicFrom(const Camera& c, Vec3 ref) {
    CameraSample s;
    const Vec3 q = ref - c.position;
    const float depth = dot(q, c.forward);
    const float sx = (dot(q, c.right) - c.shiftX) / c.scaleX, sy = (dot(q, c.up) - c.shiftY) / c.scaleY;
    s.px = (sx + 1.0f) * 0.5f * float(c.width);
    s.py = (1.0f - sy) * 0.5f * float(c.height);
    s.dist = depth - c.nearClip;
    s.wi = -c.forward;
    s.lens = ref + s.wi * s.dist;
    s.We = 1.0f / cameraPlaneArea(c);
    s.pdf = 1.0f;
    s.valid = s.dist > 0 && s.px >= 0 && s.px < float(c.width) && s.py >= 0 && s.py < float(c.height);
    return s;
}

// A pinhole's or a thin lens' (not orthographic).
inline CameraSample sampleProjectiveFrom(const Camera& c, Vec3 ref, float u1, float u2) {
    CameraSample s;
    s.lens = cameraLensPoint(c, u1, u2);
    const CameraFloats f = cameraFloats(c);
    float dist2, cosTheta;
    s.valid = c.thinLens ? cameraSampleAt<true>(f, s.lens.x, s.lens.y, s.lens.z, ref.x, ref.y, ref.z, s.wi.x, s.wi.y, s.wi.z, dist2, s.px, s.py,
                                                cosTheta, s.We, s.pdf)
                         : cameraSampleAt<false>(f, s.lens.x, s.lens.y, s.lens.z, ref.x, ref.y, ref.z, s.wi.x, s.wi.y, s.wi.z, dist2, s.px, s.py,
                                                 cosTheta, s.We, s.pdf);
    s.dist = std::sqrt(dist2);
    return s;
}
inline CameraSample sampleCameraFrom(const Camera& c, Vec3 ref, float u1, float u2) {
    return c.ortho ? sampleOrthographicFrom(c, ref) : sampleProjectiveFrom(c, ref, u1, u2);
}

// For a pinhole camera, over h < n: sampleCameraFrom(ref[3 h ..]) into wi[3 h ..], px,
// py, We, pdf and valid, and the area density at ref of the camera ray through it,
// pdfArea[h] = solidAngleToArea(1 / (A cos^3 theta), lens, ref, refN[3 h ..], true) (the
// reverse density a t = 1 strategy's MIS weight reads; cameraPdfOfRay). In one loop the
// compiler vectorises.
__attribute__((noinline)) inline void pinholeCameraSamples(const CameraFloats c, size_t n, const float* __restrict ref, const float* __restrict refN,
                                                           float* __restrict wi, float* __restrict px, float* __restrict py, float* __restrict We,
                                                           float* __restrict pdf, float* __restrict pdfArea, uint32_t* __restrict valid) {
    for (size_t h = 0; h < n; ++h) {
        const float rx = ref[3 * h], ry = ref[3 * h + 1], rz = ref[3 * h + 2];
        float wx, wy, wz, dist2, cosTheta;
        valid[h] = cameraSampleAt<false>(c, c.ox, c.oy, c.oz, rx, ry, rz, wx, wy, wz, dist2, px[h], py[h], cosTheta, We[h], pdf[h]) ? 1u : 0u;
        wi[3 * h] = wx;
        wi[3 * h + 1] = wy;
        wi[3 * h + 2] = wz;
        // cameraPdfOfRay(-wi), then solidAngleToArea from the lens to ref: d = ref - lens.
        const float pdfSa = 1.0f / (c.planeArea * cosTheta * cosTheta * cosTheta);
        const float cosRef = std::fabs(refN[3 * h] * (rx - c.ox) + refN[3 * h + 1] * (ry - c.oy) + refN[3 * h + 2] * (rz - c.oz)) / std::sqrt(dist2);
        pdfArea[h] = pdfSa * cosRef / dist2;
    }
}

}  // namespace wmlt
