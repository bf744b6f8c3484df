// The thin-lens camera of the scene format: FOV is the full angle across the shorter
// image side; image right = normalize(forward x up), so a camera looking along +z
// with +y up sees +x on its left (scene-format.md, "Camera").
#pragma once
#include "kernels/sampling.h"
#include "wavemmlt/scene_desc.h"

namespace wmlt {

struct Camera {
    Vec3 position, forward, right, up;  // orthonormal basis
    float scaleX = 1, scaleY = 1;       // half extent of the image plane at distance 1
    int width = 1, height = 1;
    bool thinLens = false;
    float lensRadius = 0, focusDistance = 1;
};

inline Camera makeCamera(const CameraDesc& d, int width, int height) {
    Camera c;
    c.position = d.position;
    c.forward = normalize(d.lookAt - d.position);
    c.right = normalize(cross(c.forward, d.up));
    c.up = cross(c.right, c.forward);
    float tanHalf = std::tan(0.5f * d.fovDegrees * kPi / 180.0f);
    float shorter = float(std::min(width, height));
    c.scaleX = tanHalf * float(width) / shorter;
    c.scaleY = tanHalf * float(height) / shorter;
    c.width = width;
    c.height = height;
    c.thinLens = d.dof;
    c.lensRadius = d.dof ? d.focalLength / (2.0f * d.fStop) : 0.0f;
    c.focusDistance = d.focalLength;
    return c;
}

// Direction (unnormalised, forward component 1) through the raster point (px, py),
// raster y pointing down, (0, 0) the image's top-left corner.
inline Vec3 cameraPlaneDirection(const Camera& c, float px, float py) {
    float sx = (2.0f * px / float(c.width) - 1.0f) * c.scaleX;
    float sy = (1.0f - 2.0f * py / float(c.height)) * c.scaleY;
    return c.forward + c.right * sx + c.up * sy;
}

// Primary ray through raster point (px, py); (u1, u2) pick the lens point when the
// camera has a thin lens (pbrt-v4 5.2.3): rays through a lens point converge on the
// plane of focus at distance focusDistance along the view direction.
inline void generateCameraRay(const Camera& c, float px, float py, float u1, float u2,
                              Vec3& origin, Vec3& dir) {
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
    float sx = dot(w, c.right) / z / c.scaleX, sy = dot(w, c.up) / z / c.scaleY;
    px = (sx + 1.0f) * 0.5f * float(c.width);
    py = (1.0f - sy) * 0.5f * float(c.height);
    return px >= 0 && px < float(c.width) && py >= 0 && py < float(c.height);
}

}  // namespace wmlt
