// Mitsuba's shapegroup and instance (issue 25): a group of shapes stored once and traced
// through Embree instances. An instanced scene renders what its flattened copy (every
// shape placed by its own composed to_world) renders, in PT, LT and BPT (z-tests of the
// difference of K-run means); it stores the group's meshes once (--stats' "meshes" and
// "embree" bytes against the flattened copy's); bad groups and instances are refused with
// file and line.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "render_stats.h"
#include "scene/scene.h"
#include "wavemmlt/error.h"
#include "wavemmlt/render.h"
#include "wavemmlt/scene_desc.h"

using namespace wmlt;

namespace {

const std::string kHead = R"(<scene version="3.0.0">
  <integrator type="path"><integer name="max_depth" value="4"/></integrator>
  <sensor type="perspective"><float name="fov" value="50"/>
    <transform name="to_world"><lookat origin="0, 2, 5" target="0, 0.5, 0" up="0, 1, 0"/></transform>
    <film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="16"/><rfilter type="box"/></film></sensor>
  <shape type="rectangle"><transform name="to_world"><scale value="5"/><rotate x="1" angle="-90"/></transform><bsdf type="diffuse"/></shape>
  <shape type="sphere"><point name="center" x="0" y="3" z="1"/><float name="radius" value="0.3"/>
    <emitter type="area"><rgb name="radiance" value="20"/></emitter></shape>
)";

// The group's shapes (a cube and a rough metal plate), each turned inside the group so that
// no face is along its axes, and the instances' transforms (one turned, one scaled
// unevenly: normals must go by the inverse transpose).
struct Part {
    std::string type, inner, bsdf;
};
const std::vector<Part> kParts = {{"cube", R"(<scale value="0.3"/><rotate z="1" angle="25"/><rotate x="1" angle="15"/><translate y="0.4"/>)",
                                   R"(<bsdf type="diffuse"><rgb name="reflectance" value="0.7, 0.3, 0.2"/></bsdf>)"},
                                  {"rectangle", R"(<scale x="0.4" y="0.6"/><rotate y="1" angle="35"/><translate x="0.6" y="0.6"/>)",
                                   R"(<bsdf type="twosided"><bsdf type="roughconductor"><float name="alpha" value="0.2"/></bsdf></bsdf>)"}};
const std::vector<std::string> kPlaces = {R"(<rotate y="1" angle="30"/><translate x="-1"/>)",
                                          R"(<scale x="1.5" y="0.7" z="1.2"/><rotate y="1" angle="-20"/><translate x="1" z="-0.5"/>)"};

std::string instanced() {
    std::string s = kHead + "<shape type=\"instance\"><ref id=\"pair\"/><transform name=\"to_world\">" + kPlaces[0] +
                    "</transform></shape>\n<shape type=\"shapegroup\" id=\"pair\">\n";
    for (const Part& p : kParts)
        s += "<shape type=\"" + p.type + "\"><transform name=\"to_world\">" + p.inner + "</transform>" + p.bsdf + "</shape>\n";
    s += "</shape>\n<shape type=\"instance\"><ref id=\"pair\"/><transform name=\"to_world\">" + kPlaces[1] + "</transform></shape>\n";
    return s + "</scene>\n";
}

std::string flattened() {
    std::string s = kHead;
    for (const std::string& place : kPlaces)
        for (const Part& p : kParts)
            s += "<shape type=\"" + p.type + "\"><transform name=\"to_world\">" + p.inner + place + "</transform>" + p.bsdf + "</shape>\n";
    return s + "</scene>\n";
}

rstats::RunStats runs(const SceneDesc& d, TracerKind t, uint64_t seed0) {
    rstats::RunStats r;
    for (int k = 0; k < 12; ++k) {
        const RenderResult res = render(d, rstats::renderOptions(t, 16, seed0 + uint64_t(k), 1, 4));
        REQUIRE(res.stats.samplesNonfiniteDiscarded == 0);
        r.add(rstats::blockMeans(res.image, 2, 1));
    }
    return r;
}

}  // namespace

TEST_CASE("instancing: an instanced scene renders what its flattened copy renders, in PT, LT and BPT", "[instancing][render]") {
    const SceneDesc a = loadMitsubaFromString(instanced(), "instanced.xml", ".");
    const SceneDesc b = loadMitsubaFromString(flattened(), "flattened.xml", ".");
    REQUIRE(a.groups == 1);
    REQUIRE(a.instances.size() == 2);
    REQUIRE(a.shapes.size() == 4);  // floor, light, the group's two
    REQUIRE(b.shapes.size() == 6);
    for (TracerKind t : {TracerKind::PT, TracerKind::LT, TracerKind::BPT}) {
        const rstats::RunStats ra = runs(a, t, 10), rb = runs(b, t, 500);
        double ratio = 0;
        const rstats::ZTestResult z = rstats::compareRuns(ra, rb, 1e-4, &ratio);
        INFO("tracer " << int(t) << ": instanced / flattened " << ratio << "; " << z.describe());
        CHECK(z.pass);
    }
    // A seed renders one image with 1 and 2 threads.
    RenderOptions o = rstats::renderOptions(TracerKind::BPT, 4, 3, 1, 4, 1);
    const Image one = render(a, o).image;
    o.threads = 2;
    CHECK(render(a, o).image.rgb == one.rgb);
}

