// One render split across ranks (mpirun; docs/mpi.md), against one process:
//  - the same seed gives the job the same samples as one process: PT's image is the same bytes
//    (each pixel is one rank's), the others' images equal to float rounding (the films are
//    summed per rank, then across ranks), MMLT's b_k and pools are the same bits on every
//    rank and in one process; the image does not depend on the threads per rank, and a
//    seed and a rank count give the same bytes every time;
//  - statistically ([stat]): K = 16 seeds with 2 and with 3 ranks against K seeds of one
//    process (other seeds), for every tracer (power.h: brightness, blocks, shape);
//  - the command line under mpirun: bad input gives one message and exit status 2 (no
//    hang: every child has a time limit), --time ends every rank together, SIGINT to mpirun
//    saves the image so far, --stats reports the ranks and the exchanges.
// Without MPI in the build each test says so and checks nothing else.
#include <catch2/catch.hpp>

#include <signal.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "child_process.h"
#include "power.h"
#include "render_stats.h"
#include "wavemmlt/image.h"
#include "wavemmlt/render.h"
#include "wavemmlt/scene_desc.h"

using namespace wmlt;

namespace {

const std::string kMpiexec = WAVEMMLT_MPIEXEC;
const std::string kRunner = WAVEMMLT_MPI_RUNNER;
const std::string kCornell = std::string(WAVEMMLT_TEST_DATA) + "/scenes/bitterli-cornell/bitterli-cornell-256.xml";
constexpr int kSize = 32, kMaxLength = 5;
constexpr double kLimit = 60;  // seconds any mpirun may take before the test kills it

bool mpiBuilt() {
    if (kMpiexec.empty()) WARN("this build has no MPI (libopenmpi-dev, openmpi-bin): the mpirun tests are skipped");
    return !kMpiexec.empty();
}

// mpirun on one machine without a network, as root in CI: shared memory between the ranks
// (vader; no single-copy mechanism, which containers often forbid), more ranks than cores
// allowed. Under AddressSanitizer, Open MPI's own allocations at exit are not reported
// (detect_leaks=0 for the ranks only; the single-process tests keep leak detection).
std::vector<std::string> mpiEnv() {
    const char* asan = std::getenv("ASAN_OPTIONS");
    return {"OMPI_ALLOW_RUN_AS_ROOT=1",
            "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1",
            "OMPI_MCA_btl=self,vader",
            "OMPI_MCA_btl_vader_single_copy_mechanism=none",
            "OMPI_MCA_rmaps_base_oversubscribe=1",
            std::string("ASAN_OPTIONS=") + (asan ? std::string(asan) + ":" : "") + "detect_leaks=0"};
}

struct Ran {
    int status = -1;
    double seconds = 0;
    std::string err;
};

// mpirun -q -np N ARGS..., to its end (killed after kLimit s: status -2).
Ran mpirun(int ranks, const std::vector<std::string>& args, const std::string& dir) {
    std::vector<std::string> argv = {kMpiexec, "-q", "-np", std::to_string(ranks)};
    argv.insert(argv.end(), args.begin(), args.end());
    const std::string err = dir + "/mpirun-stderr.txt";
    const auto t0 = child::Clock::now();
    child::Process p = child::spawn(argv, mpiEnv(), "", err);
    REQUIRE(p.started());
    Ran r;
    r.status = p.wait(kLimit);
    r.seconds = child::since(t0);
    r.err = child::readText(err);
    return r;
}

// The runner (tests/mpi_runner/mpi_runner.cpp): `runs` seeds from seed0 of each tracer spec.
void runRunner(int ranks, int threads, uint64_t seed0, int runs, const std::string& dir, const std::vector<std::string>& specs) {
    std::vector<std::string> args = {kRunner,
                                     kCornell,
                                     dir,
                                     std::to_string(kSize),
                                     std::to_string(kMaxLength),
                                     std::to_string(threads),
                                     std::to_string(seed0),
                                     std::to_string(runs)};
    args.insert(args.end(), specs.begin(), specs.end());
    const Ran r = mpirun(ranks, args, dir);
    INFO("mpirun -np " << ranks << " wavemmlt_mpi_runner: " << r.err);
    REQUIRE(r.status == 0);
}

struct TracerCase {
    const char* name;
    TracerKind kind;
    int spp;
    bool levers = false;  // MMLT's levers on (the runner's "mmlt-levers"; docs/mmlt-levers.md)
    bool metropolis() const { return kind == TracerKind::MMLT || kind == TracerKind::PSSMLT; }
    std::string spec() const { return std::string(name) + ":" + std::to_string(spp) + (metropolis() ? ":1024" : ""); }
};
// MMLT, PSSMLT: 1024 chains make 4 batches of 256, shared out 2 + 2 or 1 + 1 + 2 (PSSMLT at 64
// mutations per pixel: its mutations cost about four of MMLT's on this box).
const std::vector<TracerCase> kTracers = {{"pt", TracerKind::PT, 16},
                                          {"lt", TracerKind::LT, 16},
                                          {"bpt", TracerKind::BPT, 4},
                                          {"mmlt", TracerKind::MMLT, 128},
                                          {"pssmlt", TracerKind::PSSMLT, 64}};

// MMLT with its levers on: a target map and step sizes learned from samples every rank merges
// alike, and film steps.
const TracerCase kLevers = {"mmlt-levers", TracerKind::MMLT, 128, true};

std::vector<std::string> allSpecs() {
    std::vector<std::string> s;
    for (const TracerCase& t : kTracers) s.push_back(t.spec());
    return s;
}

SceneDesc cornell() {
    SceneDesc d = loadScene(kCornell);
    d.settings.width = d.settings.height = kSize;
    d.settings.maxPathLength = kMaxLength;
    return d;
}

RenderResult renderOne(const TracerCase& t, uint64_t seed, int threads = 2) {
    RenderOptions o = rstats::renderOptions(t.kind, t.spp, seed, 1, kMaxLength, threads);
    if (t.metropolis()) o.chains = 1024;
    if (t.levers) {
        o.mmltTarget = MmltTarget::Relative;
        o.learnSteps = true;
        o.filmSteps = FilmSteps::Always;
    }
    return render(cornell(), o);
}

std::string stem(const std::string& dir, const TracerCase& t, uint64_t seed) { return dir + "/" + t.name + "-" + std::to_string(seed); }

// The runner's MMLT record: per rank, the pools' digest and b_k as text (17 digits).
struct RankRecord {
    std::string digest;
    std::vector<std::string> b;
};
std::vector<RankRecord> rankRecords(const std::string& path) {
    std::ifstream f(path);
    std::vector<RankRecord> out;
    std::string line;
    while (std::getline(f, line)) {
        if (line.rfind("rank ", 0) != 0) continue;
        std::istringstream in(line);
        std::string word, index;
        RankRecord r;
        in >> word >> index >> word >> r.digest >> word;
        while (in >> word) r.b.push_back(word);
        out.push_back(r);
    }
    return out;
}

std::string hex(uint64_t v) {
    std::ostringstream o;
    o << std::hex << v;
    return o.str();
}

// Largest |a - b| / max(|b|, 1e-3 mean) over the pixels' channels.
double worstRelative(const Image& a, const Image& b) {
    REQUIRE(a.rgb.size() == b.rgb.size());
    double mean = 0;
    for (float v : b.rgb) mean += std::fabs(v);
    mean /= double(b.rgb.size());
    double worst = 0;
    for (size_t i = 0; i < a.rgb.size(); ++i)
        worst = std::max(worst, std::fabs(double(a.rgb[i]) - b.rgb[i]) / std::max(std::fabs(double(b.rgb[i])), 1e-3 * mean));
    return worst;
}

bool sameBytes(const std::string& a, const std::string& b) {
    const std::string x = child::readText(a), y = child::readText(b);
    return !x.empty() && x == y;
}

}  // namespace

