// The light tracer (t = 1) against the path tracer and closed forms, with tolerances from
// the measured variance over K independent seeds (render_stats.h), never hand-tuned:
//  1. camera importance: reciprocity with ray generation, and its normalisation
//     (int We cos over the image = 1 / (W H) per pixel, summed: 1) by Monte Carlo;
//  2. emission sampling: samples where the pdfs say, integrals from pdfs;
//  3. LT image = PT image (8 x 8 block means, se of both tracers' runs) on the Cornell
//     box, a glossy floor with a glass sphere (caustic), a thin lens, an environment map;
//  4. the plane under a sphere light (test_render_analytic.cpp) at length 2 via LT;
//  5. bit-identical images for 1 and 2 threads; cancel before the first pass.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "kernels/camera.h"
#include "kernels/rng.h"
#include "render_stats.h"
#include "scene/scene_lights.h"
#include "wavemmlt/image.h"
#include "wavemmlt/render.h"
#include "wavemmlt/scene_desc.h"

using namespace wmlt;

namespace {

// Mean and standard error of f over n samples, and |mean - expected| / se as N(0, 1) z.
struct McMean {
    double sum = 0, sumSq = 0;
    long n = 0;
    void add(double x) {
        sum += x;
        sumSq += x * x;
        ++n;
    }
    double mean() const { return sum / n; }
    double se() const { return std::sqrt(std::max(0.0, sumSq / n - mean() * mean()) / (n - 1)); }
    double z(double expected) const { return (mean() - expected) / se(); }
};
// Bonferroni bound at p = 1e-4 over the few MC checks of this file.
const double kMcBound = -rstats::normalQuantile(1e-4 / (2 * 16));

// LT against PT: K runs of each, per channel the 8 x 8 block means; z from the difference
// of the means with se^2 = se_LT^2 + se_PT^2 and Welch-Satterthwaite degrees of freedom.
void compareWithPt(const SceneDesc& desc, int spp, int K, int minLength, int maxLength, uint64_t seed0) {
    const int B = 8;
    rstats::RunStats pt[3], lt[3];
    for (int k = 0; k < K; ++k) {
        RenderResult a = render(desc, rstats::renderOptions(TracerKind::PT, spp, seed0 + k, minLength, maxLength));
        RenderResult b = render(desc, rstats::renderOptions(TracerKind::LT, spp, seed0 + 500 + k, minLength, maxLength));
        REQUIRE(b.stats.tracer == "lt");
        REQUIRE(b.stats.spp == uint64_t(spp));
        REQUIRE(b.stats.samplesNonfiniteDiscarded == 0);
        for (int c = 0; c < 3; ++c) {
            pt[c].add(rstats::blockMeans(a.image, B, c));
            lt[c].add(rstats::blockMeans(b.image, B, c));
        }
    }
    for (int c = 0; c < 3; ++c) {
        double ratio = 0;
        rstats::ZTestResult z = rstats::compareRuns(lt[c], pt[c], 1e-4 / 3, &ratio);
        INFO("channel " << c << ": LT / PT image mean = " << ratio << "; " << z.describe());
        CHECK(z.pass);
    }
}

// A glass ball above a glossy floor, lit from above: the camera sees the floor with the
// ball's caustic and its glossy reflection, but not the ball itself, which is above the
// view: t = 1 cannot sample paths whose vertex next to the camera is specular (Veach
// 1997, 10.2: the camera would have to be hit by chance), so such pixels stay black in LT.
const std::string kCausticXml = R"(<Scene>
  <Settings><Width value="64"/><Height value="64"/><MaxPathLength value="6"/></Settings>
  <Camera Type="Camera"><Position x="0" y="0.5" z="-2.5"/><LookAt x="-0.4" y="0" z="-0.3"/><FOV value="30"/></Camera>
  <Shader Type="Glossy" ID="0"><Diffuse r="0.4" g="0.35" b="0.3"/><Specular r="0.4" g="0.4" b="0.4"/>
    <Shininess value="30"/></Shader>
  <Shader Type="Dielectric" ID="1"><Reflect r="1" g="1" b="1"/><Refract r="1" g="1" b="1"/>
    <iIOR value="1.5"/><oIOR value="1"/></Shader>
  <Geometry Type="Plane" ID="floor"><Position x="0" y="0" z="0"/><Width value="6"/><Depth value="6"/><Shader value="0"/></Geometry>
  <Geometry Type="Sphere" ID="ball"><Position x="0" y="1.2" z="0"/><Radius value="0.4"/><Shader value="1"/></Geometry>
  <Light Type="Area" ID="light"><Position x="0.8" y="2.8" z="0.4"/><Radius value="0.3"/>
    <Intensity value="8"/><Colour r="1" g="0.9" b="0.8"/></Light>
</Scene>
)";

}  // namespace

