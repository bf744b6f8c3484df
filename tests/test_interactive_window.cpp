// The interactive mode end to end (issue 28): wavemmlt --interactive on an X server of its
// own, driven with xdotool (mouse drags, keys, typing into the panel, whose widgets the
// window lists in WAVEMMLT_PANEL_LAYOUT), read back with screenshots and the command lines
// it prints. Tagged [view], as test_view.cpp.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "app/cli.h"
#include "render_stats.h"
#include "view_display.h"
#include "wavemmlt/image.h"
#include "wavemmlt/scene_desc.h"

namespace fs = std::filesystem;
using namespace viewtest;

#if WAVEMMLT_HAVE_VIEW

namespace {

constexpr int kW = 64, kH = 48;  // the image: drawn at the window's top left, at its size

struct InteractiveRun : ViewRun {
    InteractiveRun(const VirtualDisplay& d, const std::string& folder, std::vector<std::string> args)
        : ViewRun(d, folder, std::move(args), "--interactive", {"WAVEMMLT_PANEL_LAYOUT=" + folder + "/layout.txt"}) {}

    // The image part of the window (8-bit sRGB).
    std::vector<uint8_t> image() const {
        const Screenshot s = screenshot();
        std::vector<uint8_t> out;
        if (s.width < kW || s.height < kH) return out;
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x)
                for (int c = 0; c < 3; ++c) out.push_back(s.rgb[(size_t(y) * s.width + x) * 3 + c]);
        return out;
    }
    // The panel's widget `label`: its rectangle (x, y, w, h), once the window has listed it.
    std::array<int, 4> rect(const std::string& label) const {
        const auto t0 = Clock::now();
        while (since(t0) < 10) {
            std::istringstream in(child::readText(dir + "/layout.txt"));
            for (std::string line; std::getline(in, line);) {
                const size_t tab = line.find('\t');
                if (line.substr(0, tab) != label) continue;
                std::array<int, 4> r;
                std::istringstream(line.substr(tab + 1)) >> r[0] >> r[1] >> r[2] >> r[3];
                return r;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
        }
        return {-1, -1, 0, 0};
    }
    // The window's width, the panel included (a screenshot has only its part on the screen).
    int windowWidth() const {
        const std::string g = xdotool({"getwindowgeometry", window});
        const size_t at = g.find("Geometry: ");
        return at == std::string::npos ? 0 : std::atoi(g.c_str() + at + 10);
    }
    // Its centre.
    std::pair<int, int> widget(const std::string& label) const {
        const std::array<int, 4> r = rect(label);
        return {r[0] + r[2] / 2, r[1] + r[3] / 2};
    }
    void click(const std::string& label) const {
        const auto [x, y] = widget(label);
        // Focused, and the pointer there a moment before the click (ImGui finds what is under
        // the mouse at a frame).
        xdotool(
            {"windowfocus", "--sync", window, "mousemove", "--window", window, std::to_string(x), std::to_string(y), "sleep", "0.05", "click", "1"});
    }
    // Types `text` into the panel's field `label` and presses Enter.
    void type(const std::string& label, const std::string& text) const {
        click(label);
        xdotool({"key", "ctrl+a"});
        xdotool({"type", "--delay", "20", "--", text});
        xdotool({"key", "Return"});
    }
    // The c key: the command line the window prints for what it shows now (the last stdout line).
    std::string commandLine() const {
        auto lines = [&] {
            const std::string text = out();
            return std::count(text.begin(), text.end(), '\n');
        };
        const auto before = lines();
        const auto t0 = Clock::now();
        // (again after a second: a key pressed as the panel's text field lets go may go to it)
        for (double next = 0; lines() == before && since(t0) < 10; std::this_thread::sleep_for(std::chrono::milliseconds(20)))
            if (since(t0) >= next) key("c"), next += 1;
        std::string text = out();
        text.pop_back();
        return text.substr(text.find_last_of('\n') + 1);
    }
    std::string out() const { return child::readText(dir + "/out.txt"); }
    void drag(int button, std::vector<std::pair<int, int>> path) const {
        std::vector<std::string> a = {
            "mousemove", "--window", window, std::to_string(path[0].first), std::to_string(path[0].second), "mousedown", std::to_string(button)};
        for (size_t i = 1; i < path.size(); ++i)
            a.insert(a.end(), {"sleep", "0.03", "mousemove", "--window", window, std::to_string(path[i].first), std::to_string(path[i].second)});
        a.insert(a.end(), {"mouseup", std::to_string(button)});
        xdotool(a);
    }
};

// A command line's words, the shell's quotes taken off.
std::vector<std::string> words(const std::string& cmd) {
    std::vector<std::string> w;
    std::istringstream in(cmd);
    for (std::string s; in >> s;) w.push_back(s.size() >= 2 && s.front() == '\'' ? s.substr(1, s.size() - 2) : s);
    return w;
}

wmlt::CommandLine parsed(const std::string& cmd) {
    std::vector<std::string> w = words(cmd);
    std::vector<char*> argv;
    for (std::string& s : w) argv.push_back(s.data());
    return wmlt::parseCommandLine(int(argv.size()), argv.data());
}

// `cmd` rendered afresh into `png` (its own outputs replaced).
std::vector<uint8_t> freshRender(const std::string& cmd, const std::string& png) {
    std::vector<std::string> args = {kBin, "--quiet", "--threads", "2"};
    const std::vector<std::string> w = words(cmd);
    for (size_t i = 1; i < w.size(); ++i) {
        if (w[i] == "-o") ++i;
        else args.push_back(w[i]);
    }
    args.insert(args.end(), {"-o", png});
    child::Process p = child::spawn(args, {}, "", "");
    if (p.wait(kLimit) != 0 || !fs::exists(png)) return {};
    return pngBytes(wmlt::readImage(png));
}

// The window shows `expected` (to 1/255) within `seconds`: X draws asynchronously, and the
// render may still be finishing.
bool shows(const InteractiveRun& run, const std::vector<uint8_t>& expected, double seconds, int& worst) {
    const auto t0 = Clock::now();
    do {
        const std::vector<uint8_t> got = run.image();
        worst = 256;
        if (got.size() == expected.size() && !got.empty()) {
            worst = 0;
            for (size_t i = 0; i < got.size(); ++i) worst = std::max(worst, std::abs(int(got[i]) - int(expected[i])));
        }
        if (worst <= 1) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
    } while (since(t0) < seconds);
    return false;
}

double meanDifference(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
    double d = 0;
    for (size_t i = 0; i < a.size() && i < b.size(); ++i) d += std::abs(int(a[i]) - int(b[i]));
    return a.empty() ? 0 : d / double(a.size());
}

double mean(const std::vector<uint8_t>& a) { return meanDifference(a, std::vector<uint8_t>(a.size(), 0)); }

// The angle in degrees between the eyes of two command lines, seen from `pivot`.
double turn(const wmlt::CommandLine& a, const wmlt::CommandLine& b, wmlt::Vec3 pivot) {
    const wmlt::Vec3 u = wmlt::normalize(*a.eye - pivot), v = wmlt::normalize(*b.eye - pivot);
    return std::acos(std::clamp(double(wmlt::dot(u, v)), -1.0, 1.0)) * 180.0 / M_PI;
}

}  // namespace

