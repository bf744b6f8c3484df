// The pbrt-v4 importer (docs/pbrt.md): the format (tokens, parameters, Include, gzip), the
// directives' mapping (camera, film, sampler, integrator, filter, materials, textures,
// shapes, lights, objects), closed forms for its lights on a diffuse floor in PT, LT and BPT,
// instancing against the flattened scene, Loop subdivision, and bad input with file and
// line. pbrt's own renders of real scenes: test_pbrt_scenes.cpp.
#include <catch2/catch.hpp>

#include <zlib.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "kernels/envmap.h"
#include "kernels/spectral.h"
#include "kernels/texture.h"
#include "mitsuba_floor.h"
#include "power.h"
#include "render_stats.h"
#include "scene/meshes/loop_subdivision.h"
#include "scene/pbrt/equal_area.h"
#include "scene/scene.h"
#include "scene/scene_spectra.h"
#include "scene/spectrum.h"
#include "wavemmlt/error.h"
#include "wavemmlt/image.h"
#include "wavemmlt/render.h"
#include "wavemmlt/scene_desc.h"

using namespace wmlt;

namespace {

const std::string kData = std::string(WAVEMMLT_TEST_DATA) + "/scenes/pbrt-v4/";

std::string dir() {
    static const std::string d = rstats::tempDir("pbrt");
    return d;
}
std::string write(const std::string& name, const std::string& text) {
    const std::string path = dir() + "/" + name;
    std::ofstream(path, std::ios::binary) << text;
    return path;
}
// A 16 x 16 camera looking down at the floor y = 0 from y = 1 (as mitsuba_floor.h's).
const std::string kHead = R"(LookAt 0 1 0  0 0 0  0 0 1
Camera "perspective" "float fov" [ 90 ]
Film "rgb" "integer xresolution" [ 16 ] "integer yresolution" [ 16 ]
PixelFilter "box"
WorldBegin
)";
const std::string kFloor = R"(AttributeBegin
Material "diffuse" "rgb reflectance" [ 0.6 0.6 0.6 ]
Shape "trianglemesh" "point3 P" [ -20 0 -20  20 0 -20  20 0 20  -20 0 20 ] "integer indices" [ 0 1 2 0 2 3 ]
AttributeEnd
)";
SceneDesc load(const std::string& body, const std::string& name = "t.pbrt") { return loadScene(write(name, kHead + body)); }
std::string errorOf(const std::string& text, const std::string& name = "bad.pbrt") {
    try {
        loadScene(write(name, text));
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST_CASE("pbrt import: tokens, parameters, camera, film, sampler, integrator, filter", "[pbrt][import]") {
    const SceneDesc d = loadScene(write("all.pbrt", R"(# a comment "with quotes" [ and brackets ]
Scale -1 1 1
LookAt 1 2 3   1 2 4   0 1 0   # eye, look, up
Camera "perspective" "float fov" 30 "float lensradius" [ 0.5 ] "float focaldistance" [ 4 ] "float shutterclose" 0.5
Film "rgb" "integer xresolution" [ 40 ] "integer yresolution" [ 20 ] "string filename" "out\"put.exr" "float iso" 200
Sampler "halton" "integer pixelsamples" 16
Integrator "bdpt" "integer maxdepth" [ 3 ]
PixelFilter "mitchell" "float xradius" 1.5 "float yradius" [1.5]
WorldBegin
LightSource "point" "rgb I" [ 1 2 3 ] "point3 from" [ 0 5 0 ]
Shape "sphere"
)"));
    CHECK(d.settings.width == 40);
    CHECK(d.settings.height == 20);
    CHECK(d.settings.output == "out\"put.exr");
    CHECK(d.settings.samples == 4);
    CHECK(d.settings.tracer == TracerKind::BPT);
    CHECK(d.settings.maxPathLength == 4);  // maxdepth 3 bounces: 4 segments
    CHECK(d.filter.kind == FilterKind::Mitchell);
    CHECK(d.filter.radius == 1.5f);
    CHECK(d.camera.fovDegrees == 30.0f);
    CHECK(d.camera.position.z == Approx(3.0f));
    CHECK(d.camera.lookAt.z == Approx(4.0f));
    CHECK(d.camera.dof);
    CHECK(d.camera.focalLength == 4.0f);
    CHECK(d.camera.focalLength / (2 * d.camera.fStop) == Approx(0.5f));
    // pbrt's image right is camera +x; Scale -1 1 1 mirrors it back to wavemmlt's own right
    CHECK_FALSE(d.camera.flipX);
    CHECK(loadScene(write("plain.pbrt", "LookAt 0 0 0  0 0 1  0 1 0\nCamera \"perspective\"\nWorldBegin\nLightSource \"point\"\nShape \"sphere\"\n"))
              .camera.flipX);
    // the film's iso 200 and the shutter open for 0.5: the imaging ratio 1 on every emitter
    CHECK(d.lights[0].radiance.y == Approx(2.0f));
    CHECK(d.lights[0].position.y == Approx(5.0f));
    // defaults: volpath (PT), maxdepth 5, 16 spp, gaussian 1.5 / 0.5, 1280 x 720
    const SceneDesc e = loadScene(write("defaults.pbrt", "WorldBegin\nLightSource \"point\"\nShape \"sphere\"\n"));
    CHECK(e.settings.tracer == TracerKind::PT);
    CHECK(e.settings.maxPathLength == 6);
    CHECK(e.settings.samples == 4);
    CHECK(e.settings.width == 1280);
    CHECK(e.filter.kind == FilterKind::Gaussian);
    CHECK(e.filter.radius == 1.5f);
    CHECK(e.filter.stddev == 0.5f);
    CHECK(e.camera.fovDegrees == 90.0f);
}

TEST_CASE("pbrt import: an integrator wavemmlt lacks is replaced by the command line's tracer", "[pbrt][import]") {
    const std::string text = "Integrator \"sppm\" \"integer maxdepth\" 4 \"float radius\" 0.1\n" + kHead + kFloor + "LightSource \"point\"\n";
    CHECK_THAT(errorOf(text, "sppm.pbrt"), Catch::Contains("sppm.pbrt:1:") && Catch::Contains("--tracer"));
    const SceneDesc d = loadScene(write("sppm.pbrt", text), {}, LoadOptions{true});
    REQUIRE(d.warnings.size() == 1);
    CHECK_THAT(d.warnings[0], Catch::Contains("sppm.pbrt:1") && Catch::Contains("\"sppm\" is not one of wavemmlt's"));
    CHECK(d.settings.maxPathLength == 5);  // maxdepth, pbrt's meaning for every integrator
}

TEST_CASE("pbrt import: regularize is applied by PT and BPT, the others warn, naming its line", "[pbrt][import][regularize]") {
    // (tests/test_regularize.cpp renders it)
    struct Case {
        const char* integrator;
        bool tracerGiven;
        TracerKind tracer;
        const char* warning;  // nullptr: applied, no warning
    };
    const Case cases[] = {
        {"path", false, TracerKind::PT, nullptr},
        {"volpath", false, TracerKind::PT, nullptr},
        {"bdpt", false, TracerKind::BPT, nullptr},
        {"mlt", false, TracerKind::MMLT, "bias the Markov chains' target"},
        {"lightpath", false, TracerKind::LT, "not applied by the light tracer"},
        // the command line's tracer decides
        {"path", true, TracerKind::MMLT, "bias the Markov chains' target"},
        {"path", true, TracerKind::PSSMLT, "bias the Markov chains' target"},
        {"bdpt", true, TracerKind::LT, "not applied by the light tracer"},
        {"mlt", true, TracerKind::PT, nullptr},
        {"lightpath", true, TracerKind::BPT, nullptr},
    };
    for (const Case& c : cases) {
        const std::string text =
            std::string("Integrator \"") + c.integrator + "\"\n  \"bool regularize\" true\n" + kHead + kFloor + "LightSource \"point\"\n";
        const SceneDesc d = loadScene(write("reg.pbrt", text), {}, LoadOptions{c.tracerGiven, c.tracer});
        INFO(c.integrator << (c.tracerGiven ? " with --tracer " + std::to_string(int(c.tracer)) : std::string()));
        CHECK(d.regularize);  // the scene's request: the render applies it by its tracer
        CHECK_THAT(d.regularizeAt, Catch::EndsWith("reg.pbrt:2"));
        if (!c.warning) {
            CHECK(d.warnings.empty());
        } else {
            REQUIRE(d.warnings.size() == 1);
            CHECK_THAT(d.warnings[0], Catch::Contains("reg.pbrt:2") && Catch::Contains("regularize is not applied") && Catch::Contains(c.warning));
        }
    }
    const SceneDesc off =
        loadScene(write("noreg.pbrt", "Integrator \"path\" \"bool regularize\" false\n" + kHead + kFloor + "LightSource \"point\"\n"));
    CHECK_FALSE(off.regularize);
    CHECK(off.warnings.empty());
}

TEST_CASE("pbrt import: Include, gzip, and the same scene either way", "[pbrt][import]") {
    write("inc-geom.pbrt", kFloor);
    const SceneDesc a = load("Include \"inc-geom.pbrt\"\nLightSource \"point\" \"point3 from\" [0 1 0]\n", "inc.pbrt");
    const std::string plain = kHead + kFloor + "LightSource \"point\" \"point3 from\" [0 1 0]\n";
    gzFile gz = gzopen((dir() + "/zipped.pbrt.gz").c_str(), "wb");
    REQUIRE(gz);
    gzwrite(gz, plain.data(), unsigned(plain.size()));
    gzclose(gz);
    const SceneDesc b = loadScene(dir() + "/zipped.pbrt.gz");
    REQUIRE(a.shapes.size() == 1);
    REQUIRE(b.shapes.size() == 1);
    CHECK(a.shapes[0].mesh.positions.size() == b.shapes[0].mesh.positions.size());
    CHECK(a.shapes[0].mesh.positions[2].x == b.shapes[0].mesh.positions[2].x);
    CHECK(a.lights[0].position.y == b.lights[0].position.y);
}

TEST_CASE("pbrt import: materials and textures", "[pbrt][import]") {
    std::filesystem::create_directories(dir() + "/spds");
    for (const char* f : {"Au.eta.spd", "Au.k.spd"})
        std::filesystem::copy_file(kData + "cornell-box/spds/" + f, dir() + "/spds/" + f, std::filesystem::copy_options::overwrite_existing);
    const SceneDesc d = load(R"(LightSource "point"
MakeNamedMaterial "a" "string type" "conductor" "float roughness" 0.01
MakeNamedMaterial "b" "string type" "conductor" "float uroughness" 0.04 "float vroughness" 0.09 "bool remaproughness" false
MakeNamedMaterial "c" "string type" "conductor" "spectrum eta" "metal-Au-eta" "spectrum k" "metal-Au-k"
MakeNamedMaterial "d" "string type" "conductor" "spectrum eta" "spds/Au.eta.spd" "spectrum k" "spds/Au.k.spd"
MakeNamedMaterial "e" "string type" "dielectric" "float eta" 1.33
MakeNamedMaterial "f" "string type" "diffuse"
MakeNamedMaterial "g" "string type" "mix" "string materials" [ "f" "e" ] "float amount" 0.25
Texture "checks" "spectrum" "checkerboard" "float uscale" 4 "float vscale" 2 "rgb tex1" [ 1 0 0 ] "rgb tex2" [ 0 0 1 ]
Texture "half" "spectrum" "scale" "texture tex" "checks" "float scale" 0.5
MakeNamedMaterial "h" "string type" "diffuse" "texture reflectance" "half"
)" + std::string("NamedMaterial \"a\"\nShape \"sphere\"\nNamedMaterial \"b\"\nShape \"sphere\"\nNamedMaterial \"c\"\nShape \"sphere\"\n") +
                                 "NamedMaterial \"d\"\nShape \"sphere\"\nNamedMaterial \"e\"\nShape \"sphere\"\nNamedMaterial \"g\"\nShape "
                                 "\"sphere\"\nNamedMaterial \"h\"\nShape \"sphere\"\n",
                             "materials.pbrt");
    auto mat = [&](size_t shape) { return d.materials[size_t(d.shapes[shape].material)]; };
    CHECK(mat(0).kind == MaterialKind::RoughConductor);
    CHECK(mat(0).distribution == MicrofacetType::GGX);
    CHECK(mat(0).alpha == Approx(0.1f));  // remapped: sqrt(roughness)
    CHECK(mat(1).alpha == Approx(0.04f));
    CHECK(mat(1).alphaV == Approx(0.09f));
    CHECK(mat(2).kind == MaterialKind::Conductor);
    // named gold is the D65 projection of its spectra, scaled to the spectral albedo
    SampledSpectrum eta, k;
    REQUIRE(readSpectrumFile(kData + "cornell-box/spds/Au.eta.spd", eta).empty());
    REQUIRE(readSpectrumFile(kData + "cornell-box/spds/Au.k.spd", k).empty());
    const Vec3 etaRgb = spectrumToRgb(eta, true), kRgb = spectrumToRgb(k, true);
    CHECK(mat(2).conductorEta.x == Approx(etaRgb.x).epsilon(1e-5));
    CHECK(mat(2).conductorK.z == Approx(kRgb.z).epsilon(1e-5));
    const Vec3 scale = conductorAlbedoScale(eta, k, etaRgb, kRgb);
    CHECK(mat(2).reflect.x == Approx(scale.x).epsilon(1e-5));
    CHECK(mat(2).reflect.z == Approx(scale.z).epsilon(1e-5));
    CHECK(scale.x > 1.03f);  // gold's red: out of gamut
    CHECK(mat(4).kind == MaterialKind::Dielectric);
    CHECK(mat(4).iorInside == Approx(1.33f));
    CHECK(mat(5).kind == MaterialKind::Blend);
    CHECK(mat(5).blendWeight == 0.25f);
    CHECK(d.materials[size_t(mat(5).blendPart[1])].kind == MaterialKind::Dielectric);
    // the checkerboard: tex1 where floor(4u) + floor(2v) is even, times 0.5
    const MaterialDesc& h = mat(6);
    REQUIRE(h.texture[MaterialParam::Diffuse] >= 0);
    for (const auto& [u, v] : std::vector<std::pair<float, float>>{{0.1f, 0.1f}, {0.3f, 0.1f}, {0.3f, 0.6f}, {0.9f, 0.9f}, {0.6f, 0.3f}}) {
        const bool even = (int(std::floor(4 * u)) + int(std::floor(2 * v))) % 2 == 0;
        const Vec3 c = evalTextureOf(d.textures, size_t(h.texture[MaterialParam::Diffuse]), u, v, Vec3(0.0f), Vec3(0, 0, 1));
        INFO("u " << u << " v " << v);
        CHECK(c.x == (even ? 0.5f : 0.0f));
        CHECK(c.z == (even ? 0.0f : 0.5f));
    }
    // the spectra from .spd files give what the named gold gives
    CHECK(mat(3).conductorEta.y == Approx(mat(2).conductorEta.y).epsilon(1e-5));
    CHECK(mat(3).reflect.x == Approx(mat(2).reflect.x).epsilon(1e-5));
    // no material: pbrt's diffuse 0.5
    const SceneDesc e = load("LightSource \"point\"\nShape \"sphere\"\n", "default.pbrt");
    CHECK(e.materials[size_t(e.shapes[0].material)].kind == MaterialKind::Matte);
    CHECK(e.materials[size_t(e.shapes[0].material)].diffuse.y == 0.5f);
}

TEST_CASE("pbrt import: shapes and the side an area light emits to", "[pbrt][import]") {
    const SceneDesc d = load(R"(AttributeBegin
AreaLightSource "diffuse" "rgb L" [ 2 2 2 ]
Shape "trianglemesh" "point3 P" [ 0 0 0  1 0 0  0 1 0 ]
AttributeEnd
AttributeBegin
AreaLightSource "diffuse" "rgb L" [ 2 2 2 ]
ReverseOrientation
Shape "trianglemesh" "point3 P" [ 0 0 0  1 0 0  0 1 0 ]
AttributeEnd
AttributeBegin
Scale 1 1 -1
AreaLightSource "diffuse" "rgb L" [ 2 2 2 ] "float power" [ 10 ]
Shape "trianglemesh" "point3 P" [ 0 0 0  1 0 0  0 1 0 ]
AttributeEnd
Translate 0 0 5
Scale 2 2 2
Shape "sphere" "float radius" 0.5
Shape "sphere" "float radius" 1 "float zmin" 0
Shape "disk" "float radius" 2
)");
    auto normalOf = [&](size_t i) {
        const TriangleMesh& m = d.shapes[i].mesh;
        return cross(m.positions[m.indices[1]] - m.positions[m.indices[0]], m.positions[m.indices[2]] - m.positions[m.indices[0]]);
    };
    CHECK(normalOf(0).z > 0);  // the winding's side
    CHECK(normalOf(1).z < 0);  // turned over
    CHECK(normalOf(2).z < 0);  // mirrored by the transform: pbrt keeps the object's side, -z in the world
    // power 10 W from a triangle of area 1/2: L = 10 / (pi A luminance) for rgb L 2 (luminance 2)
    CHECK(d.lights[2].radiance.x == Approx(2 * 10 / (M_PI * 0.5 * 2)).epsilon(1e-5));
    CHECK(d.lights[0].kind == LightKind::Mesh);  // a triangle
    // a quad light (a parallelogram of two triangles) is the analytic rectangle light
    const SceneDesc q = load(
        "AreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ]\nShape \"trianglemesh\" \"point3 P\" [ 0 0 0  2 0 0  3 1 0  1 1 0 ] \"integer indices\" [ 0 "
        "1 2 2 3 0 ]\n"
        "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0  2 0 0  3 1 0  1 1.5 0 ] \"integer indices\" [ 0 1 2 2 3 0 ]\n",
        "quad.pbrt");
    CHECK(q.lights[0].kind == LightKind::Rect);
    CHECK(q.lights[1].kind == LightKind::Mesh);  // not a parallelogram
    CHECK(d.shapes[3].kind == ShapeKind::Sphere);
    CHECK(d.shapes[3].radius == Approx(1.0f));
    CHECK(d.shapes[3].center.z == Approx(5.0f));
    CHECK(d.shapes[4].kind == ShapeKind::Mesh);  // half a sphere: a mesh
    for (const Vec3& p : d.shapes[4].mesh.positions) CHECK(p.z >= 5.0f - 1e-4f);
    double area = 0;
    const TriangleMesh& disk = d.shapes[5].mesh;
    for (size_t t = 0; t < disk.indices.size(); t += 3)
        area += 0.5 * length(cross(disk.positions[disk.indices[t + 1]] - disk.positions[disk.indices[t]],
                                   disk.positions[disk.indices[t + 2]] - disk.positions[disk.indices[t]]));
    CHECK(area == Approx(M_PI * 16).epsilon(1e-3));
}

TEST_CASE("pbrt import: point, spot and distant lights on a diffuse floor, in PT, LT and BPT", "[pbrt][render]") {
    using floor_test::floorRadianceOf;
    const Vec3 c(0.2f, 1.3f, -0.1f);
    auto r2 = [&](Vec3 p) { return double(lengthSquared(c - p)); };
    // point: L = rho / pi I cos / r^2
    floorRadianceOf(load(kFloor + "LightSource \"point\" \"rgb I\" [ 2 2 2 ] \"point3 from\" [ 0.2 1.3 -0.1 ]\n", "point.pbrt"),
                    [&](Vec3 p, Vec3) { return 0.6 / M_PI * 2 * c.y / std::sqrt(r2(p)) / r2(p); }, "pbrt-point", {});
    // spot along -y, cone 40, delta 15: pbrt's smoothstep in the cosine between 25 and 40 degrees
    const double cosEnd = std::cos(40 * M_PI / 180), cosStart = std::cos(25 * M_PI / 180);
    floorRadianceOf(load(kFloor + "LightSource \"spot\" \"rgb I\" [ 3 3 3 ] \"point3 from\" [ 0.2 1.3 -0.1 ] \"point3 to\" [ 0.2 0 -0.1 ]"
                                  " \"float coneangle\" 40 \"float conedeltaangle\" 15\n",
                         "spot.pbrt"),
                    [&](Vec3 p, Vec3) {
                        const double cosT = c.y / std::sqrt(r2(p));
                        double f = cosT >= cosStart ? 1 : cosT <= cosEnd ? 0 : 0;
                        if (cosT > cosEnd && cosT < cosStart) {
                            const double t = (cosT - cosEnd) / (cosStart - cosEnd);
                            f = t * t * (3 - 2 * t);
                        }
                        return 0.6 / M_PI * 3 * f * cosT / r2(p);
                    },
                    "pbrt-spot", {});
    // distant: illuminance 2 on a surface facing it, from 30 degrees off the vertical: E cos
    floorRadianceOf(load(kFloor + "LightSource \"distant\" \"rgb L\" [ 1 1 1 ] \"point3 from\" [ 0.5 0.8660254 0 ] \"point3 to\" [ 0 0 0 ]"
                                  " \"float illuminance\" 2\n",
                         "distant.pbrt"),
                    [&](Vec3, Vec3) { return 0.6 / M_PI * 2 * 0.8660254; }, "pbrt-distant", {TracerKind::PT, TracerKind::BPT});
}

TEST_CASE("pbrt import: diffusetransmission's reflected and transmitted halves, in PT, LT and BPT", "[pbrt][render]") {
    // A floor of reflectance 0.3 and transmittance 0.5 (scale 1): lit from above it reflects
    // R / pi E, lit from below it transmits T / pi E to the camera above.
    using floor_test::floorRadianceOf;
    const std::string floor = R"(AttributeBegin
Material "diffusetransmission" "rgb reflectance" [ 0.3 0.3 0.3 ] "rgb transmittance" [ 0.5 0.5 0.5 ]
Shape "trianglemesh" "point3 P" [ -20 0 -20  20 0 -20  20 0 20  -20 0 20 ] "integer indices" [ 0 1 2 0 2 3 ]
AttributeEnd
)";
    for (const float side : {1.0f, -1.0f}) {
        const Vec3 c(0.2f, 1.3f * side, -0.1f);
        const double rho = side > 0 ? 0.3 : 0.5;
        floorRadianceOf(load(floor + "LightSource \"point\" \"rgb I\" [ 2 2 2 ] \"point3 from\" [ 0.2 " + std::to_string(c.y) + " -0.1 ]\n",
                             side > 0 ? "dt-above.pbrt" : "dt-below.pbrt"),
                        [&](Vec3 p, Vec3) {
                            const double r2 = double(lengthSquared(c - p));
                            return rho / M_PI * 2 * std::fabs(c.y) / std::sqrt(r2) / r2;
                        },
                        side > 0 ? "pbrt-diffusetransmission-reflected" : "pbrt-diffusetransmission-transmitted", {});
    }
}

