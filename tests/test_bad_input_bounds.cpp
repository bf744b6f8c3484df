// Bad input, round two (issue 42), end to end through the `wavemmlt` binary, one test case per
// class: unbounded reading (gzip bombs, /dev/zero, FIFOs, a number bomb), finite numbers whose
// product is not, non-finite pixels in every importer's images, integers past their range,
// pbrt-v4's own strictness (escapes, unclosed blocks), messages that quote at most a little
// of a token, and good input that was refused (a Mitsuba cube as a medium's boundary). Each
// bad input: exit 2, one line naming the file and line, no output (bad_input_run.h); the
// reading classes also a bound on time and on peak resident memory. docs/reliability.md
// lists each class with its test.
#include <catch2/catch.hpp>

#include <sys/stat.h>
#include <zlib.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "bad_input_run.h"
#include "wavemmlt/image.h"

using namespace badinput;

namespace {

// Under AddressSanitizer (scripts/test.sh's second pass) the process's resident memory is
// the sanitizer's (shadow memory, quarantine), not the loaders': the memory bounds are
// checked in the release pass only.
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kMeasureMemory = false;
#else
constexpr bool kMeasureMemory = true;
#endif

// One gzip member holding `bytes`.
std::string gzipMember(const std::string& bytes) {
    z_stream z{};
    REQUIRE(deflateInit2(&z, 9, Z_DEFLATED, 15 + 16, 9, Z_DEFAULT_STRATEGY) == Z_OK);
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data()));
    z.avail_in = uInt(bytes.size());
    std::string out(deflateBound(&z, uLong(bytes.size())), '\0');
    z.next_out = reinterpret_cast<Bytef*>(out.data());
    z.avail_out = uInt(out.size());
    REQUIRE(deflate(&z, Z_FINISH) == Z_STREAM_END);
    out.resize(out.size() - z.avail_out);
    deflateEnd(&z);
    return out;
}

// A .gz of `head` followed by `count` MiB of `pattern` repeated: a gzip bomb of a few kB,
// written as one member per MiB (gzip allows many; each inflates to the same MiB).
std::string gzipBomb(const std::string& head, const std::string& pattern, int count) {
    std::string mib;
    while (mib.size() < (size_t(1) << 20)) mib += pattern;
    mib.resize(size_t(1) << 20);
    const std::string member = gzipMember(mib);
    std::string out = gzipMember(head);
    for (int i = 0; i < count; ++i) out += member;
    return out;
}

const std::string kPbrtHead = "WorldBegin\nLightSource \"point\"\n";  // a scene's lines 1-2

// Runs `wavemmlt scene` with a fast render's options and requires the bad-input behaviour.
Proc runBad(const TempDir& dir, const std::string& scene, const std::vector<std::string>& fragments, Limits lim = Limits()) {
    const std::string out = dir.file("out.exr");
    Proc p = run({scene, "--quiet", "--spp", "1", "--width", "8", "--height", "8", "-o", out}, dir, lim);
    INFO(p.seconds << " s, peak resident " << p.maxRssKb / 1024 << " MiB, stderr " << p.errBytes << " bytes");
    requireBad(p, fragments, out, dir);
    return p;
}

// A bad pbrt file (its text), the line its message names and a fragment of it.
struct Bad {
    const char* what;
    std::string body;
    int line;
    const char* fragment;
};
// Each case written as s.pbrt and run, a section of its own.
void requireEachBad(const TempDir& dir, const std::vector<Bad>& cases) {
    for (const Bad& b : cases) {
        DYNAMIC_SECTION(b.what) {
            const std::string s = dir.write("s.pbrt", b.body);
            runBad(dir, s, {s + ":" + std::to_string(b.line) + ": ", b.fragment});
        }
    }
}

}  // namespace

// ---- unbounded reading -------------------------------------------------------------------------

