// The Mitsuba importer on small hand-written files: plugins, transforms, defaults and
// substitution, the camera convention, and bad inputs (one message with file and line).
#include <catch2/catch.hpp>

#include <string>

#include "kernels/camera.h"
#include "render_stats.h"
#include "wavemmlt/error.h"
#include "wavemmlt/scene_desc.h"

using namespace wmlt;

namespace {

std::string scene(const std::string& body, const std::string& version = "3.0.0") {
    return "<scene version=\"" + version + "\">\n" + body + R"(
<shape type="rectangle"><emitter type="area"><rgb name="radiance" value="1, 2, 3"/></emitter></shape>
</scene>
)";
}
const std::string kSensor = R"(<sensor type="perspective"><float name="fov" value="40"/>
  <transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
  <film type="hdrfilm"><integer name="width" value="64"/><integer name="height" value="32"/></film>
</sensor>
)";

SceneDesc load(const std::string& xml, const Defines& d = {}) { return loadMitsubaFromString(xml, "t.xml", ".", d); }

std::string errorOf(const std::string& xml) {
    try {
        load(xml);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST_CASE("Mitsuba import: sensor, film, camera convention (+x to the image's left)", "[mitsuba][import]") {
    SceneDesc d = load(scene(kSensor));
    CHECK(d.settings.width == 64);
    CHECK(d.settings.height == 32);
    // fov 40 across x (the width 64): across the shorter side (32) tan(h/2) = tan(20) / 2.
    CHECK(std::tan(d.camera.fovDegrees * M_PI / 360) == Approx(std::tan(20 * M_PI / 180) / 2).epsilon(1e-5));
    Camera c = makeCamera(d.camera, 64, 32);
    // Looking along -z from +z with +y up: world +x is on the image's right (Mitsuba's
    // camera-local +x is on the left, and local +x is world -x here).
    CHECK(c.right.x == Approx(1.0f));
    CHECK(d.lights.size() == 1);
    CHECK(d.lights[0].radiance.z == 3.0f);
    // The rectangle light: [-1, 1]^2 at z = 0, emitting towards +z.
    const TriangleMesh& m = d.shapes[0].mesh;
    Vec3 n = cross(m.positions[m.indices[1]] - m.positions[m.indices[0]], m.positions[m.indices[2]] - m.positions[m.indices[0]]);
    CHECK(n.z > 0);
    // A mirroring to_world flips the image: right = +x local = world -x... flipX set.
    SceneDesc mirrored = load(scene(R"(<sensor type="perspective"><float name="fov" value="40"/>
      <transform name="to_world"><scale x="-1"/><lookat origin="0, 0, 5" target="0, 0, 0"/></transform></sensor>)"));
    CHECK(mirrored.camera.flipX);
    // ... a mirror image: the ray through (x, y) is the unmirrored camera's ray through
    // (width - x, y) turned over in the camera's x, with the same up.
    SceneDesc plain = mirrored;
    plain.camera.flipX = false;
    const Camera cm = makeCamera(mirrored.camera, 16, 12), cp = makeCamera(plain.camera, 16, 12);
    CHECK(dot(cm.up, cp.up) == Approx(1.0f));
    CHECK(dot(cm.right, cp.right) == Approx(-1.0f));
    for (const auto& [x, y] : std::vector<std::pair<float, float>>{{1.5f, 2.25f}, {12.0f, 9.5f}}) {
        Vec3 om, dm, op, dp;
        generateCameraRay(cm, x, y, 0.5f, 0.5f, om, dm);
        generateCameraRay(cp, 16 - x, y, 0.5f, 0.5f, op, dp);
        CHECK(dm.x == Approx(dp.x).margin(1e-6));
        CHECK(dm.y == Approx(dp.y).margin(1e-6));
        CHECK(dm.z == Approx(dp.z).margin(1e-6));
        CHECK(dot(dm, cm.up) == Approx(dot(dp, cp.up)).margin(1e-6));
    }
}

// focal_length (Mitsuba 3): the field of view of the 36 x 24 mm film's diagonal (43.27 mm)
// for a lens of x mm, about the image's diagonal; 50mm when neither it nor fov is given.
TEST_CASE("Mitsuba import: focal_length and its default", "[mitsuba][import]") {
    auto fovOf = [](const std::string& sensorBody) {
        const SceneDesc d =
            load(scene("<sensor type=\"perspective\">" + sensorBody +
                       "<film type=\"hdrfilm\"><integer name=\"width\" value=\"60\"/><integer name=\"height\" value=\"40\"/></film></sensor>"));
        return d.camera.fovDegrees;
    };
    for (const auto& [body, mm] : std::vector<std::pair<std::string, double>>{{"<string name=\"focal_length\" value=\"35mm\"/>", 35},
                                                                              {"<string name=\"focal_length\" value=\"85\"/>", 85},
                                                                              {"<float name=\"focal_length\" value=\"24\"/>", 24},
                                                                              {"", 50}}) {
        // tan of half the diagonal's angle is 43.27 / (2 x); across the shorter side (40 of
        // the 72.1-pixel diagonal) that tangent scales by 40 / 72.1.
        const double tDiag = std::sqrt(36.0 * 36 + 24 * 24) / (2 * mm), shorter = 40 / std::sqrt(60.0 * 60 + 40 * 40);
        INFO(body);
        CHECK(std::tan(fovOf(body) * M_PI / 360) == Approx(tDiag * shorter).epsilon(1e-5));
    }
    // the diagonal's field of view: focal_length 50mm equals fov 46.79 about the diagonal
    CHECK(fovOf("") == Approx(fovOf("<float name=\"fov\" value=\"46.7930\"/><string name=\"fov_axis\" value=\"diagonal\"/>")).epsilon(1e-4));
    for (const auto& [body, words] : std::vector<std::pair<std::string, std::string>>{
             {"<float name=\"fov\" value=\"40\"/><string name=\"focal_length\" value=\"35mm\"/>", "either fov or focal_length"},
             {"<string name=\"focal_length\" value=\"35cm\"/>", "focal_length must be"},
             {"<string name=\"focal_length\" value=\"-5mm\"/>", "focal_length must be"},
             {"<float name=\"fov\" value=\"190\"/>", "fov must be in (0, 180)"}}) {
        const std::string e = errorOf(scene("<sensor type=\"perspective\">" + body + "</sensor>"));
        INFO(body << ": " << e);
        CHECK(e.find("t.xml:") == 0);
        CHECK(e.find(words) != std::string::npos);
    }
}

TEST_CASE("Mitsuba import: transforms compose in file order", "[mitsuba][import]") {
    SceneDesc d = load(scene(kSensor + R"(
<shape type="sphere"><float name="radius" value="0.5"/>
  <transform name="to_world"><scale value="2"/><rotate y="1" angle="90"/><translate x="1" y="2" z="3"/></transform></shape>
<shape type="cube"><transform name="to_world"><translate x="10"/><scale value="3"/></transform></shape>
<shape type="rectangle"><transform name="to_world"><matrix value="0 0 1 0  0 1 0 0  -1 0 0 0  0 0 0 1"/></transform></shape>
)"));
    REQUIRE(d.shapes.size() == 4);
    CHECK(d.shapes[0].kind == ShapeKind::Sphere);
    CHECK(d.shapes[0].radius == Approx(1.0f));
    CHECK(d.shapes[0].center.x == Approx(1.0f));
    CHECK(d.shapes[0].center.z == Approx(3.0f));
    // translate then scale: the cube's centre is at 30, its half size 3.
    Vec3 lo(1e9f), hi(-1e9f);
    for (Vec3 p : d.shapes[1].mesh.positions) {
        lo = vmin(lo, p);
        hi = vmax(hi, p);
    }
    CHECK(lo.x == Approx(27.0f));
    CHECK(hi.x == Approx(33.0f));
    CHECK(d.shapes[1].mesh.indices.size() == 36);
    // The matrix (rows) turns +z into +x: the rectangle's normal points along +x.
    const TriangleMesh& m = d.shapes[2].mesh;
    Vec3 n = cross(m.positions[m.indices[1]] - m.positions[m.indices[0]], m.positions[m.indices[2]] - m.positions[m.indices[0]]);
    CHECK(n.x > 0);
}

TEST_CASE("Mitsuba import: BSDFs, defaults, $ substitution, ref, -D", "[mitsuba][import]") {
    const std::string xml = scene(R"(<default name="a" value="0.3"/><default name="d" value="ggx"/>
)" + kSensor + R"(
<bsdf type="twosided" id="metal"><bsdf type="roughconductor"><float name="alpha" value="$a"/>
  <string name="distribution" value="$d"/><rgb name="eta" value="0.2, 0.9, 1.1"/><rgb name="k" value="3.9, 2.4, 2.1"/></bsdf></bsdf>
<bsdf type="roughplastic" id="plastic"><rgb name="diffuse_reflectance" value="0.1, 0.2, 0.3"/><string name="int_ior" value="bk7"/></bsdf>
<bsdf type="dielectric" id="glass"/>
<shape type="cube"><ref id="metal"/></shape>
<shape type="cube"><ref id="plastic"/></shape>
<shape type="cube"><ref id="glass"/></shape>
<shape type="cube"><bsdf type="diffuse"/></shape>
)");
    SceneDesc d = load(xml);
    REQUIRE(d.shapes.size() == 5);
    const MaterialDesc& metal = d.materials[d.shapes[0].material];
    CHECK(metal.kind == MaterialKind::RoughConductor);
    CHECK(metal.twoSided);
    CHECK(metal.alpha == Approx(0.3f));
    CHECK(metal.distribution == MicrofacetType::GGX);
    CHECK(metal.conductorK.x == Approx(3.9f));
    const MaterialDesc& plastic = d.materials[d.shapes[1].material];
    CHECK(plastic.kind == MaterialKind::RoughPlastic);
    CHECK(plastic.iorInside == Approx(1.5046f));
    CHECK(plastic.distribution == MicrofacetType::Beckmann);  // Mitsuba's default
    CHECK(!plastic.twoSided);
    const MaterialDesc& glass = d.materials[d.shapes[2].material];
    CHECK(glass.kind == MaterialKind::Dielectric);
    CHECK(glass.iorOutside == Approx(1.000277f));
    CHECK(d.materials[d.shapes[3].material].diffuse.x == Approx(0.5f));
    // -D overrides a <default>.
    SceneDesc e = load(xml, {{"a", "0.05"}, {"d", "beckmann"}});
    CHECK(e.materials[e.shapes[0].material].alpha == Approx(0.05f));
    CHECK(e.materials[e.shapes[0].material].distribution == MicrofacetType::Beckmann);
}

TEST_CASE("Mitsuba import: integrator max_depth and the tracer", "[mitsuba][import]") {
    SceneDesc d = load(scene(kSensor + R"(<integrator type="bdpt"><integer name="max_depth" value="7"/></integrator>)"));
    CHECK(d.settings.tracer == TracerKind::BPT);
    CHECK(d.settings.maxPathLength == 7);
    SceneDesc u = load(scene(kSensor + R"(<integrator type="path"><integer name="max_depth" value="-1"/></integrator>)"));
    CHECK(u.settings.maxPathLength == 64);
    CHECK(u.warnings.size() == 1);
    // An integrator wavemmlt lacks: refused, unless the command line gives the tracer (a
    // warning naming its line, its parameters ignored)
    const std::string aov = scene(kSensor + R"(<integrator type="aov"><string name="aovs" value="dd.y:depth"/></integrator>)");
    CHECK(errorOf(aov).find("t.xml:6:") == 0);
    CHECK(errorOf(aov).find("--tracer") != std::string::npos);
    const SceneDesc a = loadMitsubaFromString(aov, "t.xml", ".", {}, LoadOptions{true});
    REQUIRE(a.warnings.size() == 1);
    CHECK(a.warnings[0].find("t.xml:6") != std::string::npos);
    CHECK(a.warnings[0].find("\"aov\" is not one of wavemmlt's") != std::string::npos);
}

TEST_CASE("Mitsuba import: bad inputs name file, line and plugin", "[mitsuba][import][bad-input]") {
    // Unknown plugin.
    std::string e = errorOf(scene(kSensor + "<shape type=\"hair\"/>"));
    CHECK(e.find("t.xml:6:") == 0);
    CHECK(e.find("hair") != std::string::npos);
    // Unknown parameter of a known plugin.
    e = errorOf(
        scene(kSensor + "<bsdf type=\"diffuse\" id=\"x\"><float name=\"sheen\" value=\"1\"/></bsdf><shape type=\"cube\"><ref id=\"x\"/></shape>"));
    CHECK(e.find("t.xml:6:") == 0);
    CHECK(e.find("sheen") != std::string::npos);
    // Missing file.
    e = errorOf(scene(kSensor + "<shape type=\"obj\"><string name=\"filename\" value=\"nope.obj\"/></shape>"));
    CHECK(e.find("t.xml:6:") == 0);
    CHECK(e.find("nope.obj") != std::string::npos);
    // Bad number.
    e = errorOf(scene(kSensor + "<shape type=\"sphere\"><float name=\"radius\" value=\"1.5x\"/></shape>"));
    CHECK(e.find("t.xml:6:") == 0);
    CHECK(e.find("1.5x") != std::string::npos);
    for (const char* bad : {"+-1", "nan", "1e39", ""}) {  // scene/number.h, shared with the thesis' format
        e = errorOf(scene(kSensor + "<shape type=\"sphere\"><float name=\"radius\" value=\"" + bad + "\"/></shape>"));
        INFO(bad << ": " << e);
        CHECK(e.find("is not a finite number") != std::string::npos);
    }
    // Wrong nesting: a float where a transform belongs; a shape inside a bsdf.
    e = errorOf(scene(kSensor + "<shape type=\"cube\"><float name=\"to_world\" value=\"1\"/></shape>"));
    CHECK(e.find("t.xml:6:") == 0);
    e = errorOf(scene(kSensor + "<bsdf type=\"diffuse\" id=\"b\"><shape type=\"cube\"/></bsdf><shape type=\"cube\"><ref id=\"b\"/></shape>"));
    CHECK(e.find("t.xml:6:") == 0);
    // Undefined $name, a bad version, a missing sensor, a ref to nothing.
    CHECK(errorOf(scene(kSensor + "<shape type=\"sphere\"><float name=\"radius\" value=\"$r\"/></shape>")).find("$r") != std::string::npos);
    CHECK(errorOf(scene(kSensor, "4.0.0")).find("version") != std::string::npos);
    CHECK(errorOf(scene("")).find("no <sensor>") != std::string::npos);
    CHECK(errorOf(scene(kSensor + "<shape type=\"cube\"><ref id=\"nothing\"/></shape>")).find("nothing") != std::string::npos);
}

TEST_CASE("wavemmlt renders a Mitsuba scene with -D and refuses a bad one (exit 2, no image)", "[mitsuba][import][bad-input][cli]") {
    const std::string dir = rstats::tempDir("mitsuba-cli");
    const std::string good = std::string(WAVEMMLT_TEST_DATA) + "/scenes/mitsuba/cornell-box/scene.xml";
    const std::string out = dir + "/c.pfm";
    int rc = std::system((std::string(WAVEMMLT_BIN) + " " + good + " -D resx=16 -D resy=16 --spp 1 -q -o " + out).c_str());
    CHECK(WEXITSTATUS(rc) == 0);
    Image im = readImage(out);
    CHECK(im.width == 16);
    const std::string bad = dir + "/bad.xml";
    FILE* f = std::fopen(bad.c_str(), "w");
    std::fputs(scene(kSensor + "<shape type=\"hair\"/>").c_str(), f);
    std::fclose(f);
    const std::string out2 = dir + "/bad.pfm";
    rc = std::system((std::string(WAVEMMLT_BIN) + " " + bad + " -q -o " + out2 + " 2>" + dir + "/err.txt").c_str());
    CHECK(WEXITSTATUS(rc) == 2);
    CHECK(!std::filesystem::exists(out2));
    rc = std::system((std::string(WAVEMMLT_BIN) + " " + good + " -D oops -q -o " + out2 + " 2>/dev/null").c_str());
    CHECK(WEXITSTATUS(rc) == 2);
}