TEST_CASE("pbrt import: a two-sided area light lights the floor from its back face, in PT, LT and BPT", "[pbrt][render][twosided]") {
    // A 1.2 x 1.2 quad at height 1.2 over (0.3, 0), its front face up, away from the floor:
    // one-sided it leaves the floor black, two-sided its back face gives the floor
    // L rectangleIrradiance; `power` counts both faces (pbrt: k_e = 2 pi A L).
    const std::string quad =
        R"(Shape "trianglemesh" "point3 P" [ -0.3 1.2 -0.6  -0.3 1.2 0.6  0.9 1.2 0.6  0.9 1.2 -0.6 ] "integer indices" [ 0 1 2 0 2 3 ]
)";
    const SceneDesc d =
        load(kFloor + "AreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ] \"bool twosided\" true \"float power\" 9.0478\n" + quad, "two-sided.pbrt");
    REQUIRE(d.lights.size() == 1);
    CHECK(d.lights[0].kind == LightKind::Mesh);  // not the one-sided rectangle light
    CHECK(d.lights[0].twoSided);
    const double L = 9.0478 / (2 * M_PI * 1.44);  // 1.0000 to 4e-5
    CHECK(d.lights[0].radiance.y == Approx(L).epsilon(1e-5));
    floor_test::floorRadianceOf(d, [&](Vec3 p, Vec3) { return 0.6 / M_PI * L * floor_test::rectangleIrradiance(p, 1.2, -0.3, 0.9, -0.6, 0.6); },
                                "pbrt-two-sided", {});
    const SceneDesc one = load(kFloor + "AreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ]\n" + quad, "one-sided-up.pbrt");
    for (TracerKind t : {TracerKind::PT, TracerKind::LT, TracerKind::BPT}) {
        const Image img = render(one, rstats::renderOptions(t, 4, 5, 1, 2)).image;
        double sum = 0;
        for (float v : img.rgb) sum += v;
        CHECK(sum == 0);
    }
}

