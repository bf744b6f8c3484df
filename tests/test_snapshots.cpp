// The image a tracer shows a viewer (RenderView, render.h) between passes or rounds: the
// last snapshot equals the final image bit for bit for every tracer, the light tracer's
// snapshot after a pass equals a render of that many samples, a viewer changes nothing in
// the image, and time paused by a viewer does not count against the time budget.
#include <catch2/catch.hpp>

#include <chrono>
#include <cstring>
#include <thread>
#include <vector>

#include "render_stats.h"
#include "wavemmlt/render.h"

using namespace wmlt;

namespace {

// Asks for every frame; pauses `pauseSeconds` at the boundary numbered `pauseAt`.
struct RecordingView : RenderView {
    std::vector<Snapshot> snapshots;
    int boundaries = 0, pauseAt = -1;
    double pauseSeconds = 0;

    bool wantsFrame() const override { return true; }
    void publish(Snapshot s) override { snapshots.push_back(std::move(s)); }
    double waitWhilePaused() override {
        if (boundaries++ != pauseAt) return 0;
        const auto t0 = std::chrono::steady_clock::now();
        std::this_thread::sleep_for(std::chrono::duration<double>(pauseSeconds));
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
};

bool sameBits(const Image& a, const Image& b) {
    return a.width == b.width && a.height == b.height && a.rgb.size() == b.rgb.size() &&
           std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
}

double meanOf(const Image& im) {
    double sum = 0;
    for (float v : im.rgb) sum += v;
    return sum / double(im.rgb.size());
}

RenderOptions options(TracerKind t, int spp) {
    RenderOptions o = rstats::renderOptions(t, spp, 5, 1, 5);
    o.chains = 256;
    o.bootstrap = 4096;
    return o;
}

struct Case {
    TracerKind kind;
    const char* name;
    int spp;  // enough for several passes (16 samples per pixel each) or MMLT rounds (2^18 proposals)
};

}  // namespace

TEST_CASE("snapshots: the last snapshot is the final image, bit for bit, for every tracer", "[snapshots]") {
    for (const Case& c :
         {Case{TracerKind::PT, "pt", 64}, Case{TracerKind::LT, "lt", 64}, Case{TracerKind::BPT, "bpt", 64}, Case{TracerKind::MMLT, "mmlt", 256}}) {
        INFO(c.name);
        RecordingView view;
        RenderOptions opt = options(c.kind, c.spp);
        opt.view = &view;
        const RenderResult r = render(rstats::cornell64(5), opt);
        REQUIRE(view.snapshots.size() >= 2);  // the image is shown while it renders
        const Snapshot& last = view.snapshots.back();
        CHECK(sameBits(last.image, r.image));
        CHECK(last.spp == r.stats.spp);
        CHECK(last.rays == r.stats.raysIntersect + r.stats.raysOccluded);
        CHECK(last.fraction == Approx(1.0));
        for (size_t i = 1; i < view.snapshots.size(); ++i) {
            CHECK(view.snapshots[i].spp > view.snapshots[i - 1].spp);
            CHECK(view.snapshots[i].rays > view.snapshots[i - 1].rays);
            CHECK(view.snapshots[i].seconds >= view.snapshots[i - 1].seconds);
            CHECK(view.snapshots[i].fraction > view.snapshots[i - 1].fraction);
        }
        // An earlier snapshot is an estimate of the same image, with fewer samples.
        const Image& first = view.snapshots.front().image;
        CHECK_FALSE(sameBits(first, r.image));
        CHECK(meanOf(first) == Approx(meanOf(r.image)).epsilon(0.2));

        // A viewer changes nothing in the image.
        const RenderResult alone = render(rstats::cornell64(5), options(c.kind, c.spp));
        CHECK(sameBits(alone.image, r.image));
    }
}

// The light tracer's passes are keyed on (seed, pixel, sample) and not stratified, so the
// snapshot after the first pass is exactly a render of that pass's samples per pixel.
TEST_CASE("snapshots: the light tracer's first snapshot equals a render of its samples", "[snapshots]") {
    RecordingView view;
    RenderOptions opt = options(TracerKind::LT, 64);
    opt.view = &view;
    render(rstats::cornell64(5), opt);
    REQUIRE(view.snapshots.size() >= 2);
    const Snapshot& first = view.snapshots.front();
    REQUIRE(first.spp < 64);
    const RenderResult part = render(rstats::cornell64(5), options(TracerKind::LT, int(first.spp)));
    CHECK(sameBits(first.image, part.image));
}

// Paused time is not render time: a render paused for 1 s at its first boundary still
// renders for its whole budget, and its statistics leave the pause out.
TEST_CASE("snapshots: a pause does not count against the time budget", "[snapshots][time]") {
    for (const Case& c : {Case{TracerKind::PT, "pt", 4}, Case{TracerKind::MMLT, "mmlt", 4}}) {
        INFO(c.name);
        RecordingView view;
        view.pauseAt = 0;
        view.pauseSeconds = 1.0;
        RenderOptions opt = options(c.kind, c.spp);
        opt.timeBudget = 1.0;
        opt.view = &view;
        const auto t0 = std::chrono::steady_clock::now();
        const RenderResult r = render(rstats::cornell64(5), opt);
        const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        INFO("wall " << wall << " s, render " << r.stats.seconds << " s");
        CHECK(r.stats.seconds >= 0.95);  // the whole budget is spent rendering
        CHECK(r.stats.seconds <= 1.5);   // and the pause is not in it (it would make it 2 s or more)
        CHECK(wall >= 1.95);             // the budget and the pause
        for (const Snapshot& s : view.snapshots) CHECK(s.seconds <= r.stats.seconds);
    }
}
