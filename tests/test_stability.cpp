// Numerical stability of every tracer (the issue: "paths of length 64, light intensities
// 1e-6 and 1e6, grazing angles: no NaN, no Inf, every discarded sample counted in
// --stats"; scene-format.md, "Extremes the format must survive"):
//  1. long paths: a closed box of 0.95-0.99 albedo walls with glass, mirror and glossy
//     objects, MaxPathLength 64: every pixel finite and >= 0, NaN/Inf discards counted
//     (and none here), the mean luminance by length finite, >= 0, adding up to the
//     image's mean, and paths of length 40-64 carrying energy;
//  2. light intensities 2^-20, 1 and 2^20 (about 1e-6 and 1e6) at MaxPathLength 64: the
//     same seed gives the same paths, so the image scales with the intensity bit for bit;
//  3. grazing angles: a camera 89.5-89.99 degrees from the normal of a large plane (Matte,
//     Glossy with Shininess 1e5, Reflective, Dielectric with IOR 1.5, 4 and 1.0001),
//     lights at grazing angles, and a smooth-shaded low-poly mesh whose shading normals
//     differ strongly from the geometric ones (plus bent vertex normals 80 degrees off
//     and a degenerate triangle);
//  4. an environment map (scaled by 1e-6, 1 and 1e6) at MaxPathLength 64.
// Every test loops over kTracers, MMLT included.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "render_stats.h"
#include "wavemmlt/image.h"
#include "wavemmlt/render.h"
#include "wavemmlt/scene_desc.h"

using namespace wmlt;

