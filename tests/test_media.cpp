// Participating media (docs/media.md): the kernels (free-path sampling's weights, the
// Henyey-Greenstein phase function), then the path tracer against closed forms on scenes
// read from pbrt-v4 files: transmittance through an absorbing slab behind pass-through
// boundaries, single scattering of a point light in an infinite medium, and white furnaces
// (an albedo-1 medium in a uniformly emitting enclosure: radiance L everywhere), with the
// camera in the medium and with the medium in a box of pass-through boundaries.
#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "kernels/camera.h"
#include "kernels/medium.h"
#include "media_scenes.h"
#include "render_stats.h"
#include "scene/pbrt/subsurface_albedo.h"
#include "wavemmlt/error.h"
#include "wavemmlt/render.h"
#include "wavemmlt/scene_desc.h"

using namespace wmlt;

namespace {

std::string dir() {
    static const std::string d = rstats::tempDir("media");
    return d;
}
SceneDesc loadText(const std::string& name, const std::string& text) { return media_scenes::load(name, text); }
// The message a Mitsuba scene's loading fails with (read as "bad.xml"), or "no error".
std::string mitsubaError(const std::string& xml) {
    try {
        loadMitsubaFromString(xml, "bad.xml", dir());
    } catch (const InputError& e) {
        return e.what();
    }
    return "no error";
}
std::string errorOf(const std::string& name, const std::string& text) {
    try {
        loadText(name, text);
    } catch (const InputError& e) {
        return e.what();
    }
    return "no error";
}

double blockMean(const std::vector<double>& v) {
    double s = 0;
    for (double x : v) s += x;
    return s / double(v.size());
}

}  // namespace

TEST_CASE("media kernels: free-path weights and the Henyey-Greenstein phase function", "[media][kernel]") {
    // E[weight] over u: past tMax the weight's mean is T(tMax), and sigma_s T(t) / p(t)
    // integrates to sigma_s int_0^tMax T dt = sigma_s (1 - T(tMax)) / sigma_t per channel.
    Medium m;
    m.sigmaS = Vec3(0.5f, 0.3f, 0.1f);
    m.sigmaT = m.sigmaS + Vec3(0.1f, 0.2f, 0.4f);
    const float tMax = 1.7f;
    const int n = 200000;
    double pass[3] = {0, 0, 0}, scatter[3] = {0, 0, 0};
    for (int i = 0; i < n; ++i) {
        const FreePath fp = sampleFreePath(m, tMax, (float(i) + 0.5f) / float(n));
        for (int c = 0; c < 3; ++c) (fp.scattered ? scatter : pass)[c] += double(fp.weight[c]) / n;
        if (fp.scattered) CHECK_FALSE(fp.t >= tMax);
    }
    const Vec3 T = transmittance(m, tMax);
    for (int c = 0; c < 3; ++c) {
        CHECK(pass[c] == Approx(T[c]).epsilon(1e-4));
        CHECK(scatter[c] == Approx(m.sigmaS[c] * (1 - T[c]) / m.sigmaT[c]).epsilon(2e-3));
    }
    // a channel with sigma_t = 0 never scatters and always passes with weight T / P
    Medium clear;
    clear.sigmaT = clear.sigmaS = Vec3(0.0f, 1.0f, 0.0f);
    const FreePath fp = sampleFreePath(clear, INFINITY, 0.1f);  // channel 0: t = infinity
    CHECK_FALSE(fp.scattered);
    CHECK(fp.weight.x == Approx(1.5f));  // T = (1, 0, 1), P = 2/3
    CHECK(fp.weight.y == 0.0f);
    // HG: normalised, its sampling's density is itself, and g is its mean cosine with -wo
    for (float g : {0.0f, 0.5f, -0.7f, 0.95f}) {
        double norm = 0, meanCos = 0;
        const int k = 200000;
        for (int i = 0; i < k; ++i) {
            const float c = -1.0f + 2.0f * (float(i) + 0.5f) / float(k);
            norm += 2 * M_PI * henyeyGreenstein(c, g) * 2.0 / k;
        }
        CHECK(norm == Approx(1.0).epsilon(2e-3));
        for (int i = 0; i < k; ++i) meanCos += -sampleHenyeyGreensteinCos(g, (float(i) + 0.5f) / float(k)) / k;
        CHECK(meanCos == Approx(g).margin(2e-3));
    }
}

TEST_CASE("media in PT: transmittance through an absorbing slab behind pass-through boundaries", "[media][render]") {
    // An orthographic camera looks along +z through a box of absorbing medium 1 deep
    // (sigma_a (0.5, 1, 2), no scattering; interface material) at an emitter of L = 1:
    // every pixel is exp(-sigma_a) per channel.
    const std::string text = R"(LookAt 0 0 -3  0 0 0  0 1 0
Camera "orthographic"
Film "rgb" "integer xresolution" [ 8 ] "integer yresolution" [ 8 ]
PixelFilter "box"
Integrator "volpath" "integer maxdepth" [ 5 ]
MakeNamedMedium "ink" "string type" "homogeneous" "rgb sigma_a" [ 0.5 1 2 ] "rgb sigma_s" [ 0 0 0 ]
WorldBegin
AttributeBegin
Material "interface"
MediumInterface "ink" ""
Scale 10 10 1
)" + media_scenes::cube(Vec3(0, 0, 0.5f), 0.5f, false) +
                             R"(AttributeEnd
AttributeBegin
AreaLightSource "diffuse" "rgb L" [ 1 1 1 ]
Shape "trianglemesh" "point3 P" [ -1.5 -1.5 5  1.5 -1.5 5  1.5 1.5 5  -1.5 1.5 5 ] "integer indices" [ 0 2 1 0 3 2 ]
AttributeEnd
)";
    const SceneDesc d = loadText("slab.pbrt", text);
    REQUIRE(d.media.size() == 1);
    REQUIRE(d.shapes[0].passThrough);
    REQUIRE(d.shapes[0].mediumBoundary);
    CHECK(d.shapes[0].mediumInside == 0);
    CHECK(d.shapes[0].mediumOutside == -1);
    for (TracerKind tr : {TracerKind::PT, TracerKind::LT, TracerKind::BPT, TracerKind::MMLT}) {
        const auto runs = rstats::channelRuns(6, 2, [&](int k) { return render(d, rstats::renderOptions(tr, 16, 10 + uint64_t(k), 1, 6)).image; });
        for (int c = 0; c < 3; ++c) {
            const double sigma = c == 0 ? 0.5 : c == 1 ? 1.0 : 2.0;
            const rstats::ZTestResult z = rstats::zTest(runs[size_t(c)], std::vector<double>(16, std::exp(-sigma)));
            INFO("tracer " << int(tr) << " channel " << c << ": " << z.describe());
            CHECK(z.pass);
        }
    }
}