TEST_CASE("instancing: a group is stored once (meshes and Embree bytes against the flattened copy)", "[instancing]") {
    // A 2000-triangle grid placed 64 times.
    const std::string dir = rstats::tempDir("instancing-memory");
    {
        std::ofstream obj(dir + "/grid.obj");
        const int n = 32;
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i) obj << "v " << i / double(n) << " " << 0.1 * ((i * 7 + j * 3) % 5) / 5 << " " << j / double(n) << "\n";
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const int v = j * (n + 1) + i + 1;
                obj << "f " << v << " " << v + 1 << " " << v + n + 2 << "\nf " << v << " " << v + n + 2 << " " << v + n + 1 << "\n";
            }
    }
    std::string inst = kHead + R"(<shape type="shapegroup" id="g"><shape type="obj"><string name="filename" value="grid.obj"/></shape></shape>)";
    std::string flat = kHead;
    for (int k = 0; k < 64; ++k) {
        const std::string t =
            "<transform name=\"to_world\"><translate x=\"" + std::to_string(k % 8 - 4) + "\" z=\"" + std::to_string(k / 8 - 4) + "\"/></transform>";
        inst += "<shape type=\"instance\"><ref id=\"g\"/>" + t + "</shape>\n";
        flat += "<shape type=\"obj\"><string name=\"filename\" value=\"grid.obj\"/>" + t + "</shape>\n";
    }
    inst += "</scene>";
    flat += "</scene>";
    const std::unique_ptr<Scene> a = Scene::build(loadMitsubaFromString(inst, "i.xml", dir), 2);
    const std::unique_ptr<Scene> b = Scene::build(loadMitsubaFromString(flat, "f.xml", dir), 2);
    INFO("meshes " << a->meshBytes << " / " << b->meshBytes << ", embree " << a->embreeBytes << " / " << b->embreeBytes);
    // The floor and the light's sphere are in both; the grid once against 64 times.
    CHECK(double(a->meshBytes) < double(b->meshBytes) / 30);
    CHECK(double(a->embreeBytes) < double(b->embreeBytes) / 10);
    // Both render the same bounds (the environment disc, the ray offsets).
    CHECK(a->radius == Approx(b->radius).epsilon(1e-5));
    // --stats reports both.
    const RenderResult r = render(loadMitsubaFromString(inst, "i.xml", dir), rstats::renderOptions(TracerKind::PT, 1, 1, 1, 2));
    bool meshes = false, embree = false;
    for (const auto& [name, bytes] : r.stats.buffers) {
        if (name == "meshes") meshes = bytes == a->meshBytes;
        if (name == "embree") embree = bytes > 0;
    }
    CHECK(meshes);
    CHECK(embree);
    std::filesystem::remove_all(dir);
}

TEST_CASE("instancing: bad groups and instances name file and line", "[instancing][badinput]") {
    auto error = [](const std::string& body) -> std::string {
        try {
            loadMitsubaFromString(kHead + body + "\n</scene>\n", "t.xml", ".");
        } catch (const InputError& e) {
            return e.what();
        }
        return "";
    };
    const std::string cube = R"(<shape type="cube"/>)";
    // kHead is 8 lines: the body starts on line 9.
    CHECK(error(R"(<shape type="instance"><ref id="nope"/></shape>)").rfind("t.xml:9:", 0) == 0);
    CHECK(error(R"(<shape type="instance"><ref id="nope"/></shape>)").find("no element has id \"nope\"") != std::string::npos);
    CHECK(error(R"(<shape type="cube" id="c"/><shape type="instance"><ref id="c"/></shape>)").find("must name a shapegroup") != std::string::npos);
    CHECK(error(R"(<shape type="instance"/>)").find("an instance needs one <ref id=...> to a shapegroup") != std::string::npos);
    CHECK(error(R"(<shape type="shapegroup" id="g"><shape type="shapegroup" id="h">)" + cube + "</shape></shape>")
              .find("a shapegroup inside a shapegroup") != std::string::npos);
    CHECK(error(R"(<shape type="shapegroup" id="g"><shape type="instance"><ref id="g"/></shape></shape>)").find("an instance inside a shapegroup") !=
          std::string::npos);
    CHECK(error(R"(<shape type="shapegroup" id="g"><shape type="cube"><emitter type="area"/></shape></shape>)")
              .find("an emitter inside a shapegroup") != std::string::npos);
    CHECK(error(R"(<shape type="shapegroup" id="g"><shape type="sphere"/></shape>)").find("a sphere inside a shapegroup") != std::string::npos);
    CHECK(error(R"(<shape type="shapegroup" id="g"><shape type="cube"><bsdf type="mask"><bsdf type="diffuse"/></bsdf></shape></shape>)")
              .find("a mask inside a shapegroup") != std::string::npos);
    CHECK(error(R"(<shape type="shapegroup" id="g"></shape>)").find("an empty shapegroup") != std::string::npos);
    CHECK(error(R"(<shape type="shapegroup" id="g"><bsdf type="diffuse"/></shape>)").find("a shapegroup holds shapes only") != std::string::npos);
    CHECK(error(R"(<shape type="shapegroup" id="g">)" + cube +
                R"(</shape><shape type="instance"><ref id="g"/><transform name="to_world"><scale value="0"/></transform></shape>)")
              .find("to_world is singular") != std::string::npos);
    // A group that no instance places is stored and never seen.
    CHECK(error(R"(<shape type="shapegroup" id="g">)" + cube + "</shape>") == "");
}
