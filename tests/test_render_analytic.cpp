// The path tracer against closed forms, with tolerances from the measured variance:
// K independent renders (seeds), per element the mean and its standard error, then
// z = (mean - expected) / se (Student t with K - 1 dof, mapped exactly to N(0, 1)).
//  1. A Lambertian plane lit by a sphere light, length 2 only: per pixel, expected value
//     from deterministic quadrature of the closed form over the pixel's footprint.
//  2. A furnace: a Matte sphere enclosure around a sphere light; all lengths, and single
//     lengths, against the geometric series of the enclosure.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "app/cli.h"
#include "kernels/camera.h"
#include "render_stats.h"
#include "wavemmlt/image.h"
#include "wavemmlt/render.h"
#include "wavemmlt/scene_desc.h"

using namespace wmlt;

namespace {

RenderOptions options(int spp, uint64_t seed, int minLength, int maxLength) {
    RenderOptions o;
    o.tracer = TracerKind::PT;
    o.spp = spp;
    o.strataPerAxis = strataForSpp(spp);
    o.threads = 2;
    o.seed = seed;
    o.minPathLength = minLength;
    o.maxPathLength = maxLength;
    return o;
}

// ---- 1. plane under a sphere light ---------------------------------------------------

constexpr int kPlaneW = 48, kPlaneH = 32;
const double kRho[3] = {0.8, 0.6, 0.4};      // plane albedo
const double kLightL[3] = {4.0, 2.0, 1.0};   // Intensity 4 * Colour (1, 0.5, 0.25)
const double kLightC[3] = {0.6, 3.0, -0.3};  // light centre
const double kLightR = 0.5;

// The scene with a plane `width` units wide (the closed form does not depend on it as
// long as the plane covers the view).
std::string planeXml(const std::string& width) {
    return R"(<Scene>
  <Settings><Width value="48"/><Height value="32"/><Sample value="4"/><Tracer name="PT"/>
    <MaxPathLength value="2"/><MinPathLength value="2"/></Settings>
  <!-- Looking straight down from height 2: the light (y >= 2.5) is behind the camera. -->
  <Camera Type="Camera"><Position x="0" y="2" z="0"/><LookAt x="0" y="0" z="0"/>
    <Up x="0" y="0" z="1"/><FOV value="60"/></Camera>
  <Shader Type="Matte" ID="0"><Diffuse r="0.8" g="0.6" b="0.4"/></Shader>
  <Geometry Type="Plane" ID="floor"><Position x="0" y="0" z="0"/><Width value=")" +
           width +
           R"("/>
    <Depth value=")" +
           width + R"("/><Shader value="0"/></Geometry>
  <Light Type="Area" ID="light"><Position x="0.6" y="3" z="-0.3"/><Radius value="0.5"/>
    <Intensity value="4"/><Colour r="1" g="0.5" b="0.25"/></Light>
</Scene>
)";
}

// Outgoing radiance of the plane at (x, 0, z): rho * L * (r / d)^2 * cos(theta).
double planeRadiance(double x, double z, int c) {
    double dx = kLightC[0] - x, dy = kLightC[1], dz = kLightC[2] - z;
    double d2 = dx * dx + dy * dy + dz * dz;
    double cosTheta = dy / std::sqrt(d2);
    return kRho[c] * kLightL[c] * kLightR * kLightR / d2 * cosTheta;
}

// Box-filtered pixel values by 16 x 16 midpoint quadrature through the camera model.
std::vector<double> expectedPlaneImage(const SceneDesc& desc, int c) {
    Camera cam = makeCamera(desc.camera, kPlaneW, kPlaneH);
    const int q = 16;
    std::vector<double> e(size_t(kPlaneW) * kPlaneH, 0.0);
    int missed = 0;
    for (int y = 0; y < kPlaneH; ++y)
        for (int x = 0; x < kPlaneW; ++x) {
            double sum = 0;
            for (int j = 0; j < q; ++j)
                for (int i = 0; i < q; ++i) {
                    Vec3 o, d;
                    generateCameraRay(cam, x + (i + 0.5f) / q, y + (j + 0.5f) / q, 0.5f, 0.5f, o, d);
                    if (!(d.y < 0)) ++missed;  // every pixel must see the plane
                    double t = -double(o.y) / d.y;
                    sum += planeRadiance(o.x + t * d.x, o.z + t * d.z, c);
                }
            e[size_t(y) * kPlaneW + x] = sum / (q * q);
        }
    REQUIRE(missed == 0);
    return e;
}