TEST_CASE("pbrt import: a two-sided area light seen from behind is L, in every tracer", "[pbrt][render][twosided]") {
    // The camera looks at the back of a two-sided quad that fills its view: every pixel is
    // L (0.7) in expectation (PT's camera rays find it: exactly); MIS weights that did not sum
    // to one (a density of the wrong face) would show. No other surface: nothing else
    // contributes.
    const SceneDesc d = load(R"(AreaLightSource "diffuse" "rgb L" [ 0.7 0.7 0.7 ] "bool twosided" true
Shape "trianglemesh" "point3 P" [ -5 -0.5 -5  5 -0.5 -5  5 -0.5 5  -5 -0.5 5 ] "integer indices" [ 0 1 2 0 2 3 ]
)",
                             "two-sided-back.pbrt");
    REQUIRE(d.lights.size() == 1);
    for (float v : render(d, rstats::renderOptions(TracerKind::PT, 4, 40, 1, 2)).image.rgb) CHECK(v == Approx(0.7f));  // PT: L, no variance
    for (TracerKind t : {TracerKind::LT, TracerKind::BPT, TracerKind::MMLT}) {
        rstats::RunStats runs;
        for (int k = 0; k < 6; ++k) runs.add(rstats::blockMeans(render(d, rstats::renderOptions(t, 16, 40 + uint64_t(k), 1, 2)).image, 4, 1));
        const rstats::ZTestResult z = rstats::zTest(runs, std::vector<double>(16, 0.7));
        INFO("tracer " << int(t) << ": " << z.describe());
        CHECK(z.pass);
    }
}