// Each of these read for ever or inflated a GiB before this issue (5.2 GB and 72 s for the
// first). Bounds: 2 s and 64 MiB resident (the process peaks near 15 MiB); the child is
// killed past 20 s or 1 GiB so that a reader that inflates everything cannot swamp the machine.
TEST_CASE("badinput bounds: gzip bombs, /dev/zero and FIFOs fail fast in bounded memory", "[badinput][bounds]") {
    TempDir dir;
    Limits lim;
    lim.seconds = 20;
    lim.rssKb = 1024 * 1024;
    auto check = [&](const Proc& p) {
        CHECK(p.seconds < 2.0);
        if (kMeasureMemory) CHECK(p.maxRssKb < 64 * 1024);
        CHECK(p.errBytes < 512);
    };
    SECTION("a .pbrt.gz that inflates to 1 GiB of NUL bytes") {
        const std::string s = dir.write("s.pbrt.gz", gzipBomb("", std::string(1, '\0'), 1024));
        CHECK(fs::file_size(s) < 2 << 20);
        check(runBad(dir, s, {s + ":1: a NUL byte (a binary file?)"}, lim));
    }
    SECTION("Include \"/dev/zero\"") {
        const std::string s = dir.write("s.pbrt", kPbrtHead + "Include \"/dev/zero\"\n");
        check(runBad(dir, s, {s + ":3: /dev/zero: the included file is not a regular file (a character device"}, lim));
    }
    SECTION("plymesh \"/dev/zero\"") {
        const std::string s = dir.write("s.pbrt", kPbrtHead + "Shape \"plymesh\" \"string filename\" \"/dev/zero\"\n");
        check(runBad(dir, s, {s + ":3: ", "/dev/zero: the PLY file is not a regular file"}, lim));
    }
    SECTION("an Include and an OBJ that are FIFOs (opening one waits for a writer)") {
        REQUIRE(mkfifo(dir.file("pipe.pbrt").c_str(), 0644) == 0);
        const std::string s = dir.write("s.pbrt", kPbrtHead + "Include \"pipe.pbrt\"\n");
        check(runBad(dir, s, {s + ":3: ", "pipe.pbrt: the included file is not a regular file (a FIFO"}, lim));
        REQUIRE(mkfifo(dir.file("m.obj").c_str(), 0644) == 0);
        const std::string m =
            dir.write("m.xml", "<scene version=\"3.0.0\">\n<shape type=\"obj\"><string name=\"filename\" value=\"m.obj\"/></shape>\n</scene>\n");
        check(runBad(dir, m, {m + ":2: ", "m.obj: the OBJ file is not a regular file (a FIFO"}, lim));
    }
    SECTION("a .ply.gz that inflates to 1 GiB of NUL bytes fails at its header") {
        dir.write("bomb.ply.gz", gzipBomb("", std::string(1, '\0'), 1024));
        const std::string s = dir.write("s.pbrt", kPbrtHead + "Shape \"plymesh\" \"string filename\" \"bomb.ply.gz\"\n");
        check(runBad(dir, s, {s + ":3: ", "bomb.ply.gz:1: not a PLY file"}, lim));
    }
    SECTION("a Mitsuba include of /dev/zero, and /dev/zero as the scene file") {
        const std::string m = dir.write("m.xml", "<scene version=\"3.0.0\">\n<include filename=\"/dev/zero\"/>\n</scene>\n");
        check(runBad(dir, m, {m + ":2: ", "/dev/zero: the included file is not a regular file"}, lim));
        check(runBad(dir, "/dev/zero", {"/dev/zero: the scene file is not a regular file"}, lim));
    }
}

