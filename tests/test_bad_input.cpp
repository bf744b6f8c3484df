// Bad input, end to end (the "Reliability" issue): every class of bad scene, OBJ, image
// and command line runs the `wavemmlt` binary and requires
//   - exit status 2,
//   - exactly one line on stderr, "error: <file>:<line>: <problem>" (the file and line
//     where there is one: the scene file and line, and for an OBJ also the OBJ's line),
//   - no output image (and no temporary file) left behind.
// Parser-level checks of the same inputs are in test_scene_load.cpp, test_image.cpp and
// test_cli.cpp; this file checks what the user sees. docs/reliability.md lists each case.
#include <catch2/catch.hpp>

#include <fcntl.h>
#include <grp.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "bad_input_run.h"
#include "wavemmlt/image.h"

using namespace badinput;

namespace {

// Small scenes: lines 1-3 are the head, a body starts on line 4, a light follows it.
const std::string kHead =
    "<Scene>\n"
    "<Camera Type=\"Camera\"><Position x=\"0\" y=\"0\" z=\"-5\"/><LookAt x=\"0\" y=\"0\" z=\"0\"/><FOV value=\"45\"/></Camera>\n"
    "<Shader Type=\"Matte\" ID=\"0\"><Diffuse r=\"0.5\" g=\"0.5\" b=\"0.5\"/></Shader>\n";
const std::string kLight =
    "<Light Type=\"Area\" ID=\"l\"><Position x=\"0\" y=\"0\" z=\"-2\"/><Radius value=\"0.5\"/><Intensity value=\"5\"/></Light>\n";
const std::string kCamera = "<Camera><Position x=\"0\" y=\"0\" z=\"0\"/><LookAt x=\"0\" y=\"0\" z=\"1\"/><FOV value=\"40\"/></Camera>";
std::string scene(const std::string& body) { return kHead + body + "\n" + kLight + "</Scene>\n"; }

// A fast render if the input were (wrongly) accepted.
const std::vector<std::string> kFast = {"--quiet", "--tracer", "pt", "--spp", "1", "--width", "16", "--height", "16"};

// Runs the scene file `xml` (written as `name`) and requires the bad-input behaviour with
// "<scene path>:<line>:" and `fragment` in the message.
void requireBadScene(const std::string& name, const std::string& xml, int line, const std::string& fragment, const TempDir& dir,
                     const std::vector<std::string>& more = {}) {
    const std::string path = dir.write(name, xml), out = dir.file("out.pfm");
    std::vector<std::string> args = {path};
    args.insert(args.end(), kFast.begin(), kFast.end());
    args.insert(args.end(), {"-o", out});
    Proc p = run(args, dir);
    std::vector<std::string> fragments = {line > 0 ? path + ":" + std::to_string(line) + ": " : path + ": ", fragment};
    fragments.insert(fragments.end(), more.begin(), more.end());
    requireBad(p, fragments, out, dir);
}

std::string geom(const std::string& type, const std::string& inner, const std::string& id = "g") {
    return "<Geometry Type=\"" + type + "\" ID=\"" + id + "\">" + inner + "<Shader value=\"0\"/></Geometry>";
}
std::string checker(const std::string& id) {
    return "<Texture Type=\"Checker\" ID=\"" + id + "\"><Colour1 r=\"0\" g=\"0\" b=\"0\"/><Colour2 r=\"1\" g=\"1\" b=\"1\"/></Texture>";
}
std::string objGeom(const std::string& file) {
    return "<Geometry Type=\"ObjFile\" ID=\"m\"><File name=\"" + file + "\"/><SmoothShading value=\"1\"/><Shader value=\"0\"/></Geometry>";
}

}  // namespace

// ---- scene XML ------------------------------------------------------------------------------

