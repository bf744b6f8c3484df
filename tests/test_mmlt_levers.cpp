// MMLT's levers (issue 44; docs/mmlt-levers.md): the relative-error target
// (RenderOptions::mmltTarget), learned step sizes (learnSteps), delayed rejection
// (delayedRejection), the tempered target (mmltTargetExponent), film steps (filmSteps, the
// default since they won on the estimator suite; the others on the luminance target and
// without film steps, where they were built and measured under the power heuristic; they run
// here under the balance heuristic, the default since 5f0e88f) and the power heuristic
// (misBeta 2, the default until the balance heuristic won on the suite). Each changes only what
// a pass holds fixed (delayed rejection and film steps: the kernel, by a second stage that
// keeps it reversible, or by another symmetric proposal), so each must keep:
//  1. the target map's kernel: a tile per film point, edges and NaN clamped, c = luminance
//     (to the exponent) times the tile's scale (kernels/mmlt_target.h);
//  2. the estimator unbiased, with the MMLT power tests' power (power.h): every length of
//     the Cornell box against BPT, where a 1% error in one length's brightness fails, and
//     the seed room (5%), each lever alone;
//  3. every replayed seed bit for bit, and one image for 1, 2 and 4 threads, over many
//     passes (a new map and new step sizes at each);
//  4. what was learned in the stats: the maps, their scales, each length's sigma and share
//     of film steps.
// The measurements that chose the defaults: bench/estimator.sh, docs/benchmarks.md.
#include <tbb/task_arena.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "kernels/chain_numbers.h"
#include "kernels/mmlt_target.h"
#include "kernels/mutation.h"
#include "power.h"
#include "render_stats.h"
#include "wavemmlt/render.h"
#include "wavemmlt/scene_desc.h"

using namespace wmlt;

namespace {

constexpr int K = 32;
constexpr double kP = 1e-4;

RenderOptions mmlt(int spp, int maxLength, MmltTarget target, bool learn, uint64_t seed = 0, int bootstrap = 0, bool delayed = false,
                   float exponent = RenderOptions{}.mmltTargetExponent, FilmSteps film = FilmSteps::Off, float misBeta = 0) {
    RenderOptions o = rstats::renderOptions(TracerKind::MMLT, spp, seed, 1, maxLength);
    o.chains = 1024;
    o.bootstrap = bootstrap;
    o.mmltTarget = target;
    o.learnSteps = learn;
    o.delayedRejection = delayed;
    o.mmltTargetExponent = exponent;
    o.filmSteps = film;
    o.misBeta = misBeta;
    return o;
}

// runs: K per side keeps the power of test_mmlt_power.cpp with luminance as the target. With
// the relative target a length's brightness also depends on where the chains are (each splat
// weighs b_k / chains_k over its tile's scale) and its pools have 3/4 of the samples (the
// rest make the map): its brightness varies more from run to run, and more mutations per
// pixel or a larger bootstrap hardly help (Cornell box, length 2's detectable error at K = 32:
// 1.01% at 512 and 1.06% at 768 mutations per pixel, 1.09% with a bootstrap of 2^17), so it
// has twice the runs. So has the tempered target: it takes mutations from the bright lengths,
// and the Cornell box's length 2 is 1.28% detectable with K runs, 0.93% with 2K.
// Film steps: always on the Cornell box (where its small steps are accepted more than 0.6 of
// the time, so learned film steps would not be taken), learned on the seed room (where its
// lengths take them from the second pass on: the test below checks both).
struct Lever {
    const char* name;
    MmltTarget target;
    bool learn;
    int runs;
    bool delayed = false;
    float exponent = 1;  // (the levers were built, measured and are tested on the luminance target)
    FilmSteps cornellFilm = FilmSteps::Off, seedRoomFilm = FilmSteps::Off;
    float misBeta = 0;  // 0: MMLT's own, the balance heuristic
};
const Lever kLevers[] = {{"relative target", MmltTarget::Relative, false, 2 * K},
                         {"learned steps", MmltTarget::Luminance, true, K},
                         {"delayed rejection", MmltTarget::Luminance, false, K, true},
                         {"tempered target", MmltTarget::Luminance, false, 2 * K, false, 0.5f},
                         {"film steps", MmltTarget::Luminance, false, K, false, 1, FilmSteps::Always, FilmSteps::Learned},
                         {"power heuristic", MmltTarget::Luminance, false, K, false, 1, FilmSteps::Off, FilmSteps::Off, 2}};

// desc rendered with o on `threads` workers (in an arena of that many).
RenderResult renderWithThreads(const SceneDesc& desc, RenderOptions o, int threads) {
    o.threads = threads;
    RenderResult r;
    tbb::task_arena(threads).execute([&] { r = render(desc, o); });
    return r;
}

}  // namespace