namespace {

// The tracers under test.
struct TracerCase {
    TracerKind kind;
    const char* name;
};
const std::vector<TracerCase> kTracers = {{TracerKind::PT, "pt"}, {TracerKind::LT, "lt"}, {TracerKind::BPT, "bpt"}, {TracerKind::MMLT, "mmlt"}};

// Options for tracer t: MMLT with 256 chains and a bootstrap of 512 samples per length.
RenderOptions optionsFor(const TracerCase& t, int spp, uint64_t seed, int maxLength) {
    RenderOptions o = rstats::renderOptions(t.kind, spp, seed, 1, maxLength);
    o.chains = 256;
    o.bootstrap = 512;
    return o;
}

// What a render must satisfy whatever the scene: every pixel finite and >= 0, nothing
// discarded (none of these scenes makes a NaN or Inf contribution), the per-length luminance finite, >= 0 and summing to the image's mean
// luminance (both leave out the same discarded contributions: a contribution counted in
// one but not the other would break the sum). Returns the image's mean luminance.
double checkRender(const RenderResult& r, const std::string& label, int spp) {
    INFO(label);
    const Image& im = r.image;
    const size_t pixels = size_t(im.width) * im.height;
    size_t nonfinite = 0, negative = 0;
    double lumSum = 0;
    for (size_t i = 0; i < pixels; ++i) {
        Vec3 c(im.rgb[i * 3], im.rgb[i * 3 + 1], im.rgb[i * 3 + 2]);
        for (int k = 0; k < 3; ++k) {
            float v = im.rgb[i * 3 + k];
            if (!std::isfinite(v)) ++nonfinite;
            else if (v < 0) ++negative;
        }
        lumSum += double(luminance(c));
    }
    const double meanLum = lumSum / double(pixels);
    const double samples = double(pixels) * spp;
    INFO(label << ": samplesNonfiniteDiscarded = " << r.stats.samplesNonfiniteDiscarded << " of " << samples << " pixel samples; mean luminance "
               << meanLum << "; " << r.stats.seconds << " s");
    CHECK(nonfinite == 0);
    CHECK(negative == 0);
    CHECK(r.stats.samplesNonfiniteDiscarded == 0);
    CHECK(r.stats.spp >= uint64_t(spp));

    const std::vector<double>& L = r.stats.lengthMeanLuminance;
    REQUIRE(L.size() == size_t(kMaxPathLength) + 1);
    double byLength = 0;
    bool lengthsOk = true;
    for (size_t k = 1; k < L.size(); ++k) {
        lengthsOk = lengthsOk && std::isfinite(L[k]) && L[k] >= 0;
        byLength += L[k];
    }
    INFO("mean luminance by length: sum " << byLength << ", image " << meanLum);
    CHECK(lengthsOk);
    // Float image (rounded from double sums) against double per-length sums.
    CHECK(std::fabs(byLength - meanLum) <= 1e-4 * std::max(meanLum, 1e-300));
    return meanLum;
}

// ---- scenes -------------------------------------------------------------------------------

// A closed box [-1, 1] x [0, 2] x [-1, 1] (planes made 1% larger so the edges overlap: no
// cracks) with high-albedo Matte walls, a glossy floor, a glass ball, a mirror ball and a
// small sphere light. Almost no path escapes: energy reaches length 64.
std::string boxXml(const std::string& intensity) {
    return R"(<Scene>
  <Settings><Width value="32"/><Height value="32"/><MaxPathLength value="64"/><MinPathLength value="1"/></Settings>
  <Camera Type="Camera"><Position x="0" y="1" z="-0.9"/><LookAt x="0" y="0.8" z="1"/><FOV value="75"/></Camera>
  <Shader Type="Matte" ID="0"><Diffuse r="0.97" g="0.97" b="0.97"/></Shader>
  <Shader Type="Matte" ID="1"><Diffuse r="0.99" g="0.95" b="0.95"/></Shader>
  <Shader Type="Matte" ID="2"><Diffuse r="0.95" g="0.99" b="0.95"/></Shader>
  <Shader Type="Glossy" ID="3"><Diffuse r="0.5" g="0.5" b="0.5"/><Specular r="0.48" g="0.48" b="0.48"/>
    <Shininess value="200"/></Shader>
  <Shader Type="Dielectric" ID="4"><Reflect r="1" g="1" b="1"/><Refract r="1" g="1" b="1"/>
    <iIOR value="1.5"/><oIOR value="1"/></Shader>
  <Shader Type="Reflective" ID="5"><Reflect r="0.98" g="0.98" b="0.98"/></Shader>
  <Geometry Type="Plane" ID="floor"><Position x="0" y="0" z="0"/><Width value="2.02"/><Depth value="2.02"/><Shader value="3"/></Geometry>
  <Geometry Type="Plane" ID="ceiling"><Position x="0" y="2" z="0"/><Rotation x="0" y="0" z="180"/><Width value="2.02"/><Depth value="2.02"/><Shader value="0"/></Geometry>
  <Geometry Type="Plane" ID="left"><Position x="-1" y="1" z="0"/><Rotation x="0" y="0" z="-90"/><Width value="2.02"/><Depth value="2.02"/><Shader value="1"/></Geometry>
  <Geometry Type="Plane" ID="right"><Position x="1" y="1" z="0"/><Rotation x="0" y="0" z="90"/><Width value="2.02"/><Depth value="2.02"/><Shader value="2"/></Geometry>
  <Geometry Type="Plane" ID="back"><Position x="0" y="1" z="1"/><Rotation x="-90" y="0" z="0"/><Width value="2.02"/><Depth value="2.02"/><Shader value="0"/></Geometry>
  <Geometry Type="Plane" ID="front"><Position x="0" y="1" z="-1"/><Rotation x="90" y="0" z="0"/><Width value="2.02"/><Depth value="2.02"/><Shader value="0"/></Geometry>
  <Geometry Type="Sphere" ID="glass"><Position x="0.35" y="0.35" z="0.3"/><Radius value="0.3"/><Shader value="4"/></Geometry>
  <Geometry Type="Sphere" ID="mirror"><Position x="-0.45" y="0.3" z="0.45"/><Radius value="0.28"/><Shader value="5"/></Geometry>
  <Light Type="Area" ID="lamp"><Position x="0" y="1.75" z="0.2"/><Radius value="0.08"/>
    <Intensity value=")" +
           intensity + R"("/><Colour r="1" g="1" b="1"/></Light>
</Scene>
)";
}