// ---- 2. furnace ----------------------------------------------------------------------

const double kWallRho[3] = {0.6, 0.5, 0.4};
const double kFurnaceL = 2.0;
const double kEnclosureR = 1.0, kFurnaceLightR = 0.3;

const std::string kFurnaceHead = R"(<Scene>
  <Settings><Width value="32"/><Height value="32"/><Tracer name="PT"/></Settings>
  <!-- Inside the enclosure at z = 0.5 looking along +z: every ray has dz > 0 and the
       light lies in z <= 0.3, so no pixel sees the light. -->
  <Camera Type="Camera"><Position x="0" y="0" z="0.5"/><LookAt x="0" y="0" z="1"/>
    <FOV value="60"/></Camera>
  <Shader Type="Matte" ID="0"><Diffuse r="0.6" g="0.5" b="0.4"/></Shader>
  <Geometry Type="Sphere" ID="wall"><Position x="0" y="0" z="0"/><Radius value="1"/>
    <Shader value="0"/></Geometry>
  <Light Type="Sphere" ID="light"><Position x="0" y="0" z="0"/><Radius value="0.3"/>
    <Intensity value="2"/><Colour r="1" g="1" b="1"/></Light>
</Scene>
)";

// Wall radiance carried by paths of length k (k >= 2): rho L s (rho (1 - s))^(k - 2).
double furnaceLength(int k, int c) {
    if (k < 2) return 0;
    double s = (kFurnaceLightR / kEnclosureR) * (kFurnaceLightR / kEnclosureR);
    return kWallRho[c] * kFurnaceL * s * std::pow(kWallRho[c] * (1 - s), k - 2);
}
double furnaceExpected(int minLength, int maxLength, int c) {
    double sum = 0;
    for (int k = minLength; k <= maxLength; ++k) sum += furnaceLength(k, c);
    return sum;
}

void planeTest(const std::string& width) {
    const SceneDesc desc = loadSceneFromString(planeXml(width), "plane.xml", ".");
    const int K = 16, spp = 16;
    rstats::RunStats runs[3];
    for (int k = 0; k < K; ++k) {
        RenderResult r = render(desc, options(spp, 1000 + k, 2, 2));
        REQUIRE(r.image.width == kPlaneW);
        REQUIRE(r.image.height == kPlaneH);
        REQUIRE(r.stats.samplesNonfiniteDiscarded == 0);
        for (int c = 0; c < 3; ++c) runs[c].add(rstats::channel(r.image, c));
    }
    // The three channels are proportional (same paths), so each gets its own test at
    // p / 3 instead of one chi^2 over correlated values.
    for (int c = 0; c < 3; ++c) {
        std::vector<double> expected = expectedPlaneImage(desc, c);
        rstats::ZTestResult z = rstats::zTest(runs[c], expected, 1e-4 / 3);
        double sumV = 0, sumE = 0;
        for (size_t i = 0; i < expected.size(); ++i) {
            sumV += runs[c].mean(i);
            sumE += expected[i];
        }
        INFO("plane width " << width << ", channel " << c << ": image mean / expected = " << sumV / sumE << "; " << z.describe());
        CHECK(z.pass);
    }
}

}  // namespace

TEST_CASE("plane under a sphere light, length 2: per-pixel closed form", "[render][analytic]") { planeTest("10"); }

// The same scene with a larger floor: nothing in view changes, but ray offsets grow with
// the scene's bounds (Scene::epsilonScale), which must not change the image.
// (Found failing: sampleLights in src/stages/pt/pt_stages.cpp casts the shadow ray from the
// offset origin along ls.wi, the direction from the un-offset point, so the segment ends
// beside ls.p, up to the offset inside the light; with a 1000-unit floor about 19 % of
// the next-event samples hit the light sphere itself and the image is 19 % dark.)
TEST_CASE("plane under a sphere light, length 2, 1000-unit floor", "[render][analytic]") { planeTest("1000"); }