TEST_CASE("media in PT: single scattering of a point light in an infinite medium", "[media][render][stat]") {
    // The camera and a point light (I = 2) in one medium everywhere (the camera's), a black
    // ball far away the only surface; paths of two segments (camera, medium vertex, light)
    // are single scattering:
    //   L = int_0^inf T(t) sigma_s p(cos) I T(r) / r^2 dt,  r = |x(t) - light|,
    // per channel (sigma_s (0.5, 0.3, 0.1), sigma_a (0.1, 0.2, 0.4), g 0.4), integrated over
    // phi with t = t0 + b tan(phi) (b the ray's distance to the light): smooth.
    const std::string text = media_scenes::pointLightInFog("0.5 0.3 0.1");
    const SceneDesc d = loadText("single.pbrt", text);
    REQUIRE(d.cameraMedium == 0);
    const Vec3 light(0.3f, 0.2f, 2.0f);
    const double sigS[3] = {0.5, 0.3, 0.1}, sigT[3] = {0.6, 0.5, 0.5}, g = 0.4, I = 2;
    auto radiance = [&](Vec3 o, Vec3 w, int c) {
        const Vec3 q = light - o;
        const double t0 = dot(q, w), b = std::sqrt(std::max(1e-12, double(lengthSquared(q)) - t0 * t0));
        const double lo = std::atan2(-t0, b), hi = M_PI / 2;
        const int n = 4000;
        double sum = 0;
        for (int i = 0; i < n; ++i) {  // midpoint rule in phi
            const double phi = lo + (hi - lo) * (i + 0.5) / n, t = t0 + b * std::tan(phi);
            const Vec3 x = o + w * float(t);
            const double r = std::sqrt(b * b + (t - t0) * (t - t0));
            const Vec3 toLight = normalize(light - x);
            const double cosT = dot(-w, toLight);  // wo = -w, wi towards the light
            const double hg = (1 - g * g) / (4 * M_PI * std::pow(1 + g * g + 2 * g * cosT, 1.5));
            // dt = b / cos^2(phi) dphi, 1 / r^2 = cos^2(phi) / b^2: the integrand times 1 / b
            sum += std::exp(-sigT[c] * t) * sigS[c] * hg * I * std::exp(-sigT[c] * r) / b;
        }
        return sum * (hi - lo) / n;
    };
    const Camera cam = makeCamera(d.camera, 16, 16);
    // (Not LT: with the camera in a scattering medium the light tracer's connections from
    // vertices near the lens weigh 1 / r^2, an estimator of infinite variance, which a
    // test from measured variance cannot judge; its media tests keep the camera outside.
    // BPT's weights give those connections little weight there.)
    const TracerKind tracers[2] = {TracerKind::PT, TracerKind::BPT};
    std::array<std::array<rstats::RunStats, 3>, 2> runs;
    for (int t = 0; t < 2; ++t)
        runs[size_t(t)] =
            rstats::channelRuns(6, 4, [&](int k) { return render(d, rstats::renderOptions(tracers[t], 64, 20 + uint64_t(k), 2, 2)).image; });
    for (int c = 0; c < 3; ++c) {
        std::vector<double> expected(16, 0.0);
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 16; ++x)
                for (int j = 0; j < 4; ++j)
                    for (int i = 0; i < 4; ++i) {
                        Vec3 o, w;
                        generateCameraRay(cam, float(x) + (float(i) + 0.5f) / 4, float(y) + (float(j) + 0.5f) / 4, 0.5f, 0.5f, o, w);
                        expected[size_t(y / 4) * 4 + size_t(x / 4)] += radiance(o, w, c) / (16 * 16);
                    }
        for (int t = 0; t < 2; ++t) {
            const rstats::ZTestResult z = rstats::zTest(runs[size_t(t)][size_t(c)], expected);
            INFO("tracer " << int(tracers[t]) << " channel " << c << ": " << z.describe() << "; mean expected " << blockMean(expected));
            CHECK(z.pass);
        }
    }
}

TEST_CASE("media in PT: white furnaces, the camera in the medium and the medium behind boundaries", "[media][render]") {
    // A closed box emitting L = 1 inwards from black walls, filled with a medium of albedo 1
    // (sigma_s 1.3, g 0.5): every ray ends on a wall, so the radiance is 1 everywhere. First
    // the camera in the medium (the walls are no boundaries, their lights in the medium as
    // pbrt-v4's rule needs them declared); then a smaller box of it
    // inside, bounded by the interface material, the camera outside it in vacuum (paths
    // leave the medium through boundaries, and light reaches it through them).
    const std::string head = R"(LookAt 0 0 -1.5  0 0 0  0 1 0
MakeNamedMedium "fog" "string type" "homogeneous" "rgb sigma_a" [ 0 0 0 ] "rgb sigma_s" [ 1.3 1.3 1.3 ] "float g" 0.5
)";
    const std::string walls =
        "AttributeBegin\nMaterial \"diffuse\" \"rgb reflectance\" [ 0 0 0 ]\nAreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ]\n" +
        media_scenes::cube(Vec3(0.0f), 2.0f, true) + "AttributeEnd\n";
    const std::string film = R"(Camera "perspective" "float fov" [ 60 ]
Film "rgb" "integer xresolution" [ 8 ] "integer yresolution" [ 8 ]
PixelFilter "box"
)";
    const SceneDesc inMedium =
        loadText("furnace-a.pbrt", head + "MediumInterface \"\" \"fog\"\n" + film + "WorldBegin\nMediumInterface \"fog\" \"fog\"\n" + walls);
    const SceneDesc boxed =
        loadText("furnace-b.pbrt", head + film + "WorldBegin\n" + walls + "AttributeBegin\nMaterial \"interface\"\nMediumInterface \"fog\" \"\"\n" +
                                       media_scenes::cube(Vec3(0.1f, 0, 0.3f), 0.8f, false) + "AttributeEnd\n");
    REQUIRE(inMedium.cameraMedium == 0);
    REQUIRE(boxed.cameraMedium == -1);
    for (TracerKind tr : {TracerKind::PT, TracerKind::LT, TracerKind::BPT, TracerKind::MMLT})
        for (const SceneDesc* d : {&inMedium, &boxed}) {
            if (tr == TracerKind::LT && d == &inMedium) continue;  // (infinite variance: see the single-scattering test)
            rstats::RunStats runs;
            for (int k = 0; k < 6; ++k)
                runs.add(rstats::blockMeans(render(*d, rstats::renderOptions(tr, 16, 30 + uint64_t(k), 1, kMaxPathLength)).image, 2, 1));
            const rstats::ZTestResult z = rstats::zTest(runs, std::vector<double>(16, 1.0));
            INFO("tracer " << int(tr) << ", " << (d == &inMedium ? "camera in the medium" : "medium in a box") << ": " << z.describe());
            CHECK(z.pass);
        }
}