TEST_CASE("pbrt import: an area light with an image, looked up at (u, 1 - v), and its power", "[pbrt][render][meshlight]") {
    // A 1 x 2 image (row 0, the top: A; row 1: B): pbrt reads v = 0 at the bottom row.
    {
        std::ofstream f(dir() + "/ab.pfm", std::ios::binary);
        f << "PF\n1 2\n-1.0\n";
        const float px[6] = {0.2f, 0.4f, 0.6f, 1.0f, 2.0f, 3.0f};  // PFM: bottom row (B) first, then A
        f.write(reinterpret_cast<const char*>(px), sizeof px);
    }
    {
        std::ofstream f(dir() + "/one.pfm", std::ios::binary);
        f << "PF\n1 1\n-1.0\n";
        const float px[3] = {0.5f, 1.0f, 2.0f};
        f.write(reinterpret_cast<const char*>(px), sizeof px);
    }
    // a 1.2 x 1.2 quad at height 1.2 over (0.3, 0), facing down, with (u, v)
    const std::string quad =
        R"(Shape "trianglemesh" "point3 P" [ -0.3 1.2 -0.6  -0.3 1.2 0.6  0.9 1.2 0.6  0.9 1.2 -0.6 ] "integer indices" [ 0 2 1 0 3 2 ]
  "point2 uv" [ 0 0  0 1  1 1  1 0 ]
)";
    const SceneDesc ab = load(kFloor + "AreaLightSource \"diffuse\" \"string filename\" \"ab.pfm\"\n" + quad, "image-light.pbrt");
    REQUIRE(ab.lights.size() == 1);
    REQUIRE(ab.lights[0].texture >= 0);
    CHECK(ab.lights[0].kind == LightKind::Mesh);
    const TextureDesc& t = ab.textures[size_t(ab.lights[0].texture)];
    CHECK(evalTexture(t, 0.5f, 0.0f, Vec3(0.0f)).x == Approx(0.2f));  // v = 0: the bottom row, B
    CHECK(evalTexture(t, 0.5f, 1.0f, Vec3(0.0f)).x == Approx(1.0f));  // v = 1: the top row, A
    CHECK(evalTexture(t, 0.5f, 0.5f, Vec3(0.0f)).x == Approx(0.6f));  // bilinear between the rows' centres
    // One texel: uniform radiance (0.5, 1, 2) times power / (pi A mean luminance), on the floor
    // as the rectangle's closed form, in PT, LT and BPT.
    const SceneDesc one =
        load(kFloor + "AreaLightSource \"diffuse\" \"string filename\" \"one.pfm\" \"float power\" 5\n" + quad, "image-light-1.pbrt");
    const double lum = 0.2126 * 0.5 + 0.7152 * 1.0 + 0.0722 * 2.0, scale = 5 / (M_PI * 1.44 * lum);
    CHECK(one.lights[0].radiance.y == Approx(scale).epsilon(1e-5));
    floor_test::floorRadianceOf(one, [&](Vec3 p, Vec3) { return 0.6 / M_PI * scale * floor_test::rectangleIrradiance(p, 1.2, -0.3, 0.9, -0.6, 0.6); },
                                "pbrt-image-light", {});
    CHECK_THAT(
        errorOf(kHead + "AreaLightSource \"diffuse\" \"string filename\" \"one.pfm\"\nShape \"trianglemesh\" \"point3 P\" [ 0 0 0  1 0 0  0 1 0 ]\n"),
        Catch::Contains("bad.pbrt:6") && Catch::Contains("(u, v)"));
    CHECK_THAT(errorOf(kHead + "AreaLightSource \"diffuse\" \"string filename\" \"one.pfm\" \"rgb L\" [ 1 1 1 ]\n" + quad),
               Catch::Contains("bad.pbrt:6") && Catch::Contains("not both"));
}