TEST_CASE("badinput: scene XML errors exit 2 with file and line and write nothing", "[badinput]") {
    struct Bad {
        const char* what;
        std::string xml;
        int line;
        const char* fragment;
    };
    const std::vector<Bad> cases = {
        {"not well-formed", scene("<Settings>\n<Width value=5/></Settings>"), 5, "not well-formed XML"},
        {"unclosed element", kHead + "<Settings>\n", 4, "not well-formed XML"},
        {"unknown element", scene("<Frobnicate value=\"1\"/>"), 4, "Frobnicate: unknown element"},
        {"unknown attribute", scene("<Settings>\n<Width value=\"5\" units=\"px\"/></Settings>"), 5, "unknown attribute \"units\""},
        {"missing required element", scene("<Geometry Type=\"Plane\" ID=\"p\"><Width value=\"1\"/><Shader value=\"0\"/></Geometry>"), 4,
         "missing required element <Depth>"},
        {"duplicate Geometry ID", scene(geom("Sphere", "<Radius value=\"1\"/>") + "\n" + geom("Sphere", "<Radius value=\"1\"/>")), 5,
         "ID \"g\" is already used by the Geometry on line 4"},
        {"duplicate Shader ID", scene("<Shader Type=\"Matte\" ID=\"0\"><Diffuse r=\"1\" g=\"1\" b=\"1\"/></Shader>"), 4,
         "already used by the Shader on line 3"},
        {"duplicate Texture ID", scene(checker("1") + "\n" + checker("1")), 5, "already used by the Texture on line 4"},
        {"dangling Shader", scene("<Geometry Type=\"Sphere\" ID=\"s\"><Radius value=\"1\"/>\n<Shader value=\"7\"/></Geometry>"), 5,
         "Shader 7 is not defined"},
        {"dangling Texture", scene("<Shader Type=\"Matte\" ID=\"1\"><Diffuse r=\"1\" g=\"1\" b=\"1\"/>\n<Texture value=\"3\"/></Shader>"), 5,
         "texture 3 is not defined"},
        {"dangling Bump",
         scene("<Shader Type=\"Glossy\" ID=\"1\"><Diffuse r=\"0.5\" g=\"0.5\" b=\"0.5\"/><Specular r=\"0.5\" g=\"0.5\" b=\"0.5\"/>"
               "<Shininess value=\"10\"/>\n<Bump value=\"4\"/></Shader>"),
         5, "texture 4 is not defined"},
        {"negative radius", scene(geom("Sphere", "\n<Radius value=\"-1\"/>")), 5, "value=\"-1\" is out of range (must be > 0)"},
        {"zero-size rectangle light", scene("<Light Type=\"Area\">\n<Width value=\"0\"/><Depth value=\"1\"/><Intensity value=\"1\"/></Light>"), 5,
         "value=\"0\" is out of range"},
        {"zero-radius sphere light", scene("<Light Type=\"Sphere\">\n<Radius value=\"0\"/><Intensity value=\"1\"/></Light>"), 5,
         "value=\"0\" is out of range"},
        {"Width 0", scene("<Settings>\n<Width value=\"0\"/></Settings>"), 5, "value=\"0\" is out of range (1 to 16384)"},
        {"Width 1000000000", scene("<Settings>\n<Width value=\"1000000000\"/></Settings>"), 5, "out of range (1 to 16384)"},
        {"Width 1e9", scene("<Settings>\n<Width value=\"1e9\"/></Settings>"), 5, "value=\"1e9\" is not an integer"},
        {"MaxPathLength 0", scene("<Settings>\n<MaxPathLength value=\"0\"/></Settings>"), 5, "out of range (1 to 64)"},
        {"MaxPathLength 1000", scene("<Settings>\n<MaxPathLength value=\"1000\"/></Settings>"), 5, "out of range (1 to 64)"},
        {"ProbLarge 0", scene("<Settings>\n<ProbLarge value=\"0\"/></Settings>"), 5, "out of range (0 < p <= 1)"},
        {"ProbLarge 2", scene("<Settings>\n<ProbLarge value=\"2\"/></Settings>"), 5, "out of range (0 < p <= 1)"},
        {"iIOR 0", scene("<Shader Type=\"Dielectric\" ID=\"1\">\n<iIOR value=\"0\"/><oIOR value=\"1\"/></Shader>"), 5, "out of range (must be > 0)"},
        {"oIOR negative", scene("<Shader Type=\"Dielectric\" ID=\"1\"><iIOR value=\"1.5\"/>\n<oIOR value=\"-1\"/></Shader>"), 5,
         "out of range (must be > 0)"},
        {"Diffuse + Specular > 1",
         scene("<Shader Type=\"Glossy\" ID=\"1\"><Diffuse r=\"0.5\" g=\"0.5\" b=\"0.5\"/>\n"
               "<Specular r=\"0.5\" g=\"0.5\" b=\"0.6\"/><Shininess value=\"1\"/></Shader>"),
         5, "Diffuse + Specular exceeds 1 in the blue channel"},
        {"two cameras", scene(kCamera), 4, "a second camera (the first is on line 2)"},
        {"no camera", "<Scene>\n<Settings/>\n" + kLight + "</Scene>\n", 1, "missing required element <Camera>"},
        {"NaN in a number", scene(geom("Sphere", "\n<Radius value=\"NaN\"/>")), 5, "value=\"NaN\" is not a finite number"},
        {"Inf in a number", scene(geom("Sphere", "<Radius value=\"1\"/>\n<Position x=\"0\" y=\"Inf\" z=\"0\"/>")), 5,
         "y=\"Inf\" is not a finite number"},
        {"-infinity in a number", scene(geom("Sphere", "<Radius value=\"1\"/>\n<Position x=\"0\" y=\"0\" z=\"-infinity\"/>")), 5,
         "not a finite number"},
        {"trailing garbage in a number", scene(geom("Sphere", "\n<Radius value=\"1.5x\"/>")), 5, "value=\"1.5x\" is not a finite number"},
        {"trailing garbage after the scene", scene("") + "\ngarbage after the end\n", 8,
         "text outside the <Scene> element (\"garbage after the end\")"},
        {"a second root element", scene("") + "<Scene/>\n", 7, "unexpected element: the file holds one <Scene>"},
        {"NUL bytes after the scene", scene("") + std::string(16, '\0'), 7, "a NUL byte"},
        {"empty file", "", 1, "not well-formed XML"},
    };
    TempDir dir;
    for (const Bad& b : cases) {
        DYNAMIC_SECTION(b.what) { requireBadScene("bad.xml", b.xml, b.line, b.fragment, dir); }
    }
    SECTION("missing scene file") {
        const std::string path = dir.file("no-such.xml"), out = dir.file("out.pfm");
        std::vector<std::string> args = {path};
        args.insert(args.end(), kFast.begin(), kFast.end());
        args.insert(args.end(), {"-o", out});
        requireBad(run(args, dir), {path + ": cannot open the scene file"}, out, dir);
    }
}