TEST_CASE("media behind glass: PT, LT and BPT agree on a scattering medium in a rough glass ball", "[media][render][stat]") {
    // A rough dielectric ball (eta 1.5) filled with a coloured scattering medium (sigma_s
    // (2, 1.5, 1), sigma_a (0.05, 0.1, 0.2), g 0.3) on a floor under an area light, the camera
    // outside in vacuum: light reaches the medium only through the glass (no next-event
    // estimation through it), the light tracer's connections leave the ball through its
    // rough surface. No closed form: the three tracers' block means agree (differences of
    // K-run means against their standard errors), per channel.
    const SceneDesc d = loadText("glass-ball.pbrt", media_scenes::glassBall());
    REQUIRE(d.cameraMedium == -1);
    REQUIRE(d.shapes[2].mediumBoundary);
    const TracerKind tracers[3] = {TracerKind::PT, TracerKind::LT, TracerKind::BPT};
    const int spp[3] = {1024, 1024, 256};   // about equal time
    std::vector<rstats::RunStats> runs(9);  // tracer x channel
    for (int tr = 0; tr < 3; ++tr)
        for (int k = 0; k < 6; ++k) {
            const Image img = render(d, rstats::renderOptions(tracers[tr], spp[tr], 100 + uint64_t(k), 1, 10)).image;
            for (int c = 0; c < 3; ++c) runs[size_t(tr * 3 + c)].add(rstats::blockMeans(img, 4, c));
        }
    for (int tr = 1; tr < 3; ++tr)
        for (int c = 0; c < 3; ++c) {
            double ratio = 0;
            const rstats::ZTestResult z = rstats::compareRuns(runs[size_t(tr * 3 + c)], runs[size_t(c)], 1e-4, &ratio);
            INFO("tracer " << int(tracers[tr]) << " against PT, channel " << c << ": " << z.describe() << ", ratio of means " << ratio);
            CHECK(z.pass);
        }
}

TEST_CASE("media in the thesis format: the furnace with a sphere of fog behind an interface", "[media][render][thesis]") {
    // An emitting closed box (six Planes facing in, L = 1, black) around a sphere of
    // albedo-1 fog behind an Interface shader: radiance 1 everywhere, as the pbrt furnace.
    std::string planes;
    const char* faces[6][2] = {{"0 -2 0", "0 0 0"}, {"0 2 0", "180 0 0"}, {"-2 0 0", "0 0 -90"},
                               {"2 0 0", "0 0 90"}, {"0 0 -2", "90 0 0"}, {"0 0 2", "-90 0 0"}};
    for (int i = 0; i < 6; ++i) {
        std::string p = faces[i][0], r = faces[i][1];
        auto xyz = [](const std::string& v, const char* a, const char* b, const char* c) {
            std::istringstream in(v);
            std::string x, y, z;
            in >> x >> y >> z;
            return std::string(" ") + a + "=\"" + x + "\" " + b + "=\"" + y + "\" " + c + "=\"" + z + "\"";
        };
        planes += "<Light Type=\"Area\" ID=\"w" + std::to_string(i) + "\"><Position" + xyz(p, "x", "y", "z") + "/><Rotation" + xyz(r, "x", "y", "z") +
                  "/><Width value=\"4\"/><Depth value=\"4\"/><Intensity value=\"1\"/><Colour r=\"1\" g=\"1\" b=\"1\"/></Light>\n";
    }
    const std::string xml = R"(<Scene>
  <Settings><Width value="8"/><Height value="8"/></Settings>
  <Camera><Position x="0" y="0" z="-1.5"/><LookAt x="0" y="0" z="0"/><FOV value="60"/></Camera>
  <Medium Type="Homogeneous" ID="3"><SigmaS r="1.3" g="1.3" b="1.3"/><G value="0.5"/></Medium>
  <Shader Type="Interface" ID="0"/>
  <Geometry Type="Sphere" ID="fog" Medium="3"><Position x="0.1" y="0" z="0.3"/><Radius value="0.8"/><Shader value="0"/></Geometry>
)" + planes + "</Scene>";
    const SceneDesc d = loadText("furnace.xml", xml);
    REQUIRE(d.media.size() == 1);
    REQUIRE(d.shapes[0].passThrough);
    CHECK(d.shapes[0].mediumInside == 0);
    CHECK(d.shapes[0].mediumOutside == -1);
    CHECK(d.media[0].sigmaS.x == Approx(1.3f));
    CHECK(d.media[0].g == Approx(0.5f));
    rstats::RunStats runs;
    for (int k = 0; k < 6; ++k)
        runs.add(rstats::blockMeans(render(d, rstats::renderOptions(TracerKind::PT, 16, 50 + uint64_t(k), 1, kMaxPathLength)).image, 2, 1));
    const rstats::ZTestResult z = rstats::zTest(runs, std::vector<double>(16, 1.0));
    INFO(z.describe());
    CHECK(z.pass);
    // bad input: an unknown medium, a coefficient below 0, g out of range
    const std::string base = R"(<Scene><Camera><Position x="0" y="0" z="-1"/><LookAt x="0" y="0" z="0"/><FOV value="60"/></Camera>
<Shader Type="Matte" ID="0"><Diffuse r="0.5" g="0.5" b="0.5"/></Shader>
)";
    CHECK_THAT(errorOf("bad1.xml", base + "<Geometry Type=\"Sphere\" ID=\"s\" Medium=\"7\"><Position x=\"0\" y=\"0\" z=\"0\"/><Radius "
                                          "value=\"1\"/><Shader value=\"0\"/></Geometry></Scene>"),
               Catch::Contains("bad1.xml:3") && Catch::Contains("no Medium"));
    CHECK_THAT(errorOf("bad2.xml", base + "<Medium Type=\"Homogeneous\" ID=\"1\"><SigmaA r=\"-1\" g=\"0\" b=\"0\"/></Medium></Scene>"),
               Catch::Contains("bad2.xml:3") && Catch::Contains(">= 0"));
    CHECK_THAT(errorOf("bad3.xml", base + "<Medium Type=\"Homogeneous\" ID=\"1\"><G value=\"-1\"/></Medium></Scene>"),
               Catch::Contains("bad3.xml:3") && Catch::Contains("-1 < g < 1"));
}