// A low-poly UV sphere (radius 1, 6 segments around, 4 bands) with unit vertex normals:
// at the silhouette the interpolated shading normal is up to ~30 degrees off the facet's
// normal. A second object: a quad whose vertex normals lean 80-85 degrees away from its
// face normal in different directions, one degenerate (zero-area) triangle and a
// duplicated vertex.
std::string lowPolySphereObj() {
    std::ostringstream o;
    const int nu = 6, nv = 4;
    const double pi = 3.14159265358979323846;
    o << "o sphere\nv 0 1 0\nvn 0 1 0\n";  // 1: north pole
    for (int j = 1; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            double th = pi * j / nv, ph = 2 * pi * i / nu;
            double x = std::sin(th) * std::cos(ph), y = std::cos(th), z = std::sin(th) * std::sin(ph);
            o << "v " << x << " " << y << " " << z << "\nvn " << x << " " << y << " " << z << "\n";
        }
    o << "v 0 -1 0\nvn 0 -1 0\n";  // south pole: index 2 + nu (nv - 1)
    auto ring = [&](int j, int i) { return 2 + (j - 1) * nu + (i % nu); };
    const int south = 2 + nu * (nv - 1);
    // Counter-clockwise seen from outside (outward winding).
    for (int i = 0; i < nu; ++i) o << "f 1//1 " << ring(1, i + 1) << "//" << ring(1, i + 1) << " " << ring(1, i) << "//" << ring(1, i) << "\n";
    for (int j = 1; j < nv - 1; ++j)
        for (int i = 0; i < nu; ++i) {
            int a = ring(j, i), b = ring(j, i + 1), c = ring(j + 1, i + 1), d = ring(j + 1, i);
            o << "f " << a << "//" << a << " " << b << "//" << b << " " << c << "//" << c << "\n";
            o << "f " << a << "//" << a << " " << c << "//" << c << " " << d << "//" << d << "\n";
        }
    for (int i = 0; i < nu; ++i)
        o << "f " << south << "//" << south << " " << ring(nv - 1, i) << "//" << ring(nv - 1, i) << " " << ring(nv - 1, i + 1) << "//"
          << ring(nv - 1, i + 1) << "\n";
    // The bent quad at y = 0 (face normal +y), x, z in [1.5, 3.5]: vertex normals 80-85
    // degrees from +y, leaning outwards in four directions.
    const int base = south;  // positions and normals so far
    o << "o bent\n";
    o << "v 1.5 0 1.5\nv 3.5 0 1.5\nv 3.5 0 3.5\nv 1.5 0 3.5\nv 3.5 0 3.5\n";  // the 5th duplicates the 3rd
    o << "vn -0.70 0.15 -0.70\nvn 0.70 0.12 -0.70\nvn 0.70 0.09 0.70\nvn -0.70 0.15 0.70\nvn 0.70 0.09 0.70\n";
    auto c = [&](int k) { return std::to_string(base + k) + "//" + std::to_string(base + k); };
    o << "f " << c(1) << " " << c(4) << " " << c(3) << "\n";
    o << "f " << c(1) << " " << c(5) << " " << c(2) << "\n";  // uses the duplicate
    o << "f " << c(1) << " " << c(3) << " " << c(5) << "\n";  // degenerate: zero area
    return o.str();
}