TEST_CASE("mpirun: N ranks make one process's image from the same samples, for any threads per rank, the same bytes every time", "[mpi]") {
    if (!mpiBuilt()) return;
    const std::string dir = rstats::tempDir("mpi-same");
    const uint64_t seed = 100;
    const std::string two = dir + "/np2", twoThreads = dir + "/np2t2", again = dir + "/np2again", three = dir + "/np3";
    for (const std::string& d : {two, twoThreads, again, three}) std::filesystem::create_directories(d);
    std::vector<std::string> specs = allSpecs();
    specs.push_back(kLevers.spec());
    runRunner(2, 1, seed, 1, two, specs);
    runRunner(2, 2, seed, 1, twoThreads, specs);
    runRunner(2, 1, seed, 1, again, specs);
    runRunner(3, 1, seed, 1, three, specs);
    std::vector<TracerCase> cases = kTracers;
    cases.push_back(kLevers);
    for (const TracerCase& t : cases) {
        INFO(t.name);
        // A seed and a rank count: the same bytes every time, whatever the threads per rank.
        CHECK(sameBytes(stem(two, t, seed) + ".pfm", stem(again, t, seed) + ".pfm"));
        CHECK(sameBytes(stem(two, t, seed) + ".pfm", stem(twoThreads, t, seed) + ".pfm"));
        // One process, the same seed: the same samples.
        const RenderResult one = renderOne(t, seed);
        for (const std::string& d : {two, three}) {
            INFO(d);
            const Image im = readImage(stem(d, t, seed) + ".pfm");
            if (t.kind == TracerKind::PT) {
                CHECK(im.rgb == one.image.rgb);  // each pixel is one rank's: bit for bit
            } else {
                const double worst = worstRelative(im, one.image);
                INFO("largest relative difference to one process " << worst);
                CHECK(worst <= 1e-6);  // float rounding of the same sums added in another order
            }
            if (!t.metropolis()) continue;
            // b_k and the pools: the same bits on every rank, and the same as one process's.
            const std::vector<RankRecord> ranks = rankRecords(stem(d, t, seed) + ".txt");
            REQUIRE(ranks.size() == (d == two ? 2u : 3u));
            std::ostringstream oneB;
            oneB.precision(17);
            std::vector<std::string> expected;
            for (double b : one.stats.mmlt.b) {
                std::ostringstream x;
                x.precision(17);
                x << b;
                expected.push_back(x.str());
            }
            for (size_t r = 0; r < ranks.size(); ++r) {
                INFO("rank " << r);
                CHECK(ranks[r].b == expected);
                CHECK(ranks[r].digest == hex(one.stats.mmlt.poolDigestByRank.at(0)));
            }
        }
    }
}

