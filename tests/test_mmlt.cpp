// Multiplexed Metropolis light transport (--tracer mmlt, mmlt.md), with tolerances from the
// measured variance over K independent runs (render_stats.h), never hand-tuned. Runs with
// different seeds are independent (every random number is hashed from the seed), so their
// per-run means give a valid z test however correlated the samples inside a run are.
// An MMLT image's mean luminance is sum_k b_k (every proposal splats luminance b_k /
// chains_k in all), an error shared by all pixels of a run; images are compared with
// power.h: brightness (one z), blocks (max |z|, valid under that shared error) and the
// blocks' shape (brightness divided out), each one test at p = 1e-4.
//  1. the bootstrap: b_k = BPT's mean image luminance by path length, within the two
//     tracers' standard errors; the image's mean luminance is sum_k b_k; chains are
//     allocated by largest remainders, never drawn at random; the default bootstrap is
//     spread over the lengths by their probed b_k;
//  2. MMLT image = BPT image, with stated power, per length: test_mmlt_power.cpp;
//  3. invariance: 1, 64 and 65536 chains, seeds far apart, bootstrap counts 1024 to 2^18;
//  4. extremes: ProbLarge 1e-3 and 1, MaxPathLength 1 and 64; a scene where no light
//     reaches the camera is an InputError (and exit status 2 on the command line);
//  5. replay: every seeded chain reproduces its bootstrap sample's contribution bit for bit
//     (checked in every render here, and over glass, mirrors, textures and 64 segments);
//  6. a fixed seed gives a bit-identical image, run twice and for 1, 2 and 4 threads.
// Set WMLT_TEST_VERBOSE=1 to print every comparison's statistics.
#include <catch2/catch.hpp>

#include <sys/wait.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "kernels/check.h"
#include "power.h"
#include "render_stats.h"
#include "stages/mmlt/mmlt.h"
#include "wavemmlt/error.h"
#include "wavemmlt/image.h"
#include "wavemmlt/render.h"
#include "wavemmlt/scene_desc.h"

using namespace wmlt;

