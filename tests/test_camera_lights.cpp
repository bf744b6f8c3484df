// Camera basis and ray generation; light sampling pdfs against their samplers.
#include <catch2/catch.hpp>

#include <random>

#include "kernels/camera.h"
#include "kernels/lights.h"
#include "kernels/rng.h"

using namespace wmlt;

TEST_CASE("a camera looking along +z with +y up sees +x on its left", "[camera]") {
    CameraDesc d;
    d.position = {0, 0, 0};
    d.lookAt = {0, 0, 1};
    d.up = {0, 1, 0};
    d.fovDegrees = 60;
    Camera c = makeCamera(d, 200, 100);
    float px, py;
    REQUIRE(cameraRasterOf(c, normalize(Vec3(0.2f, 0, 1)), px, py));
    CHECK(px < 100.0f);  // left half of the image
    CHECK(py == Approx(50.0f));
    REQUIRE(cameraRasterOf(c, normalize(Vec3(0, 0.2f, 1)), px, py));
    CHECK(py < 50.0f);   // +y is up: the top half (raster y points down)
    CHECK(px == Approx(100.0f));
}

TEST_CASE("FOV is the full angle across the shorter image side", "[camera]") {
    CameraDesc d;
    d.lookAt = {0, 0, 1};
    d.fovDegrees = 90;  // tan(45 deg) = 1
    for (auto [w, h] : {std::pair{300, 100}, std::pair{100, 300}}) {
        Camera c = makeCamera(d, w, h);
        Vec3 o, dir;
        // The centre of the shorter side's edge is 45 degrees off axis.
        if (w > h) generateCameraRay(c, w * 0.5f, 0.0f, 0.5f, 0.5f, o, dir);
        else generateCameraRay(c, 0.0f, h * 0.5f, 0.5f, 0.5f, o, dir);
        CHECK(dot(dir, Vec3(0, 0, 1)) == Approx(std::sqrt(0.5f)).epsilon(1e-5));
    }
}

TEST_CASE("raster position and camera ray are inverses", "[camera]") {
    CameraDesc d;
    d.position = {1, 2, 3};
    d.lookAt = {-2, 0.5f, 7};
    d.up = {0.1f, 1, 0};
    d.fovDegrees = 35;
    Camera c = makeCamera(d, 64, 48);
    for (float x : {0.5f, 10.25f, 63.5f})
        for (float y : {0.5f, 20.75f, 47.5f}) {
            Vec3 o, dir;
            generateCameraRay(c, x, y, 0.5f, 0.5f, o, dir);
            float px, py;
            REQUIRE(cameraRasterOf(c, dir, px, py));
            CHECK(px == Approx(x).margin(1e-3));
            CHECK(py == Approx(y).margin(1e-3));
        }
}

TEST_CASE("thin-lens rays through one pixel meet on the plane of focus", "[camera]") {
    CameraDesc d;
    d.lookAt = {0, 0, 1};
    d.fovDegrees = 40;
    d.dof = true;
    d.focalLength = 5;
    d.fStop = 2;
    Camera c = makeCamera(d, 32, 32);
    CHECK(c.lensRadius == Approx(1.25f));
    Vec3 o0, d0;
    generateCameraRay(c, 7.3f, 20.1f, 0.5f, 0.5f, o0, d0);
    Vec3 f0 = o0 + d0 * (5.0f / d0.z);
    for (float u : {0.1f, 0.9f}) {
        Vec3 o, dir;
        generateCameraRay(c, 7.3f, 20.1f, u, 1.0f - u, o, dir);
        CHECK(o.z == Approx(0.0f).margin(1e-6));
        Vec3 f = o + dir * (5.0f / dir.z);
        CHECK(f.x == Approx(f0.x).margin(1e-4));
        CHECK(f.y == Approx(f0.y).margin(1e-4));
    }
}

namespace {

// Integrates the light's solid-angle pdf over the sphere of directions around ref by
// Monte Carlo with uniform directions; returns mean and standard error.
template <class PdfOfDirection>
std::pair<double, double> integrateOverSphere(PdfOfDirection pdfOf, int n) {
    double sum = 0, sum2 = 0;
    for (int i = 0; i < n; ++i) {
        Vec3 w = sampleUniformSphere(sampleDimension(7, 2 * i), sampleDimension(7, 2 * i + 1));
        double v = pdfOf(w) / kUniformSpherePdf;
        sum += v;
        sum2 += v * v;
    }
    double mean = sum / n, var = sum2 / n - mean * mean;
    return {mean, std::sqrt(var / n)};
}

}  // namespace

