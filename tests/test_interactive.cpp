// The interactive mode's session without a window (src/app/interactive.cpp, issue 28): each
// change restarts the render on the scene built once, and the image it settles on is the one
// a fresh render of the same camera and settings makes, bit for bit; refused settings keep
// the old ones; the printed command line gives back exactly the session's camera and settings.
#include <catch2/catch.hpp>

#include <atomic>
#include <chrono>
#include <sstream>

#include "app/camera_control.h"
#include "app/cli.h"
#include "app/interactive.h"
#include "wavemmlt/error.h"

using namespace wmlt;

namespace wmlt {
extern const char* const kDefaultSceneXml;
}

namespace {

SceneDesc smallDefaultScene() {
    SceneDesc d = loadSceneFromString(kDefaultSceneXml, "<built-in scene>", ".");
    d.settings.width = 40;
    d.settings.height = 30;
    return d;
}

RenderOptions baseOptions() {
    RenderOptions o;
    o.tracer = TracerKind::PT;
    o.spp = 4;
    o.strataPerAxis = 2;
    o.threads = 2;
    o.seed = 7;
    o.maxPathLength = 6;
    return o;
}

// The render a fresh process makes of `s`: a new scene with its camera, the options' tracer.
// (Written out here, not with applyViewSettings: the test's own account of what reaches
// the render.)
Image freshRender(const ViewSettings& s, RenderOptions o) {
    SceneDesc d = smallDefaultScene();
    d.camera = s.camera;
    o.tracer = s.tracer;
    o.minPathLength = s.minPathLength;
    o.maxPathLength = s.maxPathLength;
    o.probLarge = s.probLarge;
    o.chains = s.chains;
    o.misBeta = s.misBeta;
    return render(std::move(d), o).image;
}

// The first final frame newer than `version` (the session's settled image); fails after 60 s.
ViewHub::Frame settled(const ViewHub& hub, uint64_t version) {
    const auto start = std::chrono::steady_clock::now();
    while (std::chrono::steady_clock::now() - start < std::chrono::seconds(60)) {
        const ViewHub::Frame f = hub.waitNewer(version, std::chrono::milliseconds(100));
        if (f.version > version && f.final) return f;
        if (f.version > version) version = f.version;
    }
    FAIL("the session did not settle within 60 s");
    return {};
}

}  // namespace

TEST_CASE("interactive session: each change settles on the image a fresh render makes", "[interactive]") {
    std::atomic<bool> cancel{false};
    ViewHub hub(&cancel);
    const RenderOptions base = baseOptions();
    SceneDesc desc = smallDefaultScene();
    ViewSettings s = viewSettingsOf(desc.camera, base);
    InteractiveSession session(Scene::build(std::move(desc), 2), base, s, hub);

    ViewHub::Frame f = settled(hub, 0);
    CHECK(f.snapshot->image.rgb == freshRender(s, base).rgb);

    // A drag's steps (each a preview), then still: the orbited camera.
    for (int i = 1; i <= 5; ++i) {
        ViewSettings step = s;
        step.camera = orbit(s.camera, 0.05f * float(i), 0.02f * float(i));
        REQUIRE(session.change(step, true).empty());
    }
    s = session.settings();
    f = settled(hub, hub.latest().version);
    const Image orbited = freshRender(s, base);
    CHECK(f.snapshot->image.rgb == orbited.rgb);

    // Pan, zoom and another tracer with its settings, applied at once (a panel's edit).
    s.camera = zoom(pan(s.camera, 0.1f, -0.05f), 0.2f);
    s.tracer = TracerKind::BPT;
    s.maxPathLength = 3;
    s.misBeta = 1;
    REQUIRE(session.change(s, false).empty());
    f = settled(hub, hub.latest().version);
    CHECK(f.snapshot->image.rgb == freshRender(s, base).rgb);
    CHECK(f.snapshot->image.rgb != orbited.rgb);

    // MaxPathLength 1: only what emits is seen (the preview and the render alike).
    s.maxPathLength = 1;
    s.tracer = TracerKind::MMLT;
    REQUIRE(session.change(s, false).empty());
    f = settled(hub, hub.latest().version);
    CHECK(f.snapshot->image.rgb == freshRender(s, base).rgb);
}

