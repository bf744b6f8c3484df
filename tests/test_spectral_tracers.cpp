// Spectral rendering in every tracer (docs/spectral.md): LT, BPT, MMLT and PSSMLT against PT,
// all with --spectral, on scenes where a tracer's spectral code could go wrong on its
// own: pbrt's Cornell box whose light is a saturated orange (an RGB illuminant uplifted at
// each of a tracer's emission sites: PT's hits and next-event estimation, LT's and BPT's
// light subpaths, BPT's s = 0, s = 1 and t = 1 strategies), and a dispersive BK7 glass
// sphere on a floor (the hero wavelength's index, and the path keeping only that
// wavelength: in BPT, MMLT and PSSMLT for every strategy of the sample, in LT for the splats
// after it), and a prism's spectrum against its closed form (PT, BPT, MMLT, PSSMLT).
// power.h's comparisons: K = 16 runs per tracer, at p = 1e-4 the brightness, the blocks
// (max |z|, Bonferroni) and the blocks' shape (chi^2). PT's spectral renders are checked
// against pbrt-v4's in test_pbrt_scenes.cpp, the white and grey furnaces in
// test_render_analytic.cpp. Tagged [stat].
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <tuple>

#include "chi2.h"
#include "kernels/bsdf.h"
#include "kernels/medium.h"
#include "kernels/spectral.h"
#include "media_scenes.h"
#include "power.h"
#include "render_stats.h"
#include "scene/scene.h"
#include "scene/scene_spectra.h"
#include "scene/spectrum.h"
#include "stages/render_scene.h"
#include "wavemmlt/render.h"
#include "wavemmlt/scene_desc.h"

using namespace wmlt;

namespace {

constexpr int K = 16;
constexpr double kP = 1e-4;

power::Runs runs(const SceneDesc& d, TracerKind t, int spp, int block, uint64_t seed0) {
    power::Runs r(block);
    RenderOptions o = rstats::renderOptions(t, spp, 0, 1, d.settings.maxPathLength);
    o.spectral = true;
    o.chains = 1024;  // (MMLT, PSSMLT)
    for (int k = 0; k < K; ++k) {
        o.seed = seed0 + uint64_t(k);
        const RenderResult res = render(d, o);
        REQUIRE(res.stats.spectral);
        REQUIRE(res.stats.samplesNonfiniteDiscarded == 0);
        r.add(res);
    }
    return r;
}

// LT (ltSpp; 0: not compared), BPT (bptSpp), MMLT and PSSMLT (mltSpp mutations per pixel)
// against PT (ptSpp) on d: each able to see a 5% brightness error (MMLT and PSSMLT: mltPower;
// their runs' brightness has a heavy tail where chains find a glass's caustics).
void agree(const std::string& what, const SceneDesc& d, int ptSpp, int ltSpp, int bptSpp, int mltSpp, int block, double mltPower = 0.05,
           int pssmltSpp = -1) {  // (PSSMLT: -1, mltSpp; 0, not compared)
    const power::Runs pt = runs(d, TracerKind::PT, ptSpp, block, 100);
    for (auto [t, spp, name] :
         {std::tuple{TracerKind::LT, ltSpp, "LT"}, std::tuple{TracerKind::BPT, bptSpp, "BPT"}, std::tuple{TracerKind::MMLT, mltSpp, "MMLT"},
          std::tuple{TracerKind::PSSMLT, pssmltSpp < 0 ? mltSpp : pssmltSpp, "PSSMLT"}}) {
        if (spp == 0) continue;
        const power::Runs r = runs(d, t, spp, block, 200);
        for (const power::Verdict& v : {power::brightness(r, pt, kP), power::blocks(r, pt, kP), power::scatter(r, pt, kP)}) {
            if (std::getenv("WMLT_TEST_VERBOSE")) std::cout << what << ", " << name << " vs PT: " << v.text << "\n";
            INFO(what << ", " << name << " vs PT: " << v.text);
            CHECK(v.pass);
        }
        const power::Verdict b = power::brightness(r, pt, kP);
        INFO(what << ", " << name << ": " << b.text);
        CHECK(b.detectable < (t == TracerKind::MMLT || t == TracerKind::PSSMLT ? mltPower : 0.05));
    }
}

}  // namespace

TEST_CASE("spectral tracers: LT, BPT, MMLT and PSSMLT render pbrt's orange-lit Cornell box as PT does", "[spectral][render][stat]") {
    // (pbrt's path integrator ignores its fog, and so does the importer: test_pbrt_scenes.cpp)
    SceneDesc d = loadScene(std::string(WAVEMMLT_TEST_DATA) + "/scenes/pbrt-v4/cornell-box/cornell-box-volume.pbrt");
    REQUIRE(d.media.empty());
    d.settings.width = d.settings.height = 32;
    d.settings.maxPathLength = 5;
    agree("orange Cornell box", d, 64, 64, 16, 256, 4);
}

TEST_CASE("spectral tracers: LT, BPT and MMLT render a chromatic fog as PT does", "[spectral][render][media][stat]") {
    // The same box with its fog kept (pbrt's volpath) and made chromatic: sigma_s (0.3, 0.6, 1)
    // times 0.0015 per unit, optical depths 0.25 to 0.8 across the box; each path's
    // coefficients at its wavelengths (SpectralScene::medium) in its free paths, its
    // transmittances and BPT's densities. (PSSMLT runs BPT's media stages as MMLT does.) The
    // file's walls are boundaries from vacuum inside to fog outside (its MediumInterface ""
    // "fog" holds past WorldBegin), so a path off a wall whose normal faces out of the room
    // goes on in vacuum and the tracers see different scenes (blocks apart by 2x): here the
    // fog is everywhere (MediumInterface "fog" "fog" after WorldBegin: no boundaries).
    std::ifstream in(std::string(WAVEMMLT_TEST_DATA) + "/scenes/pbrt-v4/cornell-box/cornell-box-volume.pbrt");
    std::stringstream text;
    text << in.rdbuf();
    std::string s = text.str();
    for (auto [from, to] : {std::pair<std::string, std::string>{"\"rgb sigma_s\" [ 1 1 1 ]", "\"rgb sigma_s\" [ 0.3 0.6 1 ]"},
                            std::pair<std::string, std::string>{"Integrator \"path\"", "Integrator \"volpath\""},
                            std::pair<std::string, std::string>{"WorldBegin", "WorldBegin\nMediumInterface \"fog\" \"fog\""}}) {
        const size_t at = s.find(from);
        REQUIRE(at != std::string::npos);
        s.replace(at, from.size(), to);
    }
    const std::string file = rstats::tempDir("spectral-fog") + "/fog.pbrt";
    std::ofstream(file) << s;
    SceneDesc d = loadScene(file);
    REQUIRE(d.media.size() == 1);
    d.settings.width = d.settings.height = 32;
    d.settings.maxPathLength = 5;
    agree("chromatic fog", d, 64, 64, 16, 256, 4, 0.05, 0);
}