// A .pbrt.gz of 8 MiB that inflates to 64 MiB of "0 " inside one point3 P array (and no ]):
// 32 Mi numbers. Each is kept as a double (8 bytes, 16 with the array's growth), as a good
// mesh of that size would be, not as a token (~60 bytes each: 2 GB before this issue, and a
// 1 GiB bomb was killed past 5 GiB). The array is refused at its end: no ] before the file ends.
TEST_CASE("badinput bounds: a bomb of numbers in one array costs what the numbers cost", "[badinput][bounds]") {
    TempDir dir;
    const int mib = kMeasureMemory ? 64 : 8;  // (under the sanitizers: the same path, smaller)
    const std::string s = dir.write("s.pbrt.gz", gzipBomb(kPbrtHead + "Shape \"trianglemesh\" \"point3 P\" [ ", "0 ", mib));
    Limits lim;
    lim.seconds = 120;
    lim.rssKb = 2 * 1024 * 1024;
    const Proc p = runBad(dir, s, {s + ":3: \"point3 P\": unterminated ["}, lim);
    const double numbers = double(mib) * (1 << 20) / 2;
    INFO(numbers << " numbers: " << p.maxRssKb * 1024.0 / numbers << " bytes each at the peak");
    if (kMeasureMemory) CHECK(p.maxRssKb * 1024.0 < 16 * numbers + 64.0 * (1 << 20));
}

// ---- finite numbers whose product is not ------------------------------------------------------

TEST_CASE("badinput bounds: finite parameters whose product overflows a float are refused", "[badinput][bounds]") {
    TempDir dir;
    const std::string sphere = "Shape \"sphere\"\n";
    const std::vector<Bad> cases = {
        {"point light", "WorldBegin\nLightSource \"point\" \"rgb I\" [1e38 1e38 1e38] \"float scale\" 1e38\n" + sphere, 2,
         "I times scale (1e+38 x 1e+38) is beyond a float's range"},
        {"spot light", "WorldBegin\nLightSource \"spot\" \"rgb I\" [1e38 1 1] \"float scale\" 1e38\n" + sphere, 2, "beyond a float's range"},
        {"distant light", "WorldBegin\nLightSource \"distant\" \"rgb L\" [1e38 1 1] \"float scale\" 1e38\n" + sphere, 2, "beyond a float's range"},
        {"infinite light", "WorldBegin\nLightSource \"infinite\" \"rgb L\" [1 1e38 1] \"float scale\" 1e38\n" + sphere, 2, "beyond a float's range"},
        {"area light",
         "WorldBegin\nAttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [1e38 1 1] \"float scale\" 1e38\n" + sphere + "AttributeEnd\n", 3,
         "L times scale (1e+38 x 1e+38) is beyond a float's range"},
        {"power 1e38 on a sphere of radius 1e-10",
         "WorldBegin\nAttributeBegin\nAreaLightSource \"diffuse\" \"float power\" 1e38\nShape \"sphere\" \"float radius\" 1e-10\nAttributeEnd\n" +
             sphere,
         3, "L (normalised to its power) times scale"},
        {"Scale 1e30 twice", "WorldBegin\nLightSource \"point\"\nScale 1e30 1e30 1e30\nScale 1e30 1e30 1e30\n" + sphere, 4,
         "Scale: the transform so far has an entry of 1e+60, beyond a float's range"},
        {"coordinates times the transform",
         "WorldBegin\nLightSource \"point\"\nScale 1e30 1e30 1e30\n"
         "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1e30 0 0 0 1e30 0] \"integer indices\" [0 1 2]\n",
         4, "its coordinates times the transform are beyond a float's range"},
        {"an imagemap's texels times its scale",
         kPbrtHead + "Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"ten.pfm\"\n  \"float scale\" 1e38\n", 3,
         "Texture \"t\": its values times its scale reach 1e+39, beyond a float's range"},
        {"a scale texture over an image",
         kPbrtHead + "Texture \"i\" \"spectrum\" \"imagemap\" \"string filename\" \"ten.pfm\"\n"
                     "Texture \"s\" \"spectrum\" \"scale\" \"texture tex\" \"i\" \"float scale\" 1e38\n",
         4, "Texture \"s\": its values times its scale reach 1e+39"},
        {"the film's iso times a light", "Film \"rgb\" \"float iso\" 1e30\nWorldBegin\nLightSource \"point\" \"rgb I\" [1e30 1 1]\n" + sphere, 1,
         "the film's imaging ratio"},
    };
    dir.write("ten.pfm", pfm(2, 2, 10.0f));
    requireEachBad(dir, cases);
    SECTION("Mitsuba: an envmap's pixels times scale") {
        dir.write("big.pfm", pfm(4, 3, 1e38f));
        const std::string m = dir.write("m.xml",
                                        "<scene version=\"3.0.0\">\n<emitter type=\"envmap\"><string name=\"filename\" value=\"big.pfm\"/>"
                                        "<float name=\"scale\" value=\"1e38\"/></emitter>\n<shape type=\"sphere\"/>\n</scene>\n");
        runBad(dir, m, {m + ":2: ", "big.pfm: its pixels times scale (1e+38) are beyond a float's range"});
    }
}