TEST_CASE("interactive session: refused settings keep the old ones, with the reason", "[interactive]") {
    std::atomic<bool> cancel{false};
    ViewHub hub(&cancel);
    const RenderOptions base = baseOptions();
    SceneDesc desc = smallDefaultScene();
    const ViewSettings s = viewSettingsOf(desc.camera, base);
    InteractiveSession session(Scene::build(std::move(desc), 2), base, s, hub);
    struct Case {
        const char* what;
        void (*spoil)(ViewSettings&);
        const char* says;
    };
    const Case cases[] = {
        {"ProbLarge 1.5", [](ViewSettings& v) { v.probLarge = 1.5f; }, "ProbLarge"},
        {"ProbLarge 0", [](ViewSettings& v) { v.probLarge = 0; }, "ProbLarge"},
        {"MaxPathLength < MinPathLength", [](ViewSettings& v) { v.minPathLength = 4, v.maxPathLength = 3; }, "less than MinPathLength"},
        {"MaxPathLength 65", [](ViewSettings& v) { v.maxPathLength = 65; }, "path lengths"},
        {"a negative aperture", [](ViewSettings& v) { v.camera.dof = true, v.camera.fStop = -2; }, "aperture"},
        {"FOV 0", [](ViewSettings& v) { v.camera.fovDegrees = 0; }, "FOV"},
        {"the eye at LookAt", [](ViewSettings& v) { v.camera.position = v.camera.lookAt; }, "differ"},
        {"Up along the view", [](ViewSettings& v) { v.camera.up = v.camera.lookAt - v.camera.position; }, "Up"},
        {"MIS beta 0.25", [](ViewSettings& v) { v.misBeta = 0.25f; }, "MIS"},
        {"chains -1", [](ViewSettings& v) { v.chains = -1; }, "chains"},
    };
    for (const Case& c : cases) {
        INFO(c.what);
        ViewSettings bad = s;
        c.spoil(bad);
        const std::string problem = session.change(bad, false);
        CHECK(problem.find(c.says) != std::string::npos);
        const ViewSettings now = session.settings();
        CHECK(now.probLarge == s.probLarge);
        CHECK(now.minPathLength == s.minPathLength);
        CHECK(now.maxPathLength == s.maxPathLength);
        CHECK(now.camera.fovDegrees == s.camera.fovDegrees);
        CHECK(now.camera.dof == s.camera.dof);
        CHECK(now.camera.position.x == s.camera.position.x);
        CHECK(now.misBeta == s.misBeta);
        CHECK(now.chains == s.chains);
    }
    // None restarted the render: it settles on the first image.
    CHECK(settled(hub, 0).snapshot->image.rgb == freshRender(s, base).rgb);
}

TEST_CASE("interactive: the printed command line gives back the session's camera and settings exactly", "[interactive][cli]") {
    SceneDesc d = smallDefaultScene();
    RenderOptions base = baseOptions();
    ViewSettings s = viewSettingsOf(d.camera, base);
    s.camera = zoom(dolly(orbit(s.camera, 0.731f, -0.2f), 0.37f), 0.11f);
    s.camera.dof = true;
    s.camera.focalLength = 3.3333333f;
    s.camera.fStop = 1.2345678f;
    s.tracer = TracerKind::MMLT;
    s.probLarge = 0.123456789f;
    s.chains = 5000;
    s.misBeta = 1.5f;
    s.minPathLength = 2;
    s.maxPathLength = 9;
    s.exposure = 1.5f;
    const std::string cmd = commandLineFor("scene.xml", s, base, 40, 30, {"out.png"});
    // The words, quotes removed (the scene and outputs are quoted for a shell).
    std::vector<std::string> words;
    std::istringstream in(cmd);
    for (std::string w; in >> w;) {
        if (w.size() >= 2 && w.front() == '\'' && w.back() == '\'') w = w.substr(1, w.size() - 2);
        words.push_back(w);
    }
    std::vector<char*> argv;
    for (std::string& w : words) argv.push_back(w.data());
    const CommandLine cl = parseCommandLine(int(argv.size()), argv.data());
    CameraDesc back = d.camera;
    applyCamera(cl, back);
    Settings st = d.settings;
    applyCommandLine(cl, st);
    for (int a = 0; a < 3; ++a) {
        CHECK(back.position[a] == s.camera.position[a]);
        CHECK(back.lookAt[a] == s.camera.lookAt[a]);
        CHECK(back.up[a] == s.camera.up[a]);
    }
    CHECK(back.fovDegrees == s.camera.fovDegrees);
    CHECK(back.dof);
    CHECK(back.focalLength == s.camera.focalLength);
    CHECK(back.fStop == s.camera.fStop);
    CHECK(st.tracer == TracerKind::MMLT);
    CHECK(st.probLarge == s.probLarge);
    CHECK(st.minPathLength == 2);
    CHECK(st.maxPathLength == 9);
    CHECK(st.width == 40);
    CHECK(st.height == 30);
    CHECK(cl.scenePath == "scene.xml");
    CHECK(*cl.chains == 5000);
    CHECK(*cl.misBeta == s.misBeta);
    CHECK(*cl.spp == base.spp);
    CHECK(cl.seed == base.seed);
    CHECK(cl.exposure == s.exposure);
    CHECK(cl.outputs == std::vector<std::string>{"out.png"});

    // A pinhole: --f-stop 0.
    s.camera.dof = false;
    const std::string pinhole = commandLineFor("", s, base, 40, 30, {});
    CHECK(pinhole.find("--f-stop 0 ") != std::string::npos);

    // The tracer's own MIS exponent (0) is no option: the command line leaves it to the tracer.
    s.misBeta = 0;
    CHECK(commandLineFor("", s, base, 40, 30, {}).find("--mis-beta") == std::string::npos);
}