TEST_CASE("pbrt import: cropwindow and pixelbounds render that part of the film", "[pbrt][render][crop]") {
    // 16 x 16 film, cropwindow [0.25 0.75] x [0.5 1]: pixels [4, 12) x [8, 16), an 8 x 8 image
    // whose pixel (x, y) is the film's (x + 4, y + 8): the same rays, and back (the light
    // tracer's inverse) to the same raster point.
    const std::string film = R"(LookAt 0 1 0  0 0 0  0 0 1
Camera "perspective" "float fov" [ 90 ]
Film "rgb" "integer xresolution" [ 16 ] "integer yresolution" [ 16 ] )";
    const std::string rest =
        "\nPixelFilter \"box\"\nWorldBegin\n" + kFloor + "LightSource \"point\" \"rgb I\" [ 2 2 2 ] \"point3 from\" [ 0.2 1.3 -0.1 ]\n";
    const SceneDesc full = loadScene(write("full.pbrt", film + rest));
    for (const std::string& crop : {std::string("\"float cropwindow\" [ 0.25 0.75 1 0.5 ]"), std::string("\"integer pixelbounds\" [ 4 12 8 16 ]")}) {
        const SceneDesc d = loadScene(write("crop.pbrt", film + crop + rest));
        REQUIRE(d.settings.width == 8);
        REQUIRE(d.settings.height == 8);
        for (bool ortho : {false, true}) {
            CameraDesc cf = full.camera, cc = d.camera;
            cf.orthographic = cc.orthographic = ortho;
            const Camera a = makeCamera(cf, 16, 16), b = makeCamera(cc, 8, 8);
            for (float px : {0.0f, 0.3f, 4.5f, 7.99f})
                for (float py : {0.0f, 2.25f, 7.5f}) {
                    Vec3 oa, da, ob, db;
                    generateCameraRay(a, px + 4, py + 8, 0.5f, 0.5f, oa, da);
                    generateCameraRay(b, px, py, 0.5f, 0.5f, ob, db);
                    CHECK(length(oa - ob) < 1e-5f);
                    CHECK(length(da - db) < 1e-5f);
                    if (ortho) continue;
                    float rx, ry;
                    REQUIRE(cameraRasterOf(b, db, rx, ry));
                    CHECK(rx == Approx(px).margin(1e-4));
                    CHECK(ry == Approx(py).margin(1e-4));
                }
        }
        const Vec3 c(0.2f, 1.3f, -0.1f);
        floor_test::floorRadianceOf(d,
                                    [&](Vec3 p, Vec3) {
                                        const double r2 = double(lengthSquared(c - p));
                                        return 0.6 / M_PI * 2 * c.y / std::sqrt(r2) / r2;
                                    },
                                    "pbrt-crop", {});
    }
    // Mitsuba's hdrfilm crop: the same window
    auto mitsuba = [&](const std::string& crop) {
        return loadMitsubaFromString(R"(<scene version="3.0.0">)" + floor_test::kLookingDown +
                                         R"(<film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/>)" + crop +
                                         R"(</film></sensor><emitter type="point"><point name="position" x="0" y="1" z="0"/></emitter></scene>)",
                                     "crop.xml", dir());
    };
    const SceneDesc mf = mitsuba(""), mc = mitsuba(R"(<integer name="crop_offset_x" value="4"/><integer name="crop_offset_y" value="8"/>
        <integer name="crop_width" value="8"/><integer name="crop_height" value="8"/>)");
    REQUIRE(mc.settings.width == 8);
    REQUIRE(mc.settings.height == 8);
    Vec3 oa, da, ob, db;
    generateCameraRay(makeCamera(mf.camera, 16, 16), 5.5f, 9.25f, 0.5f, 0.5f, oa, da);
    generateCameraRay(makeCamera(mc.camera, 8, 8), 1.5f, 1.25f, 0.5f, 0.5f, ob, db);
    CHECK(length(da - db) < 1e-5f);
    CHECK_THAT(errorOf(film + "\"float cropwindow\" [ 0.5 0.5 0 1 ]" + rest), Catch::Contains("bad.pbrt:3") && Catch::Contains("no pixel"));
    CHECK_THAT(errorOf(film + "\"integer pixelbounds\" [ 0 17 0 16 ]" + rest), Catch::Contains("bad.pbrt:3") && Catch::Contains("pixelbounds"));
}

TEST_CASE("pbrt import: Attribute gives default parameters to a class of directives", "[pbrt][import]") {
    const SceneDesc d = load(R"(AttributeBegin
Attribute "shape" "float radius" 2 "float uscale" 5
Attribute "material" "rgb reflectance" [ 0.2 0.3 0.4 ]
Attribute "light" "float scale" 3
Attribute "texture" "float uscale" 4
Material "diffuse"
Shape "sphere"
Shape "sphere" "float radius" 0.5
LightSource "point" "rgb I" [ 1 1 1 ]
Texture "t" "spectrum" "bilerp"
Material "diffuse" "texture reflectance" "t"
Shape "sphere"
AttributeEnd
Shape "sphere"
LightSource "point" "rgb I" [ 1 1 1 ]
)",
                             "attribute.pbrt");
    REQUIRE(d.shapes.size() == 4);
    CHECK(d.shapes[0].radius == Approx(2.0f));  // the default
    CHECK(d.shapes[1].radius == Approx(0.5f));  // its own wins
    CHECK(d.shapes[3].radius == Approx(1.0f));  // AttributeEnd restores pbrt's default
    CHECK(d.materials[size_t(d.shapes[0].material)].diffuse.z == Approx(0.4f));
    CHECK(d.lights[0].radiance.x == Approx(3.0f));
    CHECK(d.lights[1].radiance.x == Approx(1.0f));
    const TextureDesc& t = d.textures[size_t(d.materials[size_t(d.shapes[2].material)].texture[MaterialParam::Diffuse])];
    CHECK(t.uvTransform[0] == Approx(4.0f));  // uscale
    CHECK(d.warnings.empty());                // defaults a directive does not read (the texture's uscale on a sphere) are no mistake
}

TEST_CASE("pbrt import: an instanced object renders as its flattened copy", "[pbrt][render][instancing]") {
    const std::string box = R"(Shape "trianglemesh" "point3 P" [ -1 -1 0  1 -1 0  1 1 0  -1 1 0 ] "integer indices" [ 0 1 2 0 2 3 ]
Shape "sphere" "float radius" 0.3
)";
    const std::string light = "LightSource \"point\" \"rgb I\" [ 3 3 3 ] \"point3 from\" [ 0 0.9 0 ]\n";
    const std::string place1 = "Translate 0.3 0.2 0\nRotate 90 1 0 0\nScale 0.3 0.3 0.3\n",
                      place2 = "Translate -0.4 0.1 0.2\nRotate 90 1 0 0\nScale 0.2 0.2 0.2\n";
    const SceneDesc inst = load(kFloor + light + "ObjectBegin \"o\"\n" + box + "ObjectEnd\nAttributeBegin\n" + place1 +
                                    "ObjectInstance \"o\"\nAttributeEnd\nAttributeBegin\n" + place2 + "ObjectInstance \"o\"\nAttributeEnd\n",
                                "instanced.pbrt");
    const SceneDesc flat = load(
        kFloor + light + "AttributeBegin\n" + place1 + box + "AttributeEnd\nAttributeBegin\n" + place2 + box + "AttributeEnd\n", "flattened.pbrt");
    CHECK(inst.instances.size() == 2);
    CHECK(inst.groups == 1);
    CHECK(flat.instances.empty());
    rstats::RunStats a, b;
    for (int k = 0; k < 6; ++k) {
        a.add(rstats::blockMeans(render(inst, rstats::renderOptions(TracerKind::PT, 64, 40 + uint64_t(k), 1, 4)).image, 4, 1));
        b.add(rstats::blockMeans(render(flat, rstats::renderOptions(TracerKind::PT, 64, 60 + uint64_t(k), 1, 4)).image, 4, 1));
    }
    const rstats::ZTestResult z = rstats::compareRuns(a, b, 1e-4);
    INFO(z.describe());
    CHECK(z.pass);
}

TEST_CASE("pbrt import: the Cornell box equals the same box written in the thesis format", "[pbrt][render][stat]") {
    // cornell-box-thesis.xml: the vertices, reflectances, light and camera written by hand.
    // Both with a box filter at 64 x 64; pbrt's image is the thesis format's mirrored.
    SceneDesc p = loadScene(kData + "cornell-box/cornell-box.pbrt"), t = loadScene(kData + "cornell-box/cornell-box-thesis.xml");
    p.settings.width = p.settings.height = 64;
    p.filter = FilterDesc{};
    CHECK(p.settings.maxPathLength == t.settings.maxPathLength);
    auto mirrored = [](const Image& im) {
        Image m(im.width, im.height);
        for (int y = 0; y < im.height; ++y)
            for (int x = 0; x < im.width; ++x) m.set(im.width - 1 - x, y, im.at(x, y));
        return m;
    };
    rstats::RunStats a[3], b[3];
    for (int k = 0; k < 6; ++k) {
        const Image ip = render(p, rstats::renderOptions(TracerKind::PT, 16, 70 + uint64_t(k), 1, 6)).image;
        const Image it = mirrored(render(t, rstats::renderOptions(TracerKind::PT, 16, 90 + uint64_t(k), 1, 6)).image);
        for (int c = 0; c < 3; ++c) {
            a[c].add(rstats::blockMeans(ip, 8, c));
            b[c].add(rstats::blockMeans(it, 8, c));
        }
    }
    for (int c = 0; c < 3; ++c) {
        const rstats::ZTestResult z = rstats::compareRuns(a[c], b[c], 1e-4);
        INFO("channel " << c << ": " << z.describe());
        CHECK(z.pass);
    }
}

