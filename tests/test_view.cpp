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
#include "wavemmlt/image.h"

namespace fs = std::filesystem;
using child::Clock;
using child::since;
using child::kLimit;

namespace {

const std::string kBin = WAVEMMLT_BIN;

#if WAVEMMLT_HAVE_VIEW  // a build without SDL2 refuses --view: the last test case checks that

// An X server of its own: Xvfb -displayfd writes the free display number it took.
// -noreset: by default the server resets when its last client leaves, and a client that
// connects meanwhile (wavemmlt, just after an xdotool) is refused.
struct VirtualDisplay {
    child::Process server;
    std::string name;  // ":N"

    VirtualDisplay() {
        int fds[2];
        if (pipe(fds) != 0) return;
        server = child::spawn({"Xvfb", "-displayfd", std::to_string(fds[1]), "-screen", "0", "640x480x24",
                               "-nolisten", "tcp", "-noreset"});
        close(fds[1]);
        std::string number;
        pollfd p{fds[0], POLLIN, 0};
        char c;
        while (server.started() && poll(&p, 1, 10000) > 0 && read(fds[0], &c, 1) == 1 && c != '\n') number += c;
        close(fds[0]);
        if (!number.empty()) name = ":" + number;
    }
    ~VirtualDisplay() { server.kill(SIGKILL); }
    std::vector<std::string> env() const { return {"DISPLAY=" + name, "WAYLAND_DISPLAY"}; }
};

// An X window dump (xwd): the 8-bit RGB of a 24-bit TrueColor ZPixmap, 3 or 4 bytes a pixel.
struct Screenshot {
    int width = 0, height = 0;
    std::vector<uint8_t> rgb;
};

Screenshot readXwd(const std::string& path) {
    const std::string d = child::readText(path);
    Screenshot s;
    if (d.size() < 100) return s;
    auto field = [&](size_t i) {  // the header: 25 big-endian 32-bit fields
        const auto* b = reinterpret_cast<const uint8_t*>(d.data()) + 4 * i;
        return (uint32_t(b[0]) << 24) | (uint32_t(b[1]) << 16) | (uint32_t(b[2]) << 8) | b[3];
    };
    const uint32_t headerSize = field(0), format = field(2), width = field(4), height = field(5);
    const uint32_t byteOrder = field(7), bitsPerPixel = field(11), bytesPerLine = field(12);
    const uint32_t masks[3] = {field(14), field(15), field(16)}, colors = field(19);
    const size_t start = size_t(headerSize) + size_t(colors) * 12;  // after the colour map
    const uint32_t bytes = bitsPerPixel / 8;  // 4, or 3 (packed)
    if (format != 2 || (bytes != 3 && bytes != 4) || bytesPerLine < width * bytes ||
        d.size() < start + size_t(bytesPerLine) * height)
        return s;
    s.width = int(width);
    s.height = int(height);
    for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x) {
            const auto* b = reinterpret_cast<const uint8_t*>(d.data()) + start + size_t(y) * bytesPerLine + bytes * x;
            uint32_t v = 0;
            for (uint32_t i = 0; i < bytes; ++i) v |= uint32_t(b[byteOrder == 0 ? i : bytes - 1 - i]) << (8 * i);
            for (uint32_t m : masks) {
                int shift = 0;
                while (m && !((m >> shift) & 1)) ++shift;
                s.rgb.push_back(uint8_t((v & m) >> shift));
            }
        }
    return s;
}

// The 8-bit values of a PNG the render wrote (readImage linearises them; the sRGB curve
// brings them back exactly).
std::vector<uint8_t> pngBytes(const wmlt::Image& png) {
    std::vector<uint8_t> b;
    for (float v : png.rgb) b.push_back(uint8_t(std::lround(wmlt::linearToSrgb(v) * 255.0f)));
    return b;
}

// `wavemmlt --view ...` on `display`, and its window.
struct ViewRun {
    const VirtualDisplay& display;
    std::string dir, window;
    child::Process process;
    Clock::time_point start = Clock::now();

