// The --view window, end to end: each test starts its own X server (Xvfb, which picks a
// free display number), runs `wavemmlt --view` on it, drives the window with xdotool and
// takes screenshots with xwd (scripts/setup.sh installs all three). Tagged [view]. Every
// child process is killed after at most 60 s, so no test can hang.
#include <catch2/catch.hpp>

#include <poll.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "child_process.h"
#include "render_stats.h"
#include "view_display.h"
#include "wavemmlt/image.h"

namespace fs = std::filesystem;
using namespace viewtest;

#if WAVEMMLT_HAVE_VIEW

TEST_CASE("view: the window shows the PNG the render wrote, pixel for pixel, for every tracer", "[view]") {
    VirtualDisplay x;
    REQUIRE_FALSE(x.name.empty());  // Xvfb (scripts/setup.sh installs it)
    const std::string dir = rstats::tempDir("view-png");
    for (const char* tracer : {"pt", "lt", "bpt", "mmlt"}) {
        INFO(tracer);
        const std::string png = dir + "/" + tracer + ".png", exr = dir + "/" + tracer + ".exr";
        ViewRun run(x, dir, {"--tracer", tracer, "--width", "64", "--height", "48", "--spp", "16", "-o", png, "-o", exr});
        INFO("stderr: " << run.err());
        REQUIRE_FALSE(run.window.empty());
        REQUIRE(run.waitTitle(": done", kLimit));
        INFO("title: " << run.title());
        // The outputs are written before the final frame is shown, and the window stays open.
        REQUIRE(fs::exists(png));
        CHECK(run.process.running());
        const std::vector<uint8_t> expected = pngBytes(wmlt::readImage(png));
        Screenshot shot;
        int worst = 256;
        for (int attempt = 0; attempt < 5 && worst > 1; ++attempt) {  // X draws asynchronously
            shot = run.screenshot();
            REQUIRE(shot.width == 64);
            REQUIRE(shot.height == 48);
            worst = 0;
            for (size_t i = 0; i < expected.size(); ++i) worst = std::max(worst, std::abs(int(shot.rgb[i]) - expected[i]));
            if (worst > 1) std::this_thread::sleep_for(std::chrono::milliseconds(200));
        }
        CHECK(worst <= 1);  // 1/255
        // The pixel under the mouse: its value in the title.
        run.xdotool({"mousemove", "--window", run.window, "10", "20"});
        const wmlt::Vec3 v = wmlt::readImage(exr).at(10, 20);
        char value[128];
        std::snprintf(value, sizeof value, "(10, 20) %.4g %.4g %.4g", v.x, v.y, v.z);
        CHECK(run.waitTitle(value, 5));
        run.key("q");  // after the render: closes the window; the status is the render's
        CHECK(run.process.wait(kLimit) == 0);
    }
    fs::remove_all(dir);
}

TEST_CASE("view: q and Esc stop a running render as Ctrl-C does: status 130, the image so far saved", "[view]") {
    VirtualDisplay x;
    REQUIRE_FALSE(x.name.empty());
    const std::string dir = rstats::tempDir("view-quit");
    for (const auto& [tracer, key] : {std::pair<std::string, std::string>{"pt", "q"}, {"mmlt", "Escape"}}) {
        INFO(tracer << ", key " << key);
        const std::string out = dir + "/" + tracer + ".exr";
        ViewRun run(x, dir, {"--tracer", tracer, "--width", "64", "--height", "48", "--time", "60", "-o", out});
        INFO("stderr: " << run.err());
        REQUIRE_FALSE(run.window.empty());
        REQUIRE(run.waitTitle("Mrays/s", 20));  // a frame of the render is shown
        CHECK(run.title().find("done") == std::string::npos);
        const auto t0 = Clock::now();
        run.key(key);
        CHECK(run.process.wait(kLimit) == 130);
        CHECK(since(t0) < 3);
        CHECK(validImage(out, 64));
        CHECK(temporaries(dir) == 0);
    }
    fs::remove_all(dir);
}