// Nesting deeper than the importers' bound (kMaxXmlNesting = 100, scene/xml_nesting.h):
// without it, 10,000 nested Mitsuba BSDFs and 50,000 nested thesis elements exhausted the
// stack in the importers' recursive walks (SIGSEGV). The files are made here, not stored.
namespace {

// A Mitsuba sphere whose BSDF is `wrappers` twosided BSDFs around a diffuse one, one per
// line: the scene is depth 1, the shape 2 (line 5), the i-th twosided 2 + i (line 5 + i),
// the diffuse one 3 + wrappers (line 6 + wrappers).
std::string nestedMitsuba(int wrappers) {
    std::string s =
        "<scene version=\"3.0.0\">\n"
        "<sensor type=\"perspective\"><float name=\"fov\" value=\"40\"/>\n"
        "<transform name=\"to_world\"><lookat origin=\"0, 0, 5\" target=\"0, 0, 0\" up=\"0, 1, 0\"/></transform>\n"
        "<film type=\"hdrfilm\"><integer name=\"width\" value=\"16\"/><integer name=\"height\" value=\"16\"/></film></sensor>\n"
        "<shape type=\"sphere\">\n";
    for (int i = 0; i < wrappers; ++i) s += "<bsdf type=\"twosided\">\n";
    s += "<bsdf type=\"diffuse\"/>\n";
    for (int i = 0; i < wrappers; ++i) s += "</bsdf>\n";
    return s + "</shape>\n<emitter type=\"constant\"><rgb name=\"radiance\" value=\"1\"/></emitter>\n</scene>\n";
}

// <Scene> and `depth - 1` nested <Shape> elements, one per line (depth d on line d).
std::string nestedThesis(int depth) {
    std::string s = "<Scene>\n";
    for (int i = 1; i < depth; ++i) s += "<Shape>\n";
    for (int i = 1; i < depth; ++i) s += "</Shape>\n";
    return s + "</Scene>\n";
}

}  // namespace