// A BK7 sphere on a floor, lit from the side by a quad: its caustic falls on the floor
// beside it, dispersed at its edges. The camera sees the sphere (LT cannot: a glass seen
// through from the camera is a delta vertex next to the lens), then the caustic alone.
std::string bk7Scene(const std::string& camera, int fov) {
    const std::string file = rstats::tempDir("spectral-tracers") + "/bk7.pbrt";
    std::ofstream(file) << camera << R"(
Camera "perspective" "float fov" [ )"
                        << fov << R"( ]
Film "rgb" "integer xresolution" [ 32 ] "integer yresolution" [ 32 ]
PixelFilter "box"
WorldBegin
AttributeBegin
AreaLightSource "diffuse" "rgb L" [ 10 10 10 ]
Shape "trianglemesh" "point3 P" [ -1.7465 0.765 -0.5  -1.2535 1.635 -0.5  -1.2535 1.635 0.5  -1.7465 0.765 0.5 ]
  "integer indices" [ 0 1 2 0 2 3 ]
AttributeEnd
AttributeBegin
Material "dielectric" "spectrum eta" "glass-BK7"
Translate 0 0.35 0
Shape "sphere" "float radius" 0.3
AttributeEnd
Material "diffuse" "rgb reflectance" [ 0.6 0.6 0.6 ]
Shape "trianglemesh" "point3 P" [ -20 0 -20  20 0 -20  20 0 20  -20 0 20 ] "integer indices" [ 0 1 2 0 2 3 ]
)";
    return file;
}

TEST_CASE("spectral tracers: LT, BPT, MMLT and PSSMLT disperse through a BK7 sphere as PT does", "[spectral][render][stat]") {
    SceneDesc seen = loadScene(bk7Scene("LookAt 0.5 1.4 1.6  0.5 0.2 0  0 1 0", 50));
    REQUIRE(seen.spectra.size() == 1);  // BK7's Sellmeier index
    seen.settings.maxPathLength = 6;
    agree("BK7 sphere and its caustic", seen, 256, 0, 32, 256, 4, 0.1);  // (MMLT: 5.4% to 8.6% at 256 to 512 mutations)
    SceneDesc caustic = loadScene(bk7Scene("LookAt 0.75 1.2 0  0.75 0 0  0 0 1", 36));
    caustic.settings.maxPathLength = 6;
    agree("BK7 sphere's caustic", caustic, 4096, 256, 128, 1024, 4);
}

// A prism's spectrum against its closed form. An orthographic camera looks through a 30-degree
// prism of SF11 (pbrt's glass-F11, the strongest disperser of its named glasses) at a thin
// strip of white light far behind it: each pixel column sees the strip in the wavelengths
// that Snell's law, with the glass's Sellmeier index, bends onto it. In the x-z plane
// (the prism and the strip run along y, beyond the view): face 1 is z = 0, met head-on;
// face 2 runs from (-4, 0) down to (4, -4 tan 30), so a ray entering at x leaves it at
// z = -(x + 4) tan 30 with incidence 30 degrees inside; the strip is x in [14.79, 14.89]
// at z = -25. A column's value is its pixel footprint's mean of
//   int (1 - F1(l)) (1 - F2(l)) L(l) [the ray lands on the strip] cmf(l) dl / int ybar,
// F the unpolarized Fresnel reflectance at each face, L the light's illuminant spectrum, cmf
// the CIE matching functions, then XYZ to linear sRGB (the film's). Only paths of length 3
// (camera, face 1, face 2, light) are rendered, which no other path of the scene has.
namespace {

constexpr double kTan30 = 0.57735026918962576;
constexpr double kStripLo = 14.79, kStripHi = 14.89, kStripZ = -25;
const char* const kPrism = R"(LookAt 0 0 10  0 0 0  0 1 0
Camera "orthographic"
Film "rgb" "integer xresolution" [ 64 ] "integer yresolution" [ 16 ]
PixelFilter "box"
Integrator "path" "integer maxdepth" [ 2 ]
WorldBegin
AttributeBegin
AreaLightSource "diffuse" "rgb L" [ 1 1 1 ]
Shape "trianglemesh" "point3 P" [ 14.79 -20 -25  14.89 -20 -25  14.89 20 -25  14.79 20 -25 ] "integer indices" [ 0 1 2 0 2 3 ]
AttributeEnd
Material "dielectric" "spectrum eta" "glass-F11"
Shape "trianglemesh" "point3 P" [ -4 -20 0  4 -20 0  4 -20 -4.618802  -4 20 0  4 20 0  4 20 -4.618802 ]
  "integer indices" [ 0 1 4  0 4 3  1 2 5  1 5 4  2 0 3  2 3 5  0 2 1  3 4 5 ]
)";

double fresnel(double n1, double n2, double cosI, double cosT) {
    const double rs = (n1 * cosI - n2 * cosT) / (n1 * cosI + n2 * cosT), rp = (n2 * cosI - n1 * cosT) / (n2 * cosI + n1 * cosT);
    return 0.5 * (rs * rs + rp * rp);
}