TEST_CASE("interactive: a drag moves the camera, once still, the window shows what the written scene renders", "[view]") {
    VirtualDisplay x;
    REQUIRE_FALSE(x.name.empty());
    const std::string dir = rstats::tempDir("interactive-drag");
    const std::string kept = dir + "/kept.xml";
    InteractiveRun run(x, dir,
                       {"--tracer", "pt", "--width", "64", "--height", "48", "--spp", "16", "--seed", "3", "--max-length", "6", "-o",
                        dir + "/out.png", "--scene-out", kept});
    INFO("stderr: " << run.err());
    REQUIRE_FALSE(run.window.empty());
    REQUIRE(run.waitTitle("interactive pt: done", kLimit));
    const std::string first = run.commandLine();
    int worst = 256;
    REQUIRE(shows(run, freshRender(first, dir + "/first.png"), 10, worst));
    const std::vector<uint8_t> before = run.image();

    run.drag(1, {{20, 24}, {21, 24}, {22, 25}, {23, 25}});  // orbit (a pixel: 60 / 364 degrees)
    run.drag(3, {{30, 30}, {31, 29}});                      // pan
    const std::string moved = run.commandLine();
    INFO(first << "\n" << moved);
    const wmlt::CommandLine a = parsed(first), b = parsed(moved);
    CHECK(a.eye->x != b.eye->x);
    CHECK(a.lookAt->x != b.lookAt->x);  // (the pan)

    // Written back: the file loads with exactly the camera of the printed command line, and
    // renders what the window shows.
    run.key("w");
    const auto t0 = Clock::now();
    while (!fs::exists(kept) && since(t0) < 10) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    const wmlt::SceneDesc back = wmlt::loadScene(kept);
    for (int k = 0; k < 3; ++k) {
        CHECK(back.camera.position[k] == (*b.eye)[k]);
        CHECK(back.camera.lookAt[k] == (*b.lookAt)[k]);
        CHECK(back.camera.up[k] == (*b.up)[k]);
    }
    CHECK(back.camera.fovDegrees == *b.fov);
    const std::vector<uint8_t> fresh = freshRender("wavemmlt '" + kept + "' --spp 16 --seed 3", dir + "/fresh.png");
    CHECK(shows(run, fresh, 20, worst));
    INFO("worst difference " << worst);
    CHECK(meanDifference(fresh, before) > 5);                                  // the drag changed the image
    CHECK(meanDifference(fresh, std::vector<uint8_t>(fresh.size(), 0)) > 20);  // and still sees the room
    CHECK(freshRender(moved, dir + "/moved.png") == fresh);

    run.key("q");
    CHECK(run.process.wait(kLimit) == 0);
    CHECK(validImage(dir + "/out.png", kW));
    fs::remove_all(dir);
}

