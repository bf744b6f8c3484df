// --display-server, end to end: a stand-in for tev on 127.0.0.1, written here from tev's
// protocol description (not from wavemmlt's sender), receives the render's packets; the
// image they build must equal the EXR the render wrote. A server that goes away mid-render
// and comes back, or is never there, neither stops nor slows the render. Bad addresses
// exit 2.
#include <catch2/catch.hpp>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>

#include <atomic>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "child_process.h"
#include "render_stats.h"
#include "view_display.h"
#include "wavemmlt/image.h"

namespace fs = std::filesystem;
using child::Clock;
using child::kLimit;
using child::since;

namespace {

const std::string kBin = WAVEMMLT_BIN;

// What tev would hold: the image that CreateImage and UpdateImage packets built.
struct Received {
    int connections = 0, ended = 0, creates = 0, updates = 0;
    std::string name, error;  // error: the first malformed packet
    std::vector<std::string> channels;
    int width = 0, height = 0;
    std::vector<float> rgb;  // interleaved, as wmlt::Image
};

// tev's protocol: a packet is its length (uint32, these 4 bytes included), a type byte,
// then fields, little-endian: bool = 1 byte, string = bytes up to a NUL, int32, float32.
//   CreateImage = 4: grabFocus, image name, width, height, channel count, channel names
//   UpdateImage = 3: grabFocus, image name, channel name, x, y, width, height, then
//                    width * height floats of that channel, row by row
struct PacketReader {
    const std::vector<uint8_t>& p;
    size_t at = 5;
    bool ok = true;
    uint32_t u32() {
        if (at + 4 > p.size()) return ok = false, 0;
        const uint32_t v = p[at] | (uint32_t(p[at + 1]) << 8) | (uint32_t(p[at + 2]) << 16) | (uint32_t(p[at + 3]) << 24);
        at += 4;
        return v;
    }
    int32_t i32() { return int32_t(u32()); }
    float f32() {
        const uint32_t bits = u32();
        float f;
        std::memcpy(&f, &bits, 4);
        return f;
    }
    bool boolean() { return at < p.size() ? p[at++] != 0 : (ok = false); }
    std::string str() {
        std::string s;
        while (at < p.size() && p[at] != 0) s += char(p[at++]);
        if (at >= p.size()) ok = false;
        ++at;
        return s;
    }
};

void decode(const std::vector<uint8_t>& packet, Received& r) {
    PacketReader in{packet};
    auto fail = [&](const std::string& why) {
        if (r.error.empty()) r.error = why;
    };
    const uint8_t type = packet[4];
    in.boolean();
    const std::string name = in.str();
    if (type == 4) {
        r.name = name;
        r.width = in.i32();
        r.height = in.i32();
        r.channels.resize(size_t(std::max(0, in.i32())));
        for (std::string& c : r.channels) c = in.str();
        if (r.width <= 0 || r.height <= 0 || r.width > 4096 || r.height > 4096) return fail("CreateImage: bad size");
        r.rgb.assign(size_t(r.width) * size_t(r.height) * 3, 0.0f);
        ++r.creates;
    } else if (type == 3) {
        const std::string channel = in.str();
        const int x = in.i32(), y = in.i32(), w = in.i32(), h = in.i32();
        const size_t c = channel == "R" ? 0 : channel == "G" ? 1 : channel == "B" ? 2 : 3;
        if (name != r.name || c == 3) return fail("UpdateImage before CreateImage, or channel '" + channel + "'");
        if (x < 0 || y < 0 || w <= 0 || h <= 0 || x + w > r.width || y + h > r.height) return fail("UpdateImage: tile out of the image");
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i) r.rgb[(size_t(y + j) * size_t(r.width) + size_t(x + i)) * 3 + c] = in.f32();
        ++r.updates;
    } else {
        return fail("packet type " + std::to_string(type));
    }
    if (!in.ok || in.at != packet.size()) fail("packet of type " + std::to_string(type) + " has the wrong length");
}