TEST_CASE("MMLT target map: the tile of a film point, and c = luminance times its scale", "[mmlt][kernels]") {
    const float scale[6] = {1, 2, 3, 4, 5, 6};  // 3 x 2 tiles of 4 pixels
    const TargetMap m{scale, 3, 2, 0.25f};
    CHECK(targetTileOf(m, 0.0f, 0.0f) == 0);
    CHECK(targetTileOf(m, 3.99f, 3.99f) == 0);
    CHECK(targetTileOf(m, 4.0f, 0.0f) == 1);
    CHECK(targetTileOf(m, 11.9f, 7.9f) == 5);
    CHECK(targetTileOf(m, 1e30f, 1e30f) == 5);  // off the film: the edge
    CHECK(targetTileOf(m, -3.0f, 5.0f) == 3);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    CHECK(targetTileOf(m, nan, nan) == 0);
    const Vec3 F(1.0f, 0.5f, 0.25f);
    CHECK(targetOf(F, 9.0f, 5.0f, m) == luminance(F) * 6.0f);
    CHECK(targetOf(F, 9.0f, 5.0f, TargetMap{}) == luminance(F));
    CHECK(targetOf(F) == luminance(F));
    TargetMap tempered = m;  // c = luminance^beta, then the tile's scale
    tempered.exponent = 0.5f;
    CHECK(targetOf(F, 9.0f, 5.0f, tempered) == std::sqrt(luminance(F)) * 6.0f);
    CHECK(targetOf(Vec3(0.0f), 9.0f, 5.0f, tempered) == 0.0f);
    CHECK(targetOf(Vec3(nan, 0.0f, 0.0f), 1.0f, 1.0f, m) == 0.0f);
    CHECK(targetOf(Vec3(std::numeric_limits<float>::infinity(), 0.0f, 0.0f)) == 0.0f);
}

TEST_CASE("MMLT levers keep every length of the Cornell box unbiased against BPT (a 1% error in one length fails)", "[mmlt][stat]") {
    const int L = 5, B = 4;
    SceneDesc desc = rstats::cornell64(L);
    desc.settings.width = desc.settings.height = 16;
    const power::Runs ref = power::tracerRuns(desc, rstats::renderOptions(TracerKind::BPT, 64, 0, 1, L), K, 10000, B)[0];
    for (const Lever& lever : kLevers) {
        const power::Runs m = power::tracerRuns(
            desc, mmlt(256, L, lever.target, lever.learn, 0, 1 << 16, lever.delayed, lever.exponent, lever.cornellFilm, lever.misBeta), lever.runs,
            21000, B)[0];
        power::compare(m, ref, "MMLT vs BPT", std::string("Cornell box, ") + lever.name, kP, power::Claims{0.01, 0.01});
    }
}

TEST_CASE("MMLT levers keep the seed room (its light above a drop ceiling) unbiased against BPT", "[mmlt][stat]") {
    const int L = 6, B = 4;
    SceneDesc desc = loadScene(std::string(WAVEMMLT_TEST_DATA) + "/scenes/seed-room/seed-room.xml");
    desc.settings.width = desc.settings.height = 16;
    desc.settings.maxPathLength = L;
    const power::Runs ref = power::tracerRuns(desc, rstats::renderOptions(TracerKind::BPT, 256, 0, 1, L), K, 14000, B)[0];
    for (const Lever& lever : kLevers) {
        const power::Runs m = power::tracerRuns(
            desc, mmlt(1024, L, lever.target, lever.learn, 0, 1 << 14, lever.delayed, lever.exponent, lever.seedRoomFilm, lever.misBeta), lever.runs,
            22000, B)[0];
        power::compare(m, ref, "MMLT vs BPT", std::string("seed room, ") + lever.name, kP, power::Claims{0.05, 0});
    }
}