namespace {

bool verbose() { return std::getenv("WMLT_TEST_VERBOSE") != nullptr; }

double lum(double r, double g, double b) { return 0.2126 * r + 0.7152 * g + 0.0722 * b; }

double meanLuminance(const Image& im) {
    double s = 0;
    const size_t n = size_t(im.width) * im.height;
    for (size_t i = 0; i < n; ++i) s += lum(im.rgb[i * 3], im.rgb[i * 3 + 1], im.rgb[i * 3 + 2]);
    return s / double(n);
}

RenderOptions mmltOptions(int spp, uint64_t seed, int minLength, int maxLength, int chains, int bootstrap = 0, float probLarge = 0.3f,
                          int threads = 2) {
    RenderOptions o = rstats::renderOptions(TracerKind::MMLT, spp, seed, minLength, maxLength, threads);
    o.chains = chains;
    o.bootstrap = bootstrap;
    o.probLarge = probLarge;
    // the luminance target (exponent 1, the default): these tests check what holds for it, b_k
    // as BPT's mean luminance per length and the image's as sum_k b_k (the tempered target:
    // test_mmlt_levers.cpp)
    o.mmltTargetExponent = 1;
    return o;
}

// An MMLT render with the checks every run must pass: no replay mismatch, nothing
// discarded, a finite image, the mutation counts asked for, and the normalisation: each
// proposal splats a total luminance of b_k,p / chains_k,p (a F'/c' + (1 - a) F/c) in pass p,
// so the image's mean luminance is sum_k b_k (b_k: the passes' pool means weighted by
// their iterations) up to float rounding.
RenderResult renderMmlt(const SceneDesc& desc, const RenderOptions& o) {
    RenderResult r = render(desc, o);
    REQUIRE(r.stats.tracer == "mmlt");
    const RenderStats::Mmlt& m = r.stats.mmlt;
    CHECK(m.replayMismatches == 0);
    CHECK(r.stats.samplesNonfiniteDiscarded == 0);
    for (float v : r.image.rgb) REQUIRE(std::isfinite(v));
    uint64_t proposals = 0;
    double bSum = 0;
    for (size_t k = 0; k < m.chains.size(); ++k) {
        bSum += m.b[k];
        if (k < size_t(o.minPathLength) || k > size_t(o.maxPathLength)) {
            CHECK(m.chainsSeeded[k] == 0);
            CHECK(m.b[k] == 0.0);
        }
        CHECK((m.chainsSeeded[k] > 0) == (m.b[k] > 0));
        CHECK(m.distinctSeeds[k] <= m.chainsSeeded[k]);
        CHECK(m.proposedSmall[k] + m.proposedLarge[k] + m.proposedFilm[k] == m.proposals[k]);  // an iteration's three kinds
        proposals += m.proposals[k];
    }
    CHECK(m.mutations == proposals);
    CHECK(m.passes >= 1);
    CHECK(double(m.mutations) >= double(o.spp) * r.image.width * r.image.height);
    if (o.lengthImages) {  // the lengths' images add up to the image
        REQUIRE(r.lengthImages.size() == size_t(o.maxPathLength) + 1);
        for (size_t i = 0; i < r.image.rgb.size(); ++i) {
            double sum = 0;
            for (const Image& l : r.lengthImages) sum += l.rgb.empty() ? 0.0 : double(l.rgb[i]);
            REQUIRE(sum == Approx(r.image.rgb[i]).epsilon(1e-5).margin(1e-12));
        }
    }
    if (o.bootstrap > 0)
        for (int k = std::max(1, o.minPathLength); k <= o.maxPathLength; ++k) CHECK(m.bootstrapSamples[size_t(k)] == uint64_t(o.bootstrap));
    // (With the relative target a proposal splats b_k / chains_k / scale: b is in its units.)
    if (m.target == MmltTarget::Luminance) CHECK(meanLuminance(r.image) == Approx(bSum).epsilon(1e-5));
    return r;
}

// a against ref with power.h: brightness, blocks and the blocks' shape, each one test at
// p; the brightness error the comparison detects (power 0.9) is printed with WMLT_TEST_VERBOSE.
void checkSameImage(const power::Runs& a, const power::Runs& ref, double p, const std::string& what) {
    for (const power::Verdict& v : {power::brightness(a, ref, p), power::blocks(a, ref, p), power::scatter(a, ref, p)}) {
        INFO(what << ", " << v.text);
        if (verbose()) WARN(what << ", " << v.text);
        CHECK(v.pass);
    }
}

// K BPT runs at spp, seeds seed0 + i.
power::Runs bptRuns(const SceneDesc& desc, int spp, int K, int minLength, int maxLength, uint64_t seed0, int B) {
    power::Runs runs(B);
    for (int i = 0; i < K; ++i) {
        RenderResult r = render(desc, rstats::renderOptions(TracerKind::BPT, spp, seed0 + i, minLength, maxLength));
        REQUIRE(r.stats.samplesNonfiniteDiscarded == 0);
        runs.add(r);
    }
    return runs;
}

// K MMLT runs, seeds seed0 + i, with options o (its seed replaced).
power::Runs mmltRuns(const SceneDesc& desc, RenderOptions o, int K, uint64_t seed0, int B) {
    power::Runs runs(B);
    for (int i = 0; i < K; ++i) {
        o.seed = seed0 + uint64_t(i);
        runs.add(renderMmlt(desc, o));
    }
    return runs;
}

SceneDesc caustic(int maxLength, int size = 32) {
    SceneDesc d = loadSceneFromString(rstats::causticXml(32, maxLength), "caustic.xml", ".");
    d.settings.width = d.settings.height = size;
    return d;
}

SceneDesc cornell(int size, int maxLength) {
    SceneDesc d = rstats::cornell64(maxLength);
    d.settings.width = d.settings.height = size;
    return d;
}

// The seed room (tests/data/scenes/seed-room): its only light is above a drop ceiling, so
// every path to the camera has length >= 3.
SceneDesc seedRoom(int size, int maxLength) {
    SceneDesc d = loadScene(std::string(WAVEMMLT_TEST_DATA) + "/scenes/seed-room/seed-room.xml");
    d.settings.width = d.settings.height = size;
    d.settings.maxPathLength = maxLength;
    return d;
}

// A floor seen from above; the only light is under it, facing down into the void.
const char* kNoLightXml = R"(<Scene>
  <Settings><Width value="16"/><Height value="16"/><MaxPathLength value="8"/></Settings>
  <Camera Type="Camera"><Position x="0" y="3" z="-3"/><LookAt x="0" y="0" z="0"/><FOV value="45"/></Camera>
  <Shader Type="Matte" ID="0"><Diffuse r="0.8" g="0.8" b="0.8"/></Shader>
  <Geometry Type="Plane" ID="floor"><Position x="0" y="0" z="0"/><Width value="4"/><Depth value="4"/><Shader value="0"/></Geometry>
  <Light Type="Area" ID="lamp"><Position x="0" y="-1" z="0"/><Width value="1"/><Depth value="1"/>
    <Intensity value="10"/><Colour r="1" g="1" b="1"/></Light>
</Scene>
)";

}  // namespace