// p holds the render at its next pass boundary, and the time it is held is not render
// time; s writes the outputs while it renders (here: while it is paused).
TEST_CASE("view: p pauses the render outside its time budget, s saves the image shown", "[view]") {
    VirtualDisplay x;
    REQUIRE_FALSE(x.name.empty());
    const std::string dir = rstats::tempDir("view-pause");
    const std::string out = dir + "/paused.exr", stats = dir + "/stats.json";
    ViewRun run(x, dir, {"--tracer", "pt", "--width", "64", "--height", "48", "--time", "1.5", "-o", out, "--stats", stats});
    INFO("stderr: " << run.err());
    REQUIRE_FALSE(run.window.empty());
    REQUIRE(run.waitTitle("Mrays/s", 20));
    run.key("p");
    REQUIRE(run.waitTitle("paused", 5));
    std::this_thread::sleep_for(std::chrono::milliseconds(2500));
    CHECK(run.process.running());  // 1.5 s of rendering are not over while it is paused
    CHECK_FALSE(fs::exists(out));
    run.key("s");
    const auto t0 = Clock::now();
    while (!fs::exists(out) && since(t0) < 10) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    CHECK(validImage(out, 64));
    CHECK(run.process.running());
    run.key("p");
    REQUIRE(run.waitTitle(": done", kLimit));
    const double wall = since(run.start);
    const std::string json = child::readText(stats);
    const size_t at = json.find("\"seconds\": ");
    REQUIRE(at != std::string::npos);
    const double seconds = std::atof(json.c_str() + at + 11);
    INFO("render " << seconds << " s, wall " << wall << " s");
    CHECK(seconds >= 1.5 * 0.95);
    CHECK(seconds <= 1.5 * 1.05);
    CHECK(wall >= 1.5 + 2.5);
    run.key("q");
    CHECK(run.process.wait(kLimit) == 0);
    fs::remove_all(dir);
}

// The window is there before MMLT's bootstrap ends (here about 1 s of it).
TEST_CASE("view: the window opens before the scene is built and bootstrapped", "[view]") {
    VirtualDisplay x;
    REQUIRE_FALSE(x.name.empty());
    const std::string dir = rstats::tempDir("view-early");
    ViewRun run(x, dir, {"--tracer", "mmlt", "--width", "64", "--height", "48", "--spp", "4", "--bootstrap", "150000", "-o", dir + "/early.exr"});
    INFO("stderr: " << run.err());
    REQUIRE_FALSE(run.window.empty());
    const std::string title = run.title();
    INFO("title " << title << " after " << since(run.start) << " s");
    CHECK(title.find("preparing") != std::string::npos);
    const double opened = since(run.start);
    REQUIRE(run.waitTitle("Mrays/s", kLimit));  // the first frame, after the bootstrap
    const double firstFrame = since(run.start);
    INFO("window at " << opened << " s, first frame at " << firstFrame << " s");
    CHECK(firstFrame - opened > 0.5);
    REQUIRE(run.waitTitle(": done", kLimit));
    run.key("Escape");
    CHECK(run.process.wait(kLimit) == 0);
    fs::remove_all(dir);
}

#endif  // WAVEMMLT_HAVE_VIEW

// Without a display (or without SDL2 in the build) --view and --interactive are refused
// before any work.
TEST_CASE("view: --view and --interactive without a display exit 2 before rendering", "[cli]") {
    const std::string dir = rstats::tempDir("view-nodisplay");
    const std::string out = dir + "/never.exr";
    struct Case {
        std::vector<std::string> env;
        std::string says;
    };
    const std::vector<Case> cases = WAVEMMLT_HAVE_VIEW
                                        ? std::vector<Case>{{{"DISPLAY", "WAYLAND_DISPLAY"}, "neither DISPLAY nor WAYLAND_DISPLAY is set"},
                                                            {{"DISPLAY=:4095", "WAYLAND_DISPLAY"}, "cannot open a window"}}
                                        : std::vector<Case>{{{}, "is not available"}};
    for (const Case& c : cases)
        for (const std::string mode : {"--view", "--interactive"}) {
            INFO(mode << ": " << c.says);
            const auto t0 = Clock::now();
            child::Process p = child::spawn({kBin, mode, "--width", "64", "--height", "48", "--spp", "4096", "-o", out}, c.env, "", dir + "/err.txt");
            CHECK(p.wait(kLimit) == 2);
            CHECK(since(t0) < 5);  // 4096 spp would take far longer
            const std::string err = child::readText(dir + "/err.txt");
            INFO("stderr: " << err);
            CHECK(err.find(c.says) != std::string::npos);
            CHECK(err.find(mode) != std::string::npos);
            CHECK(std::count(err.begin(), err.end(), '\n') == 1);
            CHECK_FALSE(fs::exists(out));
        }
    fs::remove_all(dir);
}