// The expected linear sRGB of each of the image's 64 columns (column 0 at x = +4: pbrt's
// LookAt mirrors x), by quadrature: 32 positions per column, wavelengths every 0.05 nm.
std::vector<Vec3> prismColumns() {
    const Sellmeier* glass = namedGlass("glass-F11");
    REQUIRE(glass);
    constexpr int kColumns = 64, kSub = 32;
    std::vector<Vec3> xyz(kColumns, Vec3(0.0f));
    std::vector<double> acc(size_t(kColumns) * 3, 0.0);
    const double dl = 0.05;
    for (double l = double(kLambdaMin) + dl / 2; l < double(kLambdaMax); l += dl) {
        const double n = sellmeierEta(*glass, float(l));
        const double sinT = n * 0.5;  // face 2: sin 30 inside
        if (sinT >= 1) continue;
        const double cosI = std::sqrt(0.75), cosT = std::sqrt(1 - sinT * sinT);
        const double T = (1 - fresnel(1, n, 1, 1)) * (1 - fresnel(n, 1, cosI, cosT));
        // leaving face 2: t = n d + (n cos_i - cos_t) m, d = (0, -1), m = (sin 30, cos 30)
        const double k = n * cosI - cosT, tx = k * 0.5, tz = -n + k * cosI;
        Wavelengths w;
        for (int i = 0; i < kWavelengths; ++i) w.lambda[i] = float(l);
        const double L = rgbIlluminantAt(Vec3(1.0f), w).x;
        const Vec3 cmf = cieMatching(float(l));
        for (int c = 0; c < kColumns; ++c)
            for (int j = 0; j < kSub; ++j) {
                const double x = 4 - 8 * (c + (j + 0.5) / kSub) / kColumns;
                const double zExit = -(x + 4) * kTan30;
                const double land = x + (kStripZ - zExit) * tx / tz;
                if (land < kStripLo || land > kStripHi) continue;
                const double v = T * L * dl / kSub;
                for (int ch = 0; ch < 3; ++ch) acc[size_t(c) * 3 + size_t(ch)] += v * double(cmf[ch]);
            }
    }
    std::vector<Vec3> rgb(kColumns);
    for (int c = 0; c < kColumns; ++c) {
        const Vec3 x(float(acc[size_t(c) * 3] / cieYIntegral()), float(acc[size_t(c) * 3 + 1] / cieYIntegral()),
                     float(acc[size_t(c) * 3 + 2] / cieYIntegral()));
        rgb[size_t(c)] = xyzToSrgb(x);
    }
    return rgb;
}

}  // namespace

TEST_CASE("spectral tracers: a prism's spectrum lies where Snell's law and the glass's Sellmeier index put it", "[spectral][render][stat]") {
    const std::string file = rstats::tempDir("spectral-prism") + "/prism.pbrt";
    std::ofstream(file) << kPrism;
    const SceneDesc d = loadScene(file);
    REQUIRE(d.settings.maxPathLength == 3);
    const std::vector<Vec3> expected = prismColumns();
    double peak = 0;
    for (const Vec3& e : expected) peak = std::max(peak, double(luminance(e)));
    REQUIRE(peak > 0.1);
    // MMLT and PSSMLT: their chains visit a column in proportion to its luminance, so where
    // it is below 1% of the peak's (the spectrum's far tails, whose ybar is 1e-5 of its
    // peak) 16 runs rarely see a visit and their spread says nothing of their error: those
    // columns are held, together, to 1% of the image's light instead.
    struct Case {
        TracerKind kind;
        int spp;
        const char* name;
        double dim;  // columns below dim * peak: the total check only
    };
    for (const Case& t : {Case{TracerKind::PT, 256, "PT", 0.0}, Case{TracerKind::BPT, 256, "BPT", 0.0}, Case{TracerKind::MMLT, 1024, "MMLT", 0.01},
                          Case{TracerKind::PSSMLT, 1024, "PSSMLT", 0.01}}) {
        const char* name = t.name;
        RenderOptions o = rstats::renderOptions(t.kind, t.spp, 0, 3, 3);
        o.spectral = true;
        o.chains = 1024;
        rstats::RunStats runs;  // per column and channel, the mean over the column's 16 pixels
        for (int k = 0; k < 16; ++k) {
            o.seed = 300 + uint64_t(k);
            const RenderResult r = render(d, o);
            REQUIRE(r.stats.spectral);
            std::vector<double> cols(64 * 3, 0.0);
            for (int y = 0; y < 16; ++y)
                for (int x = 0; x < 64; ++x)
                    for (int c = 0; c < 3; ++c)
                        cols[size_t(x) * 3 + size_t(c)] += double(r.image.rgb[(size_t(y) * 64 + size_t(x)) * 3 + size_t(c)]) / 16;
            runs.add(cols);
        }
        // Every column within Bonferroni's bound at p = 1e-4 (Student's t of 16 runs; a column
        // with no light: exactly 0).
        const double bound = -rstats::normalQuantile(1e-4 / (2 * 64 * 3));
        double worst = 0;
        std::string at;
        double dimMean = 0, dimExpected = 0, total = 0;
        for (size_t i = 0; i < 64 * 3; ++i) {
            const double e = double(expected[i / 3][int(i % 3)]), se = runs.se(i);
            total += std::fabs(e);
            if (double(luminance(expected[i / 3])) < t.dim * peak) {
                dimMean += runs.mean(i);
                dimExpected += e;
                continue;
            }
            const double z =
                se > 0 ? std::fabs(rstats::tToZ((runs.mean(i) - e) / se, runs.dof())) : (std::fabs(runs.mean(i) - e) <= 1e-6 ? 0 : INFINITY);
            if (z > worst) {
                worst = z;
                at = "column " + std::to_string(i / 3) + " channel " + std::to_string(i % 3) + ": " + std::to_string(runs.mean(i)) + " expected " +
                     std::to_string(e) + " se " + std::to_string(se);
            }
        }
        INFO(name << ": worst " << at << " (|z| " << worst << ", bound " << bound << ")");
        if (std::getenv("WMLT_TEST_VERBOSE")) std::cout << name << ": worst " << at << " (|z| " << worst << ")\n";
        CHECK(worst <= bound);
        INFO(name << ": the dim columns " << dimMean << ", expected " << dimExpected << ", the image " << total);
        CHECK(std::fabs(dimMean - dimExpected) <= 0.01 * total);
    }
}