TEST_CASE("MMLT levers: seeds replay bit for bit, one image for 1, 2 and 4 threads, and what was learned is reported", "[mmlt]") {
    // Glass and a mirror: a map with bright caustics and dark corners; passes of 16
    // iterations, so that the map and the step sizes are learned again many times.
    const SceneDesc desc = loadSceneFromString(rstats::causticXml(16, 6), "caustic.xml", ".");
    RenderOptions o = mmlt(1024, 6, MmltTarget::Relative, true, 42);
    o.passLength = 16;
    const RenderResult a = render(desc, o);
    const RenderStats::Mmlt& m = a.stats.mmlt;
    INFO(m.passes << " passes");
    REQUIRE(m.passes >= 8);
    CHECK(m.replayMismatches == 0);
    CHECK(m.replayed > 0);
    CHECK(a.stats.samplesNonfiniteDiscarded == 0);
    // A new map at every pass after the first (each pool has light here), scales around 1
    // with the floor's bound: a tile at the floor of 0.1 of the mean weighs 10.
    CHECK(m.target == MmltTarget::Relative);
    CHECK(m.targetMaps == m.passes - 1);
    CHECK(m.targetTileSize == 1);
    CHECK(m.targetScaleLeast > 0);
    CHECK(m.targetScaleLeast < 1);
    CHECK(m.targetScaleMost > 1);
    CHECK(m.targetScaleMost <= 10.0f * (1 + 1e-6));
    // Each length's sigma moved from its start toward the acceptance sought (0.4), within bounds.
    REQUIRE(m.learnedSteps);
    int moved = 0;
    for (int k = 1; k <= 6; ++k) {
        const float s = m.smallStepSigma[size_t(k)];
        CHECK(s >= 1.0f / 1024);
        CHECK(s <= 0.25f);
        moved += s != kSmallStepSigma ? 1 : 0;
    }
    CHECK(moved >= 3);
    for (int threads : {4, 1}) {  // (4 first: a render with 1 thread caps the workers while it runs)
        const RenderResult b = renderWithThreads(desc, o, threads);
        INFO(threads << " threads");
        CHECK(b.image.rgb == a.image.rgb);
        CHECK(b.stats.mmlt.b == m.b);
        CHECK(b.stats.mmlt.smallStepSigma == m.smallStepSigma);
        CHECK(b.stats.mmlt.targetScaleMost == m.targetScaleMost);
        CHECK(b.stats.mmlt.replayMismatches == 0);
    }
    // Off, the stats say so and the defaults hold.
    const RenderResult off = render(desc, mmlt(16, 6, MmltTarget::Luminance, false, 42));
    CHECK(off.stats.mmlt.target == MmltTarget::Luminance);
    CHECK(off.stats.mmlt.targetMaps == 0);
    CHECK_FALSE(off.stats.mmlt.learnedSteps);
}