// ---- 1. the bootstrap ---------------------------------------------------------------------

TEST_CASE("MMLT bootstrap: b_k equals BPT's mean luminance per path length", "[mmlt][stat]") {
    // K runs of each tracer: MMLT with a large bootstrap and a token chain phase (its
    // b_k: the mean c of the bootstrap and the large steps), BPT's lengthMeanLuminance; z per
    // length from both standard errors, max |z| over the lengths at p = 1e-4 per scene.
    // Lengths that carry no light (the seed room's 1 and 2) must be exactly 0 in both.
    struct Case {
        const char* name;
        SceneDesc desc;
        int maxLength, size;
    };
    std::vector<Case> cases = {
        {"Cornell box", cornell(16, 5), 5, 16}, {"caustic scene", caustic(6, 16), 6, 16}, {"seed room", seedRoom(16, 6), 6, 16}};
    const int K = 8;
    for (const Case& cs : cases) {
        rstats::RunStats m, b;
        for (int i = 0; i < K; ++i) {
            RenderResult a = renderMmlt(cs.desc, mmltOptions(1, 100 + i, 1, cs.maxLength, 64, 1 << 16));
            REQUIRE(a.stats.mmlt.b.size() == size_t(cs.maxLength + 1));
            m.add(std::vector<double>(a.stats.mmlt.b.begin() + 1, a.stats.mmlt.b.end()));
            RenderResult r = render(cs.desc, rstats::renderOptions(TracerKind::BPT, 256, 600 + i, 1, cs.maxLength));
            REQUIRE(r.stats.lengthMeanLuminance.size() > size_t(cs.maxLength));
            b.add(std::vector<double>(r.stats.lengthMeanLuminance.begin() + 1, r.stats.lengthMeanLuminance.begin() + cs.maxLength + 1));
        }
        std::ostringstream lengths;
        for (size_t k = 0; k < m.size(); ++k)
            lengths << "\n  k = " << k + 1 << ": b_k " << m.mean(k) << " +- " << m.se(k) << ", BPT " << b.mean(k) << " +- " << b.se(k);
        const power::Verdict v = power::worstOf(m, b, 1e-4, "length");  // max |z| over the lengths
        INFO(cs.name << ": " << v.text << lengths.str());
        if (verbose()) WARN(cs.name << ": " << v.text << lengths.str());
        CHECK(v.pass);
    }
}

TEST_CASE("MMLT allocates chains to lengths by largest remainders, never at random", "[mmlt]") {
    // C chains: floor(C b_k / sum b) or one more for every length, C in all (b_k of the
    // bootstrap, which is all the first pass's allocation knows: one pass here); a length
    // with b_k > 0 gets at least one chain. Two seeds with different b_k give the allocation
    // of their own b_k (no random draw: pbrt's multinomial choice leaves a per-seed error).
    const SceneDesc desc = seedRoom(16, 6);
    for (uint64_t seed : {1u, 2u}) {
        for (int C : {1, 7, 64, 65536}) {
            RenderOptions o = mmltOptions(256, seed, 1, 6, C, 4096);
            o.passLength = 1 << 30;
            RenderResult r = renderMmlt(desc, o);
            const RenderStats::Mmlt& m = r.stats.mmlt;
            REQUIRE(m.passes == 1);
            double bSum = 0;
            uint32_t total = 0;
            int positive = 0;
            for (size_t k = 0; k < m.bBootstrap.size(); ++k) {
                bSum += m.bBootstrap[k];
                total += m.chains[k];
                positive += m.bBootstrap[k] > 0;
            }
            INFO("seed " << seed << ", chains " << C);
            CHECK(m.chains[1] == 0);
            CHECK(m.chains[2] == 0);
            CHECK(total == uint32_t(std::max(C, positive)));
            if (C >= 64) {
                for (size_t k = 3; k < m.bBootstrap.size(); ++k) {
                    const double share = double(C) * m.bBootstrap[k] / bSum;
                    INFO("k = " << k << ": share " << share << ", chains " << m.chains[k]);
                    CHECK(double(m.chains[k]) >= std::floor(share));
                    CHECK(double(m.chains[k]) <= std::floor(share) + 1);
                }
            } else {
                for (size_t k = 3; k < m.bBootstrap.size(); ++k) CHECK(m.chains[k] >= 1);
            }
        }
    }
}