// An absorbing medium's colour against its closed form: an orthographic camera inside a
// medium of sigma_a (0.9, 0.25, 0.05), sigma_s 0, looks at a white area light 2 away, so each
// pixel is int exp(-2 sigma_a(l)) L(l) cmf(l) dl / int ybar in linear sRGB, sigma_a(l) its
// RGB's unbounded spectrum (pbrt-v4's RGBUnboundedSpectrum) and L the light's illuminant
// spectrum; the RGB product exp(-2 sigma_a) per channel is far from it (checked). Once as a
// homogeneous medium (the free path's one-sample MIS over the path's wavelengths), once as
// pbrt's uniformgrid of density 0.5 and twice the sigma_a (delta and ratio tracking against
// the majorants scaled to the wavelengths, Medium::majorantScale), once as pbrt's rgbgrid of
// it in every voxel (each voxel's spectrum, voxelAt, and the spectral majorants).
namespace {

// A spectrum given as (wavelength, value) pairs at l: linear between them, 0 outside.
double pairsAt(double l, std::initializer_list<std::pair<double, double>> pairs) {
    const std::vector<std::pair<double, double>> p(pairs);
    if (l < p.front().first || l > p.back().first) return 0.0;
    for (size_t i = 0; i + 1 < p.size(); ++i)
        if (l <= p[i + 1].first) return p[i].second + (p[i + 1].second - p[i].second) * (l - p[i].first) / (p[i + 1].first - p[i].first);
    return 0.0;
}

// The film's linear sRGB of a radiance spectrum L(lambda) (nm): int L cmf / int ybar by
// quadrature every 0.05 nm, then XYZ to linear sRGB.
template <class Spectrum>
Vec3 srgbOfSpectrum(Spectrum&& L) {
    double acc[3] = {0, 0, 0};
    const double dl = 0.05;
    for (double l = double(kLambdaMin) + dl / 2; l < double(kLambdaMax); l += dl) {
        const double v = L(l) * dl;
        const Vec3 cmf = cieMatching(float(l));
        for (int c = 0; c < 3; ++c) acc[c] += v * double(cmf[c]);
    }
    return xyzToSrgb(Vec3(float(acc[0] / cieYIntegral()), float(acc[1] / cieYIntegral()), float(acc[2] / cieYIntegral())));
}

// PT, BPT and MMLT render d (paths of `length` segments only), whose every pixel is
// `expected`, 16 times each (seeds from seed0): each channel of the image's mean within
// Bonferroni's bound at p = 1e-4 (Student's t of the runs), and `rgb`, what an RGB render
// would give, 10+ standard errors away in some channel (the test tells spectral from RGB).
void checkUniform(const std::string& what, const SceneDesc& d, int length, uint64_t seed0, Vec3 expected, Vec3 rgb) {
    for (auto [kind, name] : {std::pair{TracerKind::PT, "PT"}, std::pair{TracerKind::BPT, "BPT"}, std::pair{TracerKind::MMLT, "MMLT"}}) {
        RenderOptions o = rstats::renderOptions(kind, 16, 0, length, length);
        o.spectral = true;
        o.chains = 256;
        rstats::RunStats runs;  // the image's mean per channel
        for (int k = 0; k < 16; ++k) {
            o.seed = seed0 + uint64_t(k);
            const RenderResult r = render(d, o);
            REQUIRE(r.stats.spectral);
            std::vector<double> mean(3, 0.0);
            for (size_t i = 0; i < r.image.rgb.size(); ++i) mean[i % 3] += double(r.image.rgb[i]) / double(r.image.rgb.size() / 3);
            runs.add(mean);
        }
        const double bound = -rstats::normalQuantile(1e-4 / (2 * 3));
        double rgbWorst = 0;
        for (size_t c = 0; c < 3; ++c) {
            const double z = rstats::tToZ((runs.mean(c) - double(expected[int(c)])) / runs.se(c), runs.dof());
            rgbWorst = std::max(rgbWorst, std::fabs(double(rgb[int(c)]) - double(expected[int(c)])) / runs.se(c));
            INFO(what << ", " << name << " channel " << c << ": " << runs.mean(c) << " expected " << expected[int(c)] << " se " << runs.se(c)
                      << " (|z| " << std::fabs(z) << "); RGB's " << rgb[int(c)]);
            CHECK(std::fabs(z) <= bound);
        }
        INFO(what << ", " << name << ": RGB's distance " << rgbWorst << " standard errors");
        CHECK(rgbWorst > 10);
    }
}

// The camera of the ink and glow scenes: orthographic, looking down the z axis from z = 10
// inside medium `medium`, 16 x 16 pixels, paths of one segment.
std::string lookingDownIn(const std::string& medium) {
    return "\nMediumInterface \"\" \"" + medium + R"("
LookAt 0 0 10  0 0 0  0 1 0
Camera "orthographic"
Film "rgb" "integer xresolution" [ 16 ] "integer yresolution" [ 16 ]
PixelFilter "box"
Integrator "volpath" "integer maxdepth" [ 1 ]
WorldBegin
)";
}

// The ink: a medium of sigma_a (0.9, 0.25, 0.05) (kind 0 homogeneous, 1 a density grid of
// twice that at density 0.5, 2 pbrt's rgbgrid of it in every voxel) with the camera in it.
std::string inkScene(int kind) {
    const char* names[] = {"/homogeneous.pbrt", "/grid.pbrt", "/rgbgrid.pbrt"};
    const char* media[] = {
        R"(MakeNamedMedium "ink" "string type" [ "homogeneous" ] "rgb sigma_a" [ 0.9 0.25 0.05 ] "rgb sigma_s" [ 0 0 0 ])",
        R"(MakeNamedMedium "ink" "string type" [ "uniformgrid" ] "rgb sigma_a" [ 1.8 0.5 0.1 ] "rgb sigma_s" [ 0 0 0 ]
  "integer nx" 2 "integer ny" 2 "integer nz" 2 "float density" [ 0.5 0.5 0.5 0.5 0.5 0.5 0.5 0.5 ] "point3 p0" [ -30 -30 0 ] "point3 p1" [ 30 30 20 ])",
        R"(MakeNamedMedium "ink" "string type" [ "rgbgrid" ] "integer nx" 2 "integer ny" 2 "integer nz" 2 "point3 p0" [ -30 -30 0 ] "point3 p1" [ 30 30 20 ]
  "rgb sigma_a" [ 0.9 0.25 0.05  0.9 0.25 0.05  0.9 0.25 0.05  0.9 0.25 0.05  0.9 0.25 0.05  0.9 0.25 0.05  0.9 0.25 0.05  0.9 0.25 0.05 ]
  "rgb sigma_s" [ 0 0 0  0 0 0  0 0 0  0 0 0  0 0 0  0 0 0  0 0 0  0 0 0 ])"};
    const std::string file = rstats::tempDir("spectral-ink") + names[kind];
    std::ofstream(file) << media[kind] << lookingDownIn("ink") << R"(AreaLightSource "diffuse" "rgb L" [ 1 1 1 ]
Shape "trianglemesh" "point3 P" [ -20 -20 8  20 -20 8  20 20 8  -20 20 8 ] "integer indices" [ 0 1 2 0 2 3 ]
)";
    return file;
}

}  // namespace