TEST_CASE("pbrt import: the four tracers agree on coated materials (pbrt's layered BSDF)", "[pbrt][render][stat][coated]") {
    // A coateddiffuse floor (rough coat, textured-free) and a coatedconductor sphere (rough
    // coat over rough gold) under a quad light: PT, LT and MMLT against BPT, 16 runs each
    // (power.h: brightness, blocks, their spread, p = 1e-4).
    SceneDesc d = load(R"(AttributeBegin
Material "coateddiffuse" "rgb reflectance" [ 0.7 0.4 0.2 ] "float roughness" [ 0.05 ]
Shape "trianglemesh" "point3 P" [ -20 0 -20  20 0 -20  20 0 20  -20 0 20 ] "integer indices" [ 0 1 2 0 2 3 ]
AttributeEnd
AttributeBegin
Material "coatedconductor" "float interface.roughness" [ 0.04 ] "float conductor.roughness" [ 0.02 ]
  "spectrum conductor.eta" "metal-Au-eta" "spectrum conductor.k" "metal-Au-k"
Translate 0.2 0.25 0.1
Shape "sphere" "float radius" [ 0.25 ]
AttributeEnd
AttributeBegin
AreaLightSource "diffuse" "rgb L" [ 4 4 4 ]
Shape "trianglemesh" "point3 P" [ -0.5 1.5 -0.5  -0.5 1.5 0.5  0.5 1.5 0.5  0.5 1.5 -0.5 ] "integer indices" [ 0 2 1 0 3 2 ]
AttributeEnd
)",
                       "coated-tracers.pbrt");
    d.settings.maxPathLength = 4;  // pbrt's maxdepth 3
    auto runs = [&](TracerKind t, int spp, uint64_t seed0) {
        power::Runs r(4);
        RenderOptions o = rstats::renderOptions(t, spp, 0, 1, d.settings.maxPathLength);
        if (t == TracerKind::MMLT) {
            o.chains = 1024;
            o.bootstrap = 1 << 14;
        }
        for (int k = 0; k < 16; ++k) {
            o.seed = seed0 + uint64_t(k);
            const RenderResult res = render(d, o);
            REQUIRE(res.stats.samplesNonfiniteDiscarded == 0);
            if (t == TracerKind::MMLT) REQUIRE(res.stats.mmlt.replayMismatches == 0);
            r.add(res);
        }
        return r;
    };
    const power::Runs ref = runs(TracerKind::BPT, 64, 100);
    for (const auto& [t, spp] : std::vector<std::pair<TracerKind, int>>{{TracerKind::PT, 64}, {TracerKind::LT, 64}, {TracerKind::MMLT, 64}}) {
        const power::Runs r = runs(t, spp, 200 + 100 * uint64_t(t));
        for (const power::Verdict& v : {power::brightness(r, ref, 1e-4), power::blocks(r, ref, 1e-4), power::scatter(r, ref, 1e-4)}) {
            INFO("tracer " << int(t) << " vs BPT: " << v.text);
            CHECK(v.pass);
        }
    }
}

TEST_CASE("pbrt import: the equal-area octahedral environment map against the same map in latitude-longitude form", "[pbrt][import][envmap]") {
    using namespace wmlt::pbrt;
    // The parameterisation: its inverse, and equal areas of the square are equal solid angles.
    std::mt19937 g(9);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    rstats::RunStats z, z2, octant;
    for (int i = 0; i < 20000; ++i) {
        const Vec3 d = equalAreaSquareToSphere(U(g), U(g));
        z.add({double(d.z)});
        z2.add({double(d.z) * d.z});
        octant.add({d.x > 0 && d.y > 0 && d.z > 0 ? 1.0 : 0.0});
        CHECK(length(d) == Approx(1.0f).epsilon(1e-5));
        double u, v;
        equalAreaSphereToSquare(d, u, v);
        const Vec3 e = equalAreaSquareToSphere(u, v);
        CHECK(dot(d, e) > 1 - 1e-5f);
    }
    CHECK(std::fabs(z.mean(0)) < 4.5 * z.se(0));              // uniform on the sphere: E z = 0
    CHECK(std::fabs(z2.mean(0) - 1.0 / 3) < 4.5 * z2.se(0));  // E z^2 = 1/3
    CHECK(std::fabs(octant.mean(0) - 1.0 / 8) < 4.5 * octant.se(0));
    // A map of f(d) = (1 + d) / 2 in pbrt's layout (texel centres), under Rotate -90 about x
    // (pbrt's scenes put +z up so): the importer's latitude-longitude map is f of each
    // direction taken into the light's frame, to the bilinear interpolation's error.
    const int N = 64;
    Image oct(N, N);
    for (int y = 0; y < N; ++y)
        for (int x = 0; x < N; ++x) {
            const Vec3 d = equalAreaSquareToSphere((x + 0.5) / N, (y + 0.5) / N);
            oct.set(x, y, (d + Vec3(1.0f)) * 0.5f);
        }
    writeImage(dir() + "/sky.pfm", oct);
    const SceneDesc d =
        load(kFloor + "AttributeBegin\nRotate -90 1 0 0\nLightSource \"infinite\" \"string filename\" \"sky.pfm\"\nAttributeEnd\n", "sky.pbrt");
    REQUIRE(d.envMap.width == 2 * N);
    double worst = 0;
    for (int y = 0; y < d.envMap.height; ++y)
        for (int x = 0; x < d.envMap.width; ++x) {
            const Vec3 w = envDirection((x + 0.5f) / d.envMap.width, (y + 0.5f) / d.envMap.height);
            const Vec3 l(w.x, -w.z, w.y);  // the light's frame: world y up is its +z
            const Vec3 want = (l + Vec3(1.0f)) * 0.5f, got = d.envMap.at(x, y);
            worst = std::max(worst, double(std::max(std::fabs(got.x - want.x), std::max(std::fabs(got.y - want.y), std::fabs(got.z - want.z)))));
        }
    CHECK(worst < 0.03);  // a 64 x 64 map of a linear function: bilinear error near the folds
    // illuminance: the sky scaled to give E = 3 on an upward surface
    const SceneDesc e = load(
        kFloor + "AttributeBegin\nRotate -90 1 0 0\nLightSource \"infinite\" \"string filename\" \"sky.pfm\" \"float illuminance\" 3\nAttributeEnd\n",
        "sky-e.pbrt");
    double E = 0;
    for (int y = 0; y < e.envMap.height; ++y) {
        const double dOmega = 2 * M_PI / e.envMap.width * (std::cos(M_PI * y / e.envMap.height) - std::cos(M_PI * (y + 1) / e.envMap.height));
        for (int x = 0; x < e.envMap.width; ++x) {
            const Vec3 w = envDirection((x + 0.5f) / e.envMap.width, (y + 0.5f) / e.envMap.height);
            const Vec3 c = e.envMap.at(x, y);
            if (w.y > 0) E += (0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z) * w.y * dOmega;
        }
    }
    CHECK(E == Approx(3.0).epsilon(1e-4));
}