TEST_CASE("MMLT's default bootstrap is spread over the lengths half equally, half by their probed b_k", "[mmlt]") {
    // The bootstrap (mmlt_pool.cpp, MmltRender::bootstrap): 5% of the mutations or two
    // samples per chain in all, half of it split equally over the lengths, half in proportion
    // to b_k as a probe of 256 samples per length estimates it, at least 512 each. On the
    // seed room lengths 1 and 2 carry no light: they get the equal half's part only, and the
    // lit lengths share the rest.
    const SceneDesc desc = seedRoom(16, 6);
    for (uint64_t seed : {1u, 2u}) {
        RenderOptions o = mmltOptions(256, seed, 1, 6, 4096);
        RenderResult r = renderMmlt(desc, o);
        const RenderStats::Mmlt& m = r.stats.mmlt;
        const double whole = std::max(0.05 * 256 * 16 * 16, 2.0 * 4096), equal = std::ceil(whole * 0.5 / 6);
        uint64_t total = 0, most = 0;
        for (int k = 1; k <= 6; ++k) {
            INFO("seed " << seed << ", k = " << k << ": " << m.bootstrapSamples[size_t(k)] << " samples");
            CHECK(double(m.bootstrapSamples[size_t(k)]) >= std::max(512.0, equal));
            total += m.bootstrapSamples[size_t(k)];
            most = std::max(most, m.bootstrapSamples[size_t(k)]);
        }
        CHECK(double(m.bootstrapSamples[1]) == std::max(512.0, equal));
        CHECK(double(m.bootstrapSamples[2]) == std::max(512.0, equal));
        CHECK(double(total) >= whole);
        CHECK(double(total) <= whole + 6 * 513);
        CHECK(double(most) >= equal + 0.5 * whole / 4);  // four lit lengths: one has at least a quarter of the probed half
    }
}

// ---- 2. MMLT = BPT ------------------------------------------------------------------------

// MMLT = BPT on the Cornell box, the caustic scene, the seed room and more scenes, with
// stated power: test_mmlt_power.cpp.

// ---- 3. invariance --------------------------------------------------------------------------

TEST_CASE("MMLT: 1, 64 and 65536 chains, seeds far apart and bootstrap counts give one image", "[mmlt][render][stat]") {
    // One BPT reference (16 x 16 Cornell box, 4 x 4 blocks), every MMLT setting against it,
    // each comparison at p. One chain means one chain per
    // path length with b_k > 0 (5 here), each making spp * pixels / 5 proposals.
    const int K = 8, B = 4, L = 5;
    const double p = 1e-4;
    const SceneDesc desc = cornell(16, L);
    power::Runs ref = bptRuns(desc, 64, K, 1, L, 3000, B);
    checkSameImage(mmltRuns(desc, mmltOptions(1024, 0, 1, L, 1), K, 3100, B), ref, p, "1 chain");
    checkSameImage(mmltRuns(desc, mmltOptions(1024, 0, 1, L, 64), K, 3200, B), ref, p, "64 chains");
    checkSameImage(mmltRuns(desc, mmltOptions(256, 0, 1, L, 65536), K, 3300, B), ref, p, "65536 chains");
    checkSameImage(mmltRuns(desc, mmltOptions(512, 0, 1, L, 1024), K, (uint64_t(1) << 62) - 100, B), ref, p, "seeds near 2^62");
    checkSameImage(mmltRuns(desc, mmltOptions(512, 0, 1, L, 1024, 1024), K, 3400, B), ref, p, "bootstrap 1024");
    checkSameImage(mmltRuns(desc, mmltOptions(512, 0, 1, L, 1024, 1 << 18), K, 3500, B), ref, p, "bootstrap 262144");
}

