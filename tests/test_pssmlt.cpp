// Primary-sample-space MLT over BPT (--tracer pssmlt, docs/pssmlt.md), with tolerances from
// the measured variance over K independent runs (power.h: each property one test at
// p = 1e-4, its power stated), never hand-tuned:
//  1. every render: no replay mismatch (every seed of every pass is replayed: its t = 1
//     contributions are the replay's), nothing discarded, the mutations asked for, and the
//     normalisation: each proposal splats a total luminance of b / C, so the image's mean
//     luminance is b;
//  2. PSSMLT image = BPT image on the Cornell box and the glass and mirror caustic scene
//     (the furnace's closed form: test_render_analytic.cpp), and the grid furnace of
//     scattering media is 1 everywhere;
//  3. PSSMLT asked for one length k (MinPathLength = MaxPathLength = k) = MMLT's image of
//     that length, for k = 2, 3 and 5;
//  4. a fixed seed gives a bit-identical image for 1, 2 and 4 threads; replay is exact over
//     glass, mirrors, a drop ceiling, 64 segments and media, 1 and 2 threads, few and many
//     chains, several passes;
//  5. the formats and the command line: --tracer pssmlt, Tracer PSSMLT, Mitsuba's pssmlt
//     integrator, --stats' pssmlt_* figures, length images refused.
#include <sys/wait.h>
#include <tbb/task_arena.h>
#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "media_scenes.h"
#include "power.h"
#include "render_stats.h"
#include "wavemmlt/error.h"
#include "wavemmlt/render.h"
#include "wavemmlt/scene_desc.h"

using namespace wmlt;

namespace {

constexpr double kP = 1e-4;

RenderOptions pssmltOptions(int spp, uint64_t seed, int minLength, int maxLength, int chains, int bootstrap = 0, int threads = 2) {
    RenderOptions o = rstats::renderOptions(TracerKind::PSSMLT, spp, seed, minLength, maxLength, threads);
    o.chains = chains;
    o.bootstrap = bootstrap;
    return o;
}

// A PSSMLT render with the checks every run must pass (1. above).
RenderResult renderPssmlt(const SceneDesc& desc, const RenderOptions& o) {
    RenderResult r = render(desc, o);
    REQUIRE(r.stats.tracer == "pssmlt");
    const RenderStats::Mmlt& m = r.stats.mmlt;
    CHECK(m.replayMismatches == 0);
    CHECK(m.replayed == m.chainsSeeded[0]);  // every seed, every pass
    CHECK(r.stats.samplesNonfiniteDiscarded == 0);
    for (float v : r.image.rgb) REQUIRE(std::isfinite(v));
    for (size_t k = 1; k < m.chainsSeeded.size(); ++k) CHECK(m.chainsSeeded[k] == 0);  // one group, k = 0
    CHECK(m.proposedSmall[0] + m.proposedLarge[0] == m.proposals[0]);
    CHECK(m.mutations == m.proposals[0]);
    CHECK(double(m.mutations) >= double(o.spp) * r.image.width * r.image.height);
    CHECK(power::meanLuminance(r.image) == Approx(m.b[0]).epsilon(1e-5));
    CHECK(r.stats.lengthMeanLuminance.empty());
    return r;
}

SceneDesc cornell(int size, int maxLength) {
    SceneDesc d = rstats::cornell64(maxLength);
    d.settings.width = d.settings.height = size;
    return d;
}

SceneDesc caustic(int size, int maxLength) {
    SceneDesc d = loadSceneFromString(rstats::causticXml(16, maxLength), "caustic.xml", ".");
    d.settings.width = d.settings.height = size;
    return d;
}

SceneDesc seedRoom(int size, int maxLength) {
    SceneDesc d = loadScene(std::string(WAVEMMLT_TEST_DATA) + "/scenes/seed-room/seed-room.xml");
    d.settings.width = d.settings.height = size;
    d.settings.maxPathLength = maxLength;
    return d;
}

// The grid furnace of test_media_mmlt.cpp: a closed box of black walls emitting 1 inwards,
// the camera inside, all in a grid of scattering media of albedo 1: 1 everywhere.
SceneDesc gridFurnace() {
    return media_scenes::load(
        "pssmlt-grid.pbrt",
        media_scenes::furnace(R"(MakeNamedMedium "smoke" "string type" "uniformgrid" "rgb sigma_a" [ 0 0 0 ] "rgb sigma_s" [ 0.5 1 1.5 ] "float g" 0.4
  "integer nx" 2 "integer ny" 2 "integer nz" 2 "point3 p0" [ -2.5 -2.5 -2.5 ] "point3 p1" [ 2.5 2.5 2.5 ]
  "float density" [ 0.3 1.2 0.7 1.9 0.5 1.1 1.6 0.2 ]
)",
                              "smoke"));
}

