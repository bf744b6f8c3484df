// Renders stopped early keep their brightness: an image cut short by Ctrl-C (the cancel
// flag, set here from the progress callback once half the work is done) or by a time
// budget (half of a full render's time) against full renders, K = 16 seeds per side,
// with power.h (the image's brightness, and its blocks) at p = 1e-4. What each tracer keeps
// (README): LT and BPT their complete passes, PT also the samples of an unfinished pass
// (each pixel averaged over the samples it received: the strata of that pass are unevenly
// covered, a small bias this test would see if it mattered at its power), MMLT its
// complete rounds of proposals, normalised by the proposals made: a round boundary must not
// change the normalisation (a bug there is a brightness error of the share of the render
// lost, about 50%). The brightness error each comparison detects is printed.
#include <catch2/catch.hpp>

#include <atomic>
#include <iostream>
#include <string>

#include "power.h"
#include "render_stats.h"
#include "wavemmlt/render.h"
#include "wavemmlt/scene_desc.h"

using namespace wmlt;

namespace {

constexpr int K = 16;

enum class Stop { None, Cancel, Time };

power::Runs partialRuns(const SceneDesc& desc, RenderOptions o, uint64_t seed0, Stop stop, double budget) {
    power::Runs r(4);
    for (int i = 0; i < K; ++i) {
        o.seed = seed0 + uint64_t(i);
        std::atomic<bool> cancel{false};
        o.cancel = &cancel;
        o.progress = nullptr;
        o.timeBudget = stop == Stop::Time ? budget : 0;
        if (stop == Stop::Cancel)
            o.progress = [&cancel](double done) {
                if (done >= 0.5) cancel = true;
            };
        const RenderResult res = render(desc, o);
        REQUIRE(res.stats.samplesNonfiniteDiscarded == 0);
        if (stop == Stop::Cancel) CHECK(res.stats.spp < uint64_t(o.spp));
        r.add(res);
    }
    return r;
}

}  // namespace

TEST_CASE("Ctrl-C and --time keep the image's brightness, for every tracer", "[partial][stat]") {
    SceneDesc desc = rstats::cornell64(5);
    desc.settings.width = desc.settings.height = 32;
    struct Case {
        TracerKind kind;
        const char* name;
        int spp;
    };
    for (const Case& c :
         {Case{TracerKind::PT, "pt", 64}, Case{TracerKind::LT, "lt", 64}, Case{TracerKind::BPT, "bpt", 64}, Case{TracerKind::MMLT, "mmlt", 128}}) {
        RenderOptions o = rstats::renderOptions(c.kind, c.spp, 0, 1, 5);
        o.chains = 1024;
        o.bootstrap = 1 << 14;
        const power::Runs full = partialRuns(desc, o, 100, Stop::None, 0);
        const double seconds = render(desc, o).stats.seconds;
        for (Stop stop : {Stop::Cancel, Stop::Time}) {
            const power::Runs part = partialRuns(desc, o, 200 + 100 * uint64_t(stop), stop, 0.5 * seconds);
            const std::string what = std::string(c.name) + (stop == Stop::Cancel ? ", cancelled half way" : ", half the time");
            const power::Verdict br = power::brightness(part, full, 1e-4), bl = power::blocks(part, full, 1e-4);
            std::cout << what << ": fails a brightness error of " << 100 * br.detectable << "%\n";
            INFO(what << ": " << br.text);
            CHECK(br.pass);
            CHECK(br.detectable < 0.1);
            INFO(what << ": " << bl.text);
            CHECK(bl.pass);
        }
    }
}