// ---- 1. camera importance -------------------------------------------------------------

TEST_CASE("LT camera: sampleCameraFrom is the inverse of ray generation", "[lt][camera]") {
    for (bool lens : {false, true}) {
        CameraDesc d;
        d.position = {0.3f, 1, -2};
        d.lookAt = {0, 0.5f, 1};
        d.fovDegrees = 50;
        d.dof = lens;
        d.focalLength = 2.5f;
        d.fStop = 2;
        Camera c = makeCamera(d, 40, 30);
        std::mt19937 rng(7);
        std::uniform_real_distribution<float> U(0.0f, 1.0f);
        int valid = 0;
        for (int i = 0; i < 1000; ++i) {
            Vec3 ref(4 * U(rng) - 2, 3 * U(rng) - 1, 3 * U(rng));
            float u1 = U(rng), u2 = U(rng);
            CameraSample s = sampleCameraFrom(c, ref, u1, u2);
            if (!s.valid) continue;
            ++valid;
            Vec3 o, dir;
            generateCameraRay(c, s.px, s.py, u1, u2, o, dir);
            CHECK(length(o - s.lens) < 1e-4f);
            CHECK(dot(dir, -s.wi) > 1 - 1e-4f);
            CHECK(s.We == Approx(cameraWe(c, s.lens, -s.wi)).epsilon(1e-4));
        }
        CHECK(valid > 100);
    }
}

// W H int_lens int_dirs We cos dw dA / A_lens... = 1: each pixel's share is 1 / (W H), so
// light tracing's pixel value is the box-filtered mean (camera.h, "Importance").
TEST_CASE("LT camera: importance integrates to 1 over the image, pinhole and thin lens", "[lt][camera]") {
    for (bool lens : {false, true}) {
        CameraDesc d;
        d.lookAt = {0, 0, 1};
        d.fovDegrees = 60;
        d.dof = lens;
        d.focalLength = 3;
        d.fStop = 1.5f;
        Camera c = makeCamera(d, 32, 24);
        McMean all, pixel;
        const uint32_t target = 5 * 32 + 9;  // one pixel: W H times its integral is 1 too
        for (uint32_t i = 0; i < 400000; ++i) {
            uint64_t key = sampleKey(11 + lens, i, 0);
            // Direction uniform on the hemisphere about forward (pdf 1 / 2 pi), lens
            // point uniform (pdf 1 / A_lens).
            Vec3 w = sampleUniformSphere(sampleDimension(key, 0), sampleDimension(key, 1));
            if (dot(w, c.forward) < 0) w = -w;
            float lx, ly;
            sampleConcentricDisk(sampleDimension(key, 2), sampleDimension(key, 3), lx, ly);
            Vec3 p = c.position + (c.right * lx + c.up * ly) * c.lensRadius;
            float px = 0, py = 0, cosT = 0;
            bool in = cameraRasterOfRay(c, p, w, px, py, cosT);
            double v = in ? double(cameraWe(c, p, w)) * cosT * 2 * kPi * cameraLensArea(c) : 0.0;
            all.add(v);
            bool inPixel = in && uint32_t(py) * 32 + uint32_t(px) == target;
            pixel.add(inPixel ? v * 32 * 24 : 0.0);
        }
        INFO("lens " << lens << ": image " << all.mean() << " +- " << all.se() << ", pixel " << pixel.mean() << " +- " << pixel.se());
        CHECK(std::fabs(all.z(1.0)) < kMcBound);
        CHECK(std::fabs(pixel.z(1.0)) < kMcBound);
    }
}

// ---- 2. emission sampling -------------------------------------------------------------