TEST_CASE("mpirun: --chains auto chooses one count for 1 and 2 ranks and one process, and one image", "[mpi]") {
    if (!mpiBuilt()) return;
    const std::string dir = rstats::tempDir("mpi-auto");
    const TracerCase t{"mmlt", TracerKind::MMLT, 128};
    const std::string spec = "mmlt:128:0";  // chains 0: auto
    const uint64_t seed = 300;
    RenderOptions o = rstats::renderOptions(t.kind, t.spp, seed, 1, kMaxLength, 2);
    o.chains = 0;
    const RenderResult one = render(cornell(), o);
    REQUIRE(one.stats.mmlt.chainsAuto);
    for (int n : {1, 2}) {
        INFO(n << " ranks");
        const std::string d = dir + "/np" + std::to_string(n);
        std::filesystem::create_directories(d);
        runRunner(n, 1, seed, 1, d, {spec});
        std::ifstream f(stem(d, t, seed) + ".txt");
        uint32_t chains = 0;
        for (std::string w; f >> w;)
            if (w == "chains") f >> chains;
        CHECK(chains == one.stats.mmlt.chainsRun);
        const Image im = readImage(stem(d, t, seed) + ".pfm");
        if (n == 1) CHECK(im.rgb == one.image.rgb);        // one rank is one process: bit for bit
        else CHECK(worstRelative(im, one.image) <= 1e-6);  // the same sums in another order
    }
}

TEST_CASE("mpirun -np 2 and -np 3 against one process: every tracer's images agree within the statistical tolerance", "[mpi][stat]") {
    if (!mpiBuilt()) return;
    constexpr int K = 16;
    constexpr double kP = 1e-4;
    const std::string dir = rstats::tempDir("mpi-stat");
    const std::string two = dir + "/np2", three = dir + "/np3";
    for (const std::string& d : {two, three}) std::filesystem::create_directories(d);
    runRunner(2, 1, 1000, K, two, allSpecs());
    runRunner(3, 1, 2000, K, three, allSpecs());
    for (const TracerCase& t : kTracers) {
        INFO(t.name);
        power::Runs ref(8), ranks2(8), ranks3(8);
        for (int i = 0; i < K; ++i) {
            ref.add(renderOne(t, 3000 + uint64_t(i)));
            RenderResult r;
            r.image = readImage(stem(two, t, 1000 + uint64_t(i)) + ".pfm");
            ranks2.add(r);
            r.image = readImage(stem(three, t, 2000 + uint64_t(i)) + ".pfm");
            ranks3.add(r);
        }
        for (const auto& [n, runs] : {std::pair<int, const power::Runs*>{2, &ranks2}, {3, &ranks3}}) {
            const power::Verdict br = power::brightness(*runs, ref, kP), bl = power::blocks(*runs, ref, kP), sc = power::scatter(*runs, ref, kP);
            std::cout << t.name << ", " << n << " ranks vs one process (K = " << K << ", p = " << kP << "): fails a brightness error of "
                      << 100 * br.detectable << "%, a block error of " << 100 * bl.detectable << "% (median block)\n";
            INFO(n << " ranks\n" << br.text << "\n" << bl.text << "\n" << sc.text);
            CHECK(br.pass);
            CHECK(bl.pass);
            CHECK(sc.pass);
            // The power these runs have: a 3% error in the image's brightness fails; measured
            // 0.9-1.8% (PT, LT, BPT) and 1.8-1.9% (MMLT at 128 mutations per pixel, 4 passes:
            // at 32, one pass of a 400-sample bootstrap per length, it was 7%).
            CHECK(br.detectable <= 0.03);
        }
    }
}