    ViewRun(const VirtualDisplay& d, const std::string& folder, std::vector<std::string> args) : display(d), dir(folder) {
        args.insert(args.begin(), {kBin, "--view", "--threads", "2"});
        process = child::spawn(args, display.env(), dir + "/out.txt", dir + "/err.txt");
        // The window: within a few seconds of the start, whatever the render does.
        while (window.empty() && process.running() && since(start) < 10) {
            const std::string ids = xdotool({"search", "--onlyvisible", "--name", "^wavemmlt "});
            window = ids.substr(0, ids.find('\n'));
            if (window.empty()) std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
    }
    std::string xdotool(std::vector<std::string> args) const {
        args.insert(args.begin(), "xdotool");
        return child::output(args, display.env());
    }
    std::string title() const {
        const std::string t = xdotool({"getwindowname", window});
        return t.substr(0, t.find('\n'));
    }
    // Waits until the title contains `part`; false after `seconds`.
    bool waitTitle(const std::string& part, double seconds) const {
        const auto t0 = Clock::now();
        while (since(t0) < seconds) {
            if (title().find(part) != std::string::npos) return true;
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
        }
        return false;
    }
    // A real key press (XTEST) into the focused window: events sent to a window
    // (xdotool key --window) are synthetic, and SDL may drop them.
    void key(const std::string& k) const { xdotool({"windowfocus", "--sync", window, "key", k}); }
    Screenshot screenshot() const {
        const std::string path = dir + "/window.xwd";
        child::output({"xwd", "-id", window, "-silent", "-out", path}, display.env());
        return readXwd(path);
    }
    std::string err() const { return child::readText(dir + "/err.txt"); }
};

bool validImage(const std::string& path, int width) {
    if (!fs::exists(path)) return false;
    const wmlt::Image im = wmlt::readImage(path);
    double sum = 0;
    for (float v : im.rgb) {
        if (!std::isfinite(v) || v < 0) return false;
        sum += v;
    }
    return im.width == width && sum > 0;
}

int temporaries(const std::string& dir) {
    int n = 0;
    for (const auto& e : fs::directory_iterator(dir)) n += e.path().string().find(".tmp-") != std::string::npos;
    return n;
}

#endif  // WAVEMMLT_HAVE_VIEW

}  // namespace

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
    ViewRun run(x, dir, {"--tracer", "mmlt", "--width", "64", "--height", "48", "--spp", "4", "--bootstrap", "150000",
                         "-o", dir + "/early.exr"});
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

// Without a display (or without SDL2 in the build) --view is refused before any work.
TEST_CASE("view: --view without a display exits 2 before rendering", "[cli]") {
    const std::string dir = rstats::tempDir("view-nodisplay");
    const std::string out = dir + "/never.exr";
    struct Case {
        std::vector<std::string> env;
        std::string says;
    };
    const std::vector<Case> cases = WAVEMMLT_HAVE_VIEW
        ? std::vector<Case>{{{"DISPLAY", "WAYLAND_DISPLAY"}, "neither DISPLAY nor WAYLAND_DISPLAY is set"},
                            {{"DISPLAY=:4095", "WAYLAND_DISPLAY"}, "cannot open a window"}}
        : std::vector<Case>{{{}, "--view is not available"}};
    for (const Case& c : cases) {
        INFO(c.says);
        const auto t0 = Clock::now();
        child::Process p = child::spawn({kBin, "--view", "--width", "64", "--height", "48", "--spp", "4096", "-o", out},
                                        c.env, "", dir + "/err.txt");
        CHECK(p.wait(kLimit) == 2);
        CHECK(since(t0) < 5);  // 4096 spp would take far longer
        const std::string err = child::readText(dir + "/err.txt");
        INFO("stderr: " << err);
        CHECK(err.find(c.says) != std::string::npos);
        CHECK(std::count(err.begin(), err.end(), '\n') == 1);
        CHECK_FALSE(fs::exists(out));
    }
    fs::remove_all(dir);
}