TEST_CASE("rect light: sample pdf equals rectLightPdf and integrates to 1", "[lights]") {
    Light l;
    l.type = LightType::Rect;
    l.L = Vec3(1.0f);
    l.corner = {-0.5f, 2, -0.25f};
    l.e1 = {1, 0, 0};
    l.e2 = {0, 0, 0.5f};
    l.n = {0, -1, 0};
    l.area = 0.5f;
    Vec3 ref(0.3f, 0, 0.1f);
    for (int i = 0; i < 100; ++i) {
        LightSample s;
        REQUIRE(sampleRectLight(l, ref, sampleDimension(3, 2 * i), sampleDimension(3, 2 * i + 1), s));
        CHECK(s.pdf == Approx(rectLightPdf(l, ref, s.p)).epsilon(1e-4));
    }
    // Integral of the pdf over directions that hit the rectangle = 1.
    auto pdfOf = [&](Vec3 w) -> double {
        float t = (2.0f - ref.y) / w.y;
        if (!(t > 0)) return 0.0;
        Vec3 p = ref + w * t;
        float s = p.x - l.corner.x, u = (p.z - l.corner.z) / 0.5f;
        if (s < 0 || s > 1 || u < 0 || u > 1) return 0.0;
        return rectLightPdf(l, ref, p);
    };
    auto [mean, se] = integrateOverSphere(pdfOf, 400000);
    CHECK(std::fabs(mean - 1.0) < 5 * se);
    // The back of a one-sided light cannot be sampled.
    LightSample s;
    CHECK_FALSE(sampleRectLight(l, Vec3(0, 3, 0), 0.5f, 0.5f, s));
}

TEST_CASE("sphere light: cone sampling lands on the sphere, pdf uniform over the cone", "[lights]") {
    Light l;
    l.type = LightType::Sphere;
    l.center = {1, 2, 3};
    l.radius = 0.7f;
    l.L = Vec3(2.0f);
    l.area = 4 * kPi * l.radius * l.radius;
    Vec3 ref(0, 0, 0);
    for (int i = 0; i < 200; ++i) {
        LightSample s;
        REQUIRE(sampleSphereLight(l, ref, sampleDimension(5, 2 * i), sampleDimension(5, 2 * i + 1), s));
        CHECK(length(s.p - l.center) == Approx(l.radius).epsilon(1e-3));
        CHECK(dot(s.p - l.center, -s.wi) > -1e-3f);  // the near, emitting side
        CHECK(s.pdf == Approx(sphereLightPdf(l, ref)));
    }
    // The pdf integrates to 1 over the directions that hit the sphere.
    Vec3 toC = l.center - ref;
    float sin2 = l.radius * l.radius / lengthSquared(toC);
    float cosMax = std::sqrt(1 - sin2);
    auto pdfOf = [&](Vec3 w) -> double {
        return dot(w, normalize(toC)) >= cosMax ? sphereLightPdf(l, ref) : 0.0;
    };
    auto [mean, se] = integrateOverSphere(pdfOf, 400000);
    CHECK(std::fabs(mean - 1.0) < 5 * se);
    // Inside the sphere nothing is emitted towards ref.
    LightSample s;
    CHECK_FALSE(sampleSphereLight(l, l.center, 0.3f, 0.3f, s));
}

TEST_CASE("counter-based random numbers lie in the unit interval and are uncorrelated across keys", "[rng]") {
    double sum = 0;
    const int n = 100000;
    for (int i = 0; i < n; ++i) {
        float u = sampleDimension(sampleKey(1, uint32_t(i), 0), 3);
        REQUIRE(u >= 0.0f);
        REQUIRE(u < 1.0f);
        sum += u;
    }
    // Mean of n uniforms: standard error 1 / sqrt(12 n).
    CHECK(std::fabs(sum / n - 0.5) < 5.0 / std::sqrt(12.0 * n));
    CHECK(sampleKey(1, 2, 3) != sampleKey(1, 3, 2));
    CHECK(sampleKey(1, 2, 3) != sampleKey(2, 2, 3));
}