TEST_CASE("media in Mitsuba files: furnaces with the sensor in the medium and a null-bounded sphere", "[media][render][mitsuba]") {
    // Mitsuba's homogeneous medium (sigma_t 1.3, albedo 1, hg 0.5) in an emitting cube
    // (flip_normals: it emits inwards, black): radiance 1 everywhere, as the pbrt furnaces.
    auto scene = [&](const std::string& sensorMedium, const std::string& body) {
        return R"(<scene version="3.0.0">
<medium type="homogeneous" id="fog"><rgb name="albedo" value="1"/><float name="sigma_t" value="1.3"/>
  <phase type="hg"><float name="g" value="0.5"/></phase></medium>
<sensor type="perspective"><float name="fov" value="60"/>
  <transform name="to_world"><lookat origin="0, 0, -1.5" target="0, 0, 0" up="0, 1, 0"/></transform>
  <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/><rfilter type="box"/></film>)" +
               sensorMedium + R"(</sensor>
<shape type="cube"><transform name="to_world"><scale value="2"/></transform><boolean name="flip_normals" value="true"/>
  <bsdf type="diffuse"><rgb name="reflectance" value="0"/></bsdf><emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>
)" + body + "</scene>";
    };
    const SceneDesc inMedium = loadMitsubaFromString(scene(R"(<ref name="medium" id="fog"/>)", ""), "a.xml", dir());
    const SceneDesc sphere =
        loadMitsubaFromString(scene("", R"(<shape type="sphere"><point name="center" x="0.1" y="0" z="0.3"/><float name="radius" value="0.8"/>
  <bsdf type="null"/><ref name="interior" id="fog"/></shape>
)"),
                              "b.xml", dir());
    REQUIRE(inMedium.cameraMedium == 0);
    REQUIRE(sphere.cameraMedium == -1);
    REQUIRE(sphere.shapes[1].passThrough);
    CHECK(sphere.shapes[1].mediumInside == 0);
    CHECK(sphere.media[0].sigmaS.y == Approx(1.3f));
    CHECK(sphere.media[0].sigmaA.y == Approx(0.0f).margin(1e-6));
    for (const SceneDesc* d : {&inMedium, &sphere}) {
        rstats::RunStats runs;
        for (int k = 0; k < 6; ++k)
            runs.add(rstats::blockMeans(render(*d, rstats::renderOptions(TracerKind::PT, 16, 60 + uint64_t(k), 1, kMaxPathLength)).image, 2, 1));
        const rstats::ZTestResult z = rstats::zTest(runs, std::vector<double>(16, 1.0));
        INFO((d == &inMedium ? "sensor in the medium" : "null sphere") << ": " << z.describe());
        CHECK(z.pass);
    }
    CHECK_THAT(mitsubaError(scene("", "<medium type=\"vdb\" id=\"h\"/><shape type=\"sphere\"><ref name=\"interior\" id=\"h\"/></shape>\n")),
               Catch::Contains("bad.xml:9") && Catch::Contains("medium \"vdb\" is not supported"));
    CHECK_THAT(
        mitsubaError(scene(
            "", "<shape type=\"sphere\"><medium type=\"homogeneous\" name=\"interior\"><float name=\"sigma_t\" value=\"-1\"/></medium></shape>\n")),
        Catch::Contains("bad.xml:9") && Catch::Contains(">= 0"));
}