TEST_CASE("badinput: elements nested deeper than 100 are refused before any recursion", "[badinput]") {
    TempDir dir;
    const std::string limit = "elements nested deeper than 100";
    SECTION("Mitsuba: 10,000 nested twosided BSDFs") {
        // The first element at depth 101 is the 99th twosided, on line 104.
        requireBadScene("deep.xml", nestedMitsuba(10000), 104, limit, dir);
    }
    SECTION("Mitsuba: one level past the limit") {
        requireBadScene("deep.xml", nestedMitsuba(98), 104, limit, dir);  // the diffuse BSDF is at 101
    }
    SECTION("Mitsuba: a file at the limit loads and renders") {
        // 97 twosided wrappers: the diffuse BSDF is at depth exactly 100.
        const std::string path = dir.write("limit.xml", nestedMitsuba(97)), out = dir.file("out.pfm");
        std::vector<std::string> args = {path};
        args.insert(args.end(), kFast.begin(), kFast.end());
        // The box filter: with Mitsuba's default Gaussian a pixel of the sky is 1 only in
        // expectation (its one sample's weight f / pdf varies about 1).
        args.insert(args.end(), {"--filter", "box", "-o", out});
        const Proc p = run(args, dir);
        INFO("stderr: " << p.err.substr(0, 2000));
        REQUIRE(p.status == 0);
        const wmlt::Image img = wmlt::readImage(out);
        REQUIRE(img.width == 16);
        // A grey diffuse sphere under a uniform sky of 1: the sky around it is exactly 1,
        // the sphere (its BSDF found through all 97 wrappers) is lit and not the sky.
        CHECK(img.at(0, 0).x == 1.0f);
        CHECK(img.at(8, 8).x > 0.0f);
        CHECK(img.at(8, 8).x != 1.0f);
    }
    SECTION("thesis format: 50,000 nested elements") { requireBadScene("deep.xml", nestedThesis(50000), 101, limit, dir); }
    SECTION("thesis format: at the limit the file gets its ordinary error") {
        // Depth 100 passes the bound; its second element is then an unknown element.
        requireBadScene("deep.xml", nestedThesis(100), 2, "Shape: unknown element", dir);
    }
}

// ---- pbrt-v4 ---------------------------------------------------------------------------------

TEST_CASE("badinput: pbrt-v4 scene errors exit 2 with file and line and write nothing", "[badinput][pbrt]") {
    TempDir dir;
    const std::string head = "WorldBegin\nLightSource \"point\"\n";
    struct Bad {
        const char* what;
        std::string text;
        const char* fragment;
    };
    const std::vector<Bad> cases = {
        {"unterminated bracket", head + "Shape \"sphere\" \"float radius\" [ 1\n", "s.pbrt:3: \"float radius\": unterminated ["},
        {"unknown directive", head + "Frobnicate\n", "s.pbrt:3: unknown directive \"Frobnicate\""},
        {"unknown named material", head + "NamedMaterial \"x\"\n", "s.pbrt:3: NamedMaterial: no material named \"x\""},
        {"missing include", head + "Include \"gone.pbrt\"\n", "s.pbrt:3: "},
        {"not gzip", "", "s.pbrt.gz: the scene file is named .gz but is not gzip"},
    };
    for (const Bad& b : cases) {
        DYNAMIC_SECTION(b.what) {
            const std::string name = std::string(b.what) == "not gzip" ? "s.pbrt.gz" : "s.pbrt";
            const std::string path = dir.write(name, b.text.empty() ? head : b.text);
            const std::string out = dir.file("out.exr");
            requireBad(run({path, "-o", out, "--spp", "1"}, dir), {b.fragment}, out, dir);
        }
    }
}

// ---- OBJ ------------------------------------------------------------------------------------

