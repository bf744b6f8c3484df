#include "app/tev_sender.h"

#include <fcntl.h>
#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <thread>
#include <vector>

#include "app/tev_protocol.h"
#include "wavemmlt/error.h"

namespace wmlt {

namespace {

using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;
constexpr milliseconds kFrameInterval{250};   // frames asked of the render
constexpr milliseconds kRetryInterval{1000};  // between connection attempts
constexpr milliseconds kConnectTimeout{1000};
constexpr milliseconds kFrameTimeout{3000};  // to send one frame; then the connection is dropped
constexpr int kTile = 128;                   // tile side, as pbrt-v4 sends

struct Address {
    sockaddr_storage addr;
    socklen_t length;
    int family;
};

// Waits until fd is ready for `events` or the deadline passes.
bool waitFor(int fd, short events, Clock::time_point deadline) {
    for (;;) {
        const auto left = std::chrono::duration_cast<milliseconds>(deadline - Clock::now()).count();
        if (left <= 0) return false;
        pollfd p{fd, events, 0};
        const int n = poll(&p, 1, int(left));
        if (n > 0) return true;
        if (n < 0 && errno != EINTR) return false;
    }
}

}  // namespace

struct TevSender::Thread {
    ViewHub& hub;
    const std::string where, imageName;  // where: "HOST:PORT", for messages
    const bool quiet;
    std::vector<Address> addresses;
    std::atomic<bool> stop{false};
    std::thread thread;

    int fd = -1;
    bool warned = false;  // a warning stands since the last connection
    std::string lastError;
    Image sent;  // the values tev has: black after CreateImage