TEST_CASE("MMLT delayed rejection: every rejected large step proposes again, one image for 1, 2 and 4 threads", "[mmlt]") {
    const SceneDesc desc = loadSceneFromString(rstats::causticXml(16, 6), "caustic.xml", ".");
    RenderOptions o = mmlt(256, 6, MmltTarget::Luminance, false, 43, 0, true);
    o.passLength = 16;
    const RenderResult a = render(desc, o);
    const RenderStats::Mmlt& m = a.stats.mmlt;
    REQUIRE(m.delayedRejection);
    CHECK(m.replayMismatches == 0);
    uint64_t second = 0, accepted = 0, rejectedLarge = 0;
    for (int k = 1; k <= 6; ++k) {
        second += m.proposedDelayed[size_t(k)];
        accepted += m.acceptedDelayed[size_t(k)];
        rejectedLarge += m.proposedLarge[size_t(k)] - m.acceptedLarge[size_t(k)];
    }
    CHECK(second == rejectedLarge);  // one second proposal per rejected large step, no other
    CHECK(second > 0);
    CHECK(accepted > 0);
    CHECK(accepted < second);
    for (int threads : {4, 1}) {
        const RenderResult b = renderWithThreads(desc, o, threads);
        INFO(threads << " threads");
        CHECK(b.image.rgb == a.image.rgb);
        CHECK(b.stats.mmlt.acceptedDelayed == m.acceptedDelayed);
    }
    o.delayedRejection = false;  // off: no second proposals, another image
    const RenderResult off = render(desc, o);
    CHECK_FALSE(off.stats.mmlt.delayedRejection);
    for (int k = 1; k <= 6; ++k) CHECK(off.stats.mmlt.proposedDelayed[size_t(k)] == 0);
    CHECK(off.image.rgb != a.image.rgb);
}

TEST_CASE("MMLT tempered target: the exponent is reported, replays are exact, one image for 1, 2 and 4 threads", "[mmlt]") {
    const SceneDesc desc = loadSceneFromString(rstats::causticXml(16, 6), "caustic.xml", ".");
    RenderOptions o = mmlt(256, 6, MmltTarget::Luminance, false, 44, 0, false, 0.5f);
    o.passLength = 16;
    const RenderResult a = render(desc, o);
    CHECK(a.stats.mmlt.targetExponent == 0.5f);
    CHECK(a.stats.mmlt.replayMismatches == 0);
    CHECK(a.stats.mmlt.replayed > 0);
    for (int threads : {4, 1}) {
        const RenderResult b = renderWithThreads(desc, o, threads);
        INFO(threads << " threads");
        CHECK(b.image.rgb == a.image.rgb);
        CHECK(b.stats.mmlt.b == a.stats.mmlt.b);
    }
    o.mmltTargetExponent = 1;  // the luminance: another image (b_k in other units)
    const RenderResult lum = render(desc, o);
    CHECK(lum.stats.mmlt.targetExponent == 1.0f);
    CHECK(lum.image.rgb != a.image.rgb);
    // PSSMLT keeps the luminance
    o.tracer = TracerKind::PSSMLT;
    o.mmltTargetExponent = 0.5f;
    CHECK(render(desc, o).stats.mmlt.targetExponent == 1.0f);
}