// ---- non-finite pixels -------------------------------------------------------------------------

TEST_CASE("badinput bounds: images with NaN or infinite pixels are refused by every importer", "[badinput][bounds]") {
    TempDir dir;
    dir.write("nan.pfm", pfm(2, 2, std::nanf("")));
    dir.write("inf.pfm", pfm(2, 2, INFINITY));
    const std::string tri = "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"point2 uv\" [0 0 1 0 0 1] \"integer indices\" [0 1 2]\n";
    const std::vector<Bad> cases = {
        {"pbrt imagemap", kPbrtHead + "Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"nan.pfm\"\n" + tri, 3,
         "nan.pfm: pixel (0, 0) is NaN"},
        {"pbrt infinite light's map", "WorldBegin\nLightSource \"infinite\" \"string filename\" \"inf.pfm\"\n" + tri, 2,
         "inf.pfm: pixel (0, 0) is infinite"},
        {"pbrt area light's image", "WorldBegin\nAreaLightSource \"diffuse\" \"string filename\" \"nan.pfm\"\n" + tri, 2,
         "nan.pfm: pixel (0, 0) is NaN"},
    };
    requireEachBad(dir, cases);
    SECTION("Mitsuba bitmap and envmap") {
        const std::string bitmap = dir.write(
            "m.xml",
            "<scene version=\"3.0.0\">\n<emitter type=\"constant\"/>\n<shape type=\"sphere\"><bsdf type=\"diffuse\">\n"
            "<texture type=\"bitmap\" name=\"reflectance\"><string name=\"filename\" value=\"nan.pfm\"/></texture></bsdf></shape>\n</scene>\n");
        runBad(dir, bitmap, {bitmap + ":4: ", "nan.pfm: pixel (0, 0) is NaN"});
        dir.write("inf43.pfm", pfm(4, 3, INFINITY));
        const std::string env =
            dir.write("e.xml",
                      "<scene version=\"3.0.0\">\n<emitter type=\"envmap\"><string name=\"filename\" value=\"inf43.pfm\"/></emitter>\n"
                      "<shape type=\"sphere\"/>\n</scene>\n");
        runBad(dir, env, {env + ":2: ", "inf43.pfm: pixel (0, 0) is infinite"});
    }
}

// ---- integers ----------------------------------------------------------------------------------