// K PSSMLT runs with the checks of renderPssmlt, seeds seed0 + i.
power::Runs pssmltRuns(const SceneDesc& desc, RenderOptions o, int K, uint64_t seed0, int block) {
    power::Runs runs(block);
    for (int i = 0; i < K; ++i) {
        o.seed = seed0 + uint64_t(i);
        runs.add(renderPssmlt(desc, o));
    }
    return runs;
}

// K = 32 runs of BPT (bptSpp, seeds seed0 + i) against 32 of PSSMLT (mutations per pixel, 1024
// chains, seeds seed0 + 1000 + i) on desc's lengths 1..L; `claim`: the brightness error detected.
void againstBpt(const SceneDesc& desc, int L, int bptSpp, int mutations, uint64_t seed0, double claim, const std::string& what) {
    const int B = 4, K = 32;
    const power::Runs ref = power::tracerRuns(desc, rstats::renderOptions(TracerKind::BPT, bptSpp, 0, 1, L), K, seed0, B)[0];
    const power::Runs m = pssmltRuns(desc, pssmltOptions(mutations, 0, 1, L, 1024, 1 << 14), K, seed0 + 1000, B);
    power::compare(m, ref, "PSSMLT vs BPT", what, kP, power::Claims{claim, 0});
}

}  // namespace

// ---- 2. PSSMLT image = BPT image ------------------------------------------------------------

TEST_CASE("PSSMLT power: Cornell box against BPT", "[pssmlt][stat]") { againstBpt(cornell(16, 5), 5, 64, 256, 20000, 0.005, "Cornell box"); }

TEST_CASE("PSSMLT power: glass and mirror caustics against BPT", "[pssmlt][stat]") {
    againstBpt(caustic(16, 6), 6, 256, 1024, 22000, 0.05, "caustic scene");
}

TEST_CASE("PSSMLT: the grid furnace of scattering media is 1 everywhere", "[pssmlt][media][stat]") {
    const SceneDesc grid = gridFurnace();
    std::vector<rstats::RunStats> runs(3);
    for (int k = 0; k < 8; ++k) {
        const Image im = renderPssmlt(grid, pssmltOptions(256, 300 + uint64_t(k), 1, kMaxPathLength, 1024)).image;
        for (int c = 0; c < 3; ++c) runs[size_t(c)].add(rstats::blockMeans(im, 2, c));
    }
    for (int c = 0; c < 3; ++c) {  // channels correlated: each at p / 3
        const rstats::ZTestResult z = rstats::zTest(runs[size_t(c)], std::vector<double>(16, 1.0), kP / 3);
        INFO("grid furnace, channel " << c << ": " << z.describe());
        CHECK(z.pass);
    }
}

// ---- 3. one length: PSSMLT = MMLT -----------------------------------------------------------

TEST_CASE("PSSMLT and MMLT agree per path length where PSSMLT is asked for one length", "[pssmlt][mmlt][stat]") {
    const int B = 4, K = 16;
    const SceneDesc desc = cornell(16, 5);
    for (int k : {2, 3, 5}) {
        RenderOptions mmlt = rstats::renderOptions(TracerKind::MMLT, 256, 0, k, k);
        mmlt.chains = 1024;
        mmlt.bootstrap = 1 << 14;
        const power::Runs ref = power::tracerRuns(desc, mmlt, K, 24000 + 100 * uint64_t(k), B)[0];
        const power::Runs m = pssmltRuns(desc, pssmltOptions(256, 0, k, k, 1024, 1 << 14), K, 25000 + 100 * uint64_t(k), B);
        power::compare(m, ref, "PSSMLT vs MMLT", "Cornell box, length " + std::to_string(k), kP, power::Claims{0.03, 0});
    }
}

// ---- 4. determinism and replay --------------------------------------------------------------

TEST_CASE("PSSMLT: a fixed seed gives a bit-identical image, for 1, 2 and 4 threads", "[pssmlt]") {
    const SceneDesc desc = caustic(16, 6);
    RenderOptions o = pssmltOptions(64, 42, 1, 6, 512, 4096);  // 32 iterations of 512 chains,
    o.passLength = 8;                                          // in 4 passes
    const RenderResult a = renderPssmlt(desc, o);
    const RenderResult b = renderPssmlt(desc, o);
    CHECK(a.image.rgb == b.image.rgb);
    CHECK(a.stats.mmlt.passes == 4);
    CHECK(a.stats.mmlt.acceptedSmall == b.stats.mmlt.acceptedSmall);
    RenderOptions one = o;
    one.threads = 1;
    CHECK(renderPssmlt(desc, one).image.rgb == a.image.rgb);
    RenderOptions four = o;
    four.threads = 4;
    RenderResult e;
    tbb::task_arena(4).execute([&] { e = renderPssmlt(desc, four); });
    CHECK(e.image.rgb == a.image.rgb);
    CHECK(e.stats.mmlt.b == a.stats.mmlt.b);
    RenderOptions other = o;
    other.seed = 43;
    CHECK(renderPssmlt(desc, other).image.rgb != a.image.rgb);
}