TEST_CASE("media in PT: a heterogeneous grid, unbiased (a furnace of random densities, a ramp's transmittance)", "[media][render][grid]") {
    // 1. The furnace with a 4 x 4 x 4 grid of random densities in [0, 2] over [-2.5, 2.5]^3
    //    (pbrt's uniformgrid; the enclosure [-2, 2]^3), sigma_s (0.25, 0.5, 1), no absorption:
    //    albedo 1 in every channel, so the radiance is 1 everywhere whatever the densities
    //    (spectral tracking's weights with channels apart).
    uint64_t h = 12345;
    const std::string dens = media_scenes::randomNumbers(64, 0, 2, h);
    const std::string furnace = media_scenes::furnace(
        R"(MakeNamedMedium "smoke" "string type" "uniformgrid" "rgb sigma_a" [ 0 0 0 ] "rgb sigma_s" [ 0.25 0.5 1 ] "float g" -0.3
  "integer nx" 4 "integer ny" 4 "integer nz" 4 "point3 p0" [ -2.5 -2.5 -2.5 ] "point3 p1" [ 2.5 2.5 2.5 ] "float density" [ )" +
            dens + "]",
        "smoke");
    const SceneDesc d = loadText("grid-furnace.pbrt", furnace);
    REQUIRE(d.media.size() == 1);
    REQUIRE(d.media[0].density.size() == 64);
    for (TracerKind tr : {TracerKind::PT, TracerKind::BPT}) {  // (the camera is in the medium: not LT)
        const auto runs =
            rstats::channelRuns(6, 2, [&](int k) { return render(d, rstats::renderOptions(tr, 16, 70 + uint64_t(k), 1, kMaxPathLength)).image; });
        for (int c = 0; c < 3; ++c) {
            const rstats::ZTestResult z = rstats::zTest(runs[size_t(c)], std::vector<double>(16, 1.0));
            INFO("tracer " << int(tr) << " channel " << c << ": " << z.describe());
            CHECK(z.pass);
        }
    }
    // 2. An absorbing slab z in [0, 1] whose density ramps along z (nz = 2: a, b at the voxel
    //    centres z = 1/4, 3/4, 0 outside, trilinear): the optical depth along z is
    //    sigma_a 0.4375 (a + b); x and y constant over the view (the grid four voxels wide, the
    //    view its middle half). An orthographic camera through it at an emitter of L = 1.
    // (A medium made before WorldBegin is in the space of the transform then in force, as in
    // pbrt: here the identity, before LookAt.)
    const SceneDesc slab =
        loadText("grid-slab.pbrt", R"(MakeNamedMedium "ramp" "string type" "uniformgrid" "rgb sigma_a" [ 0.5 1 2 ] "rgb sigma_s" [ 0 0 0 ]
  "integer nx" 4 "integer ny" 4 "integer nz" 2 "point3 p0" [ -4 -4 0 ] "point3 p1" [ 4 4 1 ]
  "float density" [ 0.4 0.4 0.4 0.4 0.4 0.4 0.4 0.4 0.4 0.4 0.4 0.4 0.4 0.4 0.4 0.4  1.6 1.6 1.6 1.6 1.6 1.6 1.6 1.6 1.6 1.6 1.6 1.6 1.6 1.6 1.6 1.6 ]
LookAt 0 0 -3  0 0 0  0 1 0
Camera "orthographic"
Film "rgb" "integer xresolution" [ 8 ] "integer yresolution" [ 8 ]
PixelFilter "box"
WorldBegin
AttributeBegin
Material "interface"
MediumInterface "ramp" ""
Scale 10 10 1
)" + media_scenes::cube(Vec3(0, 0, 0.5f), 0.5f, false) +
                                       R"(AttributeEnd
AttributeBegin
AreaLightSource "diffuse" "rgb L" [ 1 1 1 ]
Shape "trianglemesh" "point3 P" [ -1.5 -1.5 5  1.5 -1.5 5  1.5 1.5 5  -1.5 1.5 5 ] "integer indices" [ 0 2 1 0 3 2 ]
AttributeEnd
)");
    for (TracerKind tr : {TracerKind::PT, TracerKind::LT, TracerKind::BPT, TracerKind::MMLT}) {
        const auto runs = rstats::channelRuns(6, 2, [&](int k) { return render(slab, rstats::renderOptions(tr, 16, 80 + uint64_t(k), 1, 6)).image; });
        for (int c = 0; c < 3; ++c) {
            const double sigma = c == 0 ? 0.5 : c == 1 ? 1.0 : 2.0;
            const rstats::ZTestResult z = rstats::zTest(runs[size_t(c)], std::vector<double>(16, std::exp(-sigma * 0.4375 * 2.0)));
            INFO("slab, tracer " << int(tr) << " channel " << c << ": " << z.describe());
            CHECK(z.pass);
        }
    }
    // 3. pbrt's rgbgrid: sigma_s per voxel and channel (random in [0, 1.5]), no absorption:
    //    the furnace again, channel by channel.
    const std::string sigS = media_scenes::randomNumbers(3 * 27, 0, 1.5, h);
    std::string sigA;
    for (int i = 0; i < 3 * 27; ++i) sigA += "0 ";
    std::string rgbFurnace = furnace;
    const size_t from = rgbFurnace.find("MakeNamedMedium"), to = rgbFurnace.find("LookAt");
    rgbFurnace.replace(from, to - from,
                       "MakeNamedMedium \"smoke\" \"string type\" \"rgbgrid\" \"float g\" 0.2 \"integer nx\" 3 \"integer ny\" 3 "
                       "\"integer nz\" 3 \"point3 p0\" [ -2.5 -2.5 -2.5 ] \"point3 p1\" [ 2.5 2.5 2.5 ]\n  \"rgb sigma_a\" [ " +
                           sigA + "]\n  \"rgb sigma_s\" [ " + sigS + "]\n");
    const SceneDesc rgb = loadText("rgb-furnace.pbrt", rgbFurnace);
    REQUIRE(rgb.media.size() == 1);
    REQUIRE(rgb.media[0].sigmaSGrid.size() == 27);
    for (TracerKind tr : {TracerKind::PT, TracerKind::BPT}) {
        const auto runs =
            rstats::channelRuns(6, 2, [&](int k) { return render(rgb, rstats::renderOptions(tr, 16, 75 + uint64_t(k), 1, kMaxPathLength)).image; });
        for (int c = 0; c < 3; ++c) {
            const rstats::ZTestResult z = rstats::zTest(runs[size_t(c)], std::vector<double>(16, 1.0));
            INFO("rgbgrid, tracer " << int(tr) << " channel " << c << ": " << z.describe());
            CHECK(z.pass);
        }
    }
    // bad input: a grid whose size disagrees with its values
    CHECK_THAT(errorOf("grid-bad2.pbrt",
                       "Camera \"perspective\"\nWorldBegin\nLightSource \"point\"\nMakeNamedMedium \"g\" \"string type\" \"rgbgrid\" "
                       "\"integer nx\" 2 \"rgb sigma_a\" [ 1 1 1 ] \"rgb sigma_s\" [ 1 1 1 1 1 1 ]\nShape \"sphere\"\n"),
               Catch::Contains("grid-bad2.pbrt:4") && Catch::Contains("1 sigma_a values for a 2 x 1 x 1 grid"));
    CHECK_THAT(errorOf("grid-bad.pbrt",
                       "Camera \"perspective\"\nWorldBegin\nLightSource \"point\"\nMakeNamedMedium \"g\" \"string type\" \"uniformgrid\" "
                       "\"integer nx\" 2 \"float density\" [ 1 ]\nShape \"sphere\"\n"),
               Catch::Contains("grid-bad.pbrt:4") && Catch::Contains("1 density values for a 2 x 1 x 1 grid"));
}