// Rect and sphere: points on the surface, directions on the normal's side, and the pdfs
// reproduce known integrals: E[cos^2 / pdfDir] = int cos^2 dw = 2 pi / 3 and
// E[g(p) / pdfPos] = int g dA for g = (distance from the centre)^2-like test functions.
TEST_CASE("LT emission: rect and sphere points and directions match their pdfs", "[lt][lights]") {
    Light rect;
    rect.type = LightType::Rect;
    rect.corner = {-1, 2, -0.5f};
    rect.e1 = {2, 0, 0};
    rect.e2 = {0, 0, 1};
    rect.n = {0, -1, 0};
    rect.area = 2;
    rect.L = Vec3(1.0f);
    Light sph;
    sph.type = LightType::Sphere;
    sph.center = {1, 2, 3};
    sph.radius = 0.5f;
    sph.area = 4 * kPi * 0.25f;
    sph.L = Vec3(1.0f);
    for (const Light* l : {&rect, &sph}) {
        McMean dirInt, posInt;
        for (uint32_t i = 0; i < 200000; ++i) {
            uint64_t key = sampleKey(3, i, 0);
            LightEmission e;
            bool ok =
                l->type == LightType::Rect
                    ? sampleRectEmission(*l, sampleDimension(key, 0), sampleDimension(key, 1), sampleDimension(key, 2), sampleDimension(key, 3), e)
                    : sampleSphereEmission(*l, sampleDimension(key, 0), sampleDimension(key, 1), sampleDimension(key, 2), sampleDimension(key, 3), e);
            if (!ok) {
                dirInt.add(0);
                posInt.add(0);
                continue;
            }
            float c = dot(e.dir, e.n);
            REQUIRE(c >= 0);
            REQUIRE(e.pdfDir == Approx(c / kPi).margin(1e-6));
            REQUIRE(e.pdfPos == Approx(1.0f / l->area));
            dirInt.add(double(c) * c / e.pdfDir);
            // g = x^2 relative to the centre: rect int x^2 dA = 2/3 (x in [-1, 1], depth 1);
            // sphere: r^2 / 3 * 4 pi r^2.
            Vec3 centre = l->type == LightType::Rect ? Vec3(0, 2, 0) : l->center;
            if (l->type == LightType::Sphere) REQUIRE(length(e.p - l->center) == Approx(l->radius).epsilon(1e-5));
            double x = e.p.x - centre.x;
            posInt.add(x * x / e.pdfPos);
        }
        double posExpected = l->type == LightType::Rect ? 2.0 / 3.0 : 0.25 / 3 * l->area;
        INFO("type " << int(l->type) << ": dir " << dirInt.mean() << " pos " << posInt.mean() << " expected " << posExpected);
        CHECK(std::fabs(dirInt.z(2 * kPi / 3)) < kMcBound);
        CHECK(std::fabs(posInt.z(posExpected)) < kMcBound);
    }
}