TEST_CASE("badinput bounds: counts from a file are range-checked in a wide type, with their line", "[badinput][bounds]") {
    TempDir dir;
    const std::string world = "WorldBegin\nLightSource \"point\"\nShape \"sphere\"\n";
    SECTION("pixelsamples 2147483647") {
        const std::string s = dir.write("s.pbrt", "Sampler \"halton\" \"integer pixelsamples\" 2147483647\n" + world);
        runBad(dir, s, {s + ":1: \"integer pixelsamples\": 2147483647 is out of range [1, 16777216]"});
    }
    SECTION("mutationsperpixel 2147483647") {
        const std::string s = dir.write("s.pbrt", "Integrator \"mlt\"\n  \"integer mutationsperpixel\" 2147483647\n" + world);
        runBad(dir, s, {s + ":2: \"integer mutationsperpixel\": 2147483647 is out of range [1, 16777216]"});
    }
    SECTION("Mitsuba sample_count 2147483647") {
        const std::string m =
            dir.write("m.xml",
                      "<scene version=\"3.0.0\">\n<sensor type=\"perspective\">\n<sampler type=\"independent\"><integer name=\"sample_count\" "
                      "value=\"2147483647\"/></sampler></sensor>\n<emitter type=\"constant\"/><shape type=\"sphere\"/>\n</scene>\n");
        runBad(dir, m, {m + ":3: ", "sample_count 2147483647 is out of range [1, 16777216]"});
    }
    SECTION("maxdepth 2147483647 renders at wavemmlt's longest path, with a warning naming its line") {
        const std::string s = dir.write("s.pbrt", "Integrator \"path\"\n  \"integer maxdepth\" 2147483647\n" + world);
        const std::string out = dir.file("out.exr");
        const Proc p = run({s, "--spp", "1", "--width", "8", "--height", "8", "-o", out}, dir);
        INFO(p.err);
        CHECK(p.status == 0);
        CHECK(contains(p.err, s + ":2: maxdepth above 63 becomes 63"));
        CHECK(fs::exists(out));
    }
}

// ---- pbrt-v4's strictness ----------------------------------------------------------------------

TEST_CASE("badinput bounds: what pbrt-v4 refuses, wavemmlt refuses", "[badinput][bounds][pbrt]") {
    TempDir dir;
    const std::vector<Bad> cases = {
        {"an unknown escape", kPbrtHead + "Shape \"sphere\"\nMaterial \"diff\\use\"\n", 4, "unexpected escaped character \"\\u\""},
        {"AttributeBegin without AttributeEnd", kPbrtHead + "AttributeBegin\nShape \"sphere\"\n", 3,
         "AttributeBegin without AttributeEnd (the file ends inside it)"},
        {"ObjectBegin without ObjectEnd", kPbrtHead + "Shape \"sphere\"\nObjectBegin \"o\"\nShape \"sphere\"\n", 4,
         "ObjectBegin without ObjectEnd (the file ends inside it)"},
        {"AttributeEnd closing an ObjectBegin", kPbrtHead + "Shape \"sphere\"\nAttributeBegin\nObjectBegin \"o\"\nAttributeEnd\n", 6,
         "AttributeEnd closes the ObjectBegin of line 5 (mismatched nesting)"},
        {"TransformEnd closing an AttributeBegin", kPbrtHead + "Shape \"sphere\"\nAttributeBegin\nTransformEnd\n", 5,
         "TransformEnd closes the AttributeBegin of line 4 (mismatched nesting)"},
    };
    requireEachBad(dir, cases);
    SECTION("every escape pbrt-v4 takes is read") {
        const std::string s = dir.write("s.pbrt", kPbrtHead +
                                                      "MakeNamedMaterial \"a\\\"b\\\\c\\'d\\te\\bf\\fg\\rh\\ni\" \"string type\" \"diffuse\"\n"
                                                      "NamedMaterial \"a\\\"b\\\\c'd\\te\\bf\\fg\\rh\\ni\"\nShape \"sphere\"\n");
        const Proc p = run({s, "--quiet", "--spp", "1", "--width", "8", "--height", "8", "-o", dir.file("out.exr")}, dir);
        INFO(p.err);
        CHECK(p.status == 0);
    }
}

// ---- messages ----------------------------------------------------------------------------------