// Issue 46: the orbit turns about the surface under the view's centre, at --orbit-rate
// degrees per window width (default 60), and Bitterli's Cornell box stays in view.
TEST_CASE("interactive: on the Cornell box a drag orbits about the surface at the centre and keeps the box in view", "[view]") {
    VirtualDisplay x;
    REQUIRE_FALSE(x.name.empty());
    const std::string dir = rstats::tempDir("interactive-orbit");
    const std::string scene = std::string(WAVEMMLT_TEST_DATA) + "/scenes/mitsuba/cornell-box/scene.xml";
    InteractiveRun run(
        x, dir,
        {scene, "--tracer", "pt", "--width", "64", "--height", "48", "--spp", "16", "--seed", "3", "--max-length", "6", "-o", dir + "/out.png"});
    INFO("stderr: " << run.err());
    REQUIRE_FALSE(run.window.empty());
    REQUIRE(run.waitTitle("interactive pt: done", kLimit));
    const std::string first = run.commandLine();
    const std::vector<uint8_t> before = freshRender(first, dir + "/first.png");
    int worst = 256;
    REQUIRE(shows(run, before, 10, worst));
    const int width = run.windowWidth();
    REQUIRE(width > 300);
    // The panel's status fits in it (the title's "wavemmlt interactive pt: done, ..." did not).
    const std::array<int, 4> status = run.rect("status");
    CHECK(status[2] > 0);
    CHECK(status[0] + status[2] <= width);

    std::vector<std::pair<int, int>> right;  // 120 pixels to the right, from the image's left
    for (int i = 0; i <= 12; ++i) right.push_back({8 + 10 * i, 24});
    run.drag(1, right);
    const std::string moved = run.commandLine();
    INFO(first << "\n" << moved);
    const wmlt::CommandLine a = parsed(first), b = parsed(moved);
    // The pivot: the surface at the view's centre (the tall box's edge, 6.9 in front of the
    // eye, at x = 0 and y = 1 as the eye; the file's LookAt is 1 in front), which the eye
    // turned about at the default rate (60 degrees per window width: 20 here).
    const wmlt::Vec3 pivot = *b.lookAt;
    CHECK(std::fabs(pivot.x) < 1e-3f);
    CHECK(std::fabs(pivot.y - 1) < 1e-3f);
    CHECK(std::fabs(pivot.z) < 1);  // (inside the box, which spans -1 to 1)
    CHECK(wmlt::length(*b.eye - pivot) == Approx(wmlt::length(*a.eye - pivot)).epsilon(1e-5));
    CHECK(turn(a, b, pivot) == Approx(60.0 * 120 / width).margin(0.1));
    // Once the render is done the window shows the printed command line's image: the room,
    // about as bright as before the drag (seen from outside, the box is black: the 59-degree
    // turn of 180 degrees per window width leaves a fifth of the mean).
    const std::vector<uint8_t> after = freshRender(moved, dir + "/moved.png");
    CHECK(shows(run, after, 20, worst));
    INFO("mean before " << mean(before) << ", after " << mean(after));
    CHECK(mean(before) > 40);
    CHECK(mean(after) > 0.7 * mean(before));
    CHECK(meanDifference(after, before) > 5);  // and it turned

    // The panel's rate: half as fast; refused when not a positive number.
    run.type("orbit (deg/width)", "30");
    run.type("orbit (deg/width)", "-1");
    run.drag(1, right);
    const std::string back = run.commandLine();
    INFO(back);
    const wmlt::CommandLine c = parsed(back);
    CHECK(turn(b, c, *c.lookAt) == Approx(30.0 * 120 / width).margin(0.1));
    CHECK(run.err().find("refused: orbit (deg/width): '-1' is not a positive number") != std::string::npos);

    run.key("q");
    CHECK(run.process.wait(kLimit) == 0);
    fs::remove_all(dir);
}