TEST_CASE("PSSMLT: every seeded chain replays its pool sample bit for bit", "[pssmlt]") {
    // Over glass and mirrors, a light above a drop ceiling, 64 segments, and media (a
    // rough glass ball of scattering medium; the grid furnace), 1 and 2 threads, 3 and 1024
    // chains (32 iterations each), restarted every 16 iterations from pools of fresh samples
    // and the previous pass's large steps.
    const std::vector<std::pair<std::string, SceneDesc>> cases = {
        {"caustic", caustic(12, 12)},
        {"seed room", seedRoom(16, 12)},
        {"Cornell box, 64 segments", cornell(16, 64)},
        {"glass ball of milk", media_scenes::load("pssmlt-glass.pbrt", media_scenes::glassBall())},
        {"grid furnace", gridFurnace()}};
    for (const auto& [name, desc] : cases)
        for (int threads : {1, 2})
            for (int chains : {3, 1024}) {
                const int spp = chains * 32 / (desc.settings.width * desc.settings.height);
                RenderOptions o = pssmltOptions(std::max(spp, 1), 77, 1, desc.settings.maxPathLength, chains, 2048, threads);
                o.passLength = 16;
                const RenderResult r = renderPssmlt(desc, o);
                INFO(name << ", " << threads << " threads, " << chains << " chains: " << r.stats.mmlt.replayed << " seeds replayed in "
                          << r.stats.mmlt.passes << " passes");
                CHECK(r.stats.mmlt.passes >= 2);
                CHECK(r.stats.mmlt.chainsRun == uint32_t(chains));
                CHECK(r.stats.mmlt.replayed >= 2 * uint64_t(chains));
            }
}

// ---- 5. formats and the command line --------------------------------------------------------

TEST_CASE("PSSMLT: the thesis format's Tracer and Mitsuba's pssmlt integrator choose it", "[pssmlt][scene]") {
    const SceneDesc t = loadSceneFromString(R"(<Scene><Settings><Tracer name="PSSMLT"/></Settings>
  <Camera Type="Camera"><Position x="0" y="0" z="-3"/><LookAt x="0" y="0" z="0"/><FOV value="45"/></Camera></Scene>)",
                                            "t.xml", ".");
    CHECK(t.settings.tracer == TracerKind::PSSMLT);
    const std::string dir = rstats::tempDir("pssmlt-mitsuba");
    std::ofstream(dir + "/m.xml") << R"(<scene version="3.0.0"><integrator type="pssmlt"/>
  <sensor type="perspective"><film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film></sensor>
  <emitter type="constant"/></scene>)";
    CHECK(loadScene(dir + "/m.xml").settings.tracer == TracerKind::PSSMLT);
    std::filesystem::remove_all(dir);
}

TEST_CASE("PSSMLT: length images are refused, --tracer pssmlt writes its --stats figures", "[pssmlt][cli]") {
    RenderOptions o = pssmltOptions(4, 1, 1, 5, 256);
    o.lengthImages = true;
    CHECK_THROWS_AS(render(cornell(8, 5), o), InputError);
    const std::string dir = rstats::tempDir("pssmlt-cli");
    const std::string cmd = std::string("'") + WAVEMMLT_BIN + "' '" + WAVEMMLT_TEST_DATA +
                            "/scenes/bitterli-cornell/bitterli-cornell-256.xml' --tracer pssmlt --width 32 --height 32 "
                            "--spp 8 --chains 512 --quiet -o '" +
                            dir + "/out.exr' --stats '" + dir + "/stats.json'";
    const int status = std::system(cmd.c_str());
    REQUIRE(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 0);
    std::ifstream f(dir + "/stats.json");
    std::stringstream ss;
    ss << f.rdbuf();
    const std::string json = ss.str();
    CHECK(json.find("\"tracer\": \"pssmlt\"") != std::string::npos);
    for (const char* key : {"pssmlt_b", "pssmlt_mutations_per_second", "pssmlt_tasks_per_round", "pssmlt_replay_mismatches",
                            "pssmlt_acceptance_small", "pssmlt_acceptance_large", "pssmlt_chains_run"}) {
        INFO(key);
        CHECK(std::isfinite(rstats::jsonNumber(json, key)));
    }
    CHECK(rstats::jsonNumber(json, "pssmlt_replay_mismatches") == 0);
    CHECK(rstats::jsonNumber(json, "pssmlt_chains_run") == 512);
    CHECK(rstats::jsonNumber(json, "pssmlt_mutations_per_second") > 0);
    CHECK(json.find("\"pssmlt_acceptance\": {\"small\": ") != std::string::npos);
    CHECK(json.find("mmlt_") == std::string::npos);
    std::filesystem::remove_all(dir);
}