TEST_CASE("badinput: OBJ errors name the scene line and the OBJ file and line", "[badinput]") {
    TempDir dir;
    const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    struct Bad {
        const char* what;
        std::string obj;
        int objLine;
        const char* fragment;
    };
    const std::vector<Bad> cases = {
        {"faces indexing past the vertex list", tri + "f 1 2 3\nf 1 2 4\n", 5, "face index 4 is past the 3 vertices"},
        {"non-numeric data", "v 0 0 0\nv 1 zero 0\n", 2, "\"zero\" is not a finite number"},
        {"NaN coordinate", "v 0 0 0\nv nan 0 0\n", 2, "not a finite number"},
        {"zero faces", tri, 0, "the file has no faces"},
        {"empty file", "", 0, "the file has no faces"},
        {"binary garbage",
         std::string("\x7f"
                     "ELF\x02\x01\x01\0\0\0\0garbage",
                     18),
         1, "not a text file (a NUL byte)"},
    };
    for (const Bad& b : cases) {
        DYNAMIC_SECTION(b.what) {
            const std::string obj = dir.write("m.obj", b.obj);
            requireBadScene("obj.xml", scene(objGeom("m.obj")), 4, b.fragment, dir,
                            {b.objLine > 0 ? obj + ":" + std::to_string(b.objLine) + ": " : obj + ": "});
        }
    }
    SECTION("missing file") {
        requireBadScene("obj.xml", scene(objGeom("nothere.obj")), 4, dir.file("nothere.obj") + ": cannot open the OBJ file", dir);
    }
    SECTION("unreadable file (a folder named .obj)") {
        fs::create_directories(dir.path / "folder.obj");
        requireBadScene("obj.xml", scene(objGeom("folder.obj")), 4, dir.file("folder.obj") + ": cannot read the OBJ file", dir);
    }
    SECTION("unreadable file (no read permission)") {
        if (geteuid() == 0) {
            WARN("running as root: read permission cannot be taken away; covered by the folder case above");
        } else {
            const std::string obj = dir.write("locked.obj", tri + "f 1 2 3\n");
            fs::permissions(obj, fs::perms::none);
            requireBadScene("obj.xml", scene(objGeom("locked.obj")), 4, obj + ": cannot open the OBJ file", dir);
        }
    }
}

// A 2 GiB file of garbage must fail at once, without reading it into memory. The file is
// sparse (ftruncate): creating it costs nothing, but reading it returns 2 GiB of bytes.
// Bounds: 2 s and 256 MiB resident (the process normally peaks near 15 MiB); the child is
// killed beyond 10 s or 512 MiB so that a loader that reads the whole file cannot stall or
// swamp the test machine.
TEST_CASE("badinput: a 2 GiB OBJ of garbage fails fast in bounded memory", "[badinput][obj]") {
    TempDir dir;
    const off_t size = off_t(2) << 30;
    auto sparse = [&](const std::string& name, const std::string& head) {
        const std::string path = dir.file(name);
        const int fd = open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        REQUIRE(fd >= 0);
        REQUIRE(write(fd, head.data(), head.size()) == ssize_t(head.size()));
        REQUIRE(ftruncate(fd, size) == 0);
        close(fd);
        return path;
    };
    struct Case {
        const char* what;
        std::string head;
        const char* fragment;
    };
    const std::vector<Case> cases = {
        {"text garbage then zeros", "this is not an OBJ file\n", "unknown statement \"this\""},
        {"zeros only (no line break in 2 GiB)", "", "m.obj:1: "},
    };
    for (const Case& c : cases) {
        DYNAMIC_SECTION(c.what) {
            const std::string obj = sparse("m.obj", c.head);
            const std::string xml = dir.write("big.xml", scene(objGeom("m.obj"))), out = dir.file("out.pfm");
            std::vector<std::string> args = {xml};
            args.insert(args.end(), kFast.begin(), kFast.end());
            args.insert(args.end(), {"-o", out});
            Limits lim;
            lim.seconds = 10;
            lim.rssKb = 512 * 1024;
            Proc p = run(args, dir, lim);
            INFO(c.what << ": " << p.seconds << " s, peak resident " << p.maxRssKb / 1024 << " MiB, stderr " << p.errBytes << " bytes"
                        << (p.killed ? ", killed: " + p.why : ""));
            requireBad(p, {xml + ":4: ", obj, c.fragment}, out, dir);
            CHECK(p.seconds < 2.0);
            CHECK(p.maxRssKb < 256 * 1024);
            CHECK(p.errBytes < 4096);  // the message quotes no megabytes of garbage
        }
    }
}

// ---- images -----------------------------------------------------------------------------------