// The furnace's image mean per channel against the closed form, K runs of `tracer` with
// options o for each of all lengths and two single lengths.
void furnaceTest(const RenderOptions& base, int K, uint64_t seed0) {
    const SceneDesc desc = loadSceneFromString(kFurnaceHead, "furnace.xml", ".");
    struct Case {
        int minLength, maxLength;
    };
    const Case cases[] = {{1, 64}, {2, 2}, {4, 4}};
    // Each configuration and channel: t = (mean - expected) / se with K - 1 dof, mapped to
    // z; channels are correlated, so only the Bonferroni bound over all 9 is used.
    const int numTests = 9;
    const double p = 1e-4;
    const double bound = -rstats::normalQuantile(p / (2 * numTests));
    int caseIndex = 0;
    for (const Case& cs : cases) {
        rstats::RunStats runs;
        for (int k = 0; k < K; ++k) {
            RenderOptions o = base;
            o.seed = seed0 + uint64_t(100 * caseIndex + k);
            o.minPathLength = cs.minLength;
            o.maxPathLength = cs.maxLength;
            RenderResult r = render(desc, o);
            REQUIRE(r.stats.samplesNonfiniteDiscarded == 0);
            std::vector<double> means(3, 0.0);
            for (int c = 0; c < 3; ++c) {
                std::vector<double> v = rstats::channel(r.image, c);
                for (double x : v) means[c] += x;
                means[c] /= double(v.size());
            }
            runs.add(means);
        }
        for (int c = 0; c < 3; ++c) {
            double expected = furnaceExpected(cs.minLength, cs.maxLength, c);
            double t = (runs.mean(c) - expected) / runs.se(c);
            double z = rstats::tToZ(t, runs.dof());
            INFO(tracerName(base.tracer) << ", lengths [" << cs.minLength << ", " << cs.maxLength << "] channel " << c << ": image mean "
                                         << runs.mean(c) << " expected " << expected << " se " << runs.se(c) << " (relative " << runs.se(c) / expected
                                         << ") z " << z << " bound " << bound);
            CHECK(std::fabs(z) <= bound);
        }
        ++caseIndex;
    }
}

TEST_CASE("furnace: sphere enclosure around a sphere light, all and single lengths", "[render][analytic]") {
    furnaceTest(options(16, 0, 1, 1), 16, 7000);
}

