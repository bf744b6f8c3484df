// The interactive mode's figures (issue 28), without a window: the session (src/app/
// interactive.cpp) driven as the window drives it.
//
//   build/wavemmlt_bench_interactive [scene ...] [--spp N] [--tracer T] [--drag SECONDS] [--threads N]
//
// With no scene: ../shared/scenes/bitterli-cornell/bitterli-cornell-256.xml and
// seed-room/seed-room.xml (says so and exits 0 when the shared folder is missing). Per scene,
// at its own image size (the window's default size):
//  - preview: a drag of --drag seconds [3], an orbit step every 16 ms (a 60 Hz mouse, five
//    degrees a second); the
//    previews shown per second, and the resolution the preview settled on;
//  - after release: the seconds from the last step to the tracer's finished --spp [16] image
//    (the same image a fresh render makes, checked bit for bit), against a fresh start
//    (load, build and render: what --view takes to show that image).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "app/camera_control.h"
#include "app/cli.h"
#include "app/interactive.h"
#include "wavemmlt/error.h"

using namespace wmlt;
using Clock = std::chrono::steady_clock;

namespace {

double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// The newest frame once it is final and newer than `version` (an error, or 10 minutes: thrown).
ViewHub::Frame settled(const ViewHub& hub, const InteractiveSession& session, uint64_t version) {
    const auto start = Clock::now();
    while (since(start) < 600) {
        const ViewHub::Frame f = hub.waitNewer(version, std::chrono::milliseconds(50));
        if (f.version > version && f.final) return f;
        version = std::max(version, f.version);
        if (session.status().rfind("error", 0) == 0) throw std::runtime_error(session.status());
    }
    throw std::runtime_error("the render did not finish in 10 minutes");
}

struct Options {
    int spp = 16, threads = 0;
    double drag = 3;
    std::string tracer;
};

void run(const std::string& path, const Options& o) {
    SceneDesc desc = loadScene(path);
    RenderOptions base;
    base.tracer = desc.settings.tracer;
    if (o.tracer == "pt") base.tracer = TracerKind::PT;
    if (o.tracer == "bpt") base.tracer = TracerKind::BPT;
    if (o.tracer == "mmlt") base.tracer = TracerKind::MMLT;
    if (o.tracer == "lt") base.tracer = TracerKind::LT;
    base.spp = o.spp;
    base.strataPerAxis = strataForSpp(o.spp);
    base.threads = o.threads;
    base.seed = 1;
    base.minPathLength = desc.settings.minPathLength;
    base.maxPathLength = desc.settings.maxPathLength;
    base.probLarge = desc.settings.probLarge;
    const int width = desc.settings.width, height = desc.settings.height;
    const ViewSettings s = viewSettingsOf(desc.camera, base);
    std::atomic<bool> cancel{false};
    ViewHub hub(&cancel);
    InteractiveSession session(Scene::build(desc, o.threads), base, s, hub);
    settled(hub, session, 0);

    // The drag: previews only (the tracer never starts while it lasts).
    const uint64_t before = hub.latest().version;
    const auto start = Clock::now();
    int steps = 0;
    std::string scale;
    while (since(start) < o.drag) {
        ++steps;
        ViewSettings next = s;
        // (16 degrees in 3 s about LookAt: the Cornell box's camera stays in front of its opening)
        next.camera = orbit(s.camera, 0.0015f * float(steps), 0.0003f * float(steps));
        if (const std::string p = session.change(next, true); !p.empty()) throw std::runtime_error(p);
        std::this_thread::sleep_for(std::chrono::milliseconds(16));
        if (steps % 30 == 0) scale = session.status();
    }
    const ViewHub::Frame last = hub.latest();
    const double fps = double(last.version - before) / since(start);
    const auto release = Clock::now();
    session.endGesture();  // (the window's mouse-button release)
    const ViewHub::Frame f = settled(hub, session, last.version);
    const double interactive = since(release);

    // What a fresh start takes to show the same image.
    const auto fresh0 = Clock::now();
    SceneDesc again = loadScene(path);
    again.camera = session.settings().camera;
    RenderOptions opt = base;
    const RenderResult r = render(std::move(again), opt);
    const double fresh = since(fresh0);
    std::printf(
        "%-28s %4dx%-4d %-4s  preview %5.1f fps (%d steps in %.1f s; %s)  release -> %d spp: %6.2f s, "
        "fresh start: %6.2f s (%.2fx)  same image: %s\n",
        std::filesystem::path(path).filename().c_str(), width, height, tracerName(base.tracer), fps, steps, o.drag, scale.c_str(), o.spp, interactive,
        fresh, fresh / interactive, r.image.rgb == f.snapshot->image.rgb ? "yes" : "NO");
    session.stop();
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    std::vector<std::string> scenes;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&] { return i + 1 < argc ? std::string(argv[++i]) : std::string(); };
        if (a == "--spp") o.spp = std::max(1, std::atoi(value().c_str()));
        else if (a == "--threads") o.threads = std::atoi(value().c_str());
        else if (a == "--drag") o.drag = std::atof(value().c_str());
        else if (a == "--tracer") o.tracer = value();
        else if (!a.empty() && a[0] == '-') {
            std::fprintf(stderr, "usage: wavemmlt_bench_interactive [scene ...] [--spp N] [--tracer T] [--drag S] [--threads N]\n");
            return 2;
        } else scenes.push_back(a);
    }
    if (scenes.empty()) {
        const std::string shared = std::string(WAVEMMLT_SOURCE_DIR) + "/../shared/scenes/";
        for (const char* s : {"bitterli-cornell/bitterli-cornell-256.xml", "seed-room/seed-room.xml"}) {
            if (!std::filesystem::exists(shared + s)) {
                std::printf("bench_interactive: %s%s is missing (the shared scenes are not beside this checkout): skipped\n", shared.c_str(), s);
                continue;
            }
            scenes.push_back(shared + s);
        }
    }
    try {
        for (const std::string& s : scenes) run(s, o);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 2;
    }
    return 0;
}