TEST_CASE("media in Mitsuba files: a heterogeneous gridvolume, the furnace, and bad .vol files", "[media][render][grid][mitsuba]") {
    // A 3 x 3 x 3 grid of random sigma_t in [0, 2] (a .vol file) over the cube [-2.5, 2.5]^3
    // (to_world), albedo 1: in the emitting enclosure the radiance is 1 everywhere.
    auto writeVol = [&](const std::string& name, int n, int channels, size_t values, uint64_t seed) {
        std::ofstream f(dir() + "/" + name, std::ios::binary);
        f.write("VOL\3", 4);
        const int32_t head[5] = {1, n, n, n, channels};
        f.write(reinterpret_cast<const char*>(head), sizeof head);
        const float box[6] = {0, 0, 0, 1, 1, 1};
        f.write(reinterpret_cast<const char*>(box), sizeof box);
        for (size_t i = 0; i < values; ++i) {
            seed = seed * 6364136223846793005ull + 1442695040888963407ull;
            const float v = 2.0f * float(seed >> 40) / float(1u << 24);
            f.write(reinterpret_cast<const char*>(&v), 4);
        }
    };
    writeVol("smoke.vol", 3, 1, 27, 99);
    writeVol("short.vol", 3, 1, 20, 99);
    writeVol("rgb.vol", 2, 3, 24, 99);
    auto scene = [&](const std::string& file) {
        return R"(<scene version="3.0.0">
<medium type="heterogeneous" id="smoke"><rgb name="albedo" value="1"/>
  <volume type="gridvolume" name="sigma_t"><string name="filename" value=")" +
               file + R"("/>
    <transform name="to_world"><scale value="5"/><translate value="-2.5, -2.5, -2.5"/></transform></volume>
  <phase type="hg"><float name="g" value="0.3"/></phase></medium>
<sensor type="perspective"><float name="fov" value="60"/>
  <transform name="to_world"><lookat origin="0, 0, -1.5" target="0, 0, 0" up="0, 1, 0"/></transform>
  <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/><rfilter type="box"/></film>
  <ref name="medium" id="smoke"/></sensor>
<shape type="cube"><transform name="to_world"><scale value="2"/></transform><boolean name="flip_normals" value="true"/>
  <bsdf type="diffuse"><rgb name="reflectance" value="0"/></bsdf><emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>
</scene>)";
    };
    const SceneDesc d = loadMitsubaFromString(scene("smoke.vol"), "grid.xml", dir());
    REQUIRE(d.media.size() == 1);
    REQUIRE(d.media[0].density.size() == 27);
    CHECK(d.media[0].clampEdges);
    rstats::RunStats runs;
    for (int k = 0; k < 6; ++k)
        runs.add(rstats::blockMeans(render(d, rstats::renderOptions(TracerKind::PT, 16, 90 + uint64_t(k), 1, kMaxPathLength)).image, 2, 1));
    const rstats::ZTestResult z = rstats::zTest(runs, std::vector<double>(16, 1.0));
    INFO(z.describe());
    CHECK(z.pass);
    CHECK_THAT(mitsubaError(scene("short.vol")), Catch::Contains("bad.xml:3") && Catch::Contains("truncated: 20 values for 27"));
    CHECK_THAT(mitsubaError(scene("rgb.vol")), Catch::Contains("bad.xml:3") && Catch::Contains("3 channels"));
    CHECK_THAT(mitsubaError(scene("missing.vol")), Catch::Contains("bad.xml:3") && Catch::Contains("missing.vol"));
}

TEST_CASE("media in Mitsuba files: an albedo gridvolume on sigma_t's grid", "[media][render][grid][mitsuba]") {
    // sigma_t a random 3 x 3 x 3 grid; albedo a grid too: everywhere (0.2, 0.5, 0.9) in a
    // three-channel .vol, then 0.5 in a one-channel one with sigma_t constant. Each renders
    // what the same medium with that albedo as a constant renders (block means, K runs each).
    auto writeVol = [&](const std::string& name, int n, int channels, const std::vector<float>& perVoxel, uint64_t seed) {
        std::ofstream f(dir() + "/" + name, std::ios::binary);
        f.write("VOL\3", 4);
        const int32_t head[5] = {1, n, n, n, channels};
        f.write(reinterpret_cast<const char*>(head), sizeof head);
        const float box[6] = {0, 0, 0, 1, 1, 1};
        f.write(reinterpret_cast<const char*>(box), sizeof box);
        for (int i = 0; i < n * n * n; ++i)
            for (int c = 0; c < channels; ++c) {
                seed = seed * 6364136223846793005ull + 1442695040888963407ull;
                const float v = perVoxel.empty() ? 2.0f * float(seed >> 40) / float(1u << 24) : perVoxel[size_t(c)];
                f.write(reinterpret_cast<const char*>(&v), 4);
            }
    };
    writeVol("density.vol", 3, 1, {}, 7);
    writeVol("albedo3.vol", 3, 3, {0.2f, 0.5f, 0.9f}, 0);
    writeVol("albedo1.vol", 3, 1, {0.5f}, 0);
    writeVol("albedo-big.vol", 4, 1, {0.5f}, 0);
    const std::string toWorld = R"(<transform name="to_world"><scale value="5"/><translate value="-2.5, -2.5, -2.5"/></transform>)";
    auto grid = [&](const std::string& name, const std::string& file) {
        return "<volume type=\"gridvolume\" name=\"" + name + "\"><string name=\"filename\" value=\"" + file + "\"/>" + toWorld + "</volume>";
    };
    auto scene = [&](const std::string& sigmaT, const std::string& albedo) {
        return R"(<scene version="3.0.0">
<medium type="heterogeneous" id="smoke">)" +
               sigmaT + albedo + R"(<phase type="hg"><float name="g" value="0.3"/></phase></medium>
<sensor type="perspective"><float name="fov" value="60"/>
  <transform name="to_world"><lookat origin="0, 0, -1.5" target="0, 0, 0" up="0, 1, 0"/></transform>
  <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/><rfilter type="box"/></film>
  <ref name="medium" id="smoke"/></sensor>
<shape type="cube"><transform name="to_world"><scale value="2"/></transform><boolean name="flip_normals" value="true"/>
  <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf><emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>
</scene>)";
    };
    const std::string sigmaGrid = grid("sigma_t", "density.vol");
    const SceneDesc withGrid = loadMitsubaFromString(scene(sigmaGrid, grid("albedo", "albedo3.vol")), "a.xml", dir());
    const SceneDesc withConstant = loadMitsubaFromString(scene(sigmaGrid, R"(<rgb name="albedo" value="0.2, 0.5, 0.9"/>)"), "b.xml", dir());
    const SceneDesc oneChannel =
        loadMitsubaFromString(scene(R"(<float name="sigma_t" value="0.8"/>)", grid("albedo", "albedo1.vol")), "c.xml", dir());
    const SceneDesc homogeneousGrid =
        loadMitsubaFromString(scene(R"(<float name="sigma_t" value="0.8"/>)", R"(<float name="albedo" value="0.5"/>)"), "d.xml", dir());
    REQUIRE(withGrid.media[0].albedoGrid.size() == 27);
    REQUIRE(oneChannel.media[0].density.size() == 27);
    struct Pair {
        const SceneDesc *a, *b;
    };
    // In RGB, then spectral (docs/spectral.md): the albedo grid's voxels uplifted as
    // reflectances, read at the wavelengths, and a constant albedo's reflectance spectrum times
    // sigma_t's (as Mitsuba 3's scalar_spectral), so each grid renders what its constant
    // renders spectrally too. (The constant's sigma_s uplifted as one unbounded spectrum, as
    // until 2026-12-07, is too close for this scene to tell: test_spectral_tracers.cpp checks
    // the spectra themselves.)
    for (bool spectral : {false, true})
        for (const Pair& pr : {Pair{&withGrid, &withConstant}, Pair{&oneChannel, &homogeneousGrid}}) {
            auto runsOf = [&](const SceneDesc& d, uint64_t seed0) {
                return rstats::channelRuns(6, 2, [&](int k) {
                    RenderOptions o = rstats::renderOptions(TracerKind::PT, 16, seed0 + uint64_t(k), 1, kMaxPathLength);
                    o.spectral = spectral;
                    const RenderResult r = render(d, o);
                    REQUIRE(r.stats.spectral == spectral);
                    return r.image;
                });
            };
            const auto ra = runsOf(*pr.a, spectral ? 520 : 500), rb = runsOf(*pr.b, spectral ? 530 : 510);
            for (int c = 0; c < 3; ++c) {
                double ratio = 0;
                const rstats::ZTestResult z = rstats::compareRuns(ra[size_t(c)], rb[size_t(c)], 1e-4, &ratio);
                INFO((spectral ? "spectral, " : "") << (pr.a == &withGrid ? "three-channel albedo grid" : "one-channel albedo grid") << ", channel "
                                                    << c << ": " << z.describe() << ", ratio " << ratio);
                CHECK(z.pass);
            }
        }
    CHECK_THAT(mitsubaError(scene(sigmaGrid, grid("albedo", "albedo-big.vol"))),
               Catch::Contains("bad.xml:2") && Catch::Contains("another grid than sigma_t's"));
}