TEST_CASE("MMLT: the spread between seeds shrinks in proportion to the work", "[mmlt][render][stat]") {
    // pbrt-v4's open MLT report: each seed's image looks converged, yet seeds (and bootstrap
    // sizes) converge to different images, i.e. an error fixed per seed that more mutations
    // never remove (a random allocation of chains to lengths leaves one). Here the variance
    // between K seeds' images, S = sum over blocks and channels of the K-run variance, must
    // fall as 1 / work when the mutations grow W = 8 times, the bootstrap held at 4096
    // samples (b_k takes in every large step, so its error shrinks with the mutations too):
    // E[S_hi / S_lo] = 1 / W. An error fixed per seed keeps the ratio near 1 once it
    // dominates. The per-run squared distances to the group mean d_i are (nearly)
    // independent across seeds, so their spread gives each S a relative standard error, and
    // ln(S_hi / S_lo) one of sqrt(se_lo^2 + se_hi^2): the test is |ln(W S_hi / S_lo)| <=
    // z(p / 2) times it, at p = 1e-4. With K = 32 that fails a ratio 2.2 times too large
    // (printed: the factor it detects with power 0.9).
    const int K = 32, B = 4, L = 5, W = 8;
    const SceneDesc desc = cornell(16, L);
    struct Level {
        int spp;
        double S = 0, relSe = 0;
    };
    Level levels[2] = {{256}, {256 * W}};
    for (Level& lv : levels) {
        std::vector<std::vector<double>> x;
        for (int i = 0; i < K; ++i) {
            RenderResult r = renderMmlt(desc, mmltOptions(lv.spp, 7000 + uint64_t(lv.spp) + i, 1, L, 64, 4096));
            std::vector<double> v;
            for (int c = 0; c < 3; ++c) {
                std::vector<double> m = rstats::blockMeans(r.image, B, c);
                v.insert(v.end(), m.begin(), m.end());
            }
            x.push_back(v);
        }
        std::vector<double> mean(x[0].size(), 0.0), d(K, 0.0);
        for (const auto& v : x)
            for (size_t j = 0; j < v.size(); ++j) mean[j] += v[j] / K;
        double sumD = 0, sumD2 = 0;
        for (int i = 0; i < K; ++i) {
            for (size_t j = 0; j < mean.size(); ++j) d[size_t(i)] += (x[size_t(i)][j] - mean[j]) * (x[size_t(i)][j] - mean[j]);
            sumD += d[size_t(i)];
            sumD2 += d[size_t(i)] * d[size_t(i)];
        }
        lv.S = sumD / (K - 1);
        const double md = sumD / K;
        lv.relSe = std::sqrt(std::max(0.0, sumD2 / K - md * md) / (K - 1)) / md;
    }
    const double ratio = levels[1].S / levels[0].S;
    const double seLn = std::sqrt(levels[0].relSe * levels[0].relSe + levels[1].relSe * levels[1].relSe);
    const double zc = power::zCritical(1e-4), z = std::log(ratio * W) / seLn;
    const double detects = std::exp(power::detectableInSe(zc) * seLn);
    std::ostringstream msg;
    msg << "S at " << levels[0].spp << " mutations per pixel: " << levels[0].S << " (relative se " << levels[0].relSe << "), at " << levels[1].spp
        << ": " << levels[1].S << " (relative se " << levels[1].relSe << "); ratio " << ratio << " (1/" << W << " expected), z " << z
        << " (allowed +-" << zc << "); fails a ratio " << detects << " times too large or small (power 0.9)";
    INFO(msg.str());
    if (verbose()) WARN(msg.str());
    CHECK(std::fabs(z) <= zc);
    CHECK(detects <= 2.5);  // the power it claims
}

// ---- 4. extremes ----------------------------------------------------------------------------

TEST_CASE("MMLT with ProbLarge 1e-3 and 1 matches BPT", "[mmlt][render][stat]") {
    const int K = 8, B = 4, L = 5;
    const SceneDesc desc = cornell(16, L);
    power::Runs ref = bptRuns(desc, 64, K, 1, L, 4000, B);
    for (float pl : {1e-3f, 1.0f}) {
        RenderOptions o = mmltOptions(1024, 0, 1, L, 256, 0, pl);
        power::Runs m = mmltRuns(desc, o, K, pl < 1 ? 4100 : 4200, B);
        checkSameImage(m, ref, 1e-4, "ProbLarge " + std::to_string(pl));
    }
    // ProbLarge 1: every proposal is a large step; 1e-3: (almost) none is.
    RenderResult a = renderMmlt(desc, mmltOptions(64, 9, 1, L, 256, 0, 1.0f));
    for (size_t k = 1; k <= size_t(L); ++k) CHECK(a.stats.mmlt.proposedSmall[k] == 0);
    RenderResult b = renderMmlt(desc, mmltOptions(64, 9, 1, L, 256, 0, 1e-3f));
    uint64_t small = 0, large = 0;
    for (size_t k = 1; k <= size_t(L); ++k) {
        small += b.stats.mmlt.proposedSmall[k];
        large += b.stats.mmlt.proposedLarge[k];
    }
    CHECK(double(large) < 3e-3 * double(small + large));
}