// The grazing scene: a 400 x 400 plane at y = 0 seen from 0.05 above it, the view's
// centre 89.5 degrees from the normal and its far rows within 0.03 degrees of the
// horizon (89.97 degrees); a rectangle light standing almost perpendicular to the plane
// (its normal 0.1 degrees above the horizon), a sphere light low on the horizon and cut
// by the plane, and a tiny, very bright sphere light (Intensity 2e5) 0.01 above the
// mesh's bent quad, lighting it and the mesh ball at 2.5-3.5 degrees elevation; on the
// plane a smooth low-poly mesh ball (glossy), a glass ball and a mirror ball.
std::string grazingXml(const std::string& planeShader) {
    return R"(<Scene>
  <Settings><Width value="32"/><Height value="32"/><MaxPathLength value="64"/></Settings>
  <Camera Type="Camera"><Position x="0" y="0.05" z="0"/><LookAt x="0" y="0" z="5.7294"/><FOV value="4"/></Camera>
  <Shader Type="Matte" ID="0"><Diffuse r="0.8" g="0.8" b="0.8"/></Shader>
  <Shader Type="Glossy" ID="1"><Diffuse r="0.15" g="0.15" b="0.15"/><Specular r="0.85" g="0.85" b="0.85"/>
    <Shininess value="100000"/></Shader>
  <Shader Type="Reflective" ID="2"><Reflect r="0.95" g="0.95" b="0.95"/></Shader>
  <Shader Type="Dielectric" ID="3"><Reflect r="1" g="1" b="1"/><Refract r="1" g="1" b="1"/>
    <iIOR value="1.5"/><oIOR value="1"/></Shader>
  <Shader Type="Glossy" ID="4"><Diffuse r="0.3" g="0.2" b="0.1"/><Specular r="0.6" g="0.6" b="0.6"/>
    <Shininess value="1000"/></Shader>
  <Shader Type="Dielectric" ID="5"><Reflect r="1" g="1" b="1"/><Refract r="1" g="1" b="1"/>
    <iIOR value="4"/><oIOR value="1"/></Shader>
  <Shader Type="Dielectric" ID="6"><Reflect r="1" g="1" b="1"/><Refract r="1" g="1" b="1"/>
    <iIOR value="1.0001"/><oIOR value="1"/></Shader>
  <Geometry Type="Plane" ID="ground"><Position x="0" y="0" z="0"/><Width value="400"/><Depth value="400"/><Shader value=")" +
           planeShader + R"("/></Geometry>
  <Geometry Type="ObjFile" ID="mesh"><Position x="-0.02" y="0.03" z="2"/><Scale value="0.03"/>
    <File name="lowpoly.obj"/><SmoothShading value="1"/><Shader value="4"/></Geometry>
  <Geometry Type="Sphere" ID="glass"><Position x="0.05" y="0.02" z="2.5"/><Radius value="0.02"/><Shader value="3"/></Geometry>
  <Geometry Type="Sphere" ID="mirror"><Position x="0.12" y="0.03" z="3.5"/><Radius value="0.03"/><Shader value="2"/></Geometry>
  <Light Type="Area" ID="wall"><Position x="0" y="1" z="60"/><Rotation x="-89.9" y="0" z="0"/><Width value="40"/><Depth value="2"/>
    <Intensity value="3"/><Colour r="1" g="0.95" b="0.9"/></Light>
  <Light Type="Area" ID="sun"><Position x="-30" y="0.5" z="80"/><Radius value="2"/>
    <Intensity value="20"/><Colour r="1" g="1" b="1"/></Light>
  <Light Type="Area" ID="lamp"><Position x="0.25" y="0.04" z="2.075"/><Radius value="0.008"/>
    <Intensity value="2e5"/><Colour r="1" g="1" b="1"/></Light>
</Scene>
)";
}

// An open scene under an environment map (the sky with a sun, render_stats.h) with a
// glass ball, a mirror ball and a matte ball on a floor, MaxPathLength 64.
const std::string kEnvXml = R"(<Scene>
  <Settings><Width value="32"/><Height value="24"/><MaxPathLength value="64"/><EnvMap name="sky.pfm"/></Settings>
  <Camera Type="Camera"><Position x="0" y="1.2" z="-4"/><LookAt x="0" y="0.5" z="0"/><FOV value="45"/></Camera>
  <Shader Type="Matte" ID="0"><Diffuse r="0.9" g="0.85" b="0.8"/></Shader>
  <Shader Type="Dielectric" ID="1"><Reflect r="1" g="1" b="1"/><Refract r="1" g="1" b="1"/>
    <iIOR value="1.5"/><oIOR value="1"/></Shader>
  <Shader Type="Reflective" ID="2"><Reflect r="0.95" g="0.95" b="0.95"/></Shader>
  <Geometry Type="Plane" ID="floor"><Position x="0" y="0" z="0"/><Width value="4"/><Depth value="4"/><Shader value="0"/></Geometry>
  <Geometry Type="Sphere" ID="ball"><Position x="-0.6" y="0.5" z="0.3"/><Radius value="0.5"/><Shader value="0"/></Geometry>
  <Geometry Type="Sphere" ID="glass"><Position x="0.5" y="0.4" z="-0.4"/><Radius value="0.4"/><Shader value="1"/></Geometry>
  <Geometry Type="Sphere" ID="mirror"><Position x="0.7" y="0.5" z="0.8"/><Radius value="0.5"/><Shader value="2"/></Geometry>