// Spectral PT, LT, BPT, MMLT and PSSMLT (--spectral, docs/spectral.md): a white furnace (albedo
// 1, a white light) is the closed form L (1 - (1 - s)^(K - 1)) (K the longest path) in every channel at every wavelength, so its
// image is that in R, G and B: the wavelength sampling, the uplifted spectra, the emitters'
// spectra at every emission site of each tracer and the film's XYZ to sRGB add no bias. And a
// grey one (albedo 0.5): RGB's closed form, since grey spectra are flat.
void spectralFurnace(const std::vector<TracerKind>& tracers) {
    for (TracerKind tracer : tracers)
        for (const char* rho : {"1", "0.5"}) {
            std::string xml = kFurnaceHead;
            const std::string from = R"(<Diffuse r="0.6" g="0.5" b="0.4"/>)";
            xml.replace(xml.find(from), from.size(), std::string(R"(<Diffuse r=")") + rho + R"(" g=")" + rho + R"(" b=")" + rho + R"("/>)");
            const SceneDesc desc = loadSceneFromString(xml, "furnace.xml", ".");
            // (MMLT, PSSMLT: 64 mutations per pixel, 256 chains, as the PSSMLT furnace below, and
            // lengths up to 16: a chain tracer's every length has its pool)
            const bool chains = tracer == TracerKind::MMLT || tracer == TracerKind::PSSMLT;
            const int maxLength = chains ? 16 : 64;
            const double r = std::atof(rho), sFrac = (kFurnaceLightR / kEnclosureR) * (kFurnaceLightR / kEnclosureR);
            double expected = 0;
            for (int k = 2; k <= maxLength; ++k) expected += r * kFurnaceL * sFrac * std::pow(r * (1 - sFrac), k - 2);
            rstats::RunStats runs;
            const int K = 12;
            for (int k = 0; k < K; ++k) {
                RenderOptions o = options(chains ? 64 : 16, 7700 + uint64_t(k), 1, maxLength);
                o.tracer = tracer;
                o.spectral = true;
                if (chains) o.chains = 256;
                const RenderResult res = render(desc, o);
                REQUIRE(res.stats.spectral);
                std::vector<double> means(3, 0.0);
                for (int c = 0; c < 3; ++c) {
                    const std::vector<double> v = rstats::channel(res.image, c);
                    for (double x : v) means[c] += x / double(v.size());
                }
                runs.add(means);
            }
            const double bound = -rstats::normalQuantile(1e-4 / (2 * 6 * double(tracers.size())));
            for (int c = 0; c < 3; ++c) {
                const double z = rstats::tToZ((runs.mean(c) - expected) / runs.se(c), runs.dof());
                INFO("tracer " << int(tracer) << " albedo " << rho << " channel " << c << ": image mean " << runs.mean(c) << " expected " << expected
                               << " se " << runs.se(c));
                CHECK(std::fabs(z) <= bound);
            }
        }
}

// ([stat]: 72 renders, 57 s under the sanitizers; the spectral stages run there in the
// spectral tracers', CLI and pbrt tests.)
TEST_CASE("furnace: spectral PT, LT and BPT, white and grey", "[render][analytic][spectral][stat]") {
    spectralFurnace({TracerKind::PT, TracerKind::LT, TracerKind::BPT});
}

TEST_CASE("furnace: spectral MMLT and PSSMLT, white and grey", "[render][analytic][spectral][stat]") {
    spectralFurnace({TracerKind::MMLT, TracerKind::PSSMLT});
}

// PSSMLT (test_pssmlt.cpp): its chains' images of all lengths and of one length each.
TEST_CASE("furnace: PSSMLT, all and single lengths", "[render][analytic][pssmlt][stat]") {
    RenderOptions o = options(64, 0, 1, 1);
    o.tracer = TracerKind::PSSMLT;
    o.chains = 256;
    furnaceTest(o, 12, 7500);
}

// ---- 3. environment furnace ---------------------------------------------------------
// A Matte sphere under a constant environment map of radiance Le: a convex object sees
// only the environment, so every point of it has radiance rho * Le (paths of length 2),
// and the background Le (length 1). Exercises environment sampling, its solid-angle pdf
// (the 2 pi^2 sin(theta) Jacobian) and the MIS weights between it and BSDF sampling.
TEST_CASE("environment furnace: a Matte sphere under a constant sky", "[render][analytic]") {
    const double Le[3] = {0.5, 1.0, 2.0}, rho[3] = {0.8, 0.5, 0.3};
    const int W = 32, H = 32;
    std::string dir = rstats::tempDir("envfurnace");
    Image sky(8, 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x) sky.set(x, y, Vec3(float(Le[0]), float(Le[1]), float(Le[2])));
    writeImage(dir + "/sky.pfm", sky);
    const std::string xml = R"(<Scene>
  <Settings><Width value="32"/><Height value="32"/><MaxPathLength value="64"/>
    <MinPathLength value="1"/><EnvMap name="sky.pfm"/></Settings>
  <Camera Type="Camera"><Position x="0" y="0.3" z="-4"/><LookAt x="0" y="0" z="0"/><FOV value="40"/></Camera>
  <Shader Type="Matte" ID="0"><Diffuse r="0.8" g="0.5" b="0.3"/></Shader>
  <Geometry Type="Sphere" ID="ball"><Position x="0" y="0" z="0"/><Radius value="1"/><Shader value="0"/></Geometry>
</Scene>
)";
    SceneDesc desc = loadSceneFromString(xml, "envfurnace.xml", dir);
    // Expected: per pixel, the fraction of its footprint covered by the sphere (16 x 16
    // quadrature through the camera model) mixes rho * Le and Le.
    Camera cam = makeCamera(desc.camera, W, H);
    std::vector<double> cover(W * H, 0.0);
    const int q = 16;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            int hits = 0;
            for (int j = 0; j < q; ++j)
                for (int i = 0; i < q; ++i) {
                    Vec3 o, d;
                    generateCameraRay(cam, x + (i + 0.5f) / q, y + (j + 0.5f) / q, 0.5f, 0.5f, o, d);
                    float b = dot(o, d), c = dot(o, o) - 1.0f;
                    hits += (b * b - c > 0 && -b > 0) ? 1 : 0;
                }
            cover[y * W + x] = double(hits) / (q * q);
        }
    const int K = 12, spp = 16;
    rstats::RunStats runs[3];
    for (int k = 0; k < K; ++k) {
        RenderResult r = render(desc, options(spp, 9100 + k, 1, 64));
        REQUIRE(r.stats.samplesNonfiniteDiscarded == 0);
        for (int c = 0; c < 3; ++c) runs[c].add(rstats::channel(r.image, c));
    }
    std::filesystem::remove_all(dir);
    for (int c = 0; c < 3; ++c) {
        std::vector<double> expected(W * H);
        for (int i = 0; i < W * H; ++i) expected[i] = Le[c] * (cover[i] * rho[c] + (1 - cover[i]));
        rstats::ZTestResult z = rstats::zTest(runs[c], expected, 1e-4 / 3);
        INFO("channel " << c << ": " << z.describe());
        CHECK(z.pass);
    }
}