// A pixel filter across ranks (docs/filters.md): PT's filtered camera samples stay each
// pixel's rank's, LT's, BPT's and MMLT's film points are spread on the rank that made them
// and the films summed: the image of one process, bit for bit (PT) or to float rounding.
TEST_CASE("mpirun wavemmlt: a Gaussian-filtered render makes one process's image, every tracer", "[mpi][filter]") {
    if (!mpiBuilt()) return;
    const std::string dir = rstats::tempDir("mpi-filter");
    for (const TracerCase& t : kTracers) {
        INFO(t.name);
        auto args = [&](const std::string& out) {
            std::vector<std::string> a = {WAVEMMLT_BIN,
                                          kCornell,
                                          "--width",
                                          std::to_string(kSize),
                                          "--height",
                                          std::to_string(kSize),
                                          "--max-length",
                                          std::to_string(kMaxLength),
                                          "--tracer",
                                          t.name,
                                          "--spp",
                                          std::to_string(t.spp),
                                          "--seed",
                                          "11",
                                          "--threads",
                                          "1",
                                          "--filter",
                                          "gaussian",
                                          "--quiet",
                                          "-o",
                                          out};
            if (t.metropolis()) a.insert(a.end(), {"--chains", "1024"});
            return a;
        };
        const std::string one = dir + "/" + t.name + "-np1.pfm", two = dir + "/" + t.name + "-np2.pfm";
        REQUIRE(mpirun(1, args(one), dir).status == 0);
        REQUIRE(mpirun(2, args(two), dir).status == 0);
        const Image a = readImage(one), b = readImage(two);
        if (t.kind == TracerKind::PT) {
            CHECK(a.rgb == b.rgb);
        } else {
            const double worst = worstRelative(b, a);
            INFO("largest relative difference to one process " << worst);
            CHECK(worst <= 1e-6);
        }
    }
}

TEST_CASE("mpirun wavemmlt: bad input gives one message and exit status 2 on every rank, without a hang", "[mpi]") {
    if (!mpiBuilt()) return;
    const std::string dir = rstats::tempDir("mpi-bad");
    {
        std::ofstream(dir + "/bad.xml") << "<Scene><Settings>\n";
        const Ran r = mpirun(3, {WAVEMMLT_BIN, dir + "/bad.xml", "-o", dir + "/out.png"}, dir);
        INFO(r.err);
        CHECK(r.status == 2);
        CHECK(r.err.find("error: ") == 0);
        CHECK(r.err.find("bad.xml") != std::string::npos);
        CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);  // one message, one line
        CHECK(!std::filesystem::exists(dir + "/out.png"));
    }
    {  // a scene the ranks load but cannot render (found inside render(), on every rank)
        std::ofstream(dir + "/dark.xml")
            << "<Scene><Settings><Width value=\"16\"/><Height value=\"16\"/></Settings>\n"
               "<Camera Type=\"Camera\"><Position x=\"0\" y=\"0\" z=\"-3\"/><LookAt x=\"0\" y=\"0\" z=\"0\"/><FOV value=\"45\"/></Camera>\n"
               "<Shader Type=\"Matte\" ID=\"0\"><Diffuse r=\"0.5\" g=\"0.5\" b=\"0.5\"/></Shader>\n"
               "<Geometry Type=\"Sphere\" ID=\"s\"><Position x=\"0\" y=\"0\" z=\"0\"/><Radius value=\"1\"/><Shader value=\"0\"/></Geometry>\n"
               "</Scene>\n";
        const Ran r = mpirun(2, {WAVEMMLT_BIN, dir + "/dark.xml", "-o", dir + "/dark.png"}, dir);
        INFO(r.err);
        CHECK(r.status == 2);
        CHECK(r.err.find("error: ") == 0);
        CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
        CHECK(!std::filesystem::exists(dir + "/dark.png"));
    }
    {  // options that need one process
        const Ran r = mpirun(2, {WAVEMMLT_BIN, "--tracer", "bpt", "--strategy-images", dir + "/s", "-o", dir + "/o.png"}, dir);
        INFO(r.err);
        CHECK(r.status == 2);
        CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
        const Ran i = mpirun(2, {WAVEMMLT_BIN, "--interactive", "-o", dir + "/o.png"}, dir);
        INFO(i.err);
        CHECK(i.status == 2);
        CHECK(i.err.find("--interactive needs one process") != std::string::npos);
        CHECK(std::count(i.err.begin(), i.err.end(), '\n') == 1);
    }
}

