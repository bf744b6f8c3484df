// The scene loader (src/scene/thesis/load_scene.cpp, meshes/load_obj.cpp) against
// ../shared/spec/scene-format.md: what each element parses to, and one InputError
// "file:line: ..." for each kind of bad input.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "wavemmlt/error.h"
#include "wavemmlt/scene_desc.h"

using namespace wmlt;
namespace fs = std::filesystem;

namespace {

const std::string kData = WAVEMMLT_TEST_DATA;
const std::string kSeed = kData + "/scenes/seed-room";

// Lines 1-3; a body starts on line 4.
const std::string kHead =
    "<Scene>\n"
    "<Camera Type=\"Camera\"><Position x=\"0\" y=\"0\" z=\"-5\"/><LookAt x=\"0\" y=\"0\" z=\"0\"/>"
    "<FOV value=\"45\"/></Camera>\n"
    "<Shader Type=\"Matte\" ID=\"0\"><Diffuse r=\"0.5\" g=\"0.5\" b=\"0.5\"/></Shader>\n";
std::string scene(const std::string& body) { return kHead + body + "\n</Scene>\n"; }
SceneDesc load(const std::string& body) { return loadSceneFromString(scene(body), "t.xml", kSeed); }

std::string geom(const std::string& type, const std::string& inner, const std::string& id = "g") {
    return "<Geometry Type=\"" + type + "\" ID=\"" + id + "\">" + inner + "<Shader value=\"0\"/></Geometry>";
}
std::string checker(const std::string& id, const std::string& extra = "") {
    return "<Texture Type=\"Checker\" ID=\"" + id +
           "\"><Colour1 r=\"0\" g=\"0\" b=\"0\"/>"
           "<Colour2 r=\"1\" g=\"1\" b=\"1\"/>" +
           extra + "</Texture>";
}
std::string plane(const std::string& extra) { return geom("Plane", "<Width value=\"2\"/><Depth value=\"4\"/>" + extra); }

// The message of the InputError `f` throws ("" when none).
template <class F>
std::string errorOf(F f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}
void requireError(const std::string& xml, int line, const std::string& fragment) {
    std::string m = errorOf([&] { loadSceneFromString(xml, "t.xml", kSeed); });
    INFO("message: " << m);
    CHECK(m.rfind("t.xml:" + std::to_string(line) + ": ", 0) == 0);
    CHECK(m.find(fragment) != std::string::npos);
}

Vec3 faceNormal(const TriangleMesh& m, int tri) {
    Vec3 p0 = m.positions[m.indices[3 * tri]], p1 = m.positions[m.indices[3 * tri + 1]], p2 = m.positions[m.indices[3 * tri + 2]];
    return normalize(cross(p1 - p0, p2 - p0));
}
bool near(Vec3 a, Vec3 b, float eps = 1e-5f) { return length(a - b) <= eps; }

// A fresh folder for files a test writes, removed afterwards.
struct TempDir {
    fs::path path;
    TempDir() {
        static int count = 0;
        path = fs::temp_directory_path() / ("wmlt-scene-test-" + std::to_string(getpid()) + "-" + std::to_string(count++));
        fs::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
    std::string write(const std::string& name, const std::string& text) const {
        std::ofstream(path / name, std::ios::binary) << text;
        return (path / name).string();
    }
};

}  // namespace

TEST_CASE("Settings: values and defaults and tracer names and Output quotes", "[scene]") {
    SceneDesc d = load("");
    CHECK(d.settings.width == 512);
    CHECK(d.settings.height == 512);
    CHECK(d.settings.samples == 4);
    CHECK(d.settings.threads == 0);
    CHECK(d.settings.tracer == TracerKind::MMLT);
    CHECK(d.settings.maxPathLength == 10);
    CHECK(d.settings.minPathLength == 1);
    CHECK(d.settings.probLarge == Approx(0.3f));
    CHECK(d.settings.output == "render.exr");
    CHECK(d.settings.envMap.empty());
    CHECK(d.envMap.width == 0);
    CHECK(d.warnings.empty());

    d = load(
        "<Settings><Width value=\"640\"/><Height value=\"+480\"/><Sample value=\"3\"/><Thread value=\"2\"/>"
        "<Tracer name=\"bPt\"/><MaxPathLength value=\"64\"/><MinPathLength value=\"2\"/>"
        "<ProbLarge value=\"1\"/><Output name=\"'out.png'\"/></Settings>");
    CHECK(d.settings.width == 640);
    CHECK(d.settings.height == 480);
    CHECK(d.settings.samples == 3);
    CHECK(d.settings.threads == 2);
    CHECK(d.settings.tracer == TracerKind::BPT);
    CHECK(d.settings.maxPathLength == 64);
    CHECK(d.settings.minPathLength == 2);
    CHECK(d.settings.probLarge == 1.0f);
    CHECK(d.settings.output == "out.png");
    CHECK(load("<Settings><Output name='\"x.pfm\"'/><Tracer name=\"lt\"/></Settings>").settings.output == "x.pfm");
    CHECK(load("<Settings><Tracer name=\"pt\"/></Settings>").settings.tracer == TracerKind::PT);
    CHECK(load("<Settings><Tracer name=\"Lt\"/></Settings>").settings.tracer == TracerKind::LT);
}

TEST_CASE("Settings: EnvMap is resolved against the scene's folder and read", "[scene]") {
    SceneDesc d = load("<Settings><EnvMap name=\"sky-4x2.pfm\"/></Settings>");
    CHECK(d.settings.envMap == (fs::path(kSeed) / "sky-4x2.pfm").lexically_normal().string());
    REQUIRE(d.envMap.width == 4);
    REQUIRE(d.envMap.height == 2);
    CHECK(near(d.envMap.at(0, 0), Vec3(0.8f, 0.9f, 1.0f)));  // top row first
    CHECK(near(d.envMap.at(3, 1), Vec3(0.2f, 0.15f, 0.1f)));

    TempDir t;
    t.write("empty.pfm", "PF\n0 0\n-1.0\n");
    const std::string xml = scene("<Settings>\n<EnvMap name=\"empty.pfm\"/></Settings>");
    std::string m = errorOf([&] { loadSceneFromString(xml, "t.xml", t.path.string()); });
    CHECK(m.rfind("t.xml:5: ", 0) == 0);
    m = errorOf([&] { load("<Settings>\n<EnvMap name=\"missing.exr\"/></Settings>"); });
    CHECK(m.rfind("t.xml:5: ", 0) == 0);
    CHECK(m.find("missing.exr") != std::string::npos);
}

TEST_CASE("Transforms: translate then Rz Ry Rx then scale", "[scene]") {
    // The appendix: the plane at x = 4 rotated z = 90 becomes a wall facing -x.
    SceneDesc d = load(geom("Plane",
                            "<Position x=\"4\" y=\"0\" z=\"0\"/><Rotation x=\"0\" y=\"0\" z=\"90\"/>"
                            "<Width value=\"8\"/><Depth value=\"8\"/>"));
    REQUIRE(d.shapes.size() == 1);
    const ShapeDesc& wall = d.shapes[0];
    for (int t = 0; t < 2; ++t) CHECK(near(faceNormal(wall.mesh, t), Vec3(-1, 0, 0)));
    for (Vec3 p : wall.mesh.positions) CHECK(p.x == 4.0f);  // exact: 90 degrees has no rounding noise
    CHECK(near(wall.toWorld.vector(Vec3(0, 1, 0)), Vec3(-1, 0, 0)));

    // Order: X first, then Z. Rz(90) Rx(90) takes +y to +z; Rx(90) Rz(90) would give -x.
    d = load(plane("<Rotation x=\"90\" y=\"0\" z=\"90\"/>"));
    CHECK(near(faceNormal(d.shapes[0].mesh, 0), Vec3(0, 0, 1)));
    // Ry(90) takes +z to +x (counter-clockwise seen from +y); Rx(-90) takes +y to -z.
    CHECK(near(load(plane("<Rotation x=\"-90\" y=\"90\" z=\"0\"/>")).shapes[0].toWorld.vector(Vec3(0, 1, 0)), Vec3(-1, 0, 0)));

    // Scale applies first, in local axes; toLocal inverts toWorld.
    d =
        load(plane("<Position x=\"1\" y=\"2\" z=\"3\"/><Rotation x=\"10\" y=\"20\" z=\"30\"/>"
                   "<Scale x=\"3\" y=\"1\" z=\"0.5\"/>"));
    const ShapeDesc& s = d.shapes[0];
    CHECK(near(s.toWorld.point(Vec3(0, 0, 0)), Vec3(1, 2, 3)));
    CHECK(length(s.toWorld.vector(Vec3(1, 0, 0))) == Approx(3.0f));
    CHECK(length(s.toWorld.vector(Vec3(0, 0, 1))) == Approx(0.5f));
    Vec3 p(0.3f, -1.2f, 2.5f);
    CHECK(near(s.toLocal.point(s.toWorld.point(p)), p, 1e-5f));
    CHECK(length(s.mesh.positions[2] - s.mesh.positions[1]) == Approx(6.0f));  // Width 2 * 3
}

TEST_CASE("Plane: two triangles with normal +y by their winding and uv over the unit square", "[scene]") {
    SceneDesc d = load(plane("<Position x=\"0\" y=\"-1\" z=\"0\"/>"));
    const ShapeDesc& s = d.shapes[0];
    CHECK(s.kind == ShapeKind::Mesh);
    CHECK(s.uv == UvKind::Plane);
    CHECK(s.material == 0);
    CHECK(s.light == -1);
    CHECK(s.id == "g");
    CHECK(s.line == 4);
    REQUIRE(s.mesh.positions.size() == 4);
    REQUIRE(s.mesh.indices.size() == 6);
    REQUIRE(s.mesh.uvs.size() == 8);
    CHECK(s.mesh.normals.empty());
    for (int t = 0; t < 2; ++t) CHECK(near(faceNormal(s.mesh, t), Vec3(0, 1, 0)));
    for (size_t i = 0; i < 4; ++i) {  // u = x / Width + 0.5, v = z / Depth + 0.5
        Vec3 p = s.mesh.positions[i];
        CHECK(p.y == -1.0f);
        CHECK(s.mesh.uvs[2 * i] == Approx(p.x / 2 + 0.5f));
        CHECK(s.mesh.uvs[2 * i + 1] == Approx(p.z / 4 + 0.5f));
        CHECK(std::fabs(p.x) == 1.0f);
        CHECK(std::fabs(p.z) == 2.0f);
    }
}

TEST_CASE("Sphere: world centre and radius with a uniform Scale", "[scene]") {
    SceneDesc d = load(geom("Sphere",
                            "<Position x=\"1\" y=\"2\" z=\"3\"/><Rotation x=\"0\" y=\"45\" z=\"0\"/>"
                            "<Scale value=\"1.5\"/><Radius value=\"2\"/>"));
    const ShapeDesc& s = d.shapes[0];
    CHECK(s.kind == ShapeKind::Sphere);
    CHECK(s.uv == UvKind::Sphere);
    CHECK(near(s.center, Vec3(1, 2, 3)));
    CHECK(s.radius == Approx(3.0f));
    CHECK(s.mesh.positions.empty());
    CHECK(load(geom("Sphere", "<Scale x=\"2\" y=\"2\" z=\"2\"/><Radius value=\"1\"/>")).shapes[0].radius == 2.0f);
}

TEST_CASE("ObjFile: loaded and transformed with normals by the inverse transpose", "[scene]") {
    SceneDesc d = load(geom("ObjFile",
                            "<Position x=\"0\" y=\"1\" z=\"0\"/><Scale value=\"10\"/>"
                            "<File name=\"small-cube.obj\"/><SmoothShading value=\"1\"/>"));
    const ShapeDesc& s = d.shapes[0];
    CHECK(s.kind == ShapeKind::Mesh);
    CHECK(s.uv == UvKind::Mesh);
    CHECK(s.mesh.indices.size() == 36);  // 6 quads, fan-triangulated
    REQUIRE(s.mesh.normals.size() == s.mesh.positions.size());
    for (Vec3 p : s.mesh.positions) {
        CHECK(std::fabs(p.x) == Approx(1.0f));
        CHECK((p.y == Approx(1.0f) || p.y == Approx(3.0f)));
    }
    for (Vec3 n : s.mesh.normals) CHECK(length(n) == Approx(1.0f));
    CHECK(load(geom("ObjFile", "<File name=\"small-cube.obj\"/><SmoothShading value=\"0\"/>")).shapes[0].mesh.normals.empty());

    TempDir t;  // a triangle in the plane x + y = 0 with its normal; stretched 2x along x
    t.write("tri.obj", "v 0 0 0\nv 1 -1 0\nv 0 0 1\nvn 1 1 0\nf 1//1 3//1 2//1\n");
    d = loadSceneFromString(scene(geom("ObjFile",
                                       "<Scale x=\"2\" y=\"1\" z=\"1\"/><File name=\"tri.obj\"/>"
                                       "<SmoothShading value=\"1\"/>")),
                            "t.xml", t.path.string());
    const TriangleMesh& m = d.shapes[0].mesh;
    CHECK(d.shapes[0].uv == UvKind::None);
    REQUIRE(m.normals.size() == 3);
    CHECK(near(m.normals[0], normalize(Vec3(0.5f, 1, 0))));
    CHECK(near(m.normals[0], faceNormal(m, 0)));  // still perpendicular to the surface
}

TEST_CASE("Lights: rectangle and sphere with radiance Intensity times Colour", "[scene]") {
    SceneDesc d = load(
        "<Light Type=\"Area\" ID=\"0\"><Position x=\"0\" y=\"3\" z=\"0\"/><Rotation x=\"0\" y=\"0\" z=\"180\"/>"
        "<Width value=\"2\"/><Depth value=\"1\"/><Intensity value=\"10\"/>"
        "<Colour r=\"1\" g=\"0.5\" b=\"0.25\" t=\"0.7\"/></Light>\n"
        "<Light Type=\"Area\" ID=\"1\"><Position x=\"1\" y=\"1\" z=\"1\"/><Radius value=\"0.5\"/>"
        "<Intensity value=\"3\"/><Colour r=\"1\" g=\"1\" b=\"1\"/></Light>\n"
        "<Light Type=\"Sphere\" ID=\"2\"><Radius value=\"0.25\"/><Intensity value=\"1e-6\"/></Light>");
    REQUIRE(d.lights.size() == 3);
    REQUIRE(d.shapes.size() == 3);
    CHECK(d.warnings.empty());
    const LightDesc& r = d.lights[0];
    CHECK(r.kind == LightKind::Rect);
    CHECK(near(r.radiance, Vec3(10, 5, 2.5f)));
    const ShapeDesc& rs = d.shapes[r.shape];
    CHECK(rs.light == 0);
    CHECK(rs.material == -1);
    CHECK(rs.kind == ShapeKind::Mesh);
    for (int t = 0; t < 2; ++t) CHECK(near(faceNormal(rs.mesh, t), Vec3(0, -1, 0)));  // emits downwards
    for (Vec3 p : rs.mesh.positions) CHECK(p.y == 3.0f);
    CHECK(d.lights[1].kind == LightKind::Sphere);
    CHECK(d.shapes[d.lights[1].shape].kind == ShapeKind::Sphere);
    CHECK(near(d.shapes[d.lights[1].shape].center, Vec3(1, 1, 1)));
    CHECK(d.shapes[d.lights[1].shape].radius == 0.5f);
    CHECK(d.shapes[d.lights[1].shape].light == 1);
    CHECK(d.lights[2].kind == LightKind::Sphere);
    CHECK(near(d.lights[2].radiance, Vec3(1e-6f)));  // default colour white
}

TEST_CASE("Shaders and textures: fields and Texture and Bump resolved to indices", "[scene]") {
    SceneDesc d = load(
        "<Shader Type=\"Glossy\" ID=\"1\"><Diffuse r=\"0.15\" g=\"0.2\" b=\"0.3\"/><Specular r=\"0.85\" g=\"0.5\" b=\"0.1\"/>"
        "<Shininess value=\"100\"/><Texture value=\"7\"/><Bump value=\"2\"/><Ambient r=\"0\" g=\"0\" b=\"0\"/></Shader>\n"
        "<Shader Type=\"Reflective\" ID=\"2\"><Reflect r=\"0.9\" g=\"0.8\" b=\"0.7\"/><Bump value=\"0\"/></Shader>\n"
        "<Shader Type=\"Dielectric\" ID=\"3\"><Reflect r=\"1\" g=\"1\" b=\"1\"/><Refract r=\"0.9\" g=\"0.9\" b=\"0.9\"/>"
        "<iIOR value=\"1.5\"/><oIOR value=\"1.33\"/></Shader>\n"
        "<Shader Type=\"Matte\" ID=\"4\"><Diffuse r=\"1\" g=\"1\" b=\"1\"/><Texture value=\"0\"/>"
        "<Ambient r=\"0.1\" g=\"0\" b=\"0\"/></Shader>\n"
        "<Texture Type=\"Checker\" ID=\"2\"><Colour1 r=\"0\" g=\"0\" b=\"0\"/><Colour2 r=\"1\" g=\"1\" b=\"1\"/>"
        "<Repeat u=\"4\" v=\"2\"/></Texture>\n"
        "<Texture Type=\"Marble\" ID=\"7\"><Colour1 r=\"0.8\" g=\"0.8\" b=\"0.8\"/><Colour2 r=\"0.4\" g=\"0.2\" b=\"0.1\"/>"
        "<Colour3 r=\"0.06\" g=\"0.04\" b=\"0.02\"/></Texture>\n"
        "<Texture Type=\"ImageFile\" ID=\"9\"><File name=\"checker64.png\"/></Texture>");
    REQUIRE(d.materials.size() == 5);
    REQUIRE(d.textures.size() == 3);
    const MaterialDesc& g = d.materials[1];
    CHECK(g.id == 1);
    CHECK(g.kind == MaterialKind::Glossy);
    CHECK(near(g.diffuse, Vec3(0.15f, 0.2f, 0.3f)));
    CHECK(near(g.specular, Vec3(0.85f, 0.5f, 0.1f)));
    CHECK(g.shininess == 100.0f);
    REQUIRE(g.texture[MaterialParam::Diffuse] >= 0);
    REQUIRE(g.bump >= 0);
    CHECK(d.textures[g.texture[MaterialParam::Diffuse]].id == 7);
    CHECK(d.textures[g.texture[MaterialParam::Diffuse]].kind == TextureKind::Marble);
    CHECK(near(d.textures[g.texture[MaterialParam::Diffuse]].colour3, Vec3(0.06f, 0.04f, 0.02f)));
    CHECK(d.textures[g.bump].id == 2);
    CHECK(d.textures[g.bump].kind == TextureKind::Checker);
    CHECK(d.textures[g.bump].repeatU == 4.0f);
    CHECK(d.textures[g.bump].repeatV == 2.0f);
    CHECK(d.materials[2].kind == MaterialKind::Reflective);
    CHECK(near(d.materials[2].reflect, Vec3(0.9f, 0.8f, 0.7f)));
    CHECK(d.materials[2].bump == -1);
    CHECK(d.materials[3].kind == MaterialKind::Dielectric);
    CHECK(d.materials[3].iorInside == 1.5f);
    CHECK(d.materials[3].iorOutside == 1.33f);
    CHECK(near(d.materials[3].refract, Vec3(0.9f)));
    CHECK(d.materials[4].texture[MaterialParam::Diffuse] == -1);
    const TextureDesc& img = d.textures[2];
    CHECK(img.kind == TextureKind::ImageFile);
    CHECK(img.image.width == 64);
    CHECK(img.image.height == 64);
    CHECK(img.repeatU == 1.0f);
    REQUIRE(d.warnings.size() == 1);  // the non-black Ambient, on line 7
    CHECK(d.warnings[0].rfind("t.xml:7: ", 0) == 0);
    CHECK(d.warnings[0].find("Ambient") != std::string::npos);
}

TEST_CASE("Camera fields", "[scene]") {
    std::string xml =
        "<Scene><Camera Type=\"Camera\" ID=\"0\"><Position x=\"1\" y=\"2\" z=\"3\"/><LookAt x=\"1\" y=\"2\" z=\"4\"/>"
        "<Up x=\"1\" y=\"0\" z=\"0\"/> <!-- a comment --> <FOV value=\"53.1301\"/><DOF value=\"1\"/>"
        "<F-Length value=\"12\"/><F-Stop value=\"2.8\"/></Camera></Scene>";
    const CameraDesc c = loadSceneFromString(xml, "t.xml", "").camera;
    CHECK(near(c.position, Vec3(1, 2, 3)));
    CHECK(near(c.lookAt, Vec3(1, 2, 4)));
    CHECK(near(c.up, Vec3(1, 0, 0)));
    CHECK(c.fovDegrees == Approx(53.1301f));
    CHECK(c.dof);
    CHECK(c.focalLength == 12.0f);
    CHECK(c.fStop == 2.8f);
    const CameraDesc p = load("").camera;
    CHECK(near(p.up, Vec3(0, 1, 0)));
    CHECK_FALSE(p.dof);
}

TEST_CASE("Bad scenes: one InputError naming the file and the line", "[scene][errors]") {
    struct Bad {
        const char* what;
        std::string xml;
        int line;
        const char* fragment;
    };
    const std::string sh = "<Shader value=\"0\"/>";
    const std::vector<Bad> cases = {
        // not well-formed
        {"unquoted attribute", "<Scene>\n<Settings>\n<Width value=5/>\n</Settings>\n</Scene>", 3, "not well-formed"},
        {"mismatched end tag", "<Scene>\n<Settings>\n</Setting>\n</Scene>", 3, "not well-formed"},
        {"the appendix's damaged comments", "<Scene> <!-- fine -->\n<Settings/> <!-- the settings ->\n</Scene>\n", 2, "comment not closed"},
        {"a damaged comment hiding elements", "<Scene> <!-- fine -->\n<Settings/> <!-- the settings ->\n<Camera/>\n<!-- fine -->\n</Scene>\n", 2,
         "\"--\" inside a comment"},
        {"empty file", "", 1, "not well-formed"},
        // unknown elements and attributes, structure
        {"unknown top-level element", scene("<Foo/>"), 4, "Foo: unknown element"},
        {"unknown child",
         scene("<Geometry Type=\"Plane\" ID=\"p\">\n<Width value=\"2\"/><Depth value=\"2\"/>" + sh + "\n<Radius value=\"1\"/>\n</Geometry>"), 6,
         "Geometry ID=\"p\": Radius: unknown element"},
        {"Scale on a light", scene("<Light Type=\"Area\">\n<Scale value=\"2\"/><Radius value=\"1\"/><Intensity value=\"1\"/></Light>"), 5,
         "unknown element"},
        {"Texture on Reflective", scene("<Shader Type=\"Reflective\" ID=\"1\"><Reflect r=\"1\" g=\"1\" b=\"1\"/>\n<Texture value=\"0\"/></Shader>"),
         5, "unknown element"},
        {"unknown attribute", scene("<Settings>\n<Width value=\"5\" units=\"px\"/></Settings>"), 5, "unknown attribute \"units\""},
        {"unknown attribute on Geometry", scene(geom("Plane", "<Width value=\"1\"/><Depth value=\"1\"/>").insert(10, "Name=\"x\" ")), 4,
         "unknown attribute \"Name\""},
        {"unknown Type", scene("<Geometry Type=\"Cone\" ID=\"1\"/>"), 4, "Type=\"Cone\""},
        {"text in an element", scene("<Settings><Width value=\"5\">wide</Width></Settings>"), 4, "unexpected text"},
        {"repeated element", scene("<Settings><Width value=\"5\"/>\n<Width value=\"6\"/></Settings>"), 5, "given twice"},
        {"wrong root", "<Scenery>\n</Scenery>", 1, "unexpected element"},
        // missing required elements and attributes
        {"Plane without Depth", scene("\n" + geom("Plane", "<Width value=\"1\"/>")), 5, "missing required element <Depth>"},
        {"Matte without Diffuse", scene("<Shader Type=\"Matte\" ID=\"1\"></Shader>"), 4, "missing required element <Diffuse>"},
        {"Geometry without Shader", scene("<Geometry Type=\"Sphere\" ID=\"1\"><Radius value=\"1\"/></Geometry>"), 4, "<Shader>"},
        {"Camera without FOV", "<Scene>\n<Camera><Position x=\"0\" y=\"0\" z=\"0\"/><LookAt x=\"0\" y=\"0\" z=\"1\"/></Camera></Scene>", 2,
         "missing required element <FOV>"},
        {"Position without z", scene(plane("\n<Position x=\"1\" y=\"2\"/>")), 5, "missing attribute \"z\""},
        {"Geometry without ID", scene("<Geometry Type=\"Sphere\"><Radius value=\"1\"/>" + sh + "</Geometry>"), 4, "missing attribute \"ID\""},
        {"light with neither size", scene("<Light Type=\"Area\"><Intensity value=\"1\"/></Light>"), 4, "<Radius>"},
        {"light with both sizes",
         scene("<Light Type=\"Area\"><Radius value=\"1\"/><Width value=\"1\"/><Depth value=\"1\"/><Intensity value=\"1\"/></Light>"), 4, "not both"},
        // references and IDs
        {"dangling Shader", scene("<Geometry Type=\"Sphere\" ID=\"g\"><Radius value=\"1\"/>\n<Shader value=\"9\"/></Geometry>"), 5,
         "Shader 9 is not defined"},
        {"dangling Texture", scene("<Shader Type=\"Matte\" ID=\"1\"><Diffuse r=\"1\" g=\"1\" b=\"1\"/>\n<Texture value=\"3\"/></Shader>"), 5,
         "texture 3 is not defined"},
        {"dangling Bump", scene("<Shader Type=\"Reflective\" ID=\"1\"><Reflect r=\"1\" g=\"1\" b=\"1\"/>\n\n<Bump value=\"4\"/></Shader>"), 6,
         "texture 4 is not defined"},
        {"duplicate Geometry ID", scene(plane("") + "\n" + plane("")), 5, "ID \"g\" is already used by the Geometry on line 4"},
        {"duplicate Shader ID", scene("\n<Shader Type=\"Matte\" ID=\"0\"><Diffuse r=\"1\" g=\"1\" b=\"1\"/></Shader>"), 5,
         "already used by the Shader on line 3"},
        {"duplicate Texture ID", scene(checker("1") + "\n" + checker("1")), 5, "already used by the Texture on line 4"},
        {"Texture ID 0", scene(checker("0")), 4, "ID=\"0\" is out of range"},
        // cameras
        {"two cameras", scene("<Camera><Position x=\"0\" y=\"0\" z=\"0\"/><LookAt x=\"0\" y=\"0\" z=\"1\"/><FOV value=\"40\"/></Camera>"), 4,
         "a second camera (the first is on line 2)"},
        {"no camera", "<Scene>\n<Settings/>\n</Scene>", 1, "missing required element <Camera>"},
        {"LookAt = Position",
         "<Scene>\n<Camera><Position x=\"1\" y=\"0\" z=\"0\"/>\n<LookAt x=\"1\" y=\"0\" z=\"0\"/><FOV value=\"40\"/></Camera></Scene>", 3,
         "LookAt equals Position"},
        // values out of range
        {"Width 0", scene("<Settings>\n<Width value=\"0\"/></Settings>"), 5, "out of range (1 to 16384)"},
        {"Width 1e9", scene("<Settings>\n<Width value=\"1000000000\"/></Settings>"), 5, "out of range"},
        {"Height 16385", scene("<Settings><Height value=\"16385\"/></Settings>"), 4, "out of range"},
        {"MaxPathLength 0", scene("<Settings><MaxPathLength value=\"0\"/></Settings>"), 4, "out of range (1 to 64)"},
        {"MaxPathLength 1000", scene("<Settings><MaxPathLength value=\"1000\"/></Settings>"), 4, "out of range"},
        {"Min > Max", scene("<Settings><MaxPathLength value=\"3\"/>\n<MinPathLength value=\"4\"/></Settings>"), 5, "greater than MaxPathLength"},
        {"ProbLarge 0", scene("<Settings><ProbLarge value=\"0\"/></Settings>"), 4, "out of range"},
        {"ProbLarge 2", scene("<Settings><ProbLarge value=\"2\"/></Settings>"), 4, "out of range"},
        {"unknown tracer", scene("<Settings><Tracer name=\"MLT\"/></Settings>"), 4, "not one of MMLT, BPT, LT, PT"},
        {"Output extension", scene("<Settings><Output name=\"render.tiff\"/></Settings>"), 4, "extension"},
        {"negative Radius", scene(geom("Sphere", "\n<Radius value=\"-1\"/>")), 5, "value=\"-1\" is out of range (must be > 0)"},
        {"plane Width 0", scene(geom("Plane", "<Width value=\"0\"/><Depth value=\"1\"/>")), 4, "out of range"},
        {"zero-size light", scene("<Light Type=\"Area\" ID=\"0\">\n<Width value=\"0\"/><Depth value=\"1\"/><Intensity value=\"1\"/></Light>"), 5,
         "out of range"},
        {"zero-radius light", scene("<Light Type=\"Sphere\"><Radius value=\"0\"/><Intensity value=\"1\"/></Light>"), 4, "out of range"},
        {"negative Intensity", scene("<Light Type=\"Sphere\"><Radius value=\"1\"/>\n<Intensity value=\"-1\"/></Light>"), 5, "out of range"},
        {"iIOR 0", scene("<Shader Type=\"Dielectric\" ID=\"1\">\n<iIOR value=\"0\"/><oIOR value=\"1\"/></Shader>"), 5, "out of range"},
        {"oIOR -1", scene("<Shader Type=\"Dielectric\" ID=\"1\"><iIOR value=\"1.5\"/>\n<oIOR value=\"-1\"/></Shader>"), 5, "out of range"},
        {"Diffuse + Specular > 1",
         scene("<Shader Type=\"Glossy\" ID=\"1\"><Diffuse r=\"0.5\" g=\"0.5\" b=\"0.5\"/>\n"
               "<Specular r=\"0.5\" g=\"0.6\" b=\"0.5\"/><Shininess value=\"1\"/></Shader>"),
         5, "green channel"},
        {"Shininess < 0",
         scene("<Shader Type=\"Glossy\" ID=\"1\"><Diffuse r=\"0.5\" g=\"0.5\" b=\"0.5\"/><Specular r=\"0.5\" g=\"0.5\" b=\"0.5\"/>"
               "<Shininess value=\"-1\"/></Shader>"),
         4, "out of range"},
        {"Colour above 1", scene("<Shader Type=\"Matte\" ID=\"1\"><Diffuse r=\"1.5\" g=\"0\" b=\"0\"/></Shader>"), 4,
         "r=\"1.5\" is out of range (0 to 1)"},
        {"FOV 180", scene("").replace(kHead.find("45"), 2, "180"), 2, "out of range"},
        {"F-Stop 0 with DOF",
         "<Scene><Camera><Position x=\"0\" y=\"0\" z=\"0\"/><LookAt x=\"0\" y=\"0\" z=\"1\"/><FOV value=\"40\"/>"
         "<DOF value=\"1\"/><F-Length value=\"5\"/>\n<F-Stop value=\"0\"/></Camera></Scene>",
         2, "out of range"},
        {"DOF 2", scene("").replace(kHead.find("</Camera>"), 0, "<DOF value=\"2\"/>"), 2, "out of range (0 to 1)"},
        {"Scale 0", scene(plane("\n<Scale value=\"0\"/>")), 5, "out of range"},
        {"Repeat 0", scene(checker("1", "\n<Repeat u=\"1\" v=\"-2\"/>")), 5, "v=\"-2\" is out of range"},
        {"non-uniform Scale on a sphere", scene(geom("Sphere", "<Radius value=\"1\"/>\n<Scale x=\"1\" y=\"2\" z=\"1\"/>")), 5, "uniform"},
        {"Scale with value and x", scene(plane("<Scale value=\"1\" x=\"2\"/>")), 4, "not both"},
        // numbers: NaN, Inf, trailing garbage, overflow, non-integers
        {"trailing garbage", scene(geom("Sphere", "\n<Radius value=\"1.5x\"/>")), 5, "value=\"1.5x\" is not a finite number"},
        {"nan", scene(geom("Sphere", "\n<Radius value=\"nan\"/>")), 5, "not a finite number"},
        {"inf", scene(plane("\n<Position x=\"inf\" y=\"0\" z=\"0\"/>")), 5, "x=\"inf\" is not a finite number"},
        {"-infinity", scene(plane("\n<Rotation x=\"0\" y=\"-infinity\" z=\"0\"/>")), 5, "not a finite number"},
        {"float overflow", scene(geom("Sphere", "\n<Radius value=\"1e39\"/>")), 5, "not a finite number"},
        {"empty number", scene(geom("Sphere", "\n<Radius value=\"\"/>")), 5, "not a finite number"},
        {"hex number", scene(geom("Sphere", "\n<Radius value=\"0x10\"/>")), 5, "not a finite number"},
        {"non-integer Width", scene("<Settings>\n<Width value=\"512.5\"/></Settings>"), 5, "not an integer"},
        {"garbage ID", scene("<Shader Type=\"Matte\" ID=\"1a\"><Diffuse r=\"1\" g=\"1\" b=\"1\"/></Shader>"), 4, "ID=\"1a\" is not an integer"},
        // files
        {"missing OBJ", scene(geom("ObjFile", "\n<File name=\"nope.obj\"/>")), 5, "nope.obj: cannot open"},
        {"missing image", scene("<Texture Type=\"ImageFile\" ID=\"1\">\n<File name=\"nope.png\"/></Texture>"), 5, "nope.png"},
    };
    for (const Bad& b : cases) {
        DYNAMIC_SECTION(b.what) { requireError(b.xml, b.line, b.fragment); }
    }
}

TEST_CASE("loadScene: a missing file names itself", "[scene][errors]") {
    const std::string path = kData + "/scenes/no-such-scene.xml";
    std::string m = errorOf([&] { loadScene(path); });
    CHECK(m.rfind(path + ": ", 0) == 0);
}

TEST_CASE("loadObj: polygons and vertex sharing and uvs and normals", "[scene][obj]") {
    // Only v and f: the file's vertices are shared as they are.
    TriangleMesh box = loadObj(kData + "/scenes/bitterli-cornell/meshes/ShortBox.obj", false);
    CHECK(box.positions.size() == 8);
    CHECK(box.indices.size() == 36);
    CHECK(box.uvs.empty());
    CHECK(box.normals.empty());

    TriangleMesh cube = loadObj(kSeed + "/small-cube.obj", true);
    CHECK(cube.indices.size() == 36);  // 6 quads -> 12 triangles
    CHECK(cube.uvs.size() == 2 * cube.positions.size());
    CHECK(cube.positions.size() > 8);  // corners split by their vt
    REQUIRE(cube.normals.size() == cube.positions.size());
    // Area-weighted normals accumulated per position (not per (v, vt)): the copies of a
    // corner on both sides of a uv seam share one normal, pointing out of the cube.
    for (size_t i = 0; i < cube.positions.size(); ++i) {
        Vec3 p = cube.positions[i] - Vec3(0, 0.1f, 0), n = cube.normals[i];
        CHECK(length(n) == Approx(1.0f));
        for (int k = 0; k < 3; ++k) CHECK(n[k] * p[k] > 0);
        for (size_t j = 0; j < i; ++j)
            if (near(cube.positions[j], cube.positions[i], 0)) CHECK(near(cube.normals[j], n, 0));
    }

    TempDir t;
    // Negative indices, CRLF, ignored statements, comments, extra v components, a pentagon.
    std::string path = t.write("misc.obj",
                               "# comment\r\nmtllib x.mtl\r\no thing\r\nv 0 0 0 1\r\nv 1 0 0\r\nv 1 1 0\r\nv 0.5 1.5 0\r\n"
                               "v 0 1 0\r\ng group\r\nusemtl m\r\ns 1\r\nvt 0.5\r\nf -5/1 -4/1 -3/1 -2/1 -1/1 # pentagon\r\n");
    TriangleMesh m = loadObj(path, false);
    REQUIRE(m.indices.size() == 9);
    CHECK(m.positions.size() == 5);
    CHECK(m.uvs[0] == 0.5f);
    CHECK(m.uvs[1] == 0.0f);
    for (int tri = 0; tri < 3; ++tri) CHECK(near(faceNormal(m, tri), Vec3(0, 0, 1)));  // winding kept
    CHECK(near(m.positions[m.indices[0]], Vec3(0, 0, 0)));                             // fan from the first corner
    CHECK(near(m.positions[m.indices[8]], Vec3(0, 1, 0)));

    // The file's vn are used (normalised) when smooth shading is on.
    path = t.write("vn.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 2\nf 1//1 2//1 3//1\n");
    m = loadObj(path, true);
    REQUIRE(m.normals.size() == 3);
    CHECK(near(m.normals[2], Vec3(0, 0, 1)));
    CHECK(loadObj(path, false).positions.size() == 3);
}

TEST_CASE("loadObj errors: file and line", "[scene][obj][errors]") {
    TempDir t;
    struct Bad {
        const char* what;
        std::string text;
        int line;
        const char* fragment;
    };
    const std::vector<Bad> cases = {
        {"index past the vertex list", "v 0 0 0\nv 1 0 0\nv 0 1 0\n\nv 1 1 0\nf 1 2 3\nf 1 2 7\n", 7, "face index 7 is past the 4 vertices"},
        {"negative index past the start", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n", 4, "face index -4 is past the 3 vertices"},
        {"texture index past", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/2 3/1\n", 5, "texture index 2 is past the 1 texture coordinates"},
        {"normal index past", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//1 2//1 3//1\n", 4, "normal index 1 is past the 0 normals"},
        {"index 0", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", 4, "index 0"},
        {"non-numeric vertex", "v 0 0 0\n# fine\nv 1 abc 0\n", 3, "\"abc\" is not a finite number"},
        {"trailing garbage", "v 0 0 0\nv 1.5x 0 0\n", 2, "\"1.5x\""},
        {"nan", "v 0 0 0\nv nan 0 0\n", 2, "not a finite number"},
        {"too few numbers", "v 0 0\n", 1, "at least 3 numbers"},
        {"malformed corner", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3x\n", 4, "\"3x\" is malformed"},
        {"two-corner face", "v 0 0 0\nv 1 0 0\nf 1 2\n", 3, "at least 3 vertices"},
        {"unknown statement", "v 0 0 0\nbogus 1 2\n", 2, "unknown statement \"bogus\""},
    };
    for (const Bad& b : cases) {
        DYNAMIC_SECTION(b.what) {
            const std::string path = t.write("bad.obj", b.text);
            std::string m = errorOf([&] { loadObj(path, true); });
            INFO("message: " << m);
            CHECK(m.rfind(path + ":" + std::to_string(b.line) + ": ", 0) == 0);
            CHECK(m.find(b.fragment) != std::string::npos);
        }
    }
    SECTION("zero faces") {
        const std::string path = t.write("empty.obj", "# nothing\nv 0 0 0\n");
        std::string m = errorOf([&] { loadObj(path, false); });
        CHECK(m == path + ": the file has no faces");
    }
    SECTION("missing file") {
        const std::string path = (t.path / "missing.obj").string();
        std::string m = errorOf([&] { loadObj(path, false); });
        CHECK(m.rfind(path + ": ", 0) == 0);
        CHECK(m.find("cannot open") != std::string::npos);
    }
}

TEST_CASE("Appendix A loads with the two expected warnings", "[scene][files]") {
    const std::string path = kSeed + "/seed-appendix.xml";
    SceneDesc d = loadScene(path);
    CHECK(d.path == path);
    REQUIRE(d.warnings.size() == 2);
    CHECK(d.warnings[0] == path + ":78: Shader ID=\"3\": oIOR: iIOR equals oIOR (1.5): oIOR is taken as 1");
    CHECK(d.warnings[1].rfind(path + ":51: Light ID=\"0\": ", 0) == 0);
    CHECK(d.warnings[1].find("also used by the Light on line 43") != std::string::npos);
    CHECK(d.settings.threads == 12);
    CHECK(d.settings.minPathLength == 3);
    CHECK(d.settings.output == "render.png");
    CHECK(d.envMap.width == 4);
    CHECK(d.shapes.size() == 5);  // plane, sphere, mesh, two lights
    CHECK(d.lights.size() == 2);
    CHECK(d.materials.size() == 4);
    CHECK(d.textures.size() == 3);
    CHECK(d.materials[3].iorOutside == 1.0f);
    CHECK(near(d.shapes[0].toWorld.vector(Vec3(0, 1, 0)), Vec3(-1, 0, 0)));  // the wall faces -x
    CHECK(d.shapes[2].material == 0);
    CHECK(d.lights[0].kind == LightKind::Rect);
    CHECK(d.lights[1].kind == LightKind::Sphere);
    CHECK(near(d.lights[1].radiance, Vec3(14)));
    CHECK(d.camera.fovDegrees == Approx(53.1301f));
    CHECK_FALSE(d.camera.dof);
}

TEST_CASE("The Bitterli Cornell box (256) loads", "[scene][files]") {
    SceneDesc d = loadScene(kData + "/scenes/bitterli-cornell/bitterli-cornell-256.xml");
    CHECK(d.warnings.empty());
    REQUIRE(d.shapes.size() == 8);
    int meshes = 0;
    for (const ShapeDesc& s : d.shapes)
        if (s.material >= 0 && s.kind == ShapeKind::Mesh && s.uv == UvKind::None && s.mesh.normals.empty()) ++meshes;
    CHECK(meshes == 7);
    REQUIRE(d.lights.size() == 1);
    CHECK(d.lights[0].kind == LightKind::Rect);
    CHECK(near(d.lights[0].radiance, Vec3(17, 12, 4), 1e-4f));
    const ShapeDesc& l = d.shapes[d.lights[0].shape];
    CHECK(near(faceNormal(l.mesh, 0), Vec3(0, -1, 0)));
    CHECK(near(d.camera.position, Vec3(0, 1, 6.8f)));
    CHECK(near(d.camera.lookAt, Vec3(0, 1, 5.8f)));
    CHECK(near(d.camera.up, Vec3(0, 1, 0)));
    CHECK(d.camera.fovDegrees == 19.5f);
    CHECK(d.settings.width == 256);
    CHECK(d.settings.height == 256);
    CHECK(d.settings.samples == 8);
    CHECK(d.settings.tracer == TracerKind::PT);
    CHECK(d.settings.maxPathLength == 64);
    CHECK(d.settings.output == "bitterli-cornell-256.exr");
}