// Environment: a sky of radiance 1 above the horizon and 3 below; the origin lies on the
// disc of radius R perpendicular to the direction, outside the bounding sphere; and
// E[Le / pdfDir] = int Le dw = 8 pi, E[[in the inner half radius] / pdfPos] = pi R^2 / 4.
TEST_CASE("LT emission: environment map directions and the disc", "[lt][lights]") {
    std::string dir = rstats::tempDir("ltenv");
    Image sky(8, 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x) sky.set(x, y, Vec3(y < 2 ? 1.0f : 3.0f));
    writeImage(dir + "/sky.pfm", sky);
    const std::string xml = R"(<Scene><Settings><Width value="8"/><Height value="8"/><EnvMap name="sky.pfm"/></Settings>
  <Camera Type="Camera"><Position x="0" y="0" z="-4"/><LookAt x="0" y="0" z="0"/><FOV value="40"/></Camera>
  <Shader Type="Matte" ID="0"><Diffuse r="0.5" g="0.5" b="0.5"/></Shader>
  <Geometry Type="Sphere" ID="ball"><Position x="1" y="0" z="0"/><Radius value="1"/><Shader value="0"/></Geometry>
</Scene>)";
    std::unique_ptr<Scene> s = Scene::build(loadSceneFromString(xml, "env.xml", dir), 1);
    std::filesystem::remove_all(dir);
    REQUIRE(s->envLight >= 0);
    const float R = s->radius;
    McMean le, inner;
    for (uint32_t i = 0; i < 200000; ++i) {
        uint64_t key = sampleKey(5, i, 0);
        LightEmission e;
        if (!sampleLightEmission(*s, s->envLight, sampleDimension(key, 0), sampleDimension(key, 1), sampleDimension(key, 2), sampleDimension(key, 3),
                                 e)) {
            le.add(0);
            inner.add(0);
            continue;
        }
        Vec3 d = -e.dir, rel = e.p - s->center;
        REQUIRE(dot(rel, d) == Approx(R).epsilon(1e-4));            // on the tangent plane
        REQUIRE(length(rel - d * dot(rel, d)) <= R * (1 + 1e-5f));  // within the disc
        REQUIRE(e.pdfPos == Approx(1.0f / (kPi * R * R)));
        // float: the map coordinates of d are recomputed by atan2, so allow 1e-2 relative.
        REQUIRE(e.pdfDir == Approx(s->env.pdf(d)).epsilon(1e-2));
        le.add(e.Le.y / e.pdfDir);
        inner.add(length(rel - d * dot(rel, d)) < 0.5f * R ? 1.0 / e.pdfPos : 0.0);
    }
    INFO("int Le " << le.mean() << " +- " << le.se() << ", inner disc " << inner.mean());
    CHECK(std::fabs(le.mean() - 8 * kPi) < std::max(kMcBound * le.se(), 1e-3 * 8 * kPi));
    CHECK(std::fabs(inner.z(kPi * R * R / 4)) < kMcBound);
}

// ---- 3. LT against PT -----------------------------------------------------------------

TEST_CASE("LT = PT: Cornell box at 64 x 64, lengths 1..5", "[lt][render]") { compareWithPt(rstats::cornell64(5), 64, 8, 1, 5, 100); }

TEST_CASE("LT = PT: glossy floor and a glass sphere (caustic)", "[lt][render]") {
    compareWithPt(loadSceneFromString(kCausticXml, "caustic.xml", "."), 64, 10, 1, 6, 200);
}

TEST_CASE("LT = PT: thin-lens camera (DOF 1) in the Cornell box", "[lt][render]") {
    SceneDesc d = rstats::cornell64(4);
    d.camera.dof = true;
    d.camera.focalLength = 5.0f;
    d.camera.fStop = 4.0f;  // aperture radius 0.625: strong blur away from the focus plane
    compareWithPt(d, 64, 8, 1, 4, 300);
}

TEST_CASE("LT = PT: environment map over a sphere on a plane", "[lt][render]") {
    std::string dir = rstats::tempDir("ltsky");
    writeImage(dir + "/sky.pfm", rstats::skyWithSun());
    const std::string xml = R"(<Scene>
  <Settings><Width value="64"/><Height value="48"/><MaxPathLength value="4"/><EnvMap name="sky.pfm"/></Settings>
  <Camera Type="Camera"><Position x="0" y="1.2" z="-4"/><LookAt x="0" y="0.5" z="0"/><FOV value="45"/></Camera>
  <Shader Type="Matte" ID="0"><Diffuse r="0.7" g="0.6" b="0.5"/></Shader>
  <Shader Type="Matte" ID="1"><Diffuse r="0.3" g="0.5" b="0.7"/></Shader>
  <Geometry Type="Plane" ID="floor"><Position x="0" y="0" z="0"/><Width value="4"/><Depth value="4"/><Shader value="0"/></Geometry>
  <Geometry Type="Sphere" ID="ball"><Position x="0" y="0.7" z="0"/><Radius value="0.7"/><Shader value="1"/></Geometry>
</Scene>
)";
    SceneDesc desc = loadSceneFromString(xml, "sky.xml", dir);
    compareWithPt(desc, 64, 8, 1, 4, 400);
    std::filesystem::remove_all(dir);
}

// ---- 4. closed form: plane under a sphere light, length 2 -------------------------------
// As test_render_analytic.cpp: plane radiance rho L (r / d)^2 cos(theta), box-filtered by
// 16 x 16 midpoint quadrature through the camera model.