TEST_CASE("mpirun wavemmlt: --time ends every rank together, --stats reports the ranks and what they exchanged", "[mpi]") {
    if (!mpiBuilt()) return;
    const std::string dir = rstats::tempDir("mpi-time");
    for (const char* tracer : {"mmlt", "pt"}) {
        INFO(tracer);
        const std::string stats = dir + "/" + tracer + ".json", image = dir + "/" + tracer + ".pfm";
        // (MMLT: 4096 chains; one iteration of the default 65536 takes about a second on one
        // core, and the first round runs at least one.)
        const Ran r =
            mpirun(2, {WAVEMMLT_BIN, kCornell,   "--tracer", tracer,   "--width", "32", "--height", "32",  "--max-length", "5",  "--threads",
                       "1",          "--chains", "4096",     "--time", "1.5",     "-q", "-o",       image, "--stats",      stats},
                   dir);
        INFO(r.err);
        REQUIRE(r.status == 0);
        const std::string json = child::readText(stats);
        INFO(json);
        CHECK(rstats::jsonNumber(json, "ranks") == 2);
        CHECK(rstats::jsonNumber(json, "seconds") >= 1.2);
        CHECK(rstats::jsonNumber(json, "seconds") <= 1.8);
        // Every rank's render ended with rank 0's: the job's wall time is the budget plus
        // the start (scene loads, MPI's start), not two budgets.
        CHECK(r.seconds < 1.5 + 8.0);
        CHECK(rstats::jsonNumber(json, "mpi_bytes") > 0);
        CHECK(rstats::jsonNumber(json, "mpi_boundaries") >= 1);
        CHECK(json.find("\"mpi_seconds_by_rank\": [") != std::string::npos);
        CHECK(readImage(image).width == 32);
        if (std::string(tracer) == "mmlt") CHECK(json.find("\"mmlt_b_by_rank\": [{") != std::string::npos);
    }
}

TEST_CASE("mpirun wavemmlt: SIGINT to mpirun saves the image so far", "[mpi]") {
    if (!mpiBuilt()) return;
    const std::string dir = rstats::tempDir("mpi-sigint");
    for (const char* tracer : {"mmlt", "bpt"}) {
        INFO(tracer);
        const std::string image = dir + "/" + tracer + ".pfm", stats = dir + "/" + tracer + ".json";
        std::vector<std::string> argv = {kMpiexec,  "-q",      "-np",      "2",    WAVEMMLT_BIN,   kCornell, "--tracer",  tracer,
                                         "--width", "32",      "--height", "32",   "--max-length", "5",      "--threads", "1",
                                         "--spp",   "1000000", "--chains", "4096", "-o",           image,    "--stats",   stats};
        child::Process p = child::spawn(argv, mpiEnv(), "", dir + "/err.txt");
        REQUIRE(p.started());
        // Rendering once rank 0 prints progress (its first 10%: never, at a million spp; the
        // scene is loaded and the render started well within 4 s).
        std::this_thread::sleep_for(std::chrono::seconds(4));
        REQUIRE(p.running());
        p.kill(SIGINT);
        const int status = p.wait(kLimit);
        INFO(child::readText(dir + "/err.txt"));
        CHECK(status != -2);  // it ended, without a kill by the test
        // Open MPI's mpirun turns SIGINT into SIGTERM to the ranks, SIGKILL a second later,
        // and exits 1 itself; within that second the ranks agree to stop at the next boundary
        // and rank 0 writes what they rendered (MMLT stopped in its bootstrap still seeds
        // and runs one iteration of every chain: 4096 chains here, see docs/mpi.md).
        REQUIRE(std::filesystem::exists(image));
        const std::string json = child::readText(stats);
        CHECK(json.find("\"cancelled\": true") != std::string::npos);
        CHECK(power::meanLuminance(readImage(image)) > 0);
    }
}