TEST_CASE(
    "spectral tracers: an absorbing medium's colour is its transmittance at each wavelength, homogeneous, density grid and RGB grid, in PT, BPT and "
    "MMLT",
    "[spectral][render][media][stat]") {
    const UnboundedSpectrum sigmaA = unboundedSpectrumOfRgb(Vec3(0.9f, 0.25f, 0.05f));
    const Vec3 expected = srgbOfSpectrum([&](double l) {
        Wavelengths w;
        for (int i = 0; i < kWavelengths; ++i) w.lambda[i] = float(l);
        return std::exp(-2.0 * double(unboundedAt(sigmaA, float(l)))) * double(rgbIlluminantAt(Vec3(1.0f), w).x);
    });
    for (int kind : {0, 1, 2}) {
        const SceneDesc d = loadScene(inkScene(kind));
        REQUIRE(d.media.size() == 1);
        REQUIRE(d.media[0].density.empty() == (kind != 1));
        REQUIRE(d.media[0].sigmaAGrid.empty() == (kind != 2));
        const char* what[] = {"homogeneous", "density grid", "rgbgrid"};
        checkUniform(what[kind], d, 1, 500, expected, Vec3(std::exp(-1.8f), std::exp(-0.5f), std::exp(-0.1f)));
    }
}

// A scene with no material at all, only fog in a box of interface walls under a point light:
// PT's spectral stage met its medium vertices with the material index the hit's record held
// before (a crash here, index 0 of no materials; elsewhere a stale material's colours on a
// phase function). PT, BPT and MMLT render it spectrally and agree (6 runs each, blocks of
// 4 x 4 pixels, compareRuns at p = 1e-4).
TEST_CASE("spectral tracers: fog in a box of interface walls, no material anywhere, in PT, BPT and MMLT", "[spectral][render][media]") {
    const std::string file = rstats::tempDir("spectral-fogbox") + "/fog.pbrt";
    std::ofstream(file) << media_scenes::fogInInterfaceBox(16);
    const SceneDesc d = loadScene(file);
    REQUIRE(d.materials.empty());
    std::vector<std::vector<rstats::RunStats>> runs(3, std::vector<rstats::RunStats>(3));
    const TracerKind tracers[3] = {TracerKind::PT, TracerKind::BPT, TracerKind::MMLT};
    for (int t = 0; t < 3; ++t)
        for (int k = 0; k < 6; ++k) {
            RenderOptions o = rstats::renderOptions(tracers[t], 32, 40 + uint64_t(10 * t + k), 2, 3);
            o.spectral = true;
            o.chains = 1024;
            const RenderResult r = render(d, o);
            REQUIRE(r.stats.spectral);
            for (int c = 0; c < 3; ++c) runs[size_t(t)][size_t(c)].add(rstats::blockMeans(r.image, 4, c));
        }
    for (int t = 1; t < 3; ++t)
        for (int c = 0; c < 3; ++c) {
            double ratio = 0;
            const rstats::ZTestResult z = rstats::compareRuns(runs[size_t(t)][size_t(c)], runs[0][size_t(c)], 1e-4, &ratio);
            INFO("tracer " << int(tracers[t]) << " against PT, channel " << c << ": " << z.describe() << ", ratio of means " << ratio);
            CHECK(z.pass);
            CHECK(ratio > 0.5);
        }
}

// pbrt's rgbgrid in a spectral render (SpectralScene::medium, kernels/medium.h): at a voxel's
// centre sigma_t and sigma_s are its RGBs' unbounded spectra at the wavelengths, and at any
// point and wavelengths the majorant grid's cell bounds sigma_t (each voxel's largest value
// over 360-830 nm: a majorant made from the RGB alone would not, an unbounded spectrum
// reaching up to twice its largest component). Random values in [0, 3] on a 3 x 3 x 3 grid.
TEST_CASE("spectral tracers: an RGB grid's spectra at the voxels, and majorants that bound them at any wavelength", "[spectral][media]") {
    const std::string file = rstats::tempDir("spectral-rgbgrid") + "/grid.pbrt";
    chi2::Pcg32 rng(11);
    std::vector<Vec3> a, sc;
    std::string sa, ss;
    for (int i = 0; i < 27; ++i) {
        a.push_back(Vec3(3 * rng.uniform(), 3 * rng.uniform(), 3 * rng.uniform()));
        sc.push_back(Vec3(3 * rng.uniform(), 3 * rng.uniform(), 3 * rng.uniform()));
        for (int c = 0; c < 3; ++c) {
            sa += std::to_string(a.back()[c]) + " ";
            ss += std::to_string(sc.back()[c]) + " ";
        }
    }
    std::ofstream(file) << R"(LookAt 0 0 -5  0 0 0  0 1 0
Camera "perspective"
WorldBegin
LightSource "point" "point3 from" [ 0 3 0 ]
MakeNamedMedium "smoke" "string type" "rgbgrid" "integer nx" 3 "integer ny" 3 "integer nz" 3 "point3 p0" [ -1 -1 -1 ] "point3 p1" [ 1 1 1 ]
  "rgb sigma_a" [ )" << sa
                        << R"(] "rgb sigma_s" [ )" << ss << R"(]
MediumInterface "smoke" ""
Material "interface"
Shape "sphere" "float radius" 2
)";
    const SceneDesc d = loadScene(file);
    REQUIRE(d.media[0].sigmaAGrid.size() == 27);
    for (int i = 0; i < 27; ++i) {  // (the file's numbers as read back)
        a[size_t(i)] = d.media[0].sigmaAGrid[size_t(i)];
        sc[size_t(i)] = d.media[0].sigmaSGrid[size_t(i)];
    }
    const std::unique_ptr<Scene> scene = Scene::build(d, 1);
    const SpectralScene spectra = buildSpectralScene(*scene);
    REQUIRE(spectra.unsupported.empty());
    int above = 0;
    for (int trial = 0; trial < 200; ++trial) {
        Wavelengths w;
        for (int i = 0; i < kWavelengths; ++i) w.lambda[i] = kLambdaMin + (kLambdaMax - kLambdaMin) * rng.uniform();
        const Medium m = spectra.medium(0, scene->media[0], w);
        REQUIRE(m.specSigmaS != nullptr);
        const int v = trial % 27, x = v % 3, y = v / 3 % 3, z = v / 9;
        Vec3 sT, sS;
        gridCoefficients(m, Vec3((x + 0.5f) / 3, (y + 0.5f) / 3, (z + 0.5f) / 3), sT, sS);
        const UnboundedSpectrum us = unboundedSpectrumOfRgb(sc[size_t(v)]), ua = unboundedSpectrumOfRgb(a[size_t(v)]);
        for (int i = 0; i < kWavelengths; ++i) {
            CHECK(sS[i] == Approx(unboundedAt(us, w.lambda[i])).epsilon(1e-5).margin(1e-6));
            CHECK(sT[i] == Approx(unboundedAt(us, w.lambda[i]) + unboundedAt(ua, w.lambda[i])).epsilon(1e-5).margin(1e-6));
        }
        for (int p = 0; p < 50; ++p) {
            const Vec3 q(rng.uniform(), rng.uniform(), rng.uniform());
            gridCoefficients(m, q, sT, sS);
            const int cx = std::min(int(q.x * float(m.mx)), m.mx - 1), cy = std::min(int(q.y * float(m.my)), m.my - 1),
                      cz = std::min(int(q.z * float(m.mz)), m.mz - 1);
            const float majorant = m.majorants[(size_t(cz) * size_t(m.my) + size_t(cy)) * size_t(m.mx) + size_t(cx)] * m.majorantScale;
            CHECK(maxComponent(sT) <= majorant * (1 + 1e-5f));
            CHECK(majorant <= m.majorant);
            const Medium& rgb = scene->media[0];
            if (maxComponent(sT) > rgb.majorants[(size_t(cz) * size_t(rgb.my) + size_t(cy)) * size_t(rgb.mx) + size_t(cx)]) ++above;
        }
    }
    INFO(above << " of 10000 points' spectral sigma_t above their cell's RGB majorant");
    CHECK(above > 0);  // (what a majorant of the RGB alone would have missed)
}