// tev on 127.0.0.1, one connection at a time. With dropAfter > 0 it closes the connection
// and stops listening after that many UpdateImage packets, then listens again on the same
// port `reopenAfter` seconds later (a tev that quits and is started again).
class TevListener {
public:
    explicit TevListener(int dropAfter = 0, double reopenAfter = 0) : dropAfter_(dropAfter), reopenAfter_(reopenAfter) {
        listen_ = openListener(0);
        thread_ = std::thread([this] { serve(); });
    }
    ~TevListener() {
        stop_ = true;
        thread_.join();
        if (listen_ >= 0) close(listen_);
    }
    int port() const { return port_; }
    // What it received, once every connection made so far has been read to its end: call
    // after the sender's process has ended.
    Received received() {
        const auto t0 = Clock::now();
        const int ticks = idleTicks_;
        while (since(t0) < 10) {
            {
                std::lock_guard<std::mutex> lock(mutex_);
                // An idle tick after the call: no connection was waiting to be accepted.
                if (idleTicks_ > ticks + 1 && state_.connections == state_.ended) return state_;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        std::lock_guard<std::mutex> lock(mutex_);
        return state_;
    }

private:
    int openListener(int port) {
        const int fd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);  // not for the render's process
        const int one = 1;
        setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
        sockaddr_in a{};
        a.sin_family = AF_INET;
        a.sin_port = htons(uint16_t(port));
        a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        if (bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 || listen(fd, 4) != 0) {
            close(fd);
            return -1;
        }
        socklen_t len = sizeof a;
        getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
        port_ = ntohs(a.sin_port);
        return fd;
    }
    bool readable(int fd) {
        pollfd p{fd, POLLIN, 0};
        return poll(&p, 1, 50) > 0;
    }
    void serve() {
        while (!stop_) {
            if (listen_ < 0 || !readable(listen_)) {
                ++idleTicks_;
                continue;
            }
            const int conn = accept4(listen_, nullptr, nullptr, SOCK_CLOEXEC);
            if (conn < 0) continue;
            {
                std::lock_guard<std::mutex> lock(mutex_);
                ++state_.connections;
            }
            std::vector<uint8_t> buffer;
            bool dropped = false;
            while (!stop_ && !dropped) {
                if (!readable(conn)) continue;
                uint8_t chunk[65536];
                const ssize_t n = recv(conn, chunk, sizeof chunk, 0);
                if (n <= 0) break;
                buffer.insert(buffer.end(), chunk, chunk + n);
                while (buffer.size() >= 4) {
                    const uint32_t len = buffer[0] | (uint32_t(buffer[1]) << 8) | (uint32_t(buffer[2]) << 16) | (uint32_t(buffer[3]) << 24);
                    if (len < 5 || buffer.size() < len) break;
                    std::lock_guard<std::mutex> lock(mutex_);
                    decode(std::vector<uint8_t>(buffer.begin(), buffer.begin() + len), state_);
                    buffer.erase(buffer.begin(), buffer.begin() + len);
                    dropped = dropAfter_ > 0 && state_.updates == dropAfter_ && state_.connections == 1;
                    if (dropped) break;
                }
            }
            close(conn);
            {
                std::lock_guard<std::mutex> lock(mutex_);
                ++state_.ended;
            }
            if (dropped) {  // tev quits, and is started again
                close(listen_);
                listen_ = -1;
                const auto t0 = Clock::now();
                while (!stop_ && since(t0) < reopenAfter_) std::this_thread::sleep_for(std::chrono::milliseconds(10));
                listen_ = openListener(port_);
            }
        }
    }

    const int dropAfter_;
    const double reopenAfter_;
    int listen_ = -1, port_ = 0;
    std::atomic<bool> stop_{false};
    std::atomic<int> idleTicks_{0};
    std::mutex mutex_;
    Received state_;
    std::thread thread_;
};

bool sameBits(const std::vector<float>& a, const std::vector<float>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

// The "seconds" of a --stats file: the render's own clock.
double renderSeconds(const std::string& statsPath) {
    const std::string json = child::readText(statsPath);
    const size_t at = json.find("\"seconds\": ");
    return at == std::string::npos ? -1 : std::atof(json.c_str() + at + 11);
}

struct Run {
    int status;
    double wall;
    std::string err;
};

Run render(const std::string& dir, std::vector<std::string> args) {
    args.insert(args.begin(), {kBin, "--threads", "2"});
    const auto t0 = Clock::now();
    child::Process p = child::spawn(args, {}, "", dir + "/err.txt");
    const int status = p.wait(kLimit);
    return {status, since(t0), child::readText(dir + "/err.txt")};
}

}  // namespace

TEST_CASE("display-server: the last image tev receives equals the EXR written", "[display]") {
    const std::string dir = rstats::tempDir("display-exr");
    // 200 x 150: tiles of 128 x 128 and the partial ones at the right and bottom edges.
    for (const auto& [tracer, spp] : {std::pair<std::string, std::string>{"pt", "16"}, {"mmlt", "8"}}) {
        INFO(tracer);
        TevListener tev;
        const std::string exr = dir + "/" + tracer + ".exr";
        const Run r = render(dir, {"--tracer", tracer, "--width", "200", "--height", "150", "--spp", spp, "--quiet", "-o", exr, "--display-server",
                                   "127.0.0.1:" + std::to_string(tev.port())});
        INFO("stderr: " << r.err);
        REQUIRE(r.status == 0);
        const Received got = tev.received();
        INFO("malformed packet: " << got.error);
        CHECK(got.error.empty());
        CHECK(got.connections == 1);
        CHECK(got.creates == 1);
        CHECK(got.channels == std::vector<std::string>{"R", "G", "B"});
        CHECK(got.name.find(tracer + ".exr") != std::string::npos);
        CHECK(got.updates >= 3 * 4);  // every channel of the 4 tiles at least once
        const wmlt::Image written = wmlt::readImage(exr);
        CHECK(got.width == written.width);
        CHECK(got.height == written.height);
        CHECK(sameBits(got.rgb, written.rgb));
    }
    fs::remove_all(dir);
}

#if WAVEMMLT_HAVE_VIEW
// The interactive mode streams every render of the session, not only the first to finish,
// and at the end the image it writes.
TEST_CASE("display-server: --interactive streams each restart, tev's last image is the one written", "[display][view]") {
    viewtest::VirtualDisplay x;
    REQUIRE_FALSE(x.name.empty());
    const std::string dir = rstats::tempDir("display-interactive");
    TevListener tev;
    const std::string exr = dir + "/out.exr";
    viewtest::ViewRun run(
        x, dir,
        {"--tracer", "pt", "--width", "64", "--height", "48", "--spp", "8", "-o", exr, "--display-server", "127.0.0.1:" + std::to_string(tev.port())},
        "--interactive");
    INFO("stderr: " << run.err());
    REQUIRE_FALSE(run.window.empty());
    REQUIRE(run.waitTitle("interactive pt: done", kLimit));
    // tev has the first render, all of it, before the camera moves.
    const auto t0 = Clock::now();
    int first = 0;
    while ((first = tev.received().updates) < 3 && since(t0) < 10) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    run.xdotool({"mousemove", "--window", run.window, "20", "24", "mousedown", "1", "sleep", "0.05", "mousemove", "--window", run.window, "22", "25",
                 "mouseup", "1"});
    REQUIRE(run.waitTitle("interactive pt: done", kLimit));
    std::this_thread::sleep_for(std::chrono::milliseconds(600));  // (the sender's next frame)
    CHECK(tev.received().updates > first);                        // the restart reached tev
    run.key("q");
    REQUIRE(run.process.wait(kLimit) == 0);
    const Received got = tev.received();
    INFO("malformed packet: " << got.error);
    CHECK(got.error.empty());
    CHECK(got.connections == 1);
    CHECK(sameBits(got.rgb, wmlt::readImage(exr).rgb));
    fs::remove_all(dir);
}
#endif

// tev quits after the first tile it receives and is started again 0.2 s later: the render
// (1 to 3 s; the sender retries every second) goes on at the same speed to the same image,
// and the new tev gets the whole image. Speed: the render's own clock against the same
// render without a server, best of up to three pairs (the machine runs other tests too).
TEST_CASE("display-server: a tev that quits mid-render and comes back neither stops nor slows it", "[display]") {
    const std::string dir = rstats::tempDir("display-restart");
    const std::vector<std::string> common = {"--tracer", "pt", "--width", "128", "--height", "96", "--spp", "128", "--seed", "3"};
    std::vector<std::string> alone = common;
    alone.insert(alone.end(), {"-o", dir + "/alone.exr", "--stats", dir + "/alone.json"});
    double bestAlone = 1e9, bestWatched = 1e9;
    auto slowed = [&] { return bestWatched > 1.3 * bestAlone + 0.3; };
    for (int pair = 0; pair < 3 && (pair == 0 || slowed()); ++pair) {
        REQUIRE(render(dir, alone).status == 0);
        bestAlone = std::min(bestAlone, renderSeconds(dir + "/alone.json"));

        TevListener tev(1, 0.2);
        std::vector<std::string> watched = common;
        watched.insert(watched.end(),
                       {"-o", dir + "/watched.exr", "--stats", dir + "/watched.json", "--display-server", "127.0.0.1:" + std::to_string(tev.port())});
        const Run w = render(dir, watched);
        INFO("stderr: " << w.err);
        REQUIRE(w.status == 0);
        bestWatched = std::min(bestWatched, renderSeconds(dir + "/watched.json"));
        CHECK(w.err.find("connection lost") != std::string::npos);
        const wmlt::Image image = wmlt::readImage(dir + "/watched.exr");
        CHECK(sameBits(image.rgb, wmlt::readImage(dir + "/alone.exr").rgb));
        const Received got = tev.received();
        INFO("malformed packet: " << got.error);
        CHECK(got.error.empty());
        CHECK(got.connections == 2);
        CHECK(got.creates == 2);
        CHECK(sameBits(got.rgb, image.rgb));
    }
    INFO("render alone " << bestAlone << " s, with the tev that quits " << bestWatched << " s (best of each)");
    CHECK(bestAlone > 0.1);
    CHECK_FALSE(slowed());
    fs::remove_all(dir);
}

TEST_CASE("display-server: no server listening is a warning, and the render completes", "[display]") {
    const std::string dir = rstats::tempDir("display-none");
    int port = 0;
    {
        TevListener closed;  // a port that was free a moment ago, and nobody listens on
        port = closed.port();
    }
    const std::string out = dir + "/out.exr";
    const Run r = render(dir, {"--tracer", "pt", "--width", "64", "--height", "48", "--spp", "16", "-o", out, "--display-server",
                               "127.0.0.1:" + std::to_string(port)});
    INFO("stderr: " << r.err);
    CHECK(r.status == 0);
    CHECK(r.err.find("warning: --display-server 127.0.0.1:" + std::to_string(port)) != std::string::npos);
    CHECK(r.wall < 10);  // the final frame is given up on within seconds
    CHECK(wmlt::readImage(out).width == 64);
    fs::remove_all(dir);
}

TEST_CASE("display-server: a bad address exits 2 before rendering", "[cli]") {
    const std::string dir = rstats::tempDir("display-bad");
    const std::string out = dir + "/never.exr";
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"127.0.0.1", "has no port"},
        {"127.0.0.1:", "has no valid port"},
        {"127.0.0.1:0", "has no valid port"},
        {"localhost:70000", "has no valid port"},
        {"[::1]", "has no port"},
        {":14158", "has no valid host"},
        {"bad host:14158", "has no valid host"},
        {"no-such-host.invalid:14158", "cannot resolve the host 'no-such-host.invalid'"},
    };
    for (const auto& [address, says] : cases) {
        INFO(address);
        const Run r = render(dir, {"--width", "64", "--height", "48", "--spp", "4096", "-o", out, "--display-server", address});
        INFO("stderr: " << r.err);
        CHECK(r.status == 2);
        CHECK(r.wall < 5);  // 4096 spp would take far longer
        CHECK(r.err.find("error: wavemmlt: --display-server") == 0);
        CHECK(r.err.find(says) != std::string::npos);
        CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
        CHECK_FALSE(fs::exists(out));
    }
    fs::remove_all(dir);
}