TEST_CASE("MMLT with MaxPathLength 1 and 64 matches BPT", "[mmlt][render][stat]") {
    const int K = 8, B = 4;
    for (int L : {1, 64}) {
        const SceneDesc desc = cornell(16, L);
        power::Runs ref = bptRuns(desc, L == 1 ? 64 : 16, K, 1, L, 5000 + 100 * L, B);
        power::Runs m = mmltRuns(desc, mmltOptions(L == 1 ? 256 : 128, 0, 1, L, 1024), K, 5050 + 100 * L, B);
        checkSameImage(m, ref, 1e-4, "MaxPathLength " + std::to_string(L));
    }
}

TEST_CASE("MMLT: a scene where no light reaches the camera is an InputError", "[mmlt]") {
    auto expectNoLight = [](const SceneDesc& desc, int minLength, int maxLength) {
        try {
            render(desc, mmltOptions(4, 1, minLength, maxLength, 64));
            FAIL("render() returned");
        } catch (const InputError& e) {
            INFO(e.what());
            CHECK(std::string(e.what()).find("no light reaches the camera") != std::string::npos);
        }
    };
    // The only light faces away from everything.
    expectNoLight(loadSceneFromString(kNoLightXml, "nolight.xml", "."), 1, 8);
    // Length 1 only, and the light is outside the view (every other length carries light).
    expectNoLight(caustic(6), 1, 1);
    // The seed room's light needs at least 3 segments.
    expectNoLight(seedRoom(16, 2), 1, 2);
}

TEST_CASE("MMLT command line: no light reaching the camera exits with status 2 and says why", "[mmlt][cli]") {
    const std::string dir = rstats::tempDir("mmlt-nolight");
    const std::string scene = dir + "/nolight.xml", out = dir + "/out.pfm", err = dir + "/err.txt";
    std::ofstream(scene) << kNoLightXml;
    const std::string cmd =
        std::string("'") + WAVEMMLT_BIN + "' '" + scene + "' --tracer mmlt --spp 4 --quiet -o '" + out + "' > /dev/null 2> '" + err + "'";
    const int st = std::system(cmd.c_str());
    REQUIRE(st != -1);
    REQUIRE(WIFEXITED(st));
    CHECK(WEXITSTATUS(st) == 2);
    std::stringstream msg;
    msg << std::ifstream(err).rdbuf();
    INFO("stderr: " << msg.str());
    CHECK(msg.str().find("no light reaches the camera") != std::string::npos);
    CHECK(!std::filesystem::exists(out));
    std::filesystem::remove_all(dir);
}

TEST_CASE("MMLT: the image at MaxPathLength 64 is the sum of its lengths' images", "[mmlt]") {
    // One film serves every length; with RenderOptions::lengthImages each length's splats
    // also go to a film of their own. renderMmlt checks that those images add up to the
    // image pixel by pixel (to float rounding), and that the image's mean luminance is
    // sum_k b_k; here each length's image also carries its own b_k.
    RenderOptions o = mmltOptions(16, 5, 1, 64, 1024, 1024);
    o.lengthImages = true;
    const RenderResult r = renderMmlt(cornell(16, 64), o);
    REQUIRE(r.lengthImages.size() == 65);
    int lit = 0;
    for (int k = 1; k <= 64; ++k) {
        INFO("k = " << k);
        CHECK(meanLuminance(r.lengthImages[size_t(k)]) == Approx(r.stats.mmlt.b[size_t(k)]).epsilon(1e-4).margin(1e-12));
        lit += r.stats.mmlt.b[size_t(k)] > 0;
    }
    CHECK(lit >= 40);  // the Cornell box's light reaches most lengths
}

// ---- 5. replay ------------------------------------------------------------------------------

TEST_CASE("MMLT: every seeded chain replays its pool sample bit for bit", "[mmlt]") {
    // renderMmlt checks replayMismatches == 0 in every render of this file; here over
    // glass, mirrors, a textured floor and paths of up to 64 segments, 1 and 2 threads, few
    // and many chains, restarted every 16 iterations from pools that hold both fresh samples
    // and the previous pass's large steps.
    struct Case {
        SceneDesc desc;
        int maxLength;
    };
    std::vector<Case> cases = {{caustic(12, 16), 12}, {seedRoom(16, 12), 12}, {cornell(16, 64), 64}};
    for (const Case& cs : cases)
        for (int threads : {1, 2})
            for (int chains : {3, 65536}) {
                RenderOptions o = mmltOptions(chains > 3 ? 64 : 1, 77, 1, cs.maxLength, chains, 2048, 0.3f, threads);
                o.passLength = 16;
                RenderResult r = renderMmlt(cs.desc, o);
                uint64_t seeded = 0;
                for (uint64_t n : r.stats.mmlt.chainsSeeded) seeded += n;
                INFO("MaxPathLength " << cs.maxLength << ", " << threads << " threads, " << seeded << " chains seeded in " << r.stats.mmlt.passes
                                      << " passes");
                CHECK(seeded >= uint64_t(std::min(chains, 16 * 16)) * r.stats.mmlt.passes);
                CHECK(r.stats.mmlt.replayed >= uint64_t(std::min(chains, 16 * 16 * 64)));  // every seed of the first pass
                CHECK(r.stats.mmlt.replayMismatches == 0);
            }
}

