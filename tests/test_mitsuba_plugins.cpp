// The Mitsuba plugins added after the first importer (docs/mitsuba.md): named conductors,
// emitters with BSDFs, textures (bitmap, checkerboard), bumpmap, mask, ply, envmap, point
// lights and area lights on meshes. Importer checks on small hand-written files, bad
// inputs, and the analytic checks that fit in a few seconds; the tracers' agreement on
// each feature is in test_mitsuba_tracers.cpp.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "render_stats.h"
#include "wavemmlt/error.h"
#include "wavemmlt/image.h"
#include "wavemmlt/render.h"
#include "wavemmlt/scene_desc.h"

using namespace wmlt;

namespace {

const std::string kSensor = R"(<sensor type="perspective"><float name="fov" value="40"/>
  <transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
  <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/></film>
</sensor>
)";

// A scene with the sensor above, `body`, and (unless `light` is false) a rectangle light.
std::string scene(const std::string& body, bool light = true) {
    return "<scene version=\"3.0.0\">\n" + kSensor + body +
           (light ? "\n<shape type=\"rectangle\"><emitter type=\"area\"><rgb name=\"radiance\" value=\"1\"/></emitter></shape>" : "") +
           "\n</scene>\n";
}

SceneDesc load(const std::string& xml, const std::string& dir = ".") { return loadMitsubaFromString(xml, "t.xml", dir); }

std::string errorOf(const std::string& xml, const std::string& dir = ".") {
    try { load(xml, dir); } catch (const InputError& e) { return e.what(); }
    return "";
}

}  // namespace

TEST_CASE("Mitsuba plugins: named conductors", "[mitsuba][import]") {
    SceneDesc d = load(scene(R"(
<shape type="cube"><bsdf type="conductor"><string name="material" value="Au"/></bsdf></shape>
<shape type="cube"><bsdf type="roughconductor"><string name="material" value="Cu"/><float name="alpha" value="0.2"/></bsdf></shape>
<shape type="cube"><bsdf type="conductor"/></shape>)"));
    const MaterialDesc& au = d.materials[d.shapes[0].material];
    CHECK(au.kind == MaterialKind::Conductor);
    CHECK(au.conductorEta.z == Approx(1.4424785571f));
    CHECK(au.conductorK.x == Approx(3.9831604247f));
    const MaterialDesc& cu = d.materials[d.shapes[1].material];
    CHECK(cu.kind == MaterialKind::RoughConductor);
    CHECK(cu.conductorEta.x == Approx(0.200438f).epsilon(1e-5));  // veach-mis' copper
    const MaterialDesc& none = d.materials[d.shapes[2].material];  // Mitsuba's default: a mirror
    CHECK(none.conductorEta.x == 0.0f);
    CHECK(none.conductorK.x == 1.0f);
    std::string e = errorOf(scene(R"(<shape type="cube"><bsdf type="conductor"><string name="material" value="Unobtainium"/></bsdf></shape>)"));
    INFO(e);
    CHECK(e.find("t.xml:6:") == 0);
    CHECK(e.find("Unobtainium") != std::string::npos);
    CHECK(e.find("Au") != std::string::npos);  // the names it knows
    e = errorOf(scene(R"(<shape type="cube"><bsdf type="conductor"><string name="material" value="Au"/><rgb name="eta" value="1"/></bsdf></shape>)"));
    CHECK(e.find("not both") != std::string::npos);
}

TEST_CASE("Mitsuba plugins: an emitter keeps its BSDF (Mitsuba's default diffuse when none)", "[mitsuba][import]") {
    SceneDesc d = load(scene(R"(
<shape type="rectangle"><bsdf type="diffuse"><rgb name="reflectance" value="0.7"/></bsdf><emitter type="area"/></shape>
<shape type="sphere"><emitter type="area"/></shape>
<shape type="rectangle"><bsdf type="diffuse"><rgb name="reflectance" value="0"/></bsdf><emitter type="area"/></shape>)", false));
    REQUIRE(d.shapes.size() == 3);
    REQUIRE(d.shapes[0].material >= 0);
    CHECK(d.materials[d.shapes[0].material].diffuse.x == Approx(0.7f));
    REQUIRE(d.shapes[1].material >= 0);
    CHECK(d.materials[d.shapes[1].material].diffuse.x == Approx(0.5f));
    CHECK(!d.materials[d.shapes[1].material].twoSided);
    CHECK(d.shapes[2].material == -1);  // black: an emitter that only absorbs
    for (const ShapeDesc& s : d.shapes) CHECK(s.light >= 0);
}