</Scene>
)";

}  // namespace

// ---- 1. long paths ------------------------------------------------------------------------

TEST_CASE("Stability: paths of length 64 in a closed high-albedo box stay finite", "[stability]") {
    const SceneDesc desc = loadSceneFromString(boxXml("1"), "box.xml", ".");
    const int spp = 16;
    for (const TracerCase& t : kTracers) {
        RenderResult r = render(desc, optionsFor(t, spp, 64, 64));
        const std::string label = std::string("box, MaxPathLength 64, ") + t.name;
        INFO(label);
        const double mean = checkRender(r, label, spp);
        CHECK(mean > 0);
        CHECK(r.stats.samplesNonfiniteDiscarded == 0);
        // Energy in long paths: with walls of albedo ~0.97 a path loses only ~3% per
        // bounce, so lengths 40-64 carry a clear share of the image.
        const std::vector<double>& L = r.stats.lengthMeanLuminance;
        int lit = 0;
        double longShare = 0;
        for (int k = 40; k <= 64; ++k) {
            lit += L[k] > 0;
            longShare += L[k];
        }
        INFO(label << ": lengths 40-64 with energy: " << lit << " of 25, their share of the mean: " << longShare / mean << "; L[64] = " << L[64]);
        CHECK(lit >= 20);
        CHECK(L[64] > 0);
        CHECK(longShare > 1e-3 * mean);
    }
}

// ---- 2. light intensities -----------------------------------------------------------------

// With the same seed, each sample's random numbers are the same for any light intensity
// (rng.h: a hash of seed, pixel, sample and dimension). Every decision a tracer takes is
// independent of the light's scale:
//  - PT: Russian roulette on the camera throughput, which does not contain Le;
//  - LT and BPT light subpaths: roulette on max(beta) / max(beta_0), a ratio in which
//    Le cancels (lt_stages.cpp sampleLightBsdfs, bpt_stages.cpp sampleBptBsdfs);
//  - MMLT: acceptance on c' / c, a ratio in which Le cancels;
//  - light choice in proportion to power: one light here, so its pmf is 1;
//  - MIS weights: ratios of densities, no radiance.
// With intensities 2^-20 and 2^20 (about 1e-6 and 1e6) every float that carries Le is
// scaled by a power of two, which commutes with rounding (no value here comes near the
// float range's ends), and the ratios above are bit-identical: so is every decision, and
// the image divided by the intensity is the same bit for bit, for every tracer.
TEST_CASE("Stability: the image scales linearly with light intensity 1e-6 and 1e6", "[stability]") {
    const int spp = 4;
    for (const TracerCase& t : kTracers) {
        std::vector<float> base;
        for (int e : {0, 20, -20}) {
            char intensity[32];
            std::snprintf(intensity, sizeof intensity, "%.17g", std::ldexp(1.0, e));
            SceneDesc desc = loadSceneFromString(boxXml(intensity), "box.xml", ".");
            desc.settings.width = 16;
            desc.settings.height = 16;
            REQUIRE(desc.lights.size() == 1);
            REQUIRE(desc.lights[0].radiance.x == std::ldexp(1.0f, e));
            RenderResult r = render(desc, optionsFor(t, spp, 1234, 64));
            const std::string label = std::string("box, intensity 2^") + std::to_string(e) + ", " + t.name;
            INFO(label);
            const double mean = checkRender(r, label, spp);
            CHECK(mean > 0);
            std::vector<float> v = r.image.rgb;
            for (float& x : v) x = std::ldexp(x, -e);
            if (base.empty()) {
                base = v;
                continue;
            }
            size_t differ = 0, first = 0;
            for (size_t i = 0; i < v.size(); ++i)
                if (v[i] != base[i] && differ++ == 0) first = i;
            INFO(label << ": image / 2^" << e << " differs from the image at intensity 1 in " << differ << " values (the first: " << v[first]
                       << " vs " << base[first] << ")");
            CHECK(differ == 0);
        }
    }
}