// ---- 6. determinism -------------------------------------------------------------------------

TEST_CASE("MMLT: a fixed seed gives a bit-identical image, for 1, 2 and 4 threads", "[mmlt]") {
    const SceneDesc desc = caustic(6);
    const RenderOptions o = mmltOptions(64, 42, 1, 6, 4096, 4096, 0.3f, 2);
    RenderResult a = renderMmlt(desc, o);
    RenderResult b = renderMmlt(desc, o);
    CHECK(a.image.rgb == b.image.rgb);
    CHECK(a.stats.mmlt.b == b.stats.mmlt.b);
    CHECK(a.stats.mmlt.chains == b.stats.mmlt.chains);
    CHECK(a.stats.mmlt.acceptedSmall == b.stats.mmlt.acceptedSmall);
    CHECK(a.stats.mmlt.acceptedLarge == b.stats.mmlt.acceptedLarge);
    RenderOptions one = o;
    one.threads = 1;
    RenderResult c = renderMmlt(desc, one);
    CHECK(a.image.rgb == c.image.rgb);
    // 4 threads (in an arena of 4, whatever the machine): the rounds merge the film and the
    // pools in parallel from 4 threads on, in the same order per pixel and per pool.
    RenderOptions four = o;
    four.threads = 4;
    RenderResult e;
    tbb::task_arena(4).execute([&] { e = renderMmlt(desc, four); });
    CHECK(a.image.rgb == e.image.rgb);
    CHECK(a.stats.mmlt.b == e.stats.mmlt.b);
    RenderOptions other = o;
    other.seed = 43;
    RenderResult d = renderMmlt(desc, other);
    CHECK(a.image.rgb != d.image.rgb);
}

TEST_CASE("MMLT --chains auto: the count as a pure function of the mutations, at its edges", "[mmlt]") {
    const double T = kAutoIterationsPerChain;
    // A tiny render (none, one, a few thousand mutations): the least, 16 batches.
    CHECK(autoChains(0) == kAutoChainsLeast);
    CHECK(autoChains(1) == kAutoChainsLeast);
    CHECK(autoChains(-5) == kAutoChainsLeast);
    CHECK(autoChains(double(kAutoChainsLeast) * T) == kAutoChainsLeast);
    // Between the edges: mutations / T, rounded down to whole batches of 256 chains.
    CHECK(autoChains((4096.0 + 256.0) * T) == 4352u);
    CHECK(autoChains((4096.0 + 256.0) * T - 1) == 4096u);
    CHECK(autoChains(20000.0 * T) == 19968u);  // 78 batches
    for (double m = 1e6; m < 1e12; m *= 1.7) {
        const uint32_t c = autoChains(m);
        INFO("mutations " << m);
        CHECK(c % 256 == 0);
        CHECK(c >= kAutoChainsLeast);
        CHECK(c <= kAutoChainsMost);
        CHECK(autoChains(m * 1.7) >= c);  // more mutations, never fewer chains
    }
    // A huge render: never more than 65536 (an explicit --chains may ask for more).
    CHECK(autoChains(double(kAutoChainsMost) * T) == kAutoChainsMost);
    CHECK(autoChains(1e18) == kAutoChainsMost);
    // Under --time the least keeps every worker fed (2 batches of 256 each), never above the most.
    CHECK(autoChains(1e6, T, 1024) == 1024u);
    CHECK(autoChains(1e6, T, 1 << 20) == kAutoChainsMost);
    CHECK(autoChains(1e9, T, 1024, 65536) == 65536u);
}