// ---- 4. per-length statistics -------------------------------------------------------
// RenderStats::lengthMeanLuminance splits the image's mean luminance by path length; in
// the furnace each length has the closed form luminance(furnaceLength(k)) (every pixel
// sees the wall). Checked for the path tracer and the light tracer; and in every run the
// lengths add up to the image's own mean luminance.
TEST_CASE("furnace: mean luminance by path length matches the closed form, PT and LT", "[render][analytic]") {
    const SceneDesc desc = loadSceneFromString(kFurnaceHead, "furnace.xml", ".");
    const int maxLength = 8, K = 12, spp = 16;
    const TracerKind tracers[] = {TracerKind::PT, TracerKind::LT};
    const double p = 1e-4;
    const double bound = -rstats::normalQuantile(p / (2 * 2 * (maxLength - 1)));
    for (TracerKind tracer : tracers) {
        rstats::RunStats runs;
        for (int k = 0; k < K; ++k) {
            RenderOptions o = options(spp, 8100 + k, 1, maxLength);
            o.tracer = tracer;
            RenderResult r = render(desc, o);
            REQUIRE(r.stats.lengthMeanLuminance.size() > size_t(maxLength));
            double imageMean = 0;
            for (int i = 0; i < r.image.width * r.image.height; ++i) imageMean += luminance(r.image.at(i % r.image.width, i / r.image.width));
            imageMean /= double(r.image.width * r.image.height);
            double sum = 0;
            for (int len = 1; len <= maxLength; ++len) sum += r.stats.lengthMeanLuminance[len];
            CHECK(sum == Approx(imageMean).epsilon(1e-5));
            CHECK(r.stats.lengthMeanLuminance[1] == 0.0);  // no pixel sees the light
            runs.add(std::vector<double>(r.stats.lengthMeanLuminance.begin() + 2, r.stats.lengthMeanLuminance.begin() + maxLength + 1));
        }
        for (int len = 2; len <= maxLength; ++len) {
            double expected = 0.2126 * furnaceLength(len, 0) + 0.7152 * furnaceLength(len, 1) + 0.0722 * furnaceLength(len, 2);
            double z = rstats::tToZ((runs.mean(len - 2) - expected) / runs.se(len - 2), runs.dof());
            INFO((tracer == TracerKind::PT ? "PT" : "LT")
                 << " length " << len << ": " << runs.mean(len - 2) << " expected " << expected << " se " << runs.se(len - 2) << " z " << z);
            CHECK(std::fabs(z) <= bound);
        }
    }
}
