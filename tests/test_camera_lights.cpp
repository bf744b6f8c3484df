// Camera basis and ray generation; light sampling pdfs against their samplers.
#include <catch2/catch.hpp>

#include <cstring>
#include <random>
#include <vector>

#include "chi2.h"
#include "kernels/bsdf.h"
#include "kernels/camera.h"
#include "kernels/lights.h"
#include "kernels/nee.h"
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
    CHECK(py < 50.0f);  // +y is up: the top half (raster y points down)
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

// A camera looking obliquely, its up vector not orthogonal to the view.
static CameraDesc tiltedCamera(float fovDegrees) {
    CameraDesc d;
    d.position = {1, 2, 3};
    d.lookAt = {-2, 0.5f, 7};
    d.up = {0.1f, 1, 0};
    d.fovDegrees = fovDegrees;
    return d;
}

TEST_CASE("raster position and camera ray are inverses", "[camera]") {
    Camera c = makeCamera(tiltedCamera(35), 64, 48);
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

// The camera rays' flat loop (pinholeCameraDirections, forEachCameraRay) must give the
// plainly written pinhole ray's direction bit for bit (a refactor may change no image):
// the stratified raster point, then forward + right sx + up sy normalised, in Vec3.
TEST_CASE("camera rays: pinholeCameraDirections equals the Vec3 form bit for bit", "[camera]") {
    const Camera c = makeCamera(tiltedCamera(35), 67, 45);
    const int n = 5;        // strata per axis: 25 per round, not a power of four (cycle walking)
    const size_t m = 4099;  // not a multiple of any vector width
    std::vector<uint64_t> key(m);
    std::vector<float> x(m), y(m), sx(m), sy(m), dir(3 * m);
    const uint32_t dimX = 2, dimY = 3;
    for (size_t i = 0; i < m; ++i) {
        const uint32_t pixel = uint32_t(i * 7919 % (67 * 45)), s = uint32_t(i % 37);
        key[i] = sampleKey(11, pixel, s);
        x[i] = float(pixel % 67);
        y[i] = float(pixel / 67);
        const uint32_t stratum = permuteIndex(s % 25, 25, mix64(strataKey(11, pixel) + s / 25));
        sx[i] = float(stratum % 5);
        sy[i] = float(stratum / 5);
    }
    pinholeCameraDirections(cameraFloats(c), key.data(), x.data(), y.data(), sx.data(), sy.data(), m, float(n), dimX, dimY, dir.data());
    auto same = [](float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; };
    size_t differ = 0;
    for (size_t i = 0; i < m; ++i) {
        const uint32_t pixel = uint32_t(i * 7919 % (67 * 45)), s = uint32_t(i % 37);
        float px, py;
        stratifiedRasterPoint(int(pixel % 67), int(pixel / 67), s, n, strataKey(11, pixel), sampleDimension(key[i], dimX),
                              sampleDimension(key[i], dimY), px, py);
        const float rx = (2.0f * px / float(c.width) - 1.0f) * c.scaleX;
        const float ry = (1.0f - 2.0f * py / float(c.height)) * c.scaleY;
        const Vec3 w = c.forward + c.right * rx + c.up * ry;
        const Vec3 ref = w / std::sqrt(dot(w, w));
        Vec3 o, g;
        generateCameraRay(c, px, py, 0.5f, 0.5f, o, g);
        for (int a = 0; a < 3; ++a)
            if (!same(ref[a], dir[3 * i + a]) || !same(ref[a], g[a])) ++differ;
    }
    CHECK(differ == 0);
}

// sampleCameraFrom as it was written before its float form (cameraSampleAt), in Vec3: the
// reference the float forms must equal bit for bit.
static CameraSample sampleCameraFromVec3(const Camera& c, Vec3 ref, float u1, float u2) {
    CameraSample s;
    s.lens = cameraLensPoint(c, u1, u2);
    Vec3 d = s.lens - ref;
    float dist2 = lengthSquared(d);
    if (!(dist2 > 0)) return s;
    s.dist = std::sqrt(dist2);
    s.wi = d / s.dist;
    float cosTheta;
    if (!cameraRasterOfRay(c, s.lens, -s.wi, s.px, s.py, cosTheta)) return s;
    float cos2 = cosTheta * cosTheta;
    s.We = 1.0f / (cameraPlaneArea(c) * cameraLensArea(c) * cos2 * cos2);
    s.pdf = dist2 / (cosTheta * cameraLensArea(c));
    s.valid = std::isfinite(s.pdf) && s.pdf > 0;
    return s;
}

// The t = 1 strategies' camera samples: sampleCameraFrom (pinhole and thin lens) and the
// pinhole's flat loop (pinholeCameraSamples, with the reverse area density the MIS weight
// reads) equal the Vec3 form bit for bit, points behind the camera and outside the image
// included.
TEST_CASE("camera samples: sampleCameraFrom and pinholeCameraSamples equal the Vec3 form bit for bit", "[camera]") {
    CameraDesc d = tiltedCamera(50);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u01(0.0f, 1.0f), pos(-8.0f, 12.0f), sgn(-1.0f, 1.0f);
    auto same = [](float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; };
    for (bool lens : {false, true}) {
        d.dof = lens;
        d.focalLength = 4.5f;
        d.fStop = 2.0f;
        const Camera c = makeCamera(d, 61, 47);
        const size_t n = 3001;
        std::vector<float> ref(3 * n), refN(3 * n), wi(3 * n), px(n), py(n), We(n), pdf(n), pdfArea(n);
        std::vector<uint32_t> valid(n);
        for (size_t h = 0; h < n; ++h) {
            const Vec3 N = normalize(Vec3(sgn(rng), sgn(rng), sgn(rng)) + Vec3(0.0f, 0.0f, 0.01f));
            // half in front of the camera (most of them seen), half anywhere
            const float z = 0.5f + 10.0f * u01(rng);
            const Vec3 R =
                h % 2 ? c.position + c.forward * z + c.right * (1.2f * z * sgn(rng)) + c.up * (z * sgn(rng)) : Vec3(pos(rng), pos(rng), pos(rng));
            for (int a = 0; a < 3; ++a) {
                ref[3 * h + a] = R[a];
                refN[3 * h + a] = N[a];
            }
        }
        ref[0] = c.position.x;  // at the lens
        ref[1] = c.position.y;
        ref[2] = c.position.z;
        if (!lens)
            pinholeCameraSamples(cameraFloats(c), n, ref.data(), refN.data(), wi.data(), px.data(), py.data(), We.data(), pdf.data(), pdfArea.data(),
                                 valid.data());
        size_t differ = 0, seen = 0, unseen = 0;
        for (size_t h = 0; h < n; ++h) {
            const Vec3 r(ref[3 * h], ref[3 * h + 1], ref[3 * h + 2]), N(refN[3 * h], refN[3 * h + 1], refN[3 * h + 2]);
            const float u1 = u01(rng), u2 = u01(rng);
            const CameraSample a = sampleCameraFromVec3(c, r, u1, u2), b = sampleCameraFrom(c, r, u1, u2);
            if (a.valid != b.valid || (!lens && a.valid != (valid[h] != 0))) {
                ++differ;
                continue;
            }
            if (!a.valid) {
                ++unseen;
                continue;
            }
            ++seen;
            const float fa[] = {a.lens.x, a.lens.y, a.lens.z, a.wi.x, a.wi.y, a.wi.z, a.dist, a.px, a.py, a.We, a.pdf};
            const float fb[] = {b.lens.x, b.lens.y, b.lens.z, b.wi.x, b.wi.y, b.wi.z, b.dist, b.px, b.py, b.We, b.pdf};
            for (int k = 0; k < 11; ++k)
                if (!same(fa[k], fb[k])) ++differ;
            if (lens) continue;
            const float fl[] = {c.position.x, c.position.y, c.position.z, wi[3 * h], wi[3 * h + 1], wi[3 * h + 2],
                                a.dist,       px[h],        py[h],        We[h],     pdf[h]};
            for (int k = 0; k < 11; ++k)
                if (k != 6 && !same(fa[k], fl[k])) ++differ;
            // The reverse density: cameraPdfOfRay(-wi) (1 / (A cos^3)) as area density at ref.
            const Vec3 w = -a.wi;
            const float cosTheta = dot(w, c.forward);
            const float pdfSa = 1.0f / (cameraPlaneArea(c) * cosTheta * cosTheta * cosTheta);
            if (!same(solidAngleToArea(pdfSa, a.lens, r, N, true), pdfArea[h])) ++differ;
        }
        INFO("thin lens " << lens);
        CHECK(seen > n / 10);
        CHECK(unseen > n / 10);
        CHECK(differ == 0);
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

// A 1 x 0.5 rectangle light at y = 2 facing down.
Light testRectLight() {
    Light l;
    l.type = LightType::Rect;
    l.L = Vec3(1.0f);
    l.corner = {-0.5f, 2, -0.25f};
    l.e1 = {1, 0, 0};
    l.e2 = {0, 0, 0.5f};
    l.n = {0, -1, 0};
    l.area = 0.5f;
    return l;
}

// sampleRectLight and sampleRectEmission as first written, in Vec3 arithmetic: the
// references for the float forms the samplers and their flat loops now share.
bool rectLightVec3(const Light& l, Vec3 ref, float u1, float u2, LightSample& s) {
    s.p = l.corner + l.e1 * u1 + l.e2 * u2;
    Vec3 d = s.p - ref;
    float dist2 = lengthSquared(d);
    if (!(dist2 > 0)) return false;
    s.dist = std::sqrt(dist2);
    s.wi = d / s.dist;
    float cosL = -dot(s.wi, l.n);
    if (cosL <= 0) return false;
    s.pdf = dist2 / (cosL * l.area);
    return std::isfinite(s.pdf);
}
bool rectEmissionVec3(const Light& l, float u1, float u2, float u3, float u4, LightEmission& e) {
    e.p = l.corner + l.e1 * u1 + l.e2 * u2;
    Vec3 w = sampleCosineHemisphere(u3, u4);
    e.dir = normalize(Frame::fromNormal(l.n).toWorld(w));
    e.pdfDir = cosineHemispherePdf(w.z);
    return e.pdfDir > 0;
}

}  // namespace

// The path tracer's flat loop for a scene's one rectangle light, and sampleRectLight, must
// give the Vec3 form's samples bit for bit (a refactor may change no image), including the
// reference points behind the light (no sample) and on its plane, for a tilted light with
// uneven edges.
TEST_CASE("rect light: rectLightSamples(Of) and sampleRectLight equal the Vec3 form bit for bit", "[lights]") {
    Light l = testRectLight();
    l.corner = {-0.37f, 1.9f, -0.21f};
    l.e1 = {0.93f, 0.11f, 0.07f};
    l.e2 = {-0.05f, 0.02f, 0.61f};
    const Vec3 c = cross(l.e1, l.e2);
    l.area = length(c);
    l.n = -(c / l.area);  // facing down, towards y = 0
    std::mt19937 rng(31);
    std::uniform_real_distribution<float> u01(0.0f, 1.0f), pos(-3.0f, 3.0f), below(-3.0f, 1.5f), above(2.5f, 3.0f);
    const size_t n = 4099;  // not a multiple of any vector width
    std::vector<float> u1(n), u2(n), ref(3 * n), p(3 * n), wx(n), wy(n), wz(n), dist(n), pdf(n);
    std::vector<uint8_t> ok(n);
    for (size_t i = 0; i < n; ++i) {
        u1[i] = i % 97 == 0 ? 0.0f : u01(rng);
        u2[i] = u01(rng);
        ref[3 * i] = pos(rng);
        // most below the light (sampled), a third above it (refused), some on its corner's plane
        ref[3 * i + 1] = i % 13 == 0 ? 1.9f : i % 3 == 0 ? above(rng) : below(rng);
        ref[3 * i + 2] = pos(rng);
    }
    rectLightSamples(rectFloats(l), u1.data(), u2.data(), ref.data(), n, p.data(), wx.data(), wy.data(), wz.data(), dist.data(), pdf.data(),
                     ok.data());
    auto same = [](float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; };
    size_t differ = 0, sampled = 0, refused = 0;
    for (size_t i = 0; i < n; ++i) {
        const Vec3 r(ref[3 * i], ref[3 * i + 1], ref[3 * i + 2]);
        LightSample s, t;
        const bool valid = rectLightVec3(l, r, u1[i], u2[i], s), scalar = sampleRectLight(l, r, u1[i], u2[i], t);
        if (valid != bool(ok[i]) || valid != scalar) {
            ++differ;
            continue;
        }
        if (!valid) {
            ++refused;
            continue;
        }
        ++sampled;
        if (!same(s.p.x, p[3 * i]) || !same(s.p.y, p[3 * i + 1]) || !same(s.p.z, p[3 * i + 2]) || !same(s.wi.x, wx[i]) || !same(s.wi.y, wy[i]) ||
            !same(s.wi.z, wz[i]) || !same(s.dist, dist[i]) || !same(s.pdf, pdf[i]))
            ++differ;
        if (!same(s.p.x, t.p.x) || !same(s.p.y, t.p.y) || !same(s.p.z, t.p.z) || !same(s.wi.x, t.wi.x) || !same(s.wi.y, t.wi.y) ||
            !same(s.wi.z, t.wi.z) || !same(s.dist, t.dist) || !same(s.pdf, t.pdf))
            ++differ;
    }
    CHECK(sampled > n / 4);
    CHECK(refused > n / 4);
    CHECK(differ == 0);
    // rectLightSamplesOf: each hit its own light of three -- l, l facing up, and a light
    // that is no rectangle (zeros: never sampled) -- equals sampleRectLight of that light.
    Light up = l;
    up.n = -l.n;
    const RectFloats table[3] = {rectFloats(l), rectFloats(up), RectFloats{}};
    std::vector<uint32_t> which(n);
    for (size_t i = 0; i < n; ++i) which[i] = uint32_t((i * 7 + i / 5) % 3);
    rectLightSamplesOf(table, which.data(), u1.data(), u2.data(), ref.data(), n, p.data(), wx.data(), wy.data(), wz.data(), dist.data(), pdf.data(),
                       ok.data());
    size_t perLight[3] = {0, 0, 0};
    differ = 0;
    for (size_t i = 0; i < n; ++i) {
        const Vec3 r(ref[3 * i], ref[3 * i + 1], ref[3 * i + 2]);
        LightSample t;
        const bool valid = which[i] < 2 && sampleRectLight(which[i] ? up : l, r, u1[i], u2[i], t);
        if (valid != bool(ok[i])) ++differ;
        if (!valid) continue;
        ++perLight[which[i]];
        if (!same(t.p.x, p[3 * i]) || !same(t.p.y, p[3 * i + 1]) || !same(t.p.z, p[3 * i + 2]) || !same(t.wi.x, wx[i]) || !same(t.wi.y, wy[i]) ||
            !same(t.wi.z, wz[i]) || !same(t.dist, dist[i]) || !same(t.pdf, pdf[i]))
            ++differ;
    }
    CHECK(perLight[0] > n / 10);
    CHECK(perLight[1] > n / 20);
    CHECK(differ == 0);
}

// PT's flat loops for next-event estimation at matte hits (matteNeeValuesOf, with the one
// light's radiance and pmf or each hit's own, and shadowRaysTo)
// must make what the per-hit code makes, bit for bit: f = matteF |cos|, the power
// heuristic against mattePdf, L = beta f Le w / (pdf pmf), and the shadow ray from the
// offset origin (Scene::offsetRayOrigin's formula) to the light point, in Vec3; for
// surfaces seen from either side, lights on either side and black Kd channels.
TEST_CASE("rect light: matteNeeValuesOf and shadowRaysTo equal the per-hit NEE bit for bit", "[lights]") {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u01(0.0f, 1.0f), pos(-4.0f, 4.0f), sgn(-1.0f, 1.0f);
    auto unit = [&] {
        Vec3 v;
        do v = Vec3(sgn(rng), sgn(rng), sgn(rng));
        while (!(lengthSquared(v) > 0.01f && lengthSquared(v) < 1.0f));
        return normalize(v);
    };
    const size_t n = 2053;
    const RectNeeConsts c{3.5f, 2.25f, 0.0f, 0.37f};  // a black blue channel
    const float epsilonScale = 3e-4f;
    std::vector<float> ns(3 * n), wo(3 * n), wix(n), wiy(n), wiz(n), pdf(n), kd(3 * n), beta(3 * n), L(3 * n);
    std::vector<float> p(3 * n), ng(3 * n), lp(3 * n), origin(3 * n), dir(3 * n), tfar(n);
    std::vector<uint32_t> send(n), send2(n);
    std::vector<float> Le(3 * n), pmfs(n), L2(3 * n);  // the per-hit form: each hit's own light
    for (size_t h = 0; h < n; ++h) {
        for (int a = 0; a < 3; ++a) Le[3 * h + a] = h % 7 == 0 ? 0.0f : 4.0f * u01(rng);
        pmfs[h] = 0.05f + 0.9f * u01(rng);
    }
    for (size_t h = 0; h < n; ++h) {
        const Vec3 N = unit(), G = normalize(N + unit() * 0.2f), O = unit(), W = unit();
        const Vec3 P(pos(rng), pos(rng), pos(rng)), LP = P + W * (0.5f + 3.0f * u01(rng));
        const Vec3 K = h % 11 == 0 ? Vec3(0.0f) : Vec3(u01(rng), h % 5 == 0 ? 0.0f : u01(rng), u01(rng));
        const Vec3 B(u01(rng), u01(rng), u01(rng));
        for (int a = 0; a < 3; ++a) {
            ns[3 * h + a] = N[a];
            wo[3 * h + a] = O[a];
            p[3 * h + a] = P[a];
            ng[3 * h + a] = G[a];
            lp[3 * h + a] = LP[a];
            kd[3 * h + a] = K[a];
            beta[3 * h + a] = B[a];
        }
        wix[h] = W.x;
        wiy[h] = W.y;
        wiz[h] = W.z;
        pdf[h] = h % 13 == 0 ? 0.0f : 0.1f + 4.0f * u01(rng);
    }
    matteNeeValuesOf<false>(c, nullptr, nullptr, n, ns.data(), wo.data(), wix.data(), wiy.data(), wiz.data(), pdf.data(), kd.data(), beta.data(),
                            L.data(), send.data());
    matteNeeValuesOf<true>(c, Le.data(), pmfs.data(), n, ns.data(), wo.data(), wix.data(), wiy.data(), wiz.data(), pdf.data(), kd.data(), beta.data(),
                           L2.data(), send2.data());
    shadowRaysTo(epsilonScale, n, p.data(), ng.data(), wix.data(), wiy.data(), wiz.data(), lp.data(), origin.data(), dir.data(), tfar.data());
    auto same = [](float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; };
    size_t differ = 0, sent = 0;
    for (size_t h = 0; h < n; ++h) {
        const Frame fr = Frame::fromNormal(Vec3(ns[3 * h], ns[3 * h + 1], ns[3 * h + 2]));
        const Vec3 W(wix[h], wiy[h], wiz[h]), P(p[3 * h], p[3 * h + 1], p[3 * h + 2]);
        const Vec3 G(ng[3 * h], ng[3 * h + 1], ng[3 * h + 2]), LP(lp[3 * h], lp[3 * h + 1], lp[3 * h + 2]);
        BsdfParams m;
        m.diffuse = Vec3(kd[3 * h], kd[3 * h + 1], kd[3 * h + 2]);
        const Vec3 woL = fr.toLocal(Vec3(wo[3 * h], wo[3 * h + 1], wo[3 * h + 2])), wiL = fr.toLocal(W);
        const Vec3 f = matteF(m, woL, wiL) * absCosTheta(wiL);
        const bool black = isBlack(f);
        if (black != (send[h] == 0)) ++differ;
        if (!black) {
            ++sent;
            const float lightPdf = pdf[h] * c.pmf;
            const float w = powerHeuristic(lightPdf, mattePdf(m, woL, wiL));
            const Vec3 v = Vec3(beta[3 * h], beta[3 * h + 1], beta[3 * h + 2]) * f * Vec3(c.Lx, c.Ly, c.Lz) * (w / lightPdf);
            for (int a = 0; a < 3; ++a)
                if (!same(v[a], L[3 * h + a])) ++differ;
            const float lightPdf2 = pdf[h] * pmfs[h];
            const float w2 = powerHeuristic(lightPdf2, mattePdf(m, woL, wiL));
            const Vec3 v2 =
                Vec3(beta[3 * h], beta[3 * h + 1], beta[3 * h + 2]) * f * Vec3(Le[3 * h], Le[3 * h + 1], Le[3 * h + 2]) * (w2 / lightPdf2);
            for (int a = 0; a < 3; ++a)
                if (!same(v2[a], L2[3 * h + a])) ++differ;
        }
        if (black != (send2[h] == 0)) ++differ;
        const float mag = std::max(std::max(std::fabs(P.x), std::fabs(P.y)), std::fabs(P.z));
        const float eps = 2e-5f * mag + epsilonScale;
        const Vec3 o = dot(G, W) >= 0 ? P + G * eps : P - G * eps;
        const Vec3 toLight = LP - o;
        const float dist = length(toLight);
        const Vec3 d = toLight / dist;
        for (int a = 0; a < 3; ++a)
            if (!same(o[a], origin[3 * h + a]) || !same(d[a], dir[3 * h + a])) ++differ;
        if (!same(dist * (1.0f - 1e-4f), tfar[h])) ++differ;
    }
    CHECK(sent > n / 4);
    CHECK(sent < n * 3 / 4);
    CHECK(differ == 0);
}

// The same for the light subpaths' starts (BPT, MMLT): rectEmissionSamples and
// sampleRectEmission against the Vec3 form, including numbers 0, 1/2 and the centre of the
// direction's disc.
TEST_CASE("rect light: rectEmissionSamples and sampleRectEmission equal the Vec3 form bit for bit", "[lights]") {
    Light l = testRectLight();
    l.e1 = {0.93f, 0.11f, 0.07f};
    l.e2 = {-0.05f, 0.02f, 0.61f};
    const Vec3 c = cross(l.e1, l.e2);
    l.area = length(c);
    l.n = -(c / l.area);
    std::mt19937 rng(37);
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    const size_t n = 4099;
    std::vector<float> u1(n), u2(n), u3(n), u4(n), p(3 * n), dx(n), dy(n), dz(n), pdfDir(n);
    std::vector<uint8_t> ok(n);
    for (size_t i = 0; i < n; ++i) {
        u1[i] = u01(rng);
        u2[i] = u01(rng);
        u3[i] = i % 17 == 0 ? 0.5f : i % 19 == 0 ? 0.0f : u01(rng);
        u4[i] = i % 17 == 0 ? 0.5f : u01(rng);
    }
    rectEmissionSamples(rectFloats(l), frameFromNormal(l.n.x, l.n.y, l.n.z), u1.data(), u2.data(), u3.data(), u4.data(), n, p.data(), dx.data(),
                        dy.data(), dz.data(), pdfDir.data(), ok.data());
    auto same = [](float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; };
    size_t differ = 0, sampled = 0;
    for (size_t i = 0; i < n; ++i) {
        LightEmission e, f;
        const bool valid = rectEmissionVec3(l, u1[i], u2[i], u3[i], u4[i], e), scalar = sampleRectEmission(l, u1[i], u2[i], u3[i], u4[i], f);
        if (valid != bool(ok[i]) || valid != scalar) {
            ++differ;
            continue;
        }
        if (!valid) continue;
        ++sampled;
        if (!same(e.p.x, p[3 * i]) || !same(e.p.y, p[3 * i + 1]) || !same(e.p.z, p[3 * i + 2]) || !same(e.dir.x, dx[i]) || !same(e.dir.y, dy[i]) ||
            !same(e.dir.z, dz[i]) || !same(e.pdfDir, pdfDir[i]))
            ++differ;
        if (!same(e.p.x, f.p.x) || !same(e.p.y, f.p.y) || !same(e.p.z, f.p.z) || !same(e.dir.x, f.dir.x) || !same(e.dir.y, f.dir.y) ||
            !same(e.dir.z, f.dir.z) || !same(e.pdfDir, f.pdfDir))
            ++differ;
    }
    CHECK(sampled > n / 2);
    CHECK(differ == 0);
}

TEST_CASE("rect light: rectLightPdf integrates to 1", "[lights]") {
    const Light l = testRectLight();
    Vec3 ref(0.3f, 0, 0.1f);
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

namespace {
Light sphereLight(Vec3 center, float radius, Vec3 L) {
    Light l;
    l.type = LightType::Sphere;
    l.center = center;
    l.radius = radius;
    l.L = L;
    l.area = 4 * kPi * radius * radius;
    return l;
}
}  // namespace

TEST_CASE("sphere light: cone sampling lands on the sphere, and its pdf integrates to 1", "[lights]") {
    const Light l = sphereLight({1, 2, 3}, 0.7f, Vec3(2.0f));
    Vec3 ref(0, 0, 0);
    for (int i = 0; i < 200; ++i) {
        LightSample s;
        REQUIRE(sampleSphereLight(l, ref, sampleDimension(5, 2 * i), sampleDimension(5, 2 * i + 1), s));
        CHECK(length(s.p - l.center) == Approx(l.radius).epsilon(1e-3));
        CHECK(dot(s.p - l.center, -s.wi) > -1e-3f);  // the near, emitting side
    }
    // The pdf integrates to 1 over the directions that hit the sphere.
    Vec3 toC = l.center - ref;
    float sin2 = l.radius * l.radius / lengthSquared(toC);
    float cosMax = std::sqrt(1 - sin2);
    auto pdfOf = [&](Vec3 w) -> double { return dot(w, normalize(toC)) >= cosMax ? sphereLightPdf(l, ref) : 0.0; };
    auto [mean, se] = integrateOverSphere(pdfOf, 400000);
    CHECK(std::fabs(mean - 1.0) < 5 * se);
    // Inside the sphere nothing is emitted towards ref.
    LightSample s;
    CHECK_FALSE(sampleSphereLight(l, l.center, 0.3f, 0.3f, s));
}

// A small far sphere (veach-mis' smallest light: r = 0.05 seen from ~10 away): every
// sampled point lies on the near side of the sphere to float precision, so the stages'
// shadow ray towards it, shortened by 1e-4 of its length, never reaches the light
// itself. The intersection distance computed as b - sqrt(r^2 - (d^2 - b^2)) cancels the
// digits this needs: ~1.5% of the samples (those near the rim) landed inside the sphere
// and the light occluded its own shadow rays (PT and BPT were 1.5% dark on veach-mis).
TEST_CASE("sphere light: a small far sphere's sampled points are on its near surface", "[lights]") {
    const Light l = sphereLight({0.0f, 6.5f, 2.7f}, 0.05f, Vec3(1.0f));
    const Vec3 refs[] = {{5, 0, 0}, {10, 0, 5}, {-4.9f, 3, 8}, {14, 0, -8}};
    int inside = 0, n = 0;
    double worstOff = 0;
    for (Vec3 ref : refs)
        for (int i = 0; i < 100000; ++i, ++n) {
            LightSample s;
            REQUIRE(sampleSphereLight(l, ref, sampleDimension(9, 2 * i), sampleDimension(9, 2 * i + 1), s));
            // The exact first intersection of ref + t wi with the sphere, in double.
            double o[3] = {double(ref.x) - l.center.x, double(ref.y) - l.center.y, double(ref.z) - l.center.z};
            double w[3] = {s.wi.x, s.wi.y, s.wi.z};
            double ww = w[0] * w[0] + w[1] * w[1] + w[2] * w[2], b = (o[0] * w[0] + o[1] * w[1] + o[2] * w[2]) / ww;
            double q[3] = {o[0] - b * w[0], o[1] - b * w[1], o[2] - b * w[2]};
            double rho2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2], r = l.radius;
            if (rho2 > r * r) continue;  // rounding put the direction just past the rim: nothing to enter
            double t0 = (-b - std::sqrt(r * r - rho2)) / std::sqrt(ww);
            if (double(s.dist) * (1 - 1e-4) >= t0) ++inside;
            worstOff = std::max(worstOff, std::fabs(double(length(s.p - l.center)) - r));
        }
    INFO(inside << " of " << n << " sampled points beyond the stages' shadow-ray margin; worst |dist - r| " << worstOff);
    CHECK(inside == 0);
    CHECK(worstOff < 1e-5);
}
// Pearson's test of a light's sampled directions against its pdf (chi2.h), N = 4 10^6
// samples from several reference points. The bins partition the directions that reach
// the light:
//  - rectangle: the directions through a 16 x 16 grid of cells on the light; a cell's
//    expected count is N times the integral of the solid-angle pdf over its solid angle,
//    i.e. over the cell of pdf(p) cos_l / dist^2 dA (smooth inside the light: Simpson is
//    exact to ~1e-9);
//  - sphere: the cone it subtends, binned by the angle to its axis (16 bins up to
//    theta_max) and around it (16 bins); expected: the integral of pdf sin(theta).
// A pdf (or a sampler) off by 2% over a quarter of the light raises chi^2 by about
// 0.02^2 N / 4 = 400 over ~255 degrees of freedom (mean 255, sd 23): p < 1e-30, against the
// test's 1e-4 (with N = 10^6 it would be 100: p ~ 1e-3, too weak).
TEST_CASE("rect light: sampled directions follow rectLightPdf (chi-square)", "[lights]") {
    const Light l = testRectLight();
    const int N = 4000000, G = 16;
    for (Vec3 ref : {Vec3(0.3f, 0, 0.1f), Vec3(-3, 1.8f, 0), Vec3(0, 1.5f, 0)}) {
        std::vector<double> expected(G * G), observed(G * G, 0.0);
        for (int i = 0; i < G; ++i)
            for (int j = 0; j < G; ++j) {
                auto density = [&](double a, double b) {  // solid-angle pdf times dw/dA, per unit (a, b)
                    const Vec3 p = l.corner + l.e1 * float(a) + l.e2 * float(b), d = p - ref;
                    const double dist2 = double(lengthSquared(d)), cosL = -double(dot(d, l.n)) / std::sqrt(dist2);
                    return double(rectLightPdf(l, ref, p)) * cosL / dist2 * double(l.area);
                };
                expected[size_t(i * G + j)] =
                    N * chi2::adaptiveSimpson2D(density, double(i) / G, double(i + 1) / G, double(j) / G, double(j + 1) / G, 1e-10, 10);
            }
        chi2::Pcg32 rng(11);
        for (int n = 0; n < N; ++n) {
            LightSample s;
            if (!sampleRectLight(l, ref, rng.uniform(), rng.uniform(), s)) continue;
            // Where the sampled direction meets the light's plane, in (a, b) cell units.
            const float t = dot(l.corner - ref, l.n) / dot(s.wi, l.n);
            const Vec3 q = ref + s.wi * t - l.corner;
            const int i = std::clamp(int(dot(q, l.e1) / lengthSquared(l.e1) * G), 0, G - 1);
            const int j = std::clamp(int(dot(q, l.e2) / lengthSquared(l.e2) * G), 0, G - 1);
            observed[size_t(i * G + j)] += 1;
        }
        const chi2::Result r = chi2::pearson(observed, expected);
        INFO("reference point " << ref.x << " " << ref.y << " " << ref.z << ": " << chi2::describe(r));
        CHECK(r.message.empty());
        CHECK(r.pValue > 1e-4);
    }
}

TEST_CASE("sphere light: sampled directions follow sphereLightPdf (chi-square)", "[lights]") {
    Light l;
    l.type = LightType::Sphere;
    l.center = {1, 2, 3};
    l.radius = 0.7f;
    l.L = Vec3(2.0f);
    l.area = 4 * kPi * l.radius * l.radius;
    const int N = 4000000, G = 16;
    for (Vec3 ref : {Vec3(0, 0, 0), Vec3(1, 2, 3.8f), Vec3(40, -30, 20)}) {
        const Vec3 toC = l.center - ref;
        const double sin2 = double(l.radius) * l.radius / double(lengthSquared(toC));
        const double thetaMax = std::asin(std::sqrt(sin2));
        chi2::SphereBins bins;
        bins.setAxis(toC);
        // The last ring reaches 1e-4 beyond theta_max: a float direction at the cone's edge
        // may round a little outside (by ~1e-7 rad); beyond that nothing may be sampled.
        for (int i = 0; i < G; ++i) bins.thetaEdges.push_back(thetaMax * i / G);
        bins.thetaEdges.push_back(thetaMax * (1 + 1e-4));
        bins.thetaEdges.push_back(M_PI);
        bins.nPhi = G;
        auto pdf = [&](Vec3 w) {  // the angle to the axis as the bins compute it, in double
            return bins.theta(w) <= thetaMax ? double(sphereLightPdf(l, ref)) : 0.0;
        };
        const chi2::Result r = chi2::sphereTest(
            [&](chi2::Pcg32& g, Vec3& w) {
                LightSample s;
                if (!sampleSphereLight(l, ref, g.uniform(), g.uniform(), s)) return false;
                w = s.wi;
                return true;
            },
            pdf, bins, N);
        INFO("reference point " << ref.x << " " << ref.y << " " << ref.z << ": " << chi2::describe(r));
        CHECK(r.message.empty());
        CHECK(r.pValue > 1e-4);
    }
}

// Counter-based numbers (rng.h) are used as if independent across keys (seed, pixel,
// sample) and dimensions. Pearson's test of independence on a 16 x 16 grid of pairs
// (u_a, u_b), 10^6 pairs per relation, for neighbours in each coordinate: the next pixel,
// the next sample index, the next seed, the next dimension, and the pixel a row of 1024
// pixels below; plus each number's own uniformity (64 bins). Neighbouring keys are where
// a weak mixer shows structure. Each relation is one test at p = 1e-4; a correlation of
// 0.01 between the pair raises chi^2 by about N rho^2 = 100 over 255 degrees of freedom.
TEST_CASE("counter-based random numbers are uniform and independent across keys and dimensions", "[rng]") {
    const int N = 1000000, G = 16;
    struct Relation {
        const char* name;
        uint64_t (*keyB)(uint64_t seed, uint32_t pixel, uint32_t sample);
        uint32_t dimB;  // added to the dimension
    };
    const Relation relations[] = {
        {"next pixel", [](uint64_t s, uint32_t p, uint32_t i) { return sampleKey(s, p + 1, i); }, 0},
        {"next sample", [](uint64_t s, uint32_t p, uint32_t i) { return sampleKey(s, p, i + 1); }, 0},
        {"next seed", [](uint64_t s, uint32_t p, uint32_t i) { return sampleKey(s + 1, p, i); }, 0},
        {"next dimension", [](uint64_t s, uint32_t p, uint32_t i) { return sampleKey(s, p, i); }, 1},
        {"a row below", [](uint64_t s, uint32_t p, uint32_t i) { return sampleKey(s, p + 1024, i); }, 0},
    };
    std::vector<double> uni(64, 0.0);
    bool inRange = true;
    for (const Relation& rel : relations) {
        std::vector<double> observed(G * G, 0.0), expected(G * G, double(N) / (G * G));
        for (int n = 0; n < N; ++n) {
            const uint64_t seed = uint64_t(n % 7), pixel = uint32_t(n / 7 % 4096), sample = uint32_t(n / 28672);
            const uint32_t dim = uint32_t(n % 13);
            const float a = sampleDimension(sampleKey(seed, uint32_t(pixel), uint32_t(sample)), dim);
            const float b = sampleDimension(rel.keyB(seed, uint32_t(pixel), uint32_t(sample)), dim + rel.dimB);
            inRange = inRange && a >= 0.0f && a < 1.0f;
            observed[size_t(int(a * G) * G + int(b * G))] += 1;
            if (rel.dimB == 0 && &rel == &relations[0]) uni[size_t(a * 64)] += 1;
        }
        const chi2::Result r = chi2::pearson(observed, expected);
        INFO(rel.name << ": " << chi2::describe(r));
        CHECK(r.pValue > 1e-4);
    }
    CHECK(inRange);  // every number in [0, 1)
    const chi2::Result r = chi2::pearson(uni, std::vector<double>(64, double(N) / 64));
    INFO("uniformity: " << chi2::describe(r));
    CHECK(r.pValue > 1e-4);
    CHECK(sampleKey(1, 2, 3) != sampleKey(1, 3, 2));
    CHECK(sampleKey(1, 2, 3) != sampleKey(2, 2, 3));
}