TEST_CASE("interactive: each setting changed in the panel reaches the render, bad values keep the old one", "[view]") {
    VirtualDisplay x;
    REQUIRE_FALSE(x.name.empty());
    const std::string dir = rstats::tempDir("interactive-panel");
    InteractiveRun run(
        x, dir, {"--tracer", "pt", "--width", "64", "--height", "48", "--spp", "4", "--seed", "5", "--max-length", "5", "-o", dir + "/out.png"});
    INFO("stderr: " << run.err());
    REQUIRE_FALSE(run.window.empty());
    REQUIRE(run.waitTitle("interactive pt: done", kLimit));

    run.click("bpt");
    CHECK(run.waitTitle("interactive bpt", 10));
    run.type("MaxPathLength ([ ])", "1");
    std::string cmd = run.commandLine();
    INFO(cmd);
    CHECK(cmd.find("--tracer bpt") != std::string::npos);
    CHECK(cmd.find("--max-length 1 ") != std::string::npos);
    REQUIRE(run.waitTitle("interactive bpt: done", kLimit));
    int worst = 256;
    const std::vector<uint8_t> lights = freshRender(cmd, dir + "/lights.png");
    CHECK(shows(run, lights, 20, worst));
    // MaxPathLength 1: only the lights (the built-in scene's ceiling lamp) are not black.
    size_t lit = 0;
    for (size_t i = 0; i < lights.size(); i += 3) lit += lights[i] + lights[i + 1] + lights[i + 2] > 0;
    CHECK(lit > 0);
    CHECK(lit < lights.size() / 3 / 10);

    run.click("mmlt");
    run.type("MaxPathLength ([ ])", "4");
    run.type("ProbLarge", "0.5");
    run.type("chains (0: auto)", "1024");
    run.type("MIS beta (0: auto)", "1");
    run.type("exposure (+ -)", "1");
    run.type("FOV (degrees)", "50");
    CHECK(run.waitTitle("exposure +1.0", 10));
    cmd = run.commandLine();
    for (const char* part : {"--tracer mmlt", "--max-length 4 ", "--p-large 0.5 ", "--chains 1024 ", "--mis-beta 1 ", "--exposure 1 ", "--fov 50 "})
        CHECK(cmd.find(part) != std::string::npos);
    REQUIRE(run.waitTitle("interactive mmlt: done", kLimit));
    CHECK(shows(run, freshRender(cmd, dir + "/mmlt.png"), 20, worst));

    // Refused, each with its reason on stderr; the setting stays as it was.
    run.type("ProbLarge", "1.5");
    run.type("MinPathLength (, .)", "5");
    run.type("aperture radius", "-1");
    run.type("MIS beta (0: auto)", "abc");
    const std::string after = run.commandLine();
    CHECK(after == cmd);
    const std::string err = run.err();
    CHECK(err.find("refused: ProbLarge must be in (0, 1]") != std::string::npos);
    CHECK(err.find("refused: MaxPathLength 4 is less than MinPathLength 5") != std::string::npos);
    CHECK(err.find("refused: aperture radius: must not be negative") != std::string::npos);
    CHECK(err.find("refused: MIS beta (0: auto): 'abc' is not a number") != std::string::npos);
    CHECK(run.process.running());

    // PSSMLT, the panel's last tracer: its chains and ProbLarge reach the command line.
    run.click("pssmlt");
    CHECK(run.waitTitle("interactive pssmlt", 10));
    const std::string pss = run.commandLine();
    CHECK(pss.find("--tracer pssmlt --") != std::string::npos);
    CHECK(pss.find("--p-large 0.5 --chains 1024 ") != std::string::npos);
    REQUIRE(run.waitTitle("interactive pssmlt: done", kLimit));
    CHECK(shows(run, freshRender(pss, dir + "/pssmlt.png"), 20, worst));
    run.click("mmlt");
    CHECK(run.waitTitle("interactive mmlt", 10));

    // A thin lens, focused by ctrl-click on the image.
    run.type("aperture radius", "0.05");
    run.xdotool({"mousemove", "--window", run.window, "32", "40", "keydown", "ctrl", "click", "1", "keyup", "ctrl"});
    const std::string lens = run.commandLine();
    INFO(lens);
    const wmlt::CommandLine l = parsed(lens), c = parsed(cmd);
    CHECK(*l.fStop > 0);
    CHECK(*l.focusDistance != *c.focusDistance);
    CHECK(*l.focusDistance / (2 * *l.fStop) == Approx(0.05f).epsilon(1e-5));

    run.key("q");
    CHECK(run.process.wait(kLimit) == 0);
    fs::remove_all(dir);
}

TEST_CASE("interactive: i in --view switches, Ctrl-C in the middle of a drag saves the image and exits 130", "[view]") {
    VirtualDisplay x;
    REQUIRE_FALSE(x.name.empty());
    const std::string dir = rstats::tempDir("interactive-switch");
    const std::string out = dir + "/out.exr";
    ViewRun run(x, dir, {"--tracer", "bpt", "--width", "64", "--height", "48", "--time", "60", "-o", out});
    INFO("stderr: " << run.err());
    REQUIRE_FALSE(run.window.empty());
    REQUIRE(run.waitTitle("Mrays/s", 20));
    run.key("i");
    REQUIRE(run.waitTitle("wavemmlt interactive bpt", 20));
    CHECK_FALSE(fs::exists(out));  // the --view render was left, not finished
    run.xdotool({"mousemove", "--window", run.window, "20", "20", "mousedown", "1", "mousemove", "--window", run.window, "30", "24"});
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    run.process.kill(SIGINT);
    CHECK(run.process.wait(kLimit) == 130);
    run.xdotool({"mouseup", "1"});
    CHECK(validImage(out, kW));
    CHECK(temporaries(dir) == 0);
    fs::remove_all(dir);
}

#endif  // WAVEMMLT_HAVE_VIEW