TEST_CASE("badinput: missing and truncated and too small images", "[badinput]") {
    TempDir dir;
    const wmlt::Image img = [] {
        wmlt::Image im(16, 8);
        for (int y = 0; y < 8; ++y)
            for (int x = 0; x < 16; ++x) im.set(x, y, wmlt::Vec3(0.1f * (x % 5), 0.2f, 0.05f * y));
        return im;
    }();
    wmlt::writeImage(dir.file("full.png"), img);
    wmlt::writeImage(dir.file("full.exr"), img);
    // A Radiance HDR, flat (width < 8: no run-length encoding): header and 16 x 8 RGBE pixels.
    std::string hdr = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 8 +X 4\n";
    for (int i = 0; i < 4 * 8; ++i) hdr += std::string("\x80\x40\x20\x81", 4);
    dir.write("full.hdr", hdr);
    REQUIRE(wmlt::readImage(dir.file("full.hdr")).width == 4);
    auto truncated = [&](const std::string& from, const std::string& to, double frac) {
        const std::string bytes = readFile(dir.file(from));
        REQUIRE(bytes.size() > 64);
        return dir.write(to, bytes.substr(0, size_t(double(bytes.size()) * frac)));
    };
    auto texture = [](const std::string& file) { return "<Texture Type=\"ImageFile\" ID=\"1\">\n<File name=\"" + file + "\"/></Texture>"; };
    auto envMap = [](const std::string& file) { return "<Settings>\n<EnvMap name=\"" + file + "\"/></Settings>"; };

    SECTION("missing texture") { requireBadScene("img.xml", scene(texture("nothere.png")), 5, dir.file("nothere.png"), dir, {"No such file"}); }
    SECTION("missing environment map") {
        requireBadScene("img.xml", scene(envMap("nothere.exr")), 5, dir.file("nothere.exr"), dir, {"No such file"});
    }
    for (double frac : {0.0, 0.3, 0.9}) {
        DYNAMIC_SECTION("truncated PNG texture at " << frac) {
            const std::string p = truncated("full.png", "cut.png", frac);
            requireBadScene("img.xml", scene(texture("cut.png")), 5, p, dir);
        }
        DYNAMIC_SECTION("truncated EXR environment map at " << frac) {
            const std::string p = truncated("full.exr", "cut.exr", frac);
            requireBadScene("img.xml", scene(envMap("cut.exr")), 5, p, dir);
        }
        DYNAMIC_SECTION("truncated HDR environment map at " << frac) {
            const std::string p = truncated("full.hdr", "cut.hdr", frac);
            requireBadScene("img.xml", scene(envMap("cut.hdr")), 5, p, dir);
        }
    }
    SECTION("environment map of 0 x 0") {
        dir.write("zero.pfm", "PF\n0 0\n-1.0\n");
        requireBadScene("img.xml", scene(envMap("zero.pfm")), 5, dir.file("zero.pfm"), dir, {"empty"});
    }
    SECTION("environment map of 1 x 1") {
        dir.write("one.pfm", pfm(1, 1, 1.0f));
        requireBadScene("img.xml", scene(envMap("one.pfm")), 5, dir.file("one.pfm") + ": an environment map of 1 x 1 pixels is too small", dir);
    }
    SECTION("environment map of 4 x 1") {
        dir.write("row.pfm", pfm(4, 1, 1.0f));
        requireBadScene("img.xml", scene(envMap("row.pfm")), 5, "4 x 1 pixels is too small", dir);
    }
    SECTION("environment map with a NaN or infinite pixel") {
        dir.write("nan.pfm", pfm(4, 2, std::numeric_limits<float>::quiet_NaN()));
        requireBadScene("img.xml", scene(envMap("nan.pfm")), 5, dir.file("nan.pfm") + ": pixel (0, 0) is NaN", dir);
        dir.write("inf.pfm", pfm(4, 2, std::numeric_limits<float>::infinity()));
        requireBadScene("img.xml", scene(texture("inf.pfm")), 5, "is infinite", dir);
    }
}

// ---- command line -----------------------------------------------------------------------------