// ---- 3. grazing angles --------------------------------------------------------------------

TEST_CASE("Stability: grazing angles, a smooth low-poly mesh and bent normals stay finite", "[stability]") {
    const std::string dir = rstats::tempDir("stability-grazing");
    {
        std::ofstream f(dir + "/lowpoly.obj");
        f << lowPolySphereObj();
    }
    const int spp = 64;
    const char* shaders[] = {"0", "1", "2", "3", "5", "6"};
    const char* names[] = {"Matte", "Glossy 1e5", "Reflective", "Dielectric 1.5", "Dielectric 4", "Dielectric 1.0001"};
    for (int m = 0; m < 6; ++m) {
        const SceneDesc desc = loadSceneFromString(grazingXml(shaders[m]), "grazing.xml", dir);
        for (const TracerCase& t : kTracers) {
            RenderResult r = render(desc, optionsFor(t, spp, 89 + m, 64));
            const std::string label = std::string("grazing plane ") + names[m] + ", " + t.name;
            INFO(label);
            const double mean = checkRender(r, label, spp);
            CHECK(mean > 0);
        }
    }
    // The bent quad seen from above at a grazing light: shading normals 80-85 degrees off
    // the geometric one (and a degenerate triangle in the same mesh).
    {
        std::string xml = grazingXml("0");
        const std::string from = R"(<Camera Type="Camera"><Position x="0" y="0.05" z="0"/><LookAt x="0" y="0" z="5.7294"/><FOV value="4"/></Camera>)";
        const std::string to =
            R"(<Camera Type="Camera"><Position x="0.055" y="0.2" z="2.075"/><LookAt x="0.055" y="0.03" z="2.075"/><Up x="0" y="0" z="1"/><FOV value="40"/></Camera>)";
        REQUIRE(xml.find(from) != std::string::npos);
        xml.replace(xml.find(from), from.size(), to);
        const SceneDesc desc = loadSceneFromString(xml, "bent.xml", dir);
        for (const TracerCase& t : kTracers) {
            RenderResult r = render(desc, optionsFor(t, spp, 7, 64));
            const std::string label = std::string("bent normals from above, ") + t.name;
            INFO(label);
            const double mean = checkRender(r, label, spp);
            CHECK(mean > 0);
        }
    }
    std::filesystem::remove_all(dir);
}

// ---- 4. environment map -------------------------------------------------------------------

TEST_CASE("Stability: an environment map scaled by 1e-6, 1 and 1e6 at MaxPathLength 64", "[stability]") {
    const std::string dir = rstats::tempDir("stability-env");
    writeImage(dir + "/sky.pfm", rstats::skyWithSun());
    const SceneDesc base = loadSceneFromString(kEnvXml, "env.xml", dir);
    const int spp = 64;
    for (float scale : {1.0f, 1e6f, 1e-6f}) {
        SceneDesc desc = base;
        for (float& v : desc.envMap.rgb) v *= scale;
        for (const TracerCase& t : kTracers) {
            RenderResult r = render(desc, optionsFor(t, spp, 33, 64));
            std::ostringstream label;
            label << "environment x " << scale << ", " << t.name;
            INFO(label.str());
            const double mean = checkRender(r, label.str(), spp);
            CHECK(mean > 0);
            CHECK(r.stats.samplesNonfiniteDiscarded == 0);
        }
    }
    std::filesystem::remove_all(dir);
}