// A Mitsuba medium's constant albedo in a spectral render: sigma_s(l) = albedo(l) sigma_t(l),
// the albedo's reflectance spectrum times sigma_t's unbounded one (Mitsuba 3's scalar_spectral),
// not the RGB product albedo sigma_t uplifted as one unbounded spectrum (what it was: for a
// saturated albedo that differs by more than 10% of sigma_t somewhere in 360-830 nm).
TEST_CASE("spectral tracers: a Mitsuba constant albedo is its reflectance spectrum times sigma_t's", "[spectral][media][mitsuba]") {
    const Vec3 albedo(0.9f, 0.3f, 0.05f), sigmaT(1.0f, 2.0f, 0.5f);
    const SceneDesc d = loadMitsubaFromString(R"(<scene version="3.0.0">
  <medium type="homogeneous" id="fog"><rgb name="albedo" value="0.9, 0.3, 0.05"/><rgb name="sigma_t" value="1, 2, 0.5"/></medium>
  <sensor type="perspective"><ref id="fog"/></sensor>
  <emitter type="point"/>
</scene>)",
                                              "albedo.xml", ".");
    REQUIRE(d.media.size() == 1);
    const std::unique_ptr<Scene> scene = Scene::build(d, 1);
    const SpectralScene spectra = buildSpectralScene(*scene);
    REQUIRE(spectra.unsupported.empty());
    const SigmoidPoly a = sigmoidPolyOfRgb(albedo);
    const UnboundedSpectrum t = unboundedSpectrumOfRgb(sigmaT), product = unboundedSpectrumOfRgb(albedo * sigmaT);
    double productOff = 0;
    chi2::Pcg32 rng(5);
    for (int trial = 0; trial < 200; ++trial) {
        Wavelengths w;
        for (int i = 0; i < kWavelengths; ++i) w.lambda[i] = kLambdaMin + (kLambdaMax - kLambdaMin) * rng.uniform();
        const Medium m = spectra.medium(0, scene->media[0], w);
        for (int i = 0; i < kWavelengths; ++i) {
            const float sT = unboundedAt(t, w.lambda[i]), sS = sigmoidPolyAt(a, w.lambda[i]) * sT;
            CHECK(m.sigmaT[i] == Approx(sT).epsilon(1e-5));
            CHECK(m.sigmaS[i] == Approx(sS).epsilon(1e-5).margin(1e-7));
            productOff = std::max(productOff, double(std::fabs(unboundedAt(product, w.lambda[i]) - sS) / sT));
        }
    }
    INFO("the RGB product's spectrum is off by up to " << productOff << " of sigma_t");
    CHECK(productOff > 0.1);
}

// pbrt's rgbgrid emitting: sigma_a (0.9, 0.25, 0.05) and Le (0.2, 0.6, 1) in every voxel, the
// camera in it, 10 above a black floor (the point light below it lights no path of length 1,
// the only length rendered): each pixel is int Le(l) D(l) (1 - exp(-10 sigma_a(l)))
// cmf / int ybar (Le's and sigma_a's spectra pbrt-v4's RGBIlluminantSpectrum and
// RGBUnboundedSpectrum, D the colour space's illuminant); the RGB product is far from it.
TEST_CASE("spectral tracers: an emitting RGB grid's colour against its closed form, in PT, BPT and MMLT", "[spectral][render][media][stat]") {
    const std::string file = rstats::tempDir("spectral-glow") + "/glow.pbrt";
    std::string sigmaA, sigmaS, Le;
    for (int i = 0; i < 8; ++i) {
        sigmaA += "0.9 0.25 0.05 ";
        sigmaS += "0 0 0 ";
        Le += "0.2 0.6 1 ";
    }
    std::ofstream(file) << R"(MakeNamedMedium "glow" "string type" [ "rgbgrid" ] "integer nx" 2 "integer ny" 2 "integer nz" 2
  "point3 p0" [ -30 -30 -20 ] "point3 p1" [ 30 30 40 ] "rgb sigma_a" [ )"
                        << sigmaA << R"(] "rgb sigma_s" [ )" << sigmaS << R"(] "rgb Le" [ )" << Le << "]" << lookingDownIn("glow")
                        << R"(LightSource "point" "point3 from" [ 0 0 -100 ] "rgb I" [ 1 1 1 ]
Material "diffuse" "rgb reflectance" [ 0 0 0 ]
Shape "trianglemesh" "point3 P" [ -20 -20 0  20 -20 0  20 20 0  -20 20 0 ] "integer indices" [ 0 2 1 0 3 2 ]
)";
    const SceneDesc d = loadScene(file);
    REQUIRE(d.media.size() == 1);
    REQUIRE(d.media[0].LeGrid.size() == 8);
    REQUIRE(spectralUnsupported(d).empty());
    const UnboundedSpectrum sigmaAs = unboundedSpectrumOfRgb(Vec3(0.9f, 0.25f, 0.05f));
    const Vec3 expected = srgbOfSpectrum([&](double l) {
        Wavelengths w;
        for (int i = 0; i < kWavelengths; ++i) w.lambda[i] = float(l);
        return -std::expm1(-10.0 * double(unboundedAt(sigmaAs, float(l)))) * double(rgbIlluminantAt(Vec3(0.2f, 0.6f, 1.0f), w).x);
    });
    const Vec3 rgb(0.2f * -std::expm1(-9.0f), 0.6f * -std::expm1(-2.5f), 1.0f * -std::expm1(-0.5f));
    checkUniform("rgbgrid Le", d, 1, 600, expected, rgb);
}