TEST_CASE("media in pbrt files: the path integrator ignores them, as pbrt-v4's does", "[media][import]") {
    const std::string text = R"(MakeNamedMedium "fog" "string type" "homogeneous"
MediumInterface "" "fog"
Camera "perspective"
Integrator "INTEGRATOR"
WorldBegin
LightSource "point"
Shape "sphere"
)";
    auto with = [&](const std::string& integrator) {
        std::string t = text;
        t.replace(t.find("INTEGRATOR"), 10, integrator);
        return loadText(integrator + ".pbrt", t);
    };
    const SceneDesc volpath = with("volpath"), path = with("path");
    CHECK(volpath.media.size() == 1);
    CHECK(volpath.cameraMedium == 0);
    CHECK(volpath.shapes[0].mediumBoundary);
    CHECK(path.media.empty());
    CHECK(path.cameraMedium == -1);
    CHECK_FALSE(path.shapes[0].mediumBoundary);
    REQUIRE(path.warnings.size() == 1);
    CHECK_THAT(path.warnings[0], Catch::Contains("path.pbrt:4") && Catch::Contains("volpath"));
}

// pbrt-v4's subsurface material is what it describes (issue 43): a dielectric boundary over a
// homogeneous scattering interior. A box of it on a floor under a sphere light renders the
// same image, bit for bit, as the same box of dielectric holding the same medium written by
// hand (MakeNamedMedium, MediumInterface), in PT and BPT; without its medium (a plain
// dielectric) the image is another.
TEST_CASE("media: pbrt's subsurface is a dielectric over its medium", "[media][import]") {
    const std::string head = R"(LookAt 0 1.5 -3  0 0 0  0 1 0
Camera "perspective" "float fov" [ 40 ]
Film "rgb" "integer xresolution" [ 16 ] "integer yresolution" [ 16 ]
PixelFilter "box"
Integrator "volpath" "integer maxdepth" [ 12 ]
MakeNamedMedium "m" "string type" "homogeneous" "rgb sigma_a" [ 0.2 0.4 0.8 ] "rgb sigma_s" [ 3 2.5 2 ] "float scale" 0.5 "float g" 0.3
WorldBegin
AttributeBegin
AreaLightSource "diffuse" "rgb L" [ 8 8 8 ]
Translate 0 3 -1
Shape "sphere" "float radius" [ 0.4 ]
AttributeEnd
Shape "trianglemesh" "point3 P" [ -5 -0.5 -5  5 -0.5 -5  5 -0.5 5  -5 -0.5 5 ] "integer indices" [ 0 2 1 0 3 2 ]
AttributeBegin
)";
    const std::string box = media_scenes::cube(Vec3(0.0f), 0.5f, false) + "AttributeEnd\n";
    const SceneDesc sss = loadText(
        "sss.pbrt",
        head + R"(Material "subsurface" "float eta" 1.4 "rgb sigma_a" [ 0.2 0.4 0.8 ] "rgb sigma_s" [ 3 2.5 2 ] "float scale" 0.5 "float g" 0.3
)" + box);
    const SceneDesc byHand = loadText("sss-by-hand.pbrt", head + "Material \"dielectric\" \"float eta\" 1.4\nMediumInterface \"m\" \"\"\n" + box);
    const SceneDesc bare = loadText("sss-bare.pbrt", head + "Material \"dielectric\" \"float eta\" 1.4\n" + box);
    REQUIRE(sss.media.size() == 2);  // the file's "m" (unused) and the material's
    const MediumDesc& m = sss.media[1];
    CHECK(m.sigmaA.z == Approx(0.4f));
    CHECK(m.sigmaS.x == Approx(1.5f));
    CHECK(m.g == Approx(0.3f));
    REQUIRE(sss.shapes.back().mediumBoundary);
    CHECK(sss.shapes.back().mediumInside == 1);
    CHECK(sss.shapes.back().mediumOutside == -1);
    for (TracerKind tr : {TracerKind::PT, TracerKind::BPT}) {
        const RenderOptions o = rstats::renderOptions(tr, 16, 5, 1, 12);
        const Image a = render(sss, o).image, b = render(byHand, o).image, c = render(bare, o).image;
        INFO("tracer " << int(tr));
        CHECK(a.rgb == b.rgb);
        double meanA = 0, meanC = 0;
        for (size_t i = 0; i < a.rgb.size(); ++i) meanA += a.rgb[i], meanC += c.rgb[i];
        CHECK(std::fabs(meanA - meanC) > 0.05 * meanC);
    }
    // bad input: pbrt's measured media by name; reflectance with sigma_a; eta 1
    CHECK_THAT(errorOf("sss1.pbrt", "WorldBegin\nLightSource \"point\"\nMaterial \"subsurface\" \"string name\" \"Skin1\"\nShape \"sphere\"\n"),
               Catch::Contains("sss1.pbrt:3") && Catch::Contains("\"name\" (pbrt's measured media) is not supported yet"));
    CHECK_THAT(errorOf("sss3.pbrt",
                       "WorldBegin\nLightSource \"point\"\nMaterial \"subsurface\" \"rgb reflectance\" [ 0.5 0.5 0.5 ] \"rgb sigma_a\" [ 1 1 1 "
                       "]\nShape \"sphere\"\n"),
               Catch::Contains("sss3.pbrt:3") && Catch::Contains("not both"));
    CHECK_THAT(errorOf("sss2.pbrt", "WorldBegin\nLightSource \"point\"\nMaterial \"subsurface\" \"float eta\" 1\nShape \"sphere\"\n"),
               Catch::Contains("sss2.pbrt:3") && Catch::Contains("eta"));
}

