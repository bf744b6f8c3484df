// The `wavemmlt` command line, run as a separate process: determinism across thread
// counts, exit status 2 with "file:line" messages on bad input (and no output file),
// early checks before rendering, --describe/--help/--version, the --stats JSON, time
// budgets, and the built-in scene (Ctrl-C for every tracer: test_extremes.cpp).
#include <catch2/catch.hpp>

#include "render_stats.h"

#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "app/cli.h"
#include "wavemmlt/image.h"

namespace fs = std::filesystem;

namespace {

const std::string kBin = WAVEMMLT_BIN;
const std::string kData = WAVEMMLT_TEST_DATA;
const std::string kSmall = " --width 64 --height 48 --quiet";

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

struct TempDir {
    fs::path path;
    TempDir() {
        static int count = 0;
        path = fs::temp_directory_path() / ("wmlt-cli-test-" + std::to_string(getpid()) + "-" + std::to_string(count++));
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
    std::string file(const std::string& name) const { return (path / name).string(); }
    std::string write(const std::string& name, const std::string& text) const {
        std::ofstream(path / name, std::ios::binary) << text;
        return file(name);
    }
};

std::string readFile(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}

std::string quote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

struct Run {
    int status = -1;  // exit status, or -1 when killed by a signal
    std::string out, err;
    double seconds = 0;
};

// Runs `wavemmlt <args>` through the shell, capturing stdout and stderr in files.
Run run(const std::string& args, const TempDir& dir) {
    const std::string out = dir.file("stdout.txt"), err = dir.file("stderr.txt");
    const std::string cmd = quote(kBin) + " " + args + " > " + quote(out) + " 2> " + quote(err);
    auto t0 = Clock::now();
    int st = std::system(cmd.c_str());
    Run r;
    r.seconds = secondsSince(t0);
    r.status = (st != -1 && WIFEXITED(st)) ? WEXITSTATUS(st) : -1;
    r.out = readFile(out);
    r.err = readFile(err);
    return r;
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// A minimal strict JSON checker (RFC 8259 grammar; no semantic checks) that also
// collects the keys of the top-level object.
struct JsonChecker {
    const std::string& s;
    size_t i = 0;
    int depth = 0;
    std::set<std::string> topKeys;
    explicit JsonChecker(const std::string& text) : s(text) {}
    void ws() {
        while (i < s.size() && (s[i] == ' ' || s[i] == '\n' || s[i] == '\r' || s[i] == '\t')) ++i;
    }
    bool lit(const char* w) {
        size_t n = std::string(w).size();
        if (s.compare(i, n, w) != 0) return false;
        i += n;
        return true;
    }
    bool str(std::string* outStr = nullptr) {
        if (i >= s.size() || s[i] != '"') return false;
        ++i;
        std::string v;
        while (i < s.size() && s[i] != '"') {
            if (static_cast<unsigned char>(s[i]) < 0x20) return false;
            if (s[i] == '\\') {
                ++i;
                if (i >= s.size() || !contains("\"\\/bfnrtu", std::string(1, s[i]))) return false;
            }
            v += s[i++];
        }
        if (i >= s.size()) return false;
        ++i;
        if (outStr) *outStr = v;
        return true;
    }
    bool num() {
        size_t j = i;
        if (i < s.size() && s[i] == '-') ++i;
        if (i >= s.size() || !isdigit(static_cast<unsigned char>(s[i]))) return false;
        if (s[i] == '0') ++i;
        else
            while (i < s.size() && isdigit(static_cast<unsigned char>(s[i]))) ++i;
        if (i < s.size() && s[i] == '.') {
            ++i;
            if (i >= s.size() || !isdigit(static_cast<unsigned char>(s[i]))) return false;
            while (i < s.size() && isdigit(static_cast<unsigned char>(s[i]))) ++i;
        }
        if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
            ++i;
            if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
            if (i >= s.size() || !isdigit(static_cast<unsigned char>(s[i]))) return false;
            while (i < s.size() && isdigit(static_cast<unsigned char>(s[i]))) ++i;
        }
        return i > j;
    }
    bool value() {
        ws();
        if (i >= s.size()) return false;
        bool ok;
        if (s[i] == '{') ok = object();
        else if (s[i] == '[') ok = array();
        else if (s[i] == '"') ok = str();
        else if (s[i] == 't') ok = lit("true");
        else if (s[i] == 'f') ok = lit("false");
        else if (s[i] == 'n') ok = lit("null");
        else ok = num();
        ws();
        return ok;
    }
    bool object() {
        ++i;
        ++depth;
        ws();
        if (i < s.size() && s[i] == '}') {
            ++i;
            --depth;
            return true;
        }
        while (true) {
            ws();
            std::string key;
            if (!str(&key)) return false;
            if (depth == 1) topKeys.insert(key);
            ws();
            if (i >= s.size() || s[i] != ':') return false;
            ++i;
            if (!value()) return false;
            if (i < s.size() && s[i] == ',') {
                ++i;
                continue;
            }
            if (i < s.size() && s[i] == '}') {
                ++i;
                --depth;
                return true;
            }
            return false;
        }
    }
    bool array() {
        ++i;
        ws();
        if (i < s.size() && s[i] == ']') {
            ++i;
            return true;
        }
        while (true) {
            if (!value()) return false;
            if (i < s.size() && s[i] == ',') {
                ++i;
                continue;
            }
            if (i < s.size() && s[i] == ']') {
                ++i;
                return true;
            }
            return false;
        }
    }
    bool document() {
        ws();
        if (i >= s.size() || s[i] != '{') return false;
        if (!value()) return false;
        return i == s.size();
    }
};

// Lines 1-3 of every small scene; a body starts on line 4.
const std::string kHead =
    "<Scene>\n"
    "<Camera Type=\"Camera\"><Position x=\"0\" y=\"0\" z=\"-5\"/><LookAt x=\"0\" y=\"0\" z=\"0\"/><FOV value=\"45\"/></Camera>\n"
    "<Shader Type=\"Matte\" ID=\"0\"><Diffuse r=\"0.5\" g=\"0.5\" b=\"0.5\"/></Shader>\n";
const std::string kLight =
    "<Light Type=\"Area\" ID=\"l\"><Position x=\"0\" y=\"3\" z=\"0\"/><Radius value=\"0.5\"/>"
    "<Intensity value=\"5\"/><Colour r=\"1\" g=\"1\" b=\"1\"/></Light>\n";

// Bad input: exit 2, "error: <file>:<line>: ..." naming `fragment`, no output file.
void requireBadScene(const std::string& name, const std::string& body, int line, const std::string& fragment) {
    TempDir dir;
    std::string scene = dir.write(name, kHead + body + "\n" + kLight + "</Scene>\n");
    std::string out = dir.file("out.pfm");
    Run r = run(quote(scene) + kSmall + " -o " + quote(out), dir);
    INFO("stderr: " << r.err);
    CHECK(r.status == 2);
    CHECK(contains(r.err, "error: "));
    CHECK(contains(r.err, name + ":" + std::to_string(line) + ":"));
    CHECK(contains(r.err, fragment));
    CHECK_FALSE(fs::exists(out));
}

bool allFinite(const wmlt::Image& im) {
    for (float v : im.rgb)
        if (!std::isfinite(v)) return false;
    return true;
}
double meanValue(const wmlt::Image& im) {
    double s = 0;
    for (float v : im.rgb) s += v;
    return im.rgb.empty() ? 0 : s / im.rgb.size();
}

}  // namespace

TEST_CASE("cli: the same seed gives byte-identical images with 1 and 2 threads", "[cli]") {
    TempDir dir;
    for (const std::string& scene : {std::string(), quote(kData + "/scenes/bitterli-cornell/bitterli-cornell-256.xml")}) {
        std::string a = dir.file("t1.pfm"), b = dir.file("t2.pfm");
        Run r1 = run(scene + kSmall + " --spp 16 --seed 7 --threads 1 -o " + quote(a), dir);
        Run r2 = run(scene + kSmall + " --spp 16 --seed 7 --threads 2 -o " + quote(b), dir);
        INFO("scene " << (scene.empty() ? "built-in" : scene) << "; stderr: " << r1.err << r2.err);
        REQUIRE(r1.status == 0);
        REQUIRE(r2.status == 0);
        std::string da = readFile(a), db = readFile(b);
        REQUIRE(da.size() > 64 * 48 * 12);
        CHECK(da == db);
        // A different seed gives a different image (the seed is used).
        std::string c = dir.file("t3.pfm");
        REQUIRE(run(scene + kSmall + " --spp 16 --seed 8 --threads 2 -o " + quote(c), dir).status == 0);
        CHECK(readFile(c) != da);
    }
}

TEST_CASE("cli: bad scenes exit 2 naming file and line, and write nothing", "[cli]") {
    SECTION("unknown element") { requireBadScene("unknown.xml", "<Frobnicate value=\"1\"/>", 4, "Frobnicate"); }
    SECTION("dangling Shader ID") {
        requireBadScene("dangling.xml", "<Geometry Type=\"Sphere\" ID=\"s\"><Radius value=\"1\"/><Shader value=\"7\"/></Geometry>", 4, "7");
    }
    SECTION("missing OBJ") {
        requireBadScene("missingobj.xml",
                        "<Geometry Type=\"ObjFile\" ID=\"m\"><File name=\"nothere.obj\"/><SmoothShading value=\"0\"/>"
                        "<Shader value=\"0\"/></Geometry>",
                        4, "nothere.obj");
    }
    SECTION("missing scene file") {
        TempDir dir;
        std::string out = dir.file("out.pfm");
        Run r = run(quote(dir.file("no-such-scene.xml")) + kSmall + " -o " + quote(out), dir);
        INFO("stderr: " << r.err);
        CHECK(r.status == 2);
        CHECK(contains(r.err, "error: "));
        CHECK(contains(r.err, "no-such-scene.xml"));
        CHECK_FALSE(fs::exists(out));
    }
}

TEST_CASE("cli: an output in a missing folder exits 2 before rendering", "[cli]") {
    TempDir dir;
    std::string out = dir.file("missing-folder/out.pfm");
    // 4096 spp would take far longer than the bound below if rendering started.
    Run r = run(kSmall + " --spp 4096 -o " + quote(out), dir);
    INFO("stderr: " << r.err);
    CHECK(r.status == 2);
    CHECK(contains(r.err, "missing-folder"));
    CHECK(r.seconds < 5.0);
    CHECK_FALSE(fs::exists(out));
    // The same for a --stats file.
    std::string img = dir.file("ok.pfm");
    Run s = run(kSmall + " --spp 4096 -o " + quote(img) + " --stats " + quote(dir.file("nope/stats.json")), dir);
    INFO("stderr: " << s.err);
    CHECK(s.status == 2);
    CHECK(contains(s.err, "nope"));
    CHECK(s.seconds < 5.0);
    CHECK_FALSE(fs::exists(img));
}

TEST_CASE("cli: bad options exit 2", "[cli]") {
    TempDir dir;
    std::string out = dir.file("out.pfm");
    Run a = run("--no-such-option" + kSmall + " -o " + quote(out), dir);
    CHECK(a.status == 2);
    CHECK(contains(a.err, "--no-such-option"));
    Run b = run("--spp abc" + kSmall + " -o " + quote(out), dir);
    CHECK(b.status == 2);
    CHECK(contains(b.err, "--spp"));
    CHECK(contains(b.err, "abc"));
    Run c = run("--spp", dir);  // a missing value
    CHECK(c.status == 2);
    Run d = run("--tracer mmlt --chains 0" + kSmall + " -o " + quote(out), dir);
    INFO("stderr: " << d.err);
    CHECK(d.status == 2);
    CHECK(contains(d.err, "--chains"));
    Run e = run("--p-large 0" + kSmall + " -o " + quote(out), dir);
    CHECK(e.status == 2);
    CHECK(contains(e.err, "--p-large"));
    Run f = run("--tracer pt --strategy-images " + quote(dir.file("s")) + kSmall + " -o " + quote(out), dir);
    CHECK(f.status == 2);
    CHECK(contains(f.err, "--strategy-images"));
    for (const char* bad : {"--mmlt-target brightest", "--mmlt-steps wild", "--mmlt-film-steps on"}) {
        Run g = run(std::string(bad) + kSmall + " -o " + quote(out), dir);
        INFO(bad << ": " << g.err);
        CHECK(g.status == 2);
        CHECK(contains(g.err, std::string(bad).substr(0, std::string(bad).find(' '))));
    }
    CHECK_FALSE(fs::exists(out));
}

// --orbit-rate DEGREES (the interactive orbit, degrees per window width): a positive finite
// number; anything else exits 2 naming the option, before any render.
TEST_CASE("cli: --orbit-rate", "[cli]") {
    auto parse = [](std::vector<std::string> words) {
        words.insert(words.begin(), "wavemmlt");
        std::vector<char*> argv;
        for (std::string& w : words) argv.push_back(w.data());
        return wmlt::parseCommandLine(int(argv.size()), argv.data());
    };
    CHECK(parse({}).orbitRate == 60.0f);
    CHECK(parse({"--orbit-rate", "90"}).orbitRate == 90.0f);
    CHECK(parse({"--orbit-rate", "0.5"}).orbitRate == 0.5f);
    TempDir dir;
    std::string out = dir.file("out.pfm");
    for (const char* bad : {"0", "-30", "abc", "nan", "inf", "1e40", "1e-50", "90deg"}) {
        Run r = run(std::string("--orbit-rate ") + bad + kSmall + " -o " + quote(out), dir);
        INFO(bad << ": " << r.err);
        CHECK(r.status == 2);
        CHECK(contains(r.err, "--orbit-rate"));
        CHECK(contains(r.err, bad));
        CHECK(r.seconds < 5.0);
    }
    Run m = run("--orbit-rate", dir);  // a missing value
    CHECK(m.status == 2);
    CHECK(contains(m.err, "--orbit-rate needs a value"));
    CHECK_FALSE(fs::exists(out));
    // Accepted without a window (the i key in --view may start the interactive mode).
    Run ok = run("--orbit-rate 120 --spp 1" + kSmall + " -o " + quote(out), dir);
    INFO(ok.err);
    CHECK(ok.status == 0);
    CHECK(fs::exists(out));
    CHECK(contains(run("--help", dir).out, "--orbit-rate DEGREES"));
}

TEST_CASE("CLI: --filter", "[cli][filter]") {
    TempDir dir;
    std::string out = dir.file("out.pfm");
    // The built-in scene is in the thesis' format: the box unless told otherwise.
    Run box = run("--describe", dir);
    CHECK(contains(box.out, "pixel filter: box (radius 0.5)\n"));
    Run g = run("--describe --filter gaussian:stddev=0.4", dir);
    INFO("stdout: " << g.out << "\nstderr: " << g.err);
    CHECK(g.status == 0);
    CHECK(contains(g.out, "pixel filter: gaussian (radius 1.6, stddev 0.4)\n"));
    Run m = run("--describe --filter mitchell:B=0.2,C=0.4,radius=3", dir);
    CHECK(contains(m.out, "pixel filter: mitchell (radius 3, B 0.2, C 0.4)\n"));
    for (const auto& [arg, message] : std::vector<std::pair<std::string, std::string>>{
             {"sinc", "--filter: 'sinc' is not one of box, tent, gaussian, mitchell, catmullrom, lanczos"},
             {"tent:radius=0", "--filter: tent: radius must be > 0 and at most 16 pixels"},
             {"tent:stddev=1", "--filter: tent: stddev applies to gaussian only"},
             {"gaussian:stddev", "--filter: 'stddev' is not param=value"},
             {"gaussian:stddev=x", "--filter stddev: 'x' is not a number"}}) {
        Run r = run("--filter " + quote(arg) + kSmall + " -o " + quote(out), dir);
        INFO(arg << ": " << r.err);
        CHECK(r.status == 2);
        CHECK(contains(r.err, message));
    }
    CHECK_FALSE(fs::exists(out));
    // A render through a wide filter writes its image.
    Run ok = run("--filter lanczos --spp 4 --tracer bpt" + kSmall + " -o " + quote(out), dir);
    INFO(ok.err);
    CHECK(ok.status == 0);
    CHECK(fs::exists(out));
}

TEST_CASE("cli: --describe, --help and --version exit 0", "[cli]") {
    TempDir dir;
    std::string out = dir.file("out.pfm");
    Run d = run("--describe -o " + quote(out), dir);
    INFO("stdout: " << d.out << "\nstderr: " << d.err);
    CHECK(d.status == 0);
    CHECK(contains(d.out, "materials:"));
    CHECK(contains(d.out, "lights:"));
    CHECK_FALSE(fs::exists(out));  // describes, does not render
    // The Cornell box uses matte only and one rectangle light.
    Run c = run("--describe " + quote(kData + "/scenes/bitterli-cornell/bitterli-cornell-256.xml"), dir);
    INFO("cornell: " << c.out);
    CHECK(c.status == 0);
    CHECK(contains(c.out, "materials: matte\n"));
    CHECK(contains(c.out, "lights: rect\n"));
    Run h = run("--help", dir);
    CHECK(h.status == 0);
    CHECK(contains(h.out, "usage"));
    Run v = run("--version", dir);
    CHECK(v.status == 0);
    CHECK(contains(v.out, "wavemmlt"));
}

TEST_CASE("cli: --stats writes JSON with the documented keys", "[cli]") {
    TempDir dir;
    std::string stats = dir.file("stats.json"), out = dir.file("out.pfm");
    Run r = run(kSmall + " --spp 4 --threads 2 -o " + quote(out) + " --stats " + quote(stats), dir);
    INFO("stderr: " << r.err);
    REQUIRE(r.status == 0);
    std::string text = readFile(stats);
    INFO("stats: " << text);
    JsonChecker j(text);
    REQUIRE(j.document());
    for (const char* key : {"tracer", "seconds", "threads", "spp", "rays_intersect", "rays_occluded", "mrays_per_second",
                            "samples_nonfinite_discarded", "scene_features"})
        CHECK(j.topKeys.count(key) == 1);
    CHECK(contains(text, "\"tracer\": \"mmlt\""));  // the built-in scene's tracer
    CHECK(contains(text, "\"threads\": 2"));
    CHECK(contains(text, "\"spp\": 4"));
    for (const char* key : {"mmlt_b", "mmlt_chains", "mmlt_acceptance_small", "mmlt_acceptance_large", "mmlt_acceptance", "mmlt_mutations",
                            "mmlt_mutations_per_second", "mmlt_replay_mismatches", "mmlt_chain_state_bytes"})
        CHECK(j.topKeys.count(key) == 1);
    CHECK(contains(text, "\"mmlt_replay_mismatches\": 0"));
    CHECK(contains(text, "\"mmlt_target\": \"luminance\""));
    CHECK(contains(text, "\"mis_beta\": 1"));  // MMLT's own: the balance heuristic
    // The levers (docs/mmlt-levers.md): what they learned.
    Run l = run(kSmall + " --spp 64 --threads 2 --mmlt-target relative --mmlt-steps learned --mmlt-film-steps always --mis-beta 2 -o " + quote(out) +
                    " --stats " + quote(stats),
                dir);
    INFO("stderr: " << l.err);
    REQUIRE(l.status == 0);
    const std::string learned = readFile(stats);
    JsonChecker jl(learned);
    REQUIRE(jl.document());
    for (const char* key : {"mmlt_target", "mmlt_target_maps", "mmlt_target_tile_size", "mmlt_target_scale", "mmlt_small_step_sigma",
                            "mmlt_film_step_share", "mmlt_film_steps_proposed", "mmlt_acceptance_film"})
        CHECK(jl.topKeys.count(key) == 1);
    CHECK(contains(learned, "\"mmlt_target\": \"relative\""));
    CHECK(contains(learned, "\"mmlt_film_steps\": \"always\""));
    CHECK(contains(learned, "\"mis_beta\": 2"));
    CHECK(contains(text, "\"mmlt_film_steps\": \"learned\""));
}

TEST_CASE("cli: --spectral renders every tracer spectrally and says so, pbrt files are spectral by default", "[cli][spectral]") {
    TempDir dir;
    const std::string out = dir.file("out.pfm"), stats = dir.file("stats.json");
    for (const char* tracer : {"pt", "lt", "bpt", "mmlt", "pssmlt"}) {
        const Run r = run(
            std::string("--tracer ") + tracer + " --spp 4 --threads 2 --spectral" + kSmall + " -o " + quote(out) + " --stats " + quote(stats), dir);
        INFO(tracer << " stderr: " << r.err);
        REQUIRE(r.status == 0);
        CHECK(r.err.find("warning") == std::string::npos);
        const std::string text = readFile(stats);
        CHECK(contains(text, "\"spectral\": true"));
        CHECK(contains(text, "\"spectral_reason\": \"\""));
    }
    // a Mitsuba principled BSDF renders spectrally, and so does an RGB file's blendbsdf with
    // --spectral (one part per hit: docs/spectral.md)
    const std::string principled = quote(dir.write("principled.xml", R"(<scene version="3.0.0">
  <sensor type="perspective"><transform name="to_world"><lookat origin="0, 0, -5" target="0, 0, 0" up="0, 1, 0"/></transform></sensor>
  <emitter type="point"><point name="position" x="0" y="0" z="-4"/><spectrum name="intensity" value="400:10, 700:10"/></emitter>
  <shape type="sphere"><bsdf type="principled"/></shape>
</scene>)"));
    const std::string blend = quote(dir.write("blend.xml", R"(<scene version="3.0.0">
  <sensor type="perspective"><transform name="to_world"><lookat origin="0, 0, -5" target="0, 0, 0" up="0, 1, 0"/></transform></sensor>
  <emitter type="point"><point name="position" x="0" y="0" z="-4"/><rgb name="intensity" value="10, 8, 6"/></emitter>
  <shape type="sphere"><bsdf type="blendbsdf"><bsdf type="diffuse"/><bsdf type="conductor"/></bsdf></shape>
</scene>)"));
    Run r;
    std::string text;
    for (const std::string& f : {principled, blend}) {
        r = run(f + " --tracer bpt --spp 1 --threads 2 --spectral --width 32 --height 32 -o " + quote(out) + " --stats " + quote(stats), dir);
        INFO(f << " stderr: " << r.err);
        REQUIRE(r.status == 0);
        CHECK(r.err.find("warning") == std::string::npos);
        text = readFile(stats);
        CHECK(contains(text, "\"spectral\": true"));
        CHECK(contains(text, "\"spectral_reason\": \"\""));
    }
    // the coated gold killeroo (a coated conductor) and a fog box (a homogeneous medium) render spectrally
    const std::string coated = quote(kData + "/scenes/pbrt-v4/killeroos/killeroo-coated-gold.pbrt");
    const std::string fog = quote(kData + "/scenes/pbrt-v4/cornell-box/cornell-box-volume.pbrt");
    for (const std::string& f : {coated, fog + " --tracer bpt"}) {
        r = run(f + " --spp 1 --threads 2 --width 32 --height 32 -o " + quote(out) + " --stats " + quote(stats), dir);
        INFO(f << " stderr: " << r.err);
        REQUIRE(r.status == 0);
        CHECK(contains(readFile(stats), "\"spectral\": true"));
    }
    // --rgb (the default) after --spectral: the last one wins
    r = run("--tracer pt --spp 4 --threads 2 --spectral --rgb" + kSmall + " -o " + quote(out) + " --stats " + quote(stats), dir);
    REQUIRE(r.status == 0);
    text = readFile(stats);
    CHECK(contains(text, "\"spectral\": false"));
    CHECK(contains(text, "\"spectral_reason\": \"\""));
    // pbrt-v4 files render spectrally by default, as pbrt does; --rgb renders them in RGB; a
    // Mitsuba file that gives a spectrum renders spectrally by default, one of RGB colours in
    // RGB.
    const std::string box = quote(kData + "/scenes/pbrt-v4/cornell-box/cornell-box.pbrt");
    r = run(box + " --spp 1 --threads 2 --width 32 --height 32 -o " + quote(out) + " --stats " + quote(stats), dir);
    REQUIRE(r.status == 0);
    CHECK(r.err.find("warning") == std::string::npos);
    CHECK(contains(readFile(stats), "\"spectral\": true"));
    r = run(box + " --rgb --spp 1 --threads 2 --width 32 --height 32 -o " + quote(out) + " --stats " + quote(stats), dir);
    REQUIRE(r.status == 0);
    CHECK(contains(readFile(stats), "\"spectral\": false"));
    for (const auto& [f, spectral] : {std::pair{principled, true}, std::pair{blend, false}}) {
        r = run(f + " --tracer bpt --spp 1 --threads 2 --width 32 --height 32 -o " + quote(out) + " --stats " + quote(stats), dir);
        REQUIRE(r.status == 0);
        CHECK(contains(readFile(stats), spectral ? "\"spectral\": true" : "\"spectral\": false"));
    }
    // --describe says what a render with the same options would be, and why not spectral.
    CHECK(contains(run("--describe", dir).out, "spectral: no (RGB, the format's default"));
    CHECK(contains(run(box + " --describe", dir).out, "spectral: yes (pt, the format's default"));
    CHECK(contains(run(box + " --describe --rgb", dir).out, "spectral: no (RGB, asked for with --rgb)"));
    CHECK(contains(run("--describe --spectral --tracer mmlt", dir).out, "spectral: yes (mmlt"));
    CHECK(contains(run("--describe --spectral --tracer bpt", dir).out, "spectral: yes (bpt"));
    CHECK(contains(run("--describe --spectral", dir).out, "spectral: yes"));  // (the built-in scene's first render: PT)
    CHECK(contains(run(blend + " --describe --spectral --tracer pt", dir).out, "spectral: yes (pt, sampled"));
    CHECK(contains(run(coated + " --describe", dir).out, "spectral: yes"));
}

TEST_CASE("cli: --strategy-images writes a weighted and an unweighted EXR per strategy", "[cli]") {
    TempDir dir;
    std::string folder = dir.file("strategies"), out = dir.file("out.pfm");
    Run r = run("--tracer bpt --max-length 2 --spp 1" + kSmall + " --strategy-images " + quote(folder) + " -o " + quote(out), dir);
    INFO("stderr: " << r.err);
    REQUIRE(r.status == 0);
    for (const char* name : {"s0_t2", "s1_t1", "s0_t3", "s1_t2", "s2_t1"}) {
        CHECK(fs::exists(folder + "/" + name + "_weighted.exr"));
        CHECK(fs::exists(folder + "/" + name + "_unweighted.exr"));
    }
}

// Ctrl-C for every tracer: test_extremes.cpp ("extremes: Ctrl-C saves the image so far...").

// The renderer's own clock (stats "seconds", from the start of rendering to its end) must
// be within 2 s - 5% and + 10%; the process's wall time, which also counts start-up, the
// scene build and writing the image (slow under the sanitizers or on a loaded machine), is
// bounded by 2 s + 10% plus that fixed cost, measured as the wall time of a --spp 1 run.
TEST_CASE("cli: --time 2 ends within 2 s + 10%", "[cli]") {
    TempDir dir;
    std::string out = dir.file("timed.pfm"), stats = dir.file("timed.json");
    const Run fixed = run(kSmall + " --spp 1 -o " + quote(out), dir);
    REQUIRE(fixed.status == 0);
    Run r = run(kSmall + " --time 2 -o " + quote(out) + " --stats " + quote(stats), dir);
    const std::string json = readFile(stats);
    INFO("stderr: " << r.err << "\nstats: " << json << "\nwall " << r.seconds << " s, fixed cost " << fixed.seconds << " s");
    REQUIRE(r.status == 0);
    const double seconds = rstats::jsonNumber(json, "seconds");
    CHECK(seconds >= 1.9);  // the budget is spent, not skipped
    CHECK(seconds <= 2.2);
    CHECK(r.seconds <= 2.2 + fixed.seconds);
    wmlt::Image im = wmlt::readImage(out);
    CHECK(im.width == 64);
    CHECK(allFinite(im));
    CHECK(meanValue(im) > 0);
}

TEST_CASE("cli: the built-in scene renders to .exr and .png at once", "[cli]") {
    TempDir dir;
    std::string exr = dir.file("render.exr"), png = dir.file("render.png");
    Run r = run(kSmall + " --spp 4 -o " + quote(exr) + " -o " + quote(png), dir);
    INFO("stderr: " << r.err);
    REQUIRE(r.status == 0);
    wmlt::Image a = wmlt::readImage(exr), b = wmlt::readImage(png);
    CHECK(a.width == 64);
    CHECK(a.height == 48);
    CHECK(b.width == 64);
    CHECK(b.height == 48);
    CHECK(allFinite(a));
    CHECK(meanValue(a) > 0);
    CHECK(meanValue(b) > 0);
}

TEST_CASE("cli: the built-in scene without --spp or --time renders 10 s of PT, anything else as asked", "[cli]") {
    auto options = [](std::vector<std::string> words) {
        words.insert(words.begin(), "wavemmlt");
        std::vector<char*> argv;
        for (std::string& w : words) argv.push_back(w.data());
        const wmlt::CommandLine cl = wmlt::parseCommandLine(int(argv.size()), argv.data());
        wmlt::Settings s;
        s.samples = 4;
        return wmlt::renderOptionsFor(cl, s);
    };
    CHECK(options({}).timeBudget == wmlt::kFirstRenderSeconds);
    CHECK(options({}).tracer == wmlt::TracerKind::PT);  // the cleanest in that time
    CHECK(options({}).spp == 16);                       // (rounds of the scene's samples)
    CHECK(options({"--tracer", "mmlt"}).tracer == wmlt::TracerKind::MMLT);
    CHECK(options({"--tracer", "mmlt"}).timeBudget == wmlt::kFirstRenderSeconds);
    CHECK(options({"--spp", "4"}).tracer == wmlt::TracerKind::MMLT);  // (the scene's)
    CHECK(options({"--spp", "4"}).timeBudget == 0);
    CHECK(options({"--time", "2"}).timeBudget == 2);
    CHECK(options({"scene.xml"}).timeBudget == 0);
}

TEST_CASE("cli: a render says where its image went, the built-in scene's also what to try next", "[cli]") {
    TempDir dir;
    const std::string exr = dir.file("first.exr"), png = dir.file("first.png");
    Run r = run(" --width 32 --height 24 --spp 1 -o " + quote(exr) + " -o " + quote(png), dir);
    INFO("stderr: " << r.err);
    REQUIRE(r.status == 0);
    CHECK(contains(r.err, "wrote " + exr + ", " + png + "\n"));
    CHECK(contains(r.err, "next:\n"));
    CHECK(contains(r.err, "--interactive"));
    CHECK(contains(r.err, "docs/python.md"));
    Run q = run(" --width 32 --height 24 --spp 1 --quiet -o " + quote(exr), dir);
    CHECK(q.err.empty());
    const std::string xml = std::string(WAVEMMLT_TEST_DATA) + "/scenes/seed-room/seed-room.xml";
    Run f = run(quote(xml) + " --width 16 --height 16 --tracer pt --spp 1 -o " + quote(exr), dir);
    INFO("stderr: " << f.err);
    CHECK(contains(f.err, "wrote " + exr + "\n"));
    CHECK_FALSE(contains(f.err, "next:"));
}