// A Mitsuba file of a plane (10 x 10 about the origin, facing +z) of BSDF `bsdf` under a
// directional light along `direction` of the narrow-band irradiance `irradiance` (pairs),
// seen straight down by a 16 x 16 orthographic camera; its spectra make it spectral.
SceneDesc planeUnderBands(const std::string& direction, const std::string& irradiance, const std::string& bsdf, const std::string& name) {
    return loadMitsubaFromString(R"(<scene version="3.0.0">
  <sensor type="orthographic">
    <transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
    <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/><rfilter type="box"/></film>
  </sensor>
  <emitter type="directional"><vector name="direction" value=")" +
                                     direction + R"("/><spectrum name="irradiance" value=")" + irradiance + R"("/></emitter>
  <shape type="rectangle"><transform name="to_world"><scale value="10"/></transform>
    )" + bsdf + R"(</shape>
</scene>)",
                                 name, ".");
}

// A Mitsuba file's spectra (which make it render spectrally, as Mitsuba's scalar_spectral): a
// diffuse plane of a narrow-band reflectance R under a directional light of a narrow-band
// irradiance E, seen straight down by an orthographic camera: each pixel is
// int R(l) E(l) / pi cmf(l) dl / int ybar in linear sRGB (R and E linear between their pairs).
// The RGB render's product of the projections is far from it (checked).
TEST_CASE("spectral tracers: a Mitsuba file's reflectance and light spectra against their closed form, in PT, BPT and MMLT",
          "[spectral][render][mitsuba][stat]") {
    const SceneDesc d =
        planeUnderBands("0, 0, -1", "450:0, 500:3, 550:3, 600:0",
                        R"(<bsdf type="diffuse"><spectrum name="reflectance" value="500:0.05, 530:0.9, 580:0.9, 620:0.05"/></bsdf>)", "bands.xml");
    REQUIRE(d.settings.spectral);
    const Vec3 expected = srgbOfSpectrum([&](double l) {
        return pairsAt(l, {{500, 0.05}, {530, 0.9}, {580, 0.9}, {620, 0.05}}) * pairsAt(l, {{450, 0}, {500, 3}, {550, 3}, {600, 0}}) / kPi;
    });
    checkUniform("narrow bands", d, 2, 700, expected, d.materials[0].diffuse * d.lights[0].radiance * (1.0f / kPi));
}

// Mitsuba's principled renders spectrally: its base colour at the path's wavelengths, its
// tints the base over the RGB base's luminance Y (docs/spectral.md). A plane of spec_trans 1
// and spec_tint 1 (no diffuse: the main lobe's reflection is Schlick's of c_tint R0, c_tint =
// base / Y) of a narrow-band base under a directional light of a narrow-band irradiance E at
// 60 degrees, seen straight down: each pixel is int f(l) E(l) cos cmf / int ybar in linear
// sRGB, f(l) the kernel's principledF with the base base(l) and Y (bsdf_principled.cpp,
// checked against Mitsuba 3's closed form in test_bsdf_principled.cpp).
TEST_CASE("spectral tracers: a Mitsuba principled material's tinted reflection against its closed form, in PT, BPT and MMLT",
          "[spectral][render][mitsuba][principled][stat]") {
    const SceneDesc d = planeUnderBands("-0.8660254, 0, -0.5", "450:0, 500:3, 560:3, 620:0",
                                        R"(<bsdf type="principled"><spectrum name="base_color" value="500:0.05, 530:0.9, 580:0.9, 620:0.05"/>
      <float name="spec_trans" value="1"/><float name="spec_tint" value="1"/><float name="roughness" value="0.4"/></bsdf>)",
                                        "principled.xml");
    REQUIRE(d.settings.spectral);
    REQUIRE(spectralUnsupported(d).empty());
    const std::unique_ptr<Scene> scene = Scene::build(d, 1);
    const float Y = principledLuminance(d.materials[0].diffuse);
    const Vec3 wo(0, 0, 1), wi(0.8660254f, 0, 0.5f);
    auto f = [&](Vec3 base, float tintY) {
        BsdfParams m = scene->materials[0];
        m.diffuse = base;
        setPrincipledTintLuminance(m, tintY);
        return principledF(m, wo, wi);
    };
    const Vec3 expected = srgbOfSpectrum([&](double l) {
        const double base = pairsAt(l, {{500, 0.05}, {530, 0.9}, {580, 0.9}, {620, 0.05}});
        return double(f(Vec3(float(base)), Y).x) * pairsAt(l, {{450, 0}, {500, 3}, {560, 3}, {620, 0}}) * 0.5;
    });
    checkUniform("principled", d, 2, 1100, expected, f(d.materials[0].diffuse, 0) * d.lights[0].radiance * 0.5f);
}