    Thread(ViewHub& h, std::string w, std::string name, bool q) : hub(h), where(std::move(w)), imageName(std::move(name)), quiet(q) {}
    void warn(const std::string& what) {
        if (!quiet && !warned) std::fprintf(stderr, "warning: --display-server %s: %s\n", where.c_str(), what.c_str());
        warned = true;
    }
    bool connect();
    void disconnect(const std::string& why);
    bool sendAll(const std::vector<uint8_t>& bytes, Clock::time_point deadline);
    bool sendFrame(const Image& image);
    void run();
};

bool TevSender::Thread::connect() {
    for (const Address& a : addresses) {
        const int s = socket(a.family, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
        if (s < 0) {
            lastError = std::strerror(errno);
            continue;
        }
        int err = ::connect(s, reinterpret_cast<const sockaddr*>(&a.addr), a.length) == 0 ? 0 : errno;
        if (err == EINPROGRESS) {
            socklen_t len = sizeof err;
            err = waitFor(s, POLLOUT, Clock::now() + kConnectTimeout) ? 0 : ETIMEDOUT;
            if (!err && getsockopt(s, SOL_SOCKET, SO_ERROR, &err, &len) != 0) err = errno;
        }
        if (err) {
            lastError = std::strerror(err);
            ::close(s);
            continue;
        }
        fd = s;
        if (warned && !quiet) std::fprintf(stderr, "--display-server %s: connected\n", where.c_str());
        warned = false;
        return true;
    }
    warn(lastError + "; retrying every second");
    return false;
}

void TevSender::Thread::disconnect(const std::string& why) {
    if (fd >= 0) ::close(fd);
    fd = -1;
    warn("connection lost (" + why + "); reconnecting");
}

bool TevSender::Thread::sendAll(const std::vector<uint8_t>& bytes, Clock::time_point deadline) {
    for (size_t done = 0; done < bytes.size();) {
        const ssize_t n = ::send(fd, bytes.data() + done, bytes.size() - done, MSG_NOSIGNAL);
        if (n > 0) {
            done += size_t(n);
        } else if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) {
            if (!waitFor(fd, POLLOUT, deadline)) {
                lastError = "the server takes no data";
                return false;
            }
        } else {
            lastError = n < 0 ? std::strerror(errno) : "closed";
            return false;
        }
    }
    return true;
}

// The tiles and channels that differ from what tev has.
bool TevSender::Thread::sendFrame(const Image& image) {
    const auto deadline = Clock::now() + kFrameTimeout;
    if (sent.width != image.width || sent.height != image.height) {
        sent = Image(image.width, image.height);
        TevPacketWriter p(TevPacket::CreateImage);
        p.putBool(true).putString(imageName).putInt(image.width).putInt(image.height).putInt(3);  // tev shows it
        for (const char* c : {"R", "G", "B"}) p.putString(c);
        if (!sendAll(p.finish(), deadline)) return false;
    }
    std::vector<float> now, before;
    for (int y0 = 0; y0 < image.height; y0 += kTile)
        for (int x0 = 0; x0 < image.width; x0 += kTile) {
            const int w = std::min(kTile, image.width - x0), h = std::min(kTile, image.height - y0);
            for (int c = 0; c < 3; ++c) {
                now.clear();
                before.clear();
                for (int y = y0; y < y0 + h; ++y)
                    for (int x = x0; x < x0 + w; ++x) {
                        const size_t i = (size_t(y) * size_t(image.width) + size_t(x)) * 3 + size_t(c);
                        now.push_back(image.rgb[i]);
                        before.push_back(sent.rgb[i]);
                    }
                if (std::memcmp(now.data(), before.data(), now.size() * sizeof(float)) == 0) continue;
                TevPacketWriter p(TevPacket::UpdateImage);
                p.putBool(false).putString(imageName).putString(std::string(1, "RGB"[c]));
                p.putInt(x0).putInt(y0).putInt(w).putInt(h);
                for (float v : now) p.putFloat(v);
                if (!sendAll(p.finish(), deadline)) return false;
                for (int y = y0; y < y0 + h; ++y)
                    for (int x = x0; x < x0 + w; ++x) {
                        const size_t i = (size_t(y) * size_t(image.width) + size_t(x)) * 3 + size_t(c);
                        sent.rgb[i] = image.rgb[i];
                    }
            }
        }
    return true;
}

void TevSender::Thread::run() {
    uint64_t sentVersion = 0;
    auto nextAttempt = Clock::now();
    int finalAttempts = 0;  // after the render: two tries at the final frame, without waiting
    while (!stop) {
        const ViewHub::Frame newest = hub.latest();
        if (newest.final && !hub.sessionRunning()) {
            if (newest.version == sentVersion || finalAttempts++ == 2) break;
            nextAttempt = Clock::now();
        }
        if (fd < 0) {
            if (Clock::now() < nextAttempt) {
                std::this_thread::sleep_for(milliseconds(50));
                continue;
            }
            nextAttempt = Clock::now() + kRetryInterval;
            if (!connect()) continue;
            sentVersion = 0;  // a new connection: the image again, from CreateImage on
            sent = Image();
        }
        if (!newest.final) hub.requestFrame();
        const ViewHub::Frame f = hub.waitNewer(sentVersion, kFrameInterval);
        if (!f.snapshot || f.version == sentVersion) continue;
        if (sendFrame(f.snapshot->image)) sentVersion = f.version;
        else disconnect(lastError);
    }
    if (fd >= 0) ::close(fd);
}

TevSender::TevSender(ViewHub& hub, const std::string& host, const std::string& port, std::string imageName, bool quiet)
    : thread_(std::make_unique<Thread>(hub, host + ":" + port, std::move(imageName), quiet)) {
    addrinfo hints{};
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    hints.ai_flags = AI_NUMERICSERV;
    addrinfo* found = nullptr;
    const int err = getaddrinfo(host.c_str(), port.c_str(), &hints, &found);
    if (err != 0) throw InputError("wavemmlt: --display-server: cannot resolve the host '" + host + "': " + gai_strerror(err));
    for (addrinfo* a = found; a; a = a->ai_next) {
        Address addr{};
        std::memcpy(&addr.addr, a->ai_addr, a->ai_addrlen);
        addr.length = a->ai_addrlen;
        addr.family = a->ai_family;
        thread_->addresses.push_back(addr);
    }
    freeaddrinfo(found);
    thread_->thread = std::thread([t = thread_.get()] { t->run(); });
}

TevSender::~TevSender() {
    thread_->stop = true;
    if (thread_->thread.joinable()) thread_->thread.join();
}

void TevSender::waitFinalSent() {
    if (thread_->thread.joinable()) thread_->thread.join();
}

}  // namespace wmlt