TEST_CASE("badinput: command-line errors exit 2 before any work", "[badinput]") {
    TempDir dir;
    const std::string out = dir.file("out.pfm");
    auto cli = [&](std::vector<std::string> args) {
        args.insert(args.end(), {"--quiet", "--width", "16", "--height", "16", "--spp", "1", "-o", out});
        return run(args, dir);
    };
    SECTION("unknown option") { requireBad(cli({"--frobnicate"}), {"wavemmlt: unknown option '--frobnicate'"}, out, dir); }
    SECTION("a value missing") { requireBad(run({"--spp"}, dir), {"wavemmlt: --spp needs a value"}, out, dir); }
    SECTION("bad numbers") {
        requireBad(cli({"--threads", "two"}), {"--threads: 'two' is not a whole number"}, out, dir);
        requireBad(cli({"--max-length", "1.5"}), {"--max-length: '1.5' is not a whole number"}, out, dir);
        requireBad(cli({"--max-length", "65"}), {"--max-length: 65 is out of range [1, 64]"}, out, dir);
        requireBad(cli({"--time", "soon"}), {"--time: 'soon' is not a number"}, out, dir);
        requireBad(cli({"--time", "nan"}), {"--time: 'nan' is not a number"}, out, dir);
        requireBad(cli({"--exposure", "inf"}), {"--exposure: 'inf' is not a number"}, out, dir);
        requireBad(cli({"--seed", "-1"}), {"--seed: -1 is out of range"}, out, dir);
    }
    SECTION("--chains 0") { requireBad(cli({"--tracer", "mmlt", "--chains", "0"}), {"--chains: 0 is out of range"}, out, dir); }
    SECTION("--chains 1e12 is refused before allocating, with the memory it would need") {
        Proc p = cli({"--tracer", "mmlt", "--chains", "1e12"});
        INFO("--chains 1e12: " << p.err << p.seconds << " s, peak resident " << p.maxRssKb / 1024 << " MiB");
        requireBad(p,
                   {"wavemmlt: --chains 1000000000000 would need ", " TiB of chain state", "bytes per chain at MaxPathLength", "of this machine's",
                    "of memory"},
                   out, dir);
        CHECK(p.seconds < 2.0);
        CHECK(p.maxRssKb < 256 * 1024);
        // The exponent form of a whole number is accepted (and a fraction is not).
        requireBad(cli({"--tracer", "mmlt", "--chains", "1.5"}), {"--chains: '1.5' is not a whole number"}, out, dir);
        Proc ok = cli({"--tracer", "mmlt", "--chains", "1e3"});
        INFO(ok.err);
        CHECK(ok.status == 0);
        CHECK(fs::exists(out));
    }
    SECTION("output in a missing folder") {
        const std::string o = dir.file("missing/out.pfm");
        Proc p = run({"--quiet", "--width", "16", "--height", "16", "--spp", "4096", "-o", o}, dir);
        requireBad(p, {o + ": cannot write to folder '" + dir.file("missing") + "'"}, o, dir);
        CHECK(p.seconds < 2.0);  // refused before rendering
    }
    SECTION("output in a read-only folder") {
        fs::create_directories(dir.path / "ro");
        fs::permissions(dir.path / "ro", fs::perms::owner_read | fs::perms::owner_exec | fs::perms::group_read | fs::perms::group_exec |
                                             fs::perms::others_read | fs::perms::others_exec);
        const std::string o = dir.file("ro/out.pfm");
        Limits lim;
        lim.asNobody = geteuid() == 0;  // root writes anywhere: run as nobody instead
        Proc p = run({"--quiet", "--width", "16", "--height", "16", "--spp", "4096", "-o", o}, dir, lim);
        requireBad(p, {o + ": cannot write to folder '" + dir.file("ro") + "': Permission denied"}, o, dir);
        CHECK(p.seconds < 2.0);
    }
    SECTION("output whose folder is a file, output that is a folder") {
        dir.write("plain", "x");
        const std::string o = dir.file("plain/out.pfm");
        requireBad(run({"--quiet", "--spp", "4096", "-o", o}, dir), {o + ": cannot write to folder", "not a folder"}, o, dir);
        fs::create_directories(dir.path / "taken.pfm");
        Proc p = run({"--quiet", "--spp", "4096", "-o", dir.file("taken.pfm")}, dir);
        INFO(p.err);
        CHECK(p.status == 2);
        CHECK(contains(p.err, dir.file("taken.pfm") + ": cannot write the file: a folder of that name exists"));
        CHECK(p.seconds < 2.0);
    }
    SECTION("output with an unknown extension") {
        const std::string o = dir.file("out.tiff");
        requireBad(run({"--quiet", "-o", o}, dir), {o + ": unknown image format"}, o, dir);
    }
}
