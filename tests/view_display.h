// The view window's end-to-end tests (test_view.cpp, test_interactive_window.cpp): an X
// server of their own (Xvfb), wavemmlt run on it, xdotool to drive the window and xwd to
// take screenshots (scripts/setup.sh installs all three). Every child process is killed
// after at most 60 s, so no test can hang.
#pragma once
#include <poll.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "child_process.h"
#include "wavemmlt/image.h"

namespace viewtest {

using child::Clock;
using child::kLimit;
using child::since;

const std::string kBin = WAVEMMLT_BIN;

#if WAVEMMLT_HAVE_VIEW  // a build without SDL2 refuses --view: test_view.cpp's last test case checks that

// An X server of its own: Xvfb -displayfd writes the free display number it took.
// -noreset: by default the server resets when its last client leaves, and a client that
// connects meanwhile (wavemmlt, just after an xdotool) is refused.
struct VirtualDisplay {
    child::Process server;
    std::string name;  // ":N"

    VirtualDisplay() {
        int fds[2];
        if (pipe(fds) != 0) return;
        server = child::spawn({"Xvfb", "-displayfd", std::to_string(fds[1]), "-screen", "0", "640x480x24", "-nolisten", "tcp", "-noreset"});
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

inline Screenshot readXwd(const std::string& path) {
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
    const uint32_t bytes = bitsPerPixel / 8;                        // 4, or 3 (packed)
    if (format != 2 || (bytes != 3 && bytes != 4) || bytesPerLine < width * bytes || d.size() < start + size_t(bytesPerLine) * height) return s;
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
inline std::vector<uint8_t> pngBytes(const wmlt::Image& png) {
    std::vector<uint8_t> b;
    for (float v : png.rgb) b.push_back(uint8_t(std::lround(wmlt::linearToSrgb(v) * 255.0f)));
    return b;
}

// `wavemmlt --view ...` (or `mode`: --interactive) on `display`, and its window. `env`:
// more of the child's environment.
struct ViewRun {
    const VirtualDisplay& display;
    std::string dir, window;
    child::Process process;
    Clock::time_point start = Clock::now();

    ViewRun(const VirtualDisplay& d, const std::string& folder, std::vector<std::string> args, const std::string& mode = "--view",
            std::vector<std::string> env = {})
        : display(d), dir(folder) {
        args.insert(args.begin(), {kBin, mode, "--threads", "2"});
        for (const std::string& e : display.env()) env.push_back(e);
        process = child::spawn(args, env, dir + "/out.txt", dir + "/err.txt");
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

inline bool validImage(const std::string& path, int width) {
    if (!std::filesystem::exists(path)) return false;
    const wmlt::Image im = wmlt::readImage(path);
    double sum = 0;
    for (float v : im.rgb) {
        if (!std::isfinite(v) || v < 0) return false;
        sum += v;
    }
    return im.width == width && sum > 0;
}

inline int temporaries(const std::string& dir) {
    int n = 0;
    for (const auto& e : std::filesystem::directory_iterator(dir)) n += e.path().string().find(".tmp-") != std::string::npos;
    return n;
}

#endif  // WAVEMMLT_HAVE_VIEW

}  // namespace viewtest