// pbrt's mix renders spectrally as pbrt-v4 renders it: one part per hit (part 1 with
// probability amount, by a hash of the point), each part's colours at the path's
// wavelengths. A floor of a mix (amount 0.3) of two diffuse materials of narrow-band
// reflectances R_0, R_1 under a white sky (rgb L 1: the colour space's illuminant D), seen
// straight down: each pixel is int ((1 - a) R_0 + a R_1) D cmf / int ybar in linear sRGB;
// the RGB blend of the parts' projections is far from it (checked).
TEST_CASE("spectral tracers: pbrt's mix of two spectral reflectances against its closed form, in PT, BPT and MMLT",
          "[spectral][render][blend][stat]") {
    const std::string file = rstats::tempDir("spectral-mix") + "/mix.pbrt";
    std::ofstream(file) << R"(LookAt 0 5 0  0 0 0  0 0 1
Camera "orthographic"
Film "rgb" "integer xresolution" [ 16 ] "integer yresolution" [ 16 ]
PixelFilter "box"
Integrator "path" "integer maxdepth" [ 1 ]
WorldBegin
LightSource "infinite" "rgb L" [ 1 1 1 ]
MakeNamedMaterial "a" "string type" "diffuse" "spectrum reflectance" [ 400 0.02 495 0.02 505 0.95 520 0.95 530 0.02 700 0.02 ]
MakeNamedMaterial "b" "string type" "diffuse" "spectrum reflectance" [ 400 0.02 590 0.02 600 0.95 615 0.95 625 0.02 700 0.02 ]
Material "mix" "string materials" [ "a" "b" ] "float amount" 0.3
Shape "trianglemesh" "point3 P" [ -20 0 -20  20 0 -20  20 0 20  -20 0 20 ] "integer indices" [ 0 2 1 0 3 2 ]
)";
    const SceneDesc d = loadScene(file);
    REQUIRE(d.settings.spectral);
    const MaterialDesc& mix = d.materials[size_t(d.shapes[0].material)];
    REQUIRE(mix.kind == MaterialKind::Blend);
    REQUIRE(blendChoosesPart(d.materials, mix));
    REQUIRE(spectralUnsupported(d).empty());
    const double a = 0.3;
    const Vec3 expected = srgbOfSpectrum([&](double l) {
        Wavelengths w;
        for (int i = 0; i < kWavelengths; ++i) w.lambda[i] = float(l);
        const double R0 = pairsAt(l, {{400, 0.02}, {495, 0.02}, {505, 0.95}, {520, 0.95}, {530, 0.02}, {700, 0.02}});
        const double R1 = pairsAt(l, {{400, 0.02}, {590, 0.02}, {600, 0.95}, {615, 0.95}, {625, 0.02}, {700, 0.02}});
        return ((1 - a) * R0 + a * R1) * double(rgbIlluminantAt(Vec3(1.0f), w).x);
    });
    const Vec3 rgb = d.materials[size_t(mix.blendPart[0])].diffuse * float(1 - a) + d.materials[size_t(mix.blendPart[1])].diffuse * float(a);
    checkUniform("pbrt mix", d, 2, 900, expected, rgb);
}

// A spectral Mitsuba file's blendbsdf renders spectrally, one part per hit (part 1 with
// probability weight, docs/spectral.md): the linear blend's mean. Two diffuse parts of
// narrow-band reflectances R_0, R_1 (weight 0.3) under the narrow-band directional light E
// of the test above: each pixel is int ((1 - w) R_0 + w R_1) E / pi cmf / int ybar.
TEST_CASE("spectral tracers: a spectral Mitsuba file's blendbsdf against its closed form, in PT, BPT and MMLT",
          "[spectral][render][mitsuba][blend][stat]") {
    const SceneDesc d = planeUnderBands("0, 0, -1", "450:0, 500:3, 550:3, 600:0", R"(<bsdf type="blendbsdf"><float name="weight" value="0.3"/>
      <bsdf type="diffuse"><spectrum name="reflectance" value="450:0.02, 480:0.95, 500:0.95, 510:0.02"/></bsdf>
      <bsdf type="diffuse"><spectrum name="reflectance" value="500:0.02, 540:0.95, 560:0.95, 580:0.02"/></bsdf></bsdf>)",
                                        "blend.xml");
    REQUIRE(d.settings.spectral);
    REQUIRE(spectralUnsupported(d).empty());
    const MaterialDesc& blend = d.materials[size_t(d.shapes[0].material)];
    const double w = 0.3;
    const Vec3 expected = srgbOfSpectrum([&](double l) {
        const double R0 = pairsAt(l, {{450, 0.02}, {480, 0.95}, {500, 0.95}, {510, 0.02}});
        const double R1 = pairsAt(l, {{500, 0.02}, {540, 0.95}, {560, 0.95}, {580, 0.02}});
        return ((1 - w) * R0 + w * R1) * pairsAt(l, {{450, 0}, {500, 3}, {550, 3}, {600, 0}}) / kPi;
    });
    const Vec3 R = d.materials[size_t(blend.blendPart[0])].diffuse * float(1 - w) + d.materials[size_t(blend.blendPart[1])].diffuse * float(w);
    checkUniform("blendbsdf", d, 2, 1300, expected, R * d.lights[0].radiance * (1.0f / kPi));
}

// An RGB Mitsuba file's blendbsdf is the linear blend in RGB renders (its parts constants the
// spectral stage never sees) and one part per hit in spectral ones: render() resolves it
// (resolveBlendsForSpectral); a scene built for RGB and rendered with spectral asked renders
// in RGB and says why.
TEST_CASE("spectral tracers: a linear blend renders spectrally through render(), in RGB from a scene built without resolving it",
          "[spectral][blend]") {
    const SceneDesc d = loadMitsubaFromString(R"(<scene version="3.0.0">
  <sensor type="orthographic"><film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film></sensor>
  <emitter type="constant"/>
  <shape type="rectangle"><bsdf type="blendbsdf"><bsdf type="diffuse"/><bsdf type="roughconductor"/></bsdf></shape>
</scene>)",
                                              "rgb-blend.xml", ".");
    REQUIRE(!d.settings.spectral);
    REQUIRE(!blendChoosesPart(d.materials, d.materials[size_t(d.shapes[0].material)]));
    REQUIRE(spectralUnsupported(d).empty());
    RenderOptions o = rstats::renderOptions(TracerKind::PT, 1, 0, 1, 2);
    o.spectral = true;
    const RenderResult r = render(d, o);
    CHECK(r.stats.spectral);
    CHECK(r.stats.spectralReason.empty());
    const std::unique_ptr<Scene> scene = Scene::build(d, 1);
    const RenderResult rgb = renderScene(*scene, o);
    CHECK(!rgb.stats.spectral);
    CHECK(rgb.stats.spectralReason == "the scene has a linear blend material (not spectral yet): rendered in RGB");
}

// The wavelengths are a primary-sample number of MMLT's and PSSMLT's chains (the row's last),
// mutated like any other: a seed gives one image for any thread count, and every replayed seed
// (its wavelengths, its dispersion) gives back its pool entry bit for bit.
TEST_CASE("spectral tracers: MMLT and PSSMLT replay exactly and give one image for any thread count", "[spectral][render][mmlt]") {
    SceneDesc d = loadScene(bk7Scene("LookAt 0.5 1.4 1.6  0.5 0.2 0  0 1 0", 50));
    d.settings.maxPathLength = 6;
    for (TracerKind t : {TracerKind::MMLT, TracerKind::PSSMLT}) {
        std::vector<float> first;
        for (int threads : {1, 2}) {
            RenderOptions o = rstats::renderOptions(t, 64, 7, 1, 6, threads);
            o.spectral = true;
            o.chains = 512;
            const RenderResult r = render(d, o);
            REQUIRE(r.stats.spectral);
            CHECK(r.stats.mmlt.replayMismatches == 0);
            if (first.empty()) first = r.image.rgb;
            else CHECK(r.image.rgb == first);
        }
    }
}