TEST_CASE("MMLT film steps: a kernel that moves the raster point alone, learned where small steps are rejected, one image for 1, 2 and 4 threads",
          "[mmlt]") {
    // The kernel: value + kFilmStepScale sigma z, wrapped into [0, 1), z the coordinate's small
    // step's normal number (so that a step's numbers come from its key alone).
    for (uint64_t key : {1ull, 77ull, 123456789ull})
        for (uint32_t d : {1u, 2u}) {
            const float z = standardNormal(key, dimNormal(d)), u = filmStepOf(key, d, 0.5f, 0.01f);
            CHECK(u == wrapUnit(0.5f + kFilmStepScale * 0.01f * z));
            CHECK(u >= 0.0f);
            CHECK(u < 1.0f);
            CHECK(filmStepOf(key, d, 0.999f, 10.0f) < 1.0f);
        }

    // Always: 0.3 of every length's small steps, from the first pass on (a binomial share:
    // within 5 standard deviations), some of them accepted, none of them joining a pool.
    const SceneDesc caustic = loadSceneFromString(rstats::causticXml(16, 6), "caustic.xml", ".");
    RenderOptions o = mmlt(256, 6, MmltTarget::Luminance, false, 45, 0, false, 1, FilmSteps::Always);
    o.passLength = 16;
    const RenderResult a = render(caustic, o);
    const RenderStats::Mmlt& m = a.stats.mmlt;
    REQUIRE(m.filmSteps == FilmSteps::Always);
    CHECK(m.replayMismatches == 0);
    double film = 0, small = 0;
    for (int k = 1; k <= 6; ++k) {
        if (m.proposals[size_t(k)] == 0) continue;
        INFO("length " << k);
        CHECK(m.filmStepShare[size_t(k)] == 0.3f);
        film += double(m.proposedFilm[size_t(k)]);
        small += double(m.proposedFilm[size_t(k)] + m.proposedSmall[size_t(k)]);
        CHECK(m.acceptedFilm[size_t(k)] <= m.proposedFilm[size_t(k)]);
        if (m.proposedFilm[size_t(k)] >= 100) CHECK(m.acceptedFilm[size_t(k)] > 0);
    }
    REQUIRE(small > 10000);
    CHECK(std::abs(film / small - 0.3) < 5 * std::sqrt(0.3 * 0.7 / small));
    for (int threads : {4, 1}) {
        const RenderResult b = renderWithThreads(caustic, o, threads);
        INFO(threads << " threads");
        CHECK(b.image.rgb == a.image.rgb);
        CHECK(b.stats.mmlt.acceptedFilm == m.acceptedFilm);
    }
    o.filmSteps = FilmSteps::Off;  // off: no film steps, another image
    const RenderResult off = render(caustic, o);
    CHECK(off.stats.mmlt.filmSteps == FilmSteps::Off);
    for (int k = 1; k <= 6; ++k) CHECK(off.stats.mmlt.proposedFilm[size_t(k)] == 0);
    CHECK(off.image.rgb != a.image.rgb);
    o.tracer = TracerKind::PSSMLT;  // PSSMLT has no film steps
    o.filmSteps = FilmSteps::Always;
    CHECK(render(caustic, o).stats.mmlt.filmSteps == FilmSteps::Off);

    // Learned: none in the first pass, then 0.3 of the small steps of the lengths whose small
    // steps were accepted less than 0.6 of the time in the last pass, none in the others. On
    // the seed room every lit length takes them (its light comes through a gap); on the
    // caustic scene the short lengths do not.
    SceneDesc room = loadScene(std::string(WAVEMMLT_TEST_DATA) + "/scenes/seed-room/seed-room.xml");
    room.settings.width = room.settings.height = 16;
    room.settings.maxPathLength = 6;
    RenderOptions l = mmlt(1024, 6, MmltTarget::Luminance, false, 46, 0, false, 1, FilmSteps::Learned);
    l.passLength = 64;
    auto learnedShares = [](const RenderStats::Mmlt& n, int& taken, int& notTaken) {
        REQUIRE(n.filmSteps == FilmSteps::Learned);
        REQUIRE(n.passes >= 3);
        for (int k = 1; k <= 6; ++k) {
            INFO("length " << k);
            const float share = n.filmStepShare[size_t(k)];
            CHECK((share == 0.0f || share == 0.3f));
            if (n.proposals[size_t(k)] == 0) {
                CHECK(share == 0.0f);
                continue;
            }
            // (the last pass's acceptance decides; the whole render's is near it)
            const double a = double(n.acceptedSmall[size_t(k)]) / double(n.proposedSmall[size_t(k)]);
            if (a < 0.5) CHECK(share == 0.3f);
            if (a > 0.7) CHECK(share == 0.0f);
            (share > 0 ? taken : notTaken) += 1;
            if (share > 0) CHECK(n.proposedFilm[size_t(k)] > 0);
        }
    };
    const RenderResult r = render(room, l);
    int taken = 0, notTaken = 0;
    learnedShares(r.stats.mmlt, taken, notTaken);
    CHECK(taken >= 3);
    taken = notTaken = 0;
    o.tracer = TracerKind::MMLT;
    o.filmSteps = FilmSteps::Learned;
    learnedShares(render(caustic, o).stats.mmlt, taken, notTaken);
    CHECK(notTaken >= 2);
    const RenderStats::Mmlt& n = r.stats.mmlt;
    for (int threads : {4, 1}) {
        const RenderResult b = renderWithThreads(room, l, threads);
        INFO(threads << " threads");
        CHECK(b.image.rgb == r.image.rgb);
        CHECK(b.stats.mmlt.filmStepShare == n.filmStepShare);
    }
}