TEST_CASE(
    "MMLT --chains auto: the chosen count runs, a seed gives one image for 1, 2 and 4 threads, "
    "and an explicit 65536 runs 65536",
    "[mmlt]") {
    const SceneDesc desc = caustic(6);
    RenderOptions o = mmltOptions(64, 42, 1, 6, 0, 4096, 0.3f, 2);  // chains 0: auto
    const double mutations = 64.0 * 32 * 32;
    RenderResult a = renderMmlt(desc, o);
    CHECK(a.stats.mmlt.chainsAuto);
    CHECK(a.stats.mmlt.chainsAsked == 0);
    CHECK(a.stats.mmlt.chainsRun == autoChains(mutations));
    CHECK(a.stats.mmlt.chainsReason.find("auto: 4096 for 65.5 k mutations") == 0);
    uint64_t sum = 0;
    for (uint32_t c : a.stats.mmlt.chains) sum += c;
    CHECK(sum == a.stats.mmlt.chainsRun);
    RenderOptions one = o;
    one.threads = 1;
    RenderResult b = renderMmlt(desc, one);
    CHECK(b.stats.mmlt.chainsRun == a.stats.mmlt.chainsRun);
    CHECK(a.image.rgb == b.image.rgb);
    RenderOptions four = o;
    four.threads = 4;
    RenderResult c;
    tbb::task_arena(4).execute([&] { c = renderMmlt(desc, four); });
    CHECK(c.stats.mmlt.chainsRun == a.stats.mmlt.chainsRun);
    CHECK(a.image.rgb == c.image.rgb);
    // An explicit count runs as asked, whatever auto would choose.
    RenderOptions wide = o;
    wide.chains = 65536;
    RenderResult w = renderMmlt(desc, wide);
    CHECK_FALSE(w.stats.mmlt.chainsAuto);
    CHECK(w.stats.mmlt.chainsAsked == 65536u);
    CHECK(w.stats.mmlt.chainsRun == 65536u);
    CHECK(w.stats.mmlt.chainsReason == "--chains 65536");
    // Fewer mutations than the least: no more chains than mutations, as for an explicit count.
    RenderOptions tiny = o;
    tiny.spp = 1;
    RenderResult t = renderMmlt(desc, tiny);
    CHECK(t.stats.mmlt.chainsRun == 1024u);
    CHECK(t.stats.mmlt.chainsReason.find("no more than the 1024 mutations") != std::string::npos);
}

TEST_CASE("MMLT --chains auto under --time: chosen after the bootstrap, from its rate and the workers", "[mmlt]") {
    const SceneDesc desc = caustic(6);
    RenderOptions o = mmltOptions(1, 42, 1, 6, 0, 0, 0.3f, 2);
    o.timeBudget = 1.0;
    const RenderResult r = renderMmlt(desc, o);
    const RenderStats::Mmlt& m = r.stats.mmlt;
    CHECK(m.chainsAuto);
    INFO(m.chainsReason);
    CHECK(m.chainsReason.find("auto: ") == 0);
    CHECK(m.chainsReason.find("mutations the bootstrap's rate predicts") != std::string::npos);
    CHECK(m.chainsReason.find("2 workers") != std::string::npos);
    // At least 1024 (2 threads: 2 batches each is 1024), unless the 2% cap of --time says less.
    if (m.chainsReason.find("capped") == std::string::npos) {
        CHECK(m.chainsRun >= kAutoChainsLeastTimed);
        CHECK(m.chainsRun % 256 == 0);
    }
    CHECK(m.chainsRun <= kAutoChainsMost);
}

// A replay mismatch (issue 47) is an estimator bug: planted (RenderOptions::
// plantReplayMismatch), it is counted and reported by renderWarnings, which the application
// prints even with --quiet; where WMLT_DCHECKs are on (debug and sanitizer builds) it fails
// the render with an InvariantError. Without the plant, the same render reports nothing.
TEST_CASE("MMLT: a replay mismatch is reported, and fails the render where invariants are checked", "[mmlt]") {
    const SceneDesc desc = cornell(16, 4);
    RenderOptions o = mmltOptions(4, 1, 1, 4, 64);
    const RenderResult clean = render(desc, o);
    CHECK(clean.stats.mmlt.replayMismatches == 0);
    CHECK(renderWarnings(clean).empty());
    o.plantReplayMismatch = true;
#if WMLT_DCHECKS_ON
    CHECK_THROWS_AS(render(desc, o), InvariantError);
#else
    const RenderResult r = render(desc, o);
    CHECK(r.stats.mmlt.replayMismatches == 1);
    const std::vector<std::string> w = renderWarnings(r);
    REQUIRE(w.size() == 1);
    CHECK_THAT(w[0], Catch::StartsWith("1 of ") && Catch::Contains("replayed MMLT seeds evaluated differently") && Catch::Contains("estimator bug"));
#endif
}