TEST_CASE("badinput bounds: messages quote at most a little of a token and name bad bytes", "[badinput][bounds]") {
    TempDir dir;
    SECTION("a 10 MB bare token") {
        const std::string s = dir.write("s.pbrt", kPbrtHead + "Shape \"sphere\"\n" + std::string(10 << 20, 'a') + "\n");
        const Proc p = runBad(dir, s, {s + ":4: a token longer than 4096 bytes, starting \"aaaa"});
        CHECK(p.errBytes < 512);
    }
    SECTION("a 10 MB quoted string") {
        const std::string s = dir.write("s.pbrt", kPbrtHead + "Shape \"sphere\"\nMaterial \"" + std::string(10 << 20, 'b') + "\"\n");
        const Proc p = runBad(dir, s, {s + ":4: a string longer than 4096 bytes"});
        CHECK(p.errBytes < 512);
    }
    SECTION("a NUL byte inside a directive") {
        const std::string s = dir.write("s.pbrt", kPbrtHead + "Shape \"sphere\"\nSha" + std::string(1, '\0') + "pe \"sphere\"\n");
        runBad(dir, s, {s + ":4: a NUL byte (a binary file?) after \"Sha\""});
    }
    SECTION("invalid UTF-8 and control bytes are shown as \\xNN") {
        const std::string s = dir.write("s.pbrt", kPbrtHead + "Shape \"sphere\"\nFr\xC3(bnicate \"a\"\n");
        const Proc p = runBad(dir, s, {s + ":4: unknown directive \"Fr\\xC3(bnicate\""});
        CHECK_FALSE(contains(p.err, "\xC3"));
        const std::string t = dir.write("t.pbrt", kPbrtHead +
                                                      "Shape \"sphere\"\nAb\x01"
                                                      "cd\n");
        runBad(dir, t, {t + ":4: a control byte 0x01 (a binary file?) after \"Ab\""});
    }
    SECTION("a 5000-byte unknown directive under the limit is quoted to 60 characters") {
        const std::string s = dir.write("s.pbrt", kPbrtHead + std::string(4000, 'z') + "\n");
        const Proc p = runBad(dir, s, {s + ":3: unknown directive \"" + std::string(60, 'z') + "...\" (4000 bytes)"});
        CHECK(p.errBytes < 256);
    }
}

// ---- good input that was refused ---------------------------------------------------------------

// Mitsuba's cube has 24 vertices (4 per face, for its flat normals): its closedness is
// found on positions, not indices, so it bounds a medium (it was "an open mesh").
TEST_CASE("badinput bounds: a Mitsuba cube with a null BSDF bounds an interior medium", "[badinput][bounds][media]") {
    TempDir dir;
    const std::string m =
        dir.write("cube.xml",
                  "<scene version=\"3.0.0\">\n"
                  "<sensor type=\"perspective\"><float name=\"fov\" value=\"40\"/><transform name=\"to_world\"><lookat origin=\"0,0,5\" "
                  "target=\"0,0,0\" up=\"0,1,0\"/></transform><film type=\"hdrfilm\"><integer name=\"width\" value=\"8\"/><integer "
                  "name=\"height\" value=\"8\"/></film></sensor>\n"
                  "<medium type=\"homogeneous\" id=\"fog\"><rgb name=\"albedo\" value=\"0.8\"/><float name=\"sigma_t\" value=\"1\"/></medium>\n"
                  "<shape type=\"cube\"><bsdf type=\"null\"/><ref name=\"interior\" id=\"fog\"/></shape>\n"
                  "<emitter type=\"constant\"><rgb name=\"radiance\" value=\"1\"/></emitter>\n"
                  "</scene>\n");
    const std::string out = dir.file("out.pfm");
    const Proc p = run({m, "--quiet", "--spp", "64", "-o", out}, dir);
    INFO(p.err);
    REQUIRE(p.status == 0);
    const wmlt::Image img = wmlt::readImage(out);
    // The centre looks through the fog (albedo 0.8 under a sky of 1: 0.66 at 1024 samples per
    // pixel, darker than the sky); a corner sees the sky past the cube (1, to the pixel
    // filter's weights over its neighbours, one of which sees the cube's edge).
    const wmlt::Vec3 centre = img.at(4, 4), corner = img.at(0, 0);
    CHECK(std::isfinite(centre.x));
    CHECK(centre.x < 0.99f);
    CHECK(corner.x == Approx(1.0f).margin(0.01));
}