TEST_CASE("Loop subdivision: pbrt's scheme", "[pbrt][loopsubdiv]") {
    // A flat patch stays in its plane, its normals the plane's; 4^levels triangles.
    std::vector<Vec3> P = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5f, 0.5f, 0}};
    std::vector<uint32_t> idx = {0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4};
    std::vector<Vec3> N;
    REQUIRE(loopSubdivide(P, idx, 2, N).empty());
    CHECK(idx.size() == 4 * 16 * 3);
    for (const Vec3& p : P) CHECK(p.z == 0.0f);
    for (const Vec3& n : N) CHECK(std::fabs(n.z) == Approx(1.0f));
    // An octahedron's limit is symmetric: its six original vertices end at one distance from
    // the centre, their normals radial.
    std::vector<Vec3> O = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    std::vector<uint32_t> oi = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
    REQUIRE(loopSubdivide(O, oi, 3, N).empty());
    CHECK(oi.size() == 8 * 64 * 3);
    for (int i = 0; i < 6; ++i) {
        CHECK(length(O[size_t(i)]) == Approx(length(O[0])).epsilon(1e-5));
        CHECK(std::fabs(dot(N[size_t(i)], normalize(O[size_t(i)]))) == Approx(1.0f).epsilon(1e-5));
    }
    CHECK(length(O[0]) < 1.0f);  // pulled in by the smoothing
    CHECK(length(O[0]) > 0.4f);
    // bad meshes: an edge of three faces
    std::vector<Vec3> T = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
    std::vector<uint32_t> ti = {0, 1, 2, 1, 0, 3, 0, 1, 4};
    CHECK_FALSE(loopSubdivide(T, ti, 1, N).empty());
}

TEST_CASE("pbrt import: bad input names file and line", "[pbrt][import][bad-input]") {
    const std::string head = "WorldBegin\nLightSource \"point\"\n";
    struct Bad {
        std::string text;
        std::string want;
    };
    const std::vector<Bad> cases = {
        {head + "Shape \"sphere\" \"float radius\" [ 1\n", "bad.pbrt:3: \"float radius\": unterminated ["},
        {head + "Shape \"sphere\" \"string name\" \"unterminated\n", "bad.pbrt:3: unterminated string"},
        {head + "Frobnicate 1 2\n", "bad.pbrt:3: unknown directive \"Frobnicate\""},
        {head + "Shape \"sphere\"\n  \"float radius\" [ \"one\" ]\n", "bad.pbrt:4: \"float radius\": expected a number, found \"one\""},
        {head + "Shape \"sphere\"\n  \"float radius\" [ 1 2 ]\n", "bad.pbrt:4: \"float radius\": expected one value, found 2"},
        {head + "Shape \"sphere\" \"integer radius\" [ 1 ]\n", "bad.pbrt:3: \"integer radius\": expected a float parameter"},
        {head + "Shape \"sphere\" \"complex radius\" [ 1 ]\n", "bad.pbrt:3: unknown parameter type \"complex\""},
        {head + "NamedMaterial \"nope\"\n", "bad.pbrt:3: NamedMaterial: no material named \"nope\""},
        {head + "Material \"diffuse\" \"texture reflectance\" \"nope\"\n", "bad.pbrt:3: \"texture reflectance\": no texture named \"nope\""},
        {head + "ObjectInstance \"nope\"\n", "bad.pbrt:3: ObjectInstance of an unknown object \"nope\""},
        {head + "Include \"missing.pbrt\"\n", "bad.pbrt:3:"},
        {head + "Shape \"plymesh\" \"string filename\" \"missing.ply\"\n", "missing.ply: cannot open"},
        {head + "Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"missing.png\"\n", "bad.pbrt:3:"},
        {head + "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0 1 0 0 0 1 0 ] \"integer indices\" [ 0 1 3 ]\n",
         "bad.pbrt:3: \"indices\": index 3 out of range (3 points)"},
        {head + "Include \"bad.pbrt\"\n", "bad.pbrt:3: \""},
        {head + "MakeNamedMedium \"fog\" \"string type\" \"cloud\"\n", "bad.pbrt:3: MakeNamedMedium type \"cloud\" is not supported yet"},
        {head + "Material \"hair\"\n", "bad.pbrt:3: Material \"hair\" is not supported yet"},
        {head + "ObjectBegin \"a\"\nObjectBegin \"b\"\n", "bad.pbrt:4: ObjectBegin inside an object"},
        {"Film \"rgb\" \"integer xresolution\" [ 0 ]\n" + head + "Shape \"sphere\"\n", "bad.pbrt:1: the film's resolution must be 1 to 16384"},
        {"PixelFilter \"gaussian\" \"float xradius\" [ -1 ] \"float yradius\" [ -1 ]\n" + head + "Shape \"sphere\"\n",
         "bad.pbrt:1: the filter radius must be > 0"},
        {head + "Shape \"sphere\"\nAttributeEnd\n", "bad.pbrt:4: AttributeEnd without a matching begin"},
        {head + "Attribute \"camera\" \"float fov\" 30\n", "bad.pbrt:3: Attribute \"camera\" is not"},
        {head + "Shape \"sphere\" \"float radius\" 1 2\n", "bad.pbrt:3: expected a directive, found 2"},
    };
    for (const Bad& b : cases) {
        INFO(b.text);
        const std::string e = errorOf(b.text);
        INFO(e);
        CHECK(e.find(b.want) != std::string::npos);
    }
    // a recursive Include names the including line
    write("loop-a.pbrt", "Include \"loop-b.pbrt\"\n");
    write("loop-b.pbrt", "\nInclude \"loop-a.pbrt\"\n");
    CHECK(errorOf("Include \"loop-a.pbrt\"\n", "loop.pbrt").find("loop-b.pbrt:2: \"") != std::string::npos);
    // a .gz that is not gzip; a PLY whose indices exceed its vertices
    write("notgz.pbrt.gz", "WorldBegin\n");
    std::string e;
    try {
        loadScene(dir() + "/notgz.pbrt.gz");
    } catch (const InputError& x) {
        e = x.what();
    }
    CHECK(e.find("notgz.pbrt.gz: the scene file is named .gz but is not gzip") != std::string::npos);
    write("bad.ply",
          "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
          "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n");
    CHECK(errorOf(head + "Shape \"plymesh\" \"string filename\" \"bad.ply\"\n").find("vertex index 7 is out of range") != std::string::npos);
}