// pbrt's subsurface given by a diffuse reflectance: the albedo from pbrt's photon-beam-
// diffusion table (subsurface_albedo.h), inverted. The splines are exact on linear data; the
// table rises from 0 (measured at eta 1.33, g 0: rho_eff 0.079 at rho 0.554, 0.593 at 0.983,
// 1.019 at 1, as pbrt's model gives slightly over 1); the inversion returns each sampled albedo
// at its own rho_eff; the importer makes sigma_s = rho / (mfp scale), sigma_a = (1 - rho) / (mfp scale).
TEST_CASE("media: pbrt's subsurface by reflectance: the diffusion albedo table, inverted", "[media][import]") {
    using namespace wmlt::pbrt;
    const std::vector<double> x = {0, 1, 3, 4}, f = {1, 3, 7, 9};  // f = 2x + 1
    CHECK(integrateCatmullRom(x, f) == Approx(20.0).epsilon(1e-12));
    CHECK(invertCatmullRom(x, f, 5.0) == Approx(2.0).epsilon(1e-8));
    const DiffusionAlbedo t = diffusionAlbedo(0, 1.33);
    REQUIRE(t.rho.size() == 100);
    CHECK(t.rhoEff.front() == 0);
    for (size_t i = 1; i < t.rhoEff.size(); ++i) CHECK(t.rhoEff[i] > t.rhoEff[i - 1]);
    CHECK(t.rhoEff.back() > 0.95);
    CHECK(t.rhoEff.back() < 1.05);
    for (size_t i = 1; i + 1 < t.rho.size(); i += 7) CHECK(albedoOf(t, t.rhoEff[i]) == Approx(t.rho[i]).epsilon(1e-6));
    const SceneDesc d = loadText("sss-r.pbrt",
                                 "WorldBegin\nLightSource \"point\"\nMaterial \"subsurface\" \"rgb reflectance\" [ 0.1 0.5 0.8 ] "
                                 "\"rgb mfp\" [ 1 2 4 ] \"float scale\" 0.5\nShape \"sphere\"\n");
    REQUIRE(d.media.size() == 1);
    const MediumDesc& m = d.media[0];
    const double r[3] = {0.1, 0.5, 0.8}, mfp[3] = {0.5, 1, 2};
    for (int c = 0; c < 3; ++c) {
        const double rho = albedoOf(t, r[c]);
        INFO("channel " << c << ": rho " << rho);
        CHECK(m.sigmaS[c] + m.sigmaA[c] == Approx(1 / mfp[c]).epsilon(1e-6));
        CHECK(m.sigmaS[c] * mfp[c] == Approx(rho).epsilon(1e-6));
    }
}

TEST_CASE("media: bad input names file and line", "[media][bad-input]") {
    const std::string head = "Camera \"perspective\"\nWorldBegin\nLightSource \"point\"\n";
    CHECK_THAT(errorOf("m1.pbrt", head + "MakeNamedMedium \"f\" \"string type\" \"homogeneous\" \"rgb sigma_a\" [ -1 0 0 ]\nShape \"sphere\"\n"),
               Catch::Contains("m1.pbrt:4") && Catch::Contains(">= 0"));
    CHECK_THAT(errorOf("m2.pbrt", head + "MakeNamedMedium \"f\" \"string type\" \"homogeneous\" \"float g\" 1\nShape \"sphere\"\n"),
               Catch::Contains("m2.pbrt:4") && Catch::Contains("(-1, 1)"));
    CHECK_THAT(errorOf("m3.pbrt", head + "MediumInterface \"nope\" \"\"\nShape \"sphere\"\n"),
               Catch::Contains("m3.pbrt:5") && Catch::Contains("no medium named \"nope\""));
    CHECK_THAT(errorOf("m4.pbrt", head + "MakeNamedMedium \"f\" \"string type\" \"uniformgrid\"\nShape \"sphere\"\n"),
               Catch::Contains("m4.pbrt:4") && Catch::Contains("uniformgrid"));
    // an open mesh as a pass-through boundary: legal in pbrt's files (a ray's medium is set by
    // the side it leaves through), refused in the thesis format's (it has no inside)
    const SceneDesc open = loadText("m5.pbrt", head +
                                                   "MakeNamedMedium \"f\" \"string type\" \"homogeneous\"\nMediumInterface \"f\" \"\"\n"
                                                   "Material \"interface\"\nShape \"trianglemesh\" \"point3 P\" [ 0 0 0  1 0 0  0 1 0 ]\n");
    CHECK(open.mediaAsDeclared);
    CHECK_NOTHROW(render(open, rstats::renderOptions(TracerKind::PT, 1, 1, 1, 2)));
    const SceneDesc plane = loadText("m5.xml", R"(<Scene><Camera><Position x="0" y="0" z="-1"/><LookAt x="0" y="0" z="0"/><FOV value="60"/></Camera>
<Medium Type="Homogeneous" ID="1"><SigmaS r="1" g="1" b="1"/></Medium><Shader Type="Interface" ID="0"/>
<Light Type="Sphere" ID="l"><Position x="0" y="2" z="0"/><Radius value="0.1"/><Intensity value="1"/></Light>
<Geometry Type="Plane" ID="p" Medium="1"><Position x="0" y="0" z="0"/><Width value="1"/><Depth value="1"/><Shader value="0"/></Geometry>
</Scene>)");
    try {
        render(plane, rstats::renderOptions(TracerKind::PT, 1, 1, 1, 2));
        FAIL("rendered an open boundary of the thesis format");
    } catch (const InputError& e) {
        CHECK_THAT(std::string(e.what()), Catch::Contains("m5.xml:4") && Catch::Contains("open mesh"));
    }
}
