// The interactive mode's camera motions (src/app/camera_control.h, issue 28): each keeps
// what its gesture must not change, and undoes itself when the gesture is reversed.
#include <catch2/catch.hpp>

#include <cmath>

#include "app/camera_control.h"

using namespace wmlt;

namespace {

CameraDesc someCamera() {
    CameraDesc c;
    c.position = Vec3(1.0f, 2.0f, -4.0f);
    c.lookAt = Vec3(0.5f, 0.8f, 0.3f);
    c.up = Vec3(0.0f, 1.0f, 0.0f);
    c.fovDegrees = 40;
    return c;
}

float distanceOf(const CameraDesc& c) { return length(c.lookAt - c.position); }
Vec3 directionOf(const CameraDesc& c) { return normalize(c.lookAt - c.position); }
bool near(Vec3 a, Vec3 b, float eps) { return length(a - b) <= eps; }

}  // namespace

TEST_CASE("camera control: orbit keeps the point looked at and its distance, and undoes itself", "[camera-control]") {
    const CameraDesc c = someCamera();
    const CameraDesc o = orbit(c, 0.7f, 0.3f);
    CHECK(near(o.lookAt, c.lookAt, 0.0f));
    CHECK(distanceOf(o) == Approx(distanceOf(c)).epsilon(1e-5));
    CHECK(!near(o.position, c.position, 0.1f));
    CHECK(near(orbit(orbit(o, 0.0f, -0.3f), -0.7f, 0.0f).position, c.position, 1e-4f));
    // a full turn of yaw comes back
    CHECK(near(orbit(c, 2.0f * kPi, 0.0f).position, c.position, 1e-4f));
    // pitching far past the pole stops a degree short of it: the view never runs along up
    const CameraDesc top = orbit(c, 0.0f, 10.0f);
    const float cosToUp = dot(normalize(top.position - top.lookAt), normalize(top.up));
    CHECK(cosToUp == Approx(std::cos(kPi / 180.0f)).epsilon(1e-4));
    CHECK(distanceOf(top) == Approx(distanceOf(c)).epsilon(1e-5));
}

TEST_CASE("camera control: pan, dolly, zoom and fly keep what they must", "[camera-control]") {
    const CameraDesc c = someCamera();
    const CameraDesc p = pan(c, 0.25f, -0.1f);
    CHECK(near(directionOf(p), directionOf(c), 1e-5f));
    CHECK(distanceOf(p) == Approx(distanceOf(c)).epsilon(1e-5));
    // a quarter of the image height to the right: lookAt moves by a quarter of the view's height there
    const float extent = 2.0f * distanceOf(c) * std::tan(0.5f * 40.0f * kPi / 180.0f);
    CHECK(length(p.lookAt - c.lookAt) == Approx(extent * std::sqrt(0.25f * 0.25f + 0.1f * 0.1f)).epsilon(1e-4));
    CHECK(near(pan(p, -0.25f, 0.1f).position, c.position, 1e-4f));

    const CameraDesc d = dolly(c, 0.5f);
    CHECK(near(d.lookAt, c.lookAt, 0.0f));
    CHECK(near(directionOf(d), directionOf(c), 1e-5f));
    CHECK(distanceOf(d) == Approx(distanceOf(c) * std::exp(-0.5f)).epsilon(1e-5));
    CHECK(near(dolly(d, -0.5f).position, c.position, 1e-4f));

    CHECK(zoom(c, std::log(2.0f)).fovDegrees == Approx(20.0f));
    CHECK(zoom(c, -100.0f).fovDegrees == 170.0f);
    CHECK(zoom(c, 100.0f).fovDegrees == 1.0f);
    CHECK(near(zoom(c, 1.0f).position, c.position, 0.0f));

    const CameraDesc f = fly(c, Vec3(0.5f, 0.0f, 1.0f));
    CHECK(near(directionOf(f), directionOf(c), 1e-5f));
    CHECK(dot(f.position - c.position, directionOf(c)) == Approx(1.0f).epsilon(1e-5));
    CHECK(near(fly(f, Vec3(-0.5f, 0.0f, -1.0f)).position, c.position, 1e-4f));
}

TEST_CASE("camera control: recentre keeps the image and puts LookAt at the distance asked", "[camera-control]") {
    // A Mitsuba camera: LookAt one unit ahead of the eye (Bitterli's Cornell box).
    CameraDesc c;
    c.position = Vec3(0.0f, 1.0f, 6.8f);
    c.lookAt = Vec3(0.0f, 1.0f, 5.8f);
    c.up = Vec3(0.0f, 1.0f, 0.0f);
    const CameraDesc r = recentre(c, 7.8f);
    CHECK(near(r.position, c.position, 0.0f));
    CHECK(near(r.up, c.up, 0.0f));
    CHECK(near(directionOf(r), directionOf(c), 1e-6f));
    CHECK(distanceOf(r) == Approx(7.8f).epsilon(1e-6));
    CHECK(near(r.lookAt, Vec3(0.0f, 1.0f, -1.0f), 1e-5f));  // the back wall's centre
    // The same for any camera, nearer or farther than its LookAt.
    const CameraDesc s = someCamera();
    for (float d : {0.25f, 3.0f, 40.0f}) {
        const CameraDesc t = recentre(s, d);
        CHECK(near(t.position, s.position, 0.0f));
        CHECK(near(directionOf(t), directionOf(s), 1e-5f));
        CHECK(distanceOf(t) == Approx(d).epsilon(1e-5));
    }
    // The orbit then turns about the recentred point: the eye stays 7.8 from the back wall
    // (about the file's LookAt it would stay 1 unit from a point in front of the box).
    const CameraDesc o = orbit(r, 20.0f * kPi / 180.0f, 0.0f);
    CHECK(near(o.lookAt, r.lookAt, 0.0f));
    CHECK(length(o.position - Vec3(0.0f, 1.0f, -1.0f)) == Approx(7.8f).epsilon(1e-5));
    CHECK(std::acos(dot(directionOf(o), directionOf(r))) == Approx(20.0f * kPi / 180.0f).epsilon(1e-4));
}