TEST_CASE("pbrt import: spectra are kept beside their RGB (for spectral rendering)", "[pbrt][import][spectral]") {
    // Y of spectrum i times its scale, against E (the film's normalisation).
    auto Y = [](const SceneDesc& d, int i) {
        const SpectrumDesc& s = d.spectra[size_t(i)];
        double y = 0;
        for (double l = 360.5; l < 830; l += 1) {
            double v = 0;
            if (s.kind == SpectrumDesc::Kind::Blackbody) {
                v = blackbodyNormalized(l, s.kelvin);
            } else if (l >= s.lambda.front() && l <= s.lambda.back()) {
                size_t j = 0;
                while (j + 2 < s.lambda.size() && s.lambda[j + 1] < l) ++j;
                const double t = (l - s.lambda[j]) / (s.lambda[j + 1] - s.lambda[j]);
                v = s.value[j] * (1 - t) + s.value[j + 1] * t;
            }
            y += v * s.scale * cieMatching(float(l)).y;
        }
        return y / cieYIntegral();
    };
    const std::string au = kData + "killeroos/spds/Au.";
    const SceneDesc d = load(R"(LightSource "point" "blackbody I" [ 5500 ] "float scale" [ 3 ] "point3 from" [ 0 2 0 ]
LightSource "distant" "rgb L" [ 1 1 1 ]
AttributeBegin
AreaLightSource "diffuse" "spectrum L" [ 400 1  500 2  600 2  700 1 ]
Shape "trianglemesh" "point3 P" [ -1 3 -1  1 3 -1  1 3 1  -1 3 1 ] "integer indices" [ 0 1 2 0 2 3 ]
Shape "sphere" "float radius" 0.1
AttributeEnd
Material "diffuse" "spectrum reflectance" [ 400 0.2  700 0.8 ]
Shape "sphere" "float radius" 0.3
Material "conductor" "spectrum eta" ")" +
                                 au + R"(eta.spd" "spectrum k" ")" + au + R"(k.spd"
Shape "sphere" "float radius" 0.3
Material "conductor" "spectrum eta" "metal-Ag-eta" "spectrum k" "metal-Ag-k"
Shape "sphere" "float radius" 0.3
Material "coateddiffuse" "rgb reflectance" [ 0.5 0.4 0.3 ] "spectrum albedo" [ 400 0.1  700 0.3 ]
Shape "sphere" "float radius" 0.3
Material "dielectric" "spectrum eta" [ 400 1.53  550 1.52  700 1.51 ]
Shape "sphere" "float radius" 0.3
)" + kFloor,
                             "spectra.pbrt");
    // Lights: the blackbody (Y 1, its scale in radiance), the RGB one, one spectrum for both shapes.
    REQUIRE(d.lights.size() == 4);
    const LightDesc &point = d.lights[0], &distant = d.lights[1], &area0 = d.lights[2], &area1 = d.lights[3];
    REQUIRE(point.spectrum >= 0);
    CHECK(d.spectra[size_t(point.spectrum)].kind == SpectrumDesc::Kind::Blackbody);
    CHECK(d.spectra[size_t(point.spectrum)].kelvin == 5500.0f);
    CHECK(d.spectra[size_t(point.spectrum)].source == "blackbody 5500 K");
    CHECK(Y(d, point.spectrum) == Approx(1.0).epsilon(2e-3));
    CHECK(luminance(point.radiance) == Approx(3.0f).epsilon(1e-4));
    CHECK(distant.spectrum == -1);
    REQUIRE(area0.spectrum >= 0);
    CHECK(area1.spectrum == area0.spectrum);
    CHECK(d.spectra[size_t(area0.spectrum)].lambda == std::vector<float>{400, 500, 600, 700});
    CHECK(Y(d, area0.spectrum) == Approx(1.0).epsilon(2e-3));
    // Materials, in file order after pbrt's default (the area lights' shapes): a spectral
    // reflectance, gold's files, a named metal (RGB only so far), a coat's spectral albedo
    // over an RGB base, a dielectric's spectral index; the floor's RGB.
    std::vector<const MaterialDesc*> ms;
    for (const MaterialDesc& m : d.materials) ms.push_back(&m);
    REQUIRE(ms.size() == 7);
    CHECK(ms[0]->spectra[MaterialParam::Diffuse] == -1);
    ms.erase(ms.begin());
    const int refl = ms[0]->spectra[MaterialParam::Diffuse];
    REQUIRE(refl >= 0);
    CHECK(d.spectra[size_t(refl)].value == std::vector<float>{0.2f, 0.8f});
    CHECK(d.spectra[size_t(refl)].scale == 1.0f);
    const int eta = ms[1]->spectra[MaterialParam::ConductorEta], k = ms[1]->spectra[MaterialParam::ConductorK];
    REQUIRE(eta >= 0);
    REQUIRE(k >= 0);
    CHECK(d.spectra[size_t(eta)].source.find("Au.eta.spd") != std::string::npos);
    CHECK(d.spectra[size_t(k)].source.find("Au.k.spd") != std::string::npos);
    CHECK(d.spectra[size_t(eta)].lambda.size() > 10);
    CHECK(ms[2]->spectra[MaterialParam::ConductorEta] == -1);
    CHECK(ms[3]->spectra[MaterialParam::Albedo] >= 0);
    CHECK(ms[3]->spectra[MaterialParam::Diffuse] == -1);
    REQUIRE(ms[4]->etaSpectrum >= 0);
    CHECK(d.spectra[size_t(ms[4]->etaSpectrum)].value == std::vector<float>{1.53f, 1.52f, 1.51f});
    CHECK(ms[5]->spectra[MaterialParam::Diffuse] == -1);
}

TEST_CASE("pbrt import: a named glass loads with its Sellmeier index, and spectral PT disperses it", "[pbrt][import][spectral]") {
    const std::string body = R"(AttributeBegin
AreaLightSource "diffuse" "rgb L" [ 4 4 4 ]
Shape "trianglemesh" "point3 P" [ -1 3 -1  1 3 -1  1 3 1  -1 3 1 ] "integer indices" [ 0 1 2 0 2 3 ]
AttributeEnd
Material "dielectric" "spectrum eta" "glass-BK7"
Shape "sphere" "float radius" 0.3
)" + kFloor;
    const SceneDesc d = load(body, "glass.pbrt");
    const Sellmeier* bk7 = namedGlass("glass-BK7");
    REQUIRE(bk7);
    const MaterialDesc* glass = nullptr;
    for (const MaterialDesc& m : d.materials)
        if (m.kind == MaterialKind::Dielectric) glass = &m;
    REQUIRE(glass);
    CHECK(glass->iorInside == Approx(sellmeierEta(*bk7, 550.0f)).epsilon(1e-6));  // RGB: the index at 550 nm
    REQUIRE(glass->etaSpectrum >= 0);
    CHECK(d.spectra[size_t(glass->etaSpectrum)].kind == SpectrumDesc::Kind::Sellmeier);
    // No warning at load (pbrt files render spectrally by default); an RGB render says it
    // took the index at 550 nm.
    for (const std::string& w : d.warnings) CHECK(w.find("dispersive") == std::string::npos);
    {
        const RenderResult r = render(d, rstats::renderOptions(TracerKind::PT, 1, 1, 1, 4));
        bool warned = false;
        for (const std::string& w : renderWarnings(r)) warned = warned || w.find("a dispersive glass rendered in RGB") != std::string::npos;
        CHECK(warned);
    }
    CHECK(errorOf(kHead + R"(Material "dielectric" "spectrum eta" "glass-Fake")" + "\n" + kFloor).find("glass-Fake") != std::string::npos);
    // The spectral stage: the hero wavelength's index, and the path keeps only that wavelength.
    const std::unique_ptr<Scene> scene = Scene::build(d);
    const SpectralScene spectra = buildSpectralScene(*scene);
    REQUIRE(spectra.unsupported.empty());
    const int id = int(glass - d.materials.data());
    BsdfParams p = scene->materials[size_t(id)];
    Wavelengths w = sampleWavelengths(0.2f);
    CHECK(spectra.colours(id, *glass, p, w));
    CHECK(p.eta == Approx(sellmeierEta(*bk7, w.lambda[0])).epsilon(1e-5));
    const float hero = w.pdf[0];
    terminateSecondary(w);
    CHECK(w.pdf[1] == 0.0f);
    CHECK(w.pdf[2] == 0.0f);
    CHECK(w.pdf[0] == Approx(hero / 3));
    terminateSecondary(w);  // once per path
    CHECK(w.pdf[0] == Approx(hero / 3));
    // Rendered: spectral, finite; the image as bright as with the glass's index at 550 nm,
    // within 5 standard errors of the difference of 8 runs each (dispersion moves light, it
    // makes little: only the Fresnel terms change with the index).
    auto meansOf = [&](const SceneDesc& desc) {
        std::vector<double> means;
        for (int k = 0; k < 8; ++k) {
            RenderOptions o = rstats::renderOptions(TracerKind::PT, 16, 100 + uint64_t(k), 2, 8);
            o.spectral = true;
            const RenderResult r = render(desc, o);
            REQUIRE(r.stats.spectral);
            REQUIRE(r.stats.samplesNonfiniteDiscarded == 0);
            double sum = 0;
            for (float v : r.image.rgb) sum += v;
            means.push_back(sum / double(r.image.rgb.size()));
        }
        return means;
    };
    SceneDesc flat = d;
    for (MaterialDesc& m : flat.materials) m.etaSpectrum = -1;
    const std::vector<double> a = meansOf(d), b = meansOf(flat);
    auto meanVar = [](const std::vector<double>& v, double& mean, double& var) {
        mean = 0;
        for (double x : v) mean += x / double(v.size());
        var = 0;
        for (double x : v) var += (x - mean) * (x - mean) / double(v.size() - 1);
    };
    double ma, va, mb, vb;
    meanVar(a, ma, va);
    meanVar(b, mb, vb);
    const double se = std::sqrt(va / double(a.size()) + vb / double(b.size()));
    INFO("dispersed " << ma << ", index at 550 nm " << mb << ", se " << se);
    CHECK(ma > 0);
    CHECK(std::fabs(ma - mb) < 5 * se);
}