TEST_CASE("LT: plane under a sphere light, length 2, per-pixel closed form", "[lt][render][analytic]") {
    const int W = 48, H = 32;
    const double rho[3] = {0.8, 0.6, 0.4}, Le[3] = {4.0, 2.0, 1.0}, C[3] = {0.6, 3.0, -0.3}, r = 0.5;
    const std::string xml = R"(<Scene>
  <Settings><Width value="48"/><Height value="32"/></Settings>
  <Camera Type="Camera"><Position x="0" y="2" z="0"/><LookAt x="0" y="0" z="0"/>
    <Up x="0" y="0" z="1"/><FOV value="60"/></Camera>
  <Shader Type="Matte" ID="0"><Diffuse r="0.8" g="0.6" b="0.4"/></Shader>
  <Geometry Type="Plane" ID="floor"><Position x="0" y="0" z="0"/><Width value="10"/>
    <Depth value="10"/><Shader value="0"/></Geometry>
  <Light Type="Area" ID="light"><Position x="0.6" y="3" z="-0.3"/><Radius value="0.5"/>
    <Intensity value="4"/><Colour r="1" g="0.5" b="0.25"/></Light>
</Scene>
)";
    const SceneDesc desc = loadSceneFromString(xml, "plane.xml", ".");
    Camera cam = makeCamera(desc.camera, W, H);
    const int q = 16, K = 16, spp = 64;
    rstats::RunStats runs[3];
    for (int k = 0; k < K; ++k) {
        RenderResult res = render(desc, rstats::renderOptions(TracerKind::LT, spp, 600 + k, 2, 2));
        REQUIRE(res.stats.samplesNonfiniteDiscarded == 0);
        for (int c = 0; c < 3; ++c) runs[c].add(rstats::channel(res.image, c));
    }
    for (int c = 0; c < 3; ++c) {
        std::vector<double> e(size_t(W) * H, 0.0);
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                double sum = 0;
                for (int j = 0; j < q; ++j)
                    for (int i = 0; i < q; ++i) {
                        Vec3 o, d;
                        generateCameraRay(cam, x + (i + 0.5f) / q, y + (j + 0.5f) / q, 0.5f, 0.5f, o, d);
                        double t = -double(o.y) / d.y, px = o.x + t * d.x, pz = o.z + t * d.z;
                        double dx = C[0] - px, dy = C[1], dz = C[2] - pz, d2 = dx * dx + dy * dy + dz * dz;
                        sum += rho[c] * Le[c] * r * r / d2 * (dy / std::sqrt(d2));
                    }
                e[size_t(y) * W + x] = sum / (q * q);
            }
        rstats::ZTestResult z = rstats::zTest(runs[c], e, 1e-4 / 3);
        INFO("channel " << c << ": " << z.describe());
        CHECK(z.pass);
    }
}

// ---- 5. determinism and cancel -----------------------------------------------------------

TEST_CASE("LT: the image is bit-identical for 1 and 2 threads", "[lt][render]") {
    const SceneDesc desc = loadSceneFromString(kCausticXml, "caustic.xml", ".");
    RenderResult a = render(desc, rstats::renderOptions(TracerKind::LT, 16, 42, 1, 6, 1));
    RenderResult b = render(desc, rstats::renderOptions(TracerKind::LT, 16, 42, 1, 6, 2));
    REQUIRE(a.image.rgb.size() == b.image.rgb.size());
    CHECK(a.image.rgb == b.image.rgb);
    CHECK(a.stats.raysIntersect == b.stats.raysIntersect);
    CHECK(a.stats.raysOccluded == b.stats.raysOccluded);
    CHECK(a.stats.raysIntersect > 0);
    RenderResult c = render(desc, rstats::renderOptions(TracerKind::LT, 16, 43, 1, 6, 2));
    CHECK(a.image.rgb != c.image.rgb);  // the seed matters
}

TEST_CASE("LT: cancelled before the first pass gives a black image and spp 0", "[lt][render]") {
    std::atomic<bool> cancel{true};
    RenderOptions o = rstats::renderOptions(TracerKind::LT, 16, 1, 1, 6);
    o.cancel = &cancel;
    RenderResult r = render(loadSceneFromString(kCausticXml, "caustic.xml", "."), o);
    CHECK(r.stats.cancelled);
    CHECK(r.stats.spp == 0);
    for (float v : r.image.rgb) CHECK(v == 0.0f);
}
