// Camera motions for the interactive mode (issue 28): pure functions from a camera
// description and a mouse or keyboard gesture to the moved camera, each keeping what the
// gesture should not change (orbit: the point looked at and its distance; pan and fly: the
// direction of view; dolly: the direction and the point; zoom: the position; recentre: the
// image).
#pragma once
#include <algorithm>
#include <cmath>

#include "wavemmlt/scene_desc.h"

namespace wmlt {

// The camera's orthonormal frame: towards lookAt, right, and up made orthogonal to them
// (right = forward x up, as the camera's rays have it; flipX mirrors the image, not this).
struct CameraFrame {
    Vec3 forward, right, up;
    float distance = 0;  // from position to lookAt
};
inline CameraFrame cameraFrame(const CameraDesc& c) {
    CameraFrame f;
    const Vec3 d = c.lookAt - c.position;
    f.distance = length(d);
    f.forward = d / f.distance;
    f.right = normalize(cross(f.forward, c.up));
    f.up = cross(f.right, f.forward);
    return f;
}

// v rotated by angle a about the unit axis k (Rodrigues).
inline Vec3 rotateAbout(Vec3 v, Vec3 k, float a) {
    const float c = std::cos(a), s = std::sin(a);
    return v * c + cross(k, v) * s + k * (dot(k, v) * (1 - c));
}

// The orbit's default rate, in degrees per window width (--orbit-rate; the window's width,
// the panel included). Lower than the 180 of many viewers: Bitterli's Cornell box is seen
// through its open side (from outside it is black), and turned about the point at its
// view's centre its image keeps 84% of its mean at 20 degrees, 46% at 40, 13% at 60; a
// 120-pixel drag in the 364-pixel window of a 64 x 48 image turns 20 degrees at 60, 59 at
// 180 (docs/interactive.md).
constexpr float kOrbitRateDefault = 60.0f;

// Recentre: lookAt moved along the view direction to `distance` from the eye (the image is
// unchanged: the same position and direction); the orbit's pivot at the drag's start.
inline CameraDesc recentre(CameraDesc c, float distance) {
    c.lookAt = c.position + cameraFrame(c).forward * distance;
    return c;
}

// Orbit about lookAt: yaw about the camera's up vector (the file's up), then pitch about
// the right axis, the pitch limited so that the view stays at least a degree from up.
inline CameraDesc orbit(CameraDesc c, float yaw, float pitch) {
    const Vec3 worldUp = normalize(c.up);
    Vec3 back = c.position - c.lookAt;  // from the point to the camera
    back = rotateAbout(back, worldUp, yaw);
    const float r = length(back);
    const float angle = std::acos(std::clamp(dot(back / r, worldUp), -1.0f, 1.0f));  // from up
    const float limit = 1.0f * kPi / 180.0f;
    const float target = std::clamp(angle - pitch, limit, kPi - limit);
    const Vec3 right = normalize(cross(worldUp, back));
    back = rotateAbout(back, right, target - angle);
    c.position = c.lookAt + back;
    return c;
}

// Pan: position and lookAt move along right and up by (dx, dy) times the image height's
// extent at the lookAt distance (a drag across the whole image height moves the point
// looked at by the view's height there).
inline CameraDesc pan(CameraDesc c, float dx, float dy) {
    const CameraFrame f = cameraFrame(c);
    const float extent = 2.0f * f.distance * std::tan(0.5f * c.fovDegrees * kPi / 180.0f);
    const Vec3 move = (f.right * dx + f.up * dy) * extent;
    c.position = c.position + move;
    c.lookAt = c.lookAt + move;
    return c;
}

// Dolly: the distance to lookAt times exp(-amount) (amount > 0: closer), the direction kept.
inline CameraDesc dolly(CameraDesc c, float amount) {
    const CameraFrame f = cameraFrame(c);
    c.position = c.lookAt - f.forward * (f.distance * std::exp(-amount));
    return c;
}

// Zoom: the field of view times exp(-amount), within [1, 170] degrees.
inline CameraDesc zoom(CameraDesc c, float amount) {
    c.fovDegrees = std::clamp(c.fovDegrees * std::exp(-amount), 1.0f, 170.0f);
    return c;
}

// Fly: position and lookAt move by (right, up, forward) distances in the camera's frame.
inline CameraDesc fly(CameraDesc c, Vec3 local) {
    const CameraFrame f = cameraFrame(c);
    const Vec3 move = f.right * local.x + f.up * local.y + f.forward * local.z;
    c.position = c.position + move;
    c.lookAt = c.lookAt + move;
    return c;
}

}  // namespace wmlt
