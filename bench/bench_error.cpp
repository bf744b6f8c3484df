// Error against time: each tracer's RMSE to a converged reference after equal time budgets.
//
//   build/wavemmlt_bench_error [scene.xml ...] [options]
//
// With no scene, runs ../shared/scenes/bitterli-cornell/bitterli-cornell-256.xml and
// seed-room/seed-room.xml (read from the shared folder beside the checkout; says so and
// exits 0 when it is missing). Options (defaults in brackets):
//   --tracers pt,bpt          tracers to compare (pt, lt, bpt, mmlt, pssmlt) [pt,bpt]
//   --budgets 1,2,4,8,16      time budgets in seconds [1,2,4,8,16]
//   --size WxH                image size [256x256] (the scene's camera, other resolution)
//   --max-length N            MaxPathLength [the scene's]
//   --round-spp N             samples per pixel per round of a timed render [1]
//   --reps N                  repetitions per point, seeds seed, seed+1, ... [1]
//   --seed N                  first seed of the runs [1] (the reference uses its own seeds)
//   --threads N               threads, 0: all [0]
//   --ref-spp N               reference samples per pixel (BPT) [per scene, see kRefSpp]
//   --ref-tracer T            the reference's tracer (bpt, pt, mmlt; mmlt: --ref-spp counts
//                             mutations per pixel, its own defaults otherwise) [bpt]
//   --ref-only                make (or read) each scene's reference, print it, and run nothing
//   --cache DIR               reference cache [<folder of this executable>/bench-cache]
//   --csv PATH                CSV output [bench-error.csv]
//   --chains N, --bootstrap N, --pass-length N, --p-large X, --mis-beta X   passed to
//                             RenderOptions (MMLT, BPT; chains: the default is auto, and
//                             --sweep chains=auto,1024,65536 compares it with fixed counts)
//   --mmlt-target luminance|relative, --mmlt-steps fixed|learned, --mmlt-delayed-rejection
//                             off|on, --mmlt-target-exponent B, --mmlt-film-steps
//                             off|learned|always
//                             MMLT's levers of issue 44, passed to RenderOptions (mmltTarget,
//                             learnSteps, delayedRejection, mmltTargetExponent, filmSteps)
//                             [RenderOptions']
//   --sweep NAME=V1,V2,...    run every tracer once per value; NAME is one of p-large, chains,
//                             bootstrap, pass-length, mis-beta, max-length, round-spp,
//                             mmlt-target, mmlt-steps; "a,b,...,z" fills in the arithmetic
//                             progression (max-length=3,5,...,15)
//
// The reference: a BPT render (--ref-tracer) of ref-spp samples per pixel at the same size
// and MaxPathLength, in two halves with two seeds that no run uses; the cached file is their
// mean, <cache>/<scene>-<W>x<H>-L<len>-<spp>spp.pfm (another tracer's:
// ...-L<len>-<tracer>-<spp>spp.pfm), with a .txt beside it (render time and the reference's
// own noise, estimated from the halves: RMSE(A, B) / 2, and relMSE(A, B) / 4 with the mean
// as the denominator's reference; a run's relMSE against it includes that much of the
// reference's noise). Rendered once, reused.
//
// Exit status: 0; 1 when a run could not be made (a render that threw, an unknown tracer:
// "skipped" in the table, no row in the CSV); 2 on bad options or an unreadable scene.
//
// Per run: RMSE over all pixels and RGB channels against the reference, relative RMSE
// (RMSE / the reference's mean) and relative MSE (the mean over pixels and channels of
// (x - ref)^2 / (ref^2 + 0.01): dark pixels count as much as bright ones), the speed
// (samples per second; MMLT and PSSMLT: mutations per second) and, for MMLT and PSSMLT, the
// acceptance rates of small and large steps. With --reps, the figures are over the
// repetitions (seconds, spp, speed, acceptance and relMSE: means; RMSE: sqrt of the mean
// squared error), with the spread of RMSE and relMSE (least and greatest run). Printed as
// a table with RMSE-refnoise = sqrt(MSE - the reference's noise^2) (the error against the
// true image, estimated) and ns per sample (seconds / (spp W H); spp counts completed
// rounds), then the equal-time ratios RMSE(pt) / RMSE(bpt) and RMSE(mmlt) / RMSE(pssmlt)
// per budget and the tracer with the least error at each; written as CSV
// (scene,tracer,param,budget_s,seconds,spp,rmse,rel_rmse,rmse_min,rmse_max,relmse,
// relmse_min,relmse_max,samples_per_s,accept_small,accept_large; the acceptance columns
// empty for PT, LT and BPT) for bench/plot_error.sh.
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "wavemmlt/error.h"
#include "wavemmlt/image.h"
#include "wavemmlt/render.h"
#include "wavemmlt/scene_desc.h"

using namespace wmlt;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

// Runs that could not be made (an unknown tracer, a render that threw): their rows are left
// out, and the program says so and exits 1, so that a script reading the CSV cannot take a
// missing row for a result. (A missing scene is not a failure: the shared folder is optional.)
int failedRuns = 0;

// Reference spp (BPT) per scene and size. At 256 x 256, some 20 to 40 times the samples BPT
// gets in 16 s, measured on a shared 2-core machine (issue 29; builds ran beside them): the
// seed room 609 s, the Cornell box 589 s, veach-bidir (../shared/scenes/mitsuba/veach-bidir/
// scene.xml: a Mitsuba file is named by its folder) 336 s. The smaller sizes are
// bench/estimator.sh's (issue 44; the volumetric caustic as the copy that script writes, its
// integrator made volpath): their own relMSE at most a tenth of MMLT's at 6 s on a quiet
// 2-core machine, each rendered in 4 to 11 minutes with nice -n 10 beside another
// developer's work (times and own noise: docs/benchmarks.md, "Estimator suite").
// Other sizes and scenes: 256 unless --ref-spp says otherwise.
struct RefSpp {
    const char* scene;
    int width, height, spp;
};
const RefSpp kRefSpp[] = {{"bitterli-cornell-256", 256, 256, 4096},
                          {"seed-room", 256, 256, 2048},
                          {"veach-bidir", 256, 256, 2048},
                          {"seed-room", 128, 128, 4096},
                          {"bitterli-cornell-256", 128, 128, 8192},
                          {"veach-bidir-256", 128, 128, 8192},
                          {"volumetric-caustic-volpath", 128, 128, 4096},
                          {"veach-ajar", 160, 90, 8192}};
constexpr uint64_t kRefSeedA = 0x5eed0000a, kRefSeedB = 0x5eed0000b;

struct Options {
    std::vector<std::string> scenes;
    std::vector<std::string> tracers{"pt", "bpt"};
    std::vector<double> budgets{1, 2, 4, 8, 16};
    int width = 256, height = 256;
    int maxLength = 0;  // 0: the scene's
    int roundSpp = 1;
    int reps = 1;
    uint64_t seed = 1;
    int threads = 0;
    int refSpp = 0;  // 0: kRefSpp
    std::string cacheDir, csv = "bench-error.csv";
    int chains = 0, bootstrap = -1, passLength = 0;  // 0 / -1: RenderOptions' defaults
    double probLarge = -1, misBeta = -1;             // < 0: the scene's / RenderOptions' default
    int mmltTarget = -1, mmltSteps = -1;             // < 0: RenderOptions' defaults (else MmltTarget; 1: learned)
    int mmltDelayed = -1;                            // < 0: RenderOptions' default; 1: delayed rejection on
    int mmltFilm = -1;                               // < 0: RenderOptions' default; else FilmSteps
    double targetExponent = -1;                      // < 0: RenderOptions' default (--mmlt-target-exponent)
    std::string refTracer = "bpt";
    bool refOnly = false;
    std::string sweepName;
    std::vector<std::string> sweepValues;
};

[[noreturn]] void usage(const std::string& msg) {
    std::fprintf(stderr, "wavemmlt_bench_error: %s (see the comment at the top of bench/bench_error.cpp)\n", msg.c_str());
    std::exit(2);
}

std::vector<std::string> splitList(const std::string& s) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    for (std::string item; std::getline(ss, item, ',');)
        if (!item.empty()) out.push_back(item);
    return out;
}

// --mmlt-target's and --mmlt-steps' values (the CLI's names), as Options' ints.
int parseMmltTarget(const std::string& v) {
    MmltTarget t;
    if (parseMmltTarget(v, t)) return int(t);
    usage("--mmlt-target: '" + v + "' is not one of luminance, relative");
}
int parseMmltSteps(const std::string& v) {
    if (v == "fixed" || v == "learned") return v == "learned";
    usage("--mmlt-steps: '" + v + "' is not one of fixed, learned");
}

double toNumber(const std::string& s, const char* what) {
    char* end = nullptr;
    double v = std::strtod(s.c_str(), &end);
    if (s.empty() || *end) usage(std::string("bad number '") + s + "' for " + what);
    return v;
}

// "3,5,...,15" -> 3,5,7,...,15 (the step from the two values before "...").
std::vector<std::string> expandProgression(const std::vector<std::string>& in) {
    std::vector<std::string> out;
    for (size_t i = 0; i < in.size(); ++i) {
        if (in[i] != "...") {
            out.push_back(in[i]);
            continue;
        }
        if (out.size() < 2 || i + 1 >= in.size()) usage("'...' needs two values before it and one after");
        double a = toNumber(out[out.size() - 2], "--sweep"), b = toNumber(out.back(), "--sweep");
        double last = toNumber(in[i + 1], "--sweep"), step = b - a;
        if (step == 0 || (last - b) / step < 0) usage("'...' does not reach " + in[i + 1]);
        for (double v = b + step; (step > 0 ? v < last - 1e-9 : v > last + 1e-9); v += step) {
            char buf[32];
            std::snprintf(buf, sizeof buf, "%g", v);
            out.push_back(buf);
        }
    }
    return out;
}

bool parseTracer(const std::string& name, TracerKind& t) {
    if (name == "pt") t = TracerKind::PT;
    else if (name == "lt") t = TracerKind::LT;
    else if (name == "bpt") t = TracerKind::BPT;
    else if (name == "mmlt") t = TracerKind::MMLT;
    else if (name == "pssmlt") t = TracerKind::PSSMLT;
    else return false;
    return true;
}

Options parseArgs(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) usage(a + " needs a value");
            return argv[++i];
        };
        if (a == "--tracers") o.tracers = splitList(value());
        else if (a == "--budgets") {
            o.budgets.clear();
            for (const std::string& b : splitList(value())) o.budgets.push_back(toNumber(b, "--budgets"));
        } else if (a == "--size") {
            std::string v = value();
            if (std::sscanf(v.c_str(), "%dx%d", &o.width, &o.height) != 2 || o.width < 1 || o.height < 1) usage("--size wants WxH, e.g. 256x256");
        } else if (a == "--max-length") o.maxLength = int(toNumber(value(), "--max-length"));
        else if (a == "--round-spp") o.roundSpp = int(toNumber(value(), "--round-spp"));
        else if (a == "--reps") o.reps = int(toNumber(value(), "--reps"));
        else if (a == "--seed") o.seed = uint64_t(toNumber(value(), "--seed"));
        else if (a == "--threads") o.threads = int(toNumber(value(), "--threads"));
        else if (a == "--ref-spp") o.refSpp = int(toNumber(value(), "--ref-spp"));
        else if (a == "--ref-tracer") o.refTracer = value();
        else if (a == "--ref-only") o.refOnly = true;
        else if (a == "--cache") o.cacheDir = value();
        else if (a == "--csv") o.csv = value();
        else if (a == "--chains") o.chains = int(toNumber(value(), "--chains"));
        else if (a == "--bootstrap") o.bootstrap = int(toNumber(value(), "--bootstrap"));
        else if (a == "--pass-length") o.passLength = int(toNumber(value(), "--pass-length"));
        else if (a == "--p-large") o.probLarge = toNumber(value(), "--p-large");
        else if (a == "--mis-beta") o.misBeta = toNumber(value(), "--mis-beta");
        else if (a == "--mmlt-target") o.mmltTarget = parseMmltTarget(value());
        else if (a == "--mmlt-steps") o.mmltSteps = parseMmltSteps(value());
        else if (a == "--mmlt-target-exponent") {
            o.targetExponent = toNumber(value(), "--mmlt-target-exponent");
            if (!(o.targetExponent > 0 && o.targetExponent <= 1)) usage("--mmlt-target-exponent: must be in (0, 1]");
        } else if (a == "--mmlt-delayed-rejection") {
            const std::string v = value();
            if (v != "on" && v != "off") usage("--mmlt-delayed-rejection: '" + v + "' is not one of off, on");
            o.mmltDelayed = v == "on";
        } else if (a == "--mmlt-film-steps") {
            const std::string v = value();
            FilmSteps f;
            if (!parseFilmSteps(v, f)) usage("--mmlt-film-steps: '" + v + "' is not one of off, learned, always");
            o.mmltFilm = int(f);
        } else if (a == "--sweep") {
            std::string v = value();
            size_t eq = v.find('=');
            if (eq == std::string::npos) usage("--sweep wants NAME=V1,V2,...");
            o.sweepName = v.substr(0, eq);
            o.sweepValues = expandProgression(splitList(v.substr(eq + 1)));
            static const char* names[] = {"p-large",    "chains",    "bootstrap",   "pass-length", "mis-beta",
                                          "max-length", "round-spp", "mmlt-target", "mmlt-steps",  "mmlt-target-exponent"};
            bool known = false;
            for (const char* n : names) known |= o.sweepName == n;
            if (!known) usage("unknown --sweep parameter '" + o.sweepName + "'");
            if (o.sweepValues.empty()) usage("--sweep " + o.sweepName + " has no values");
            for (const std::string& x : o.sweepValues) {  // the named values, checked before anything runs
                if (o.sweepName == "mmlt-target") parseMmltTarget(x);
                if (o.sweepName == "mmlt-steps") parseMmltSteps(x);
            }
        } else if (a == "-h" || a == "--help") usage("usage");
        else if (!a.empty() && a[0] == '-') usage("unknown option '" + a + "'");
        else o.scenes.push_back(a);
    }
    if (o.roundSpp < 1 || o.reps < 1 || o.budgets.empty() || o.tracers.empty()) usage("nothing to run");
    TracerKind refTracer;
    if (!parseTracer(o.refTracer, refTracer) || refTracer == TracerKind::LT || refTracer == TracerKind::PSSMLT)
        usage("--ref-tracer: '" + o.refTracer + "' is not one of bpt, pt, mmlt");
    return o;
}

// What one run varies: the sweep's parameter (or none) applied to the defaults.
struct Variant {
    std::string label = "-";  // the CSV's param column
    int maxLength = 0, roundSpp = 1, chains = 0, bootstrap = -1, passLength = 0;
    double probLarge = -1, misBeta = -1;
    int mmltTarget = -1, mmltSteps = -1, mmltDelayed = -1, mmltFilm = -1;  // < 0: RenderOptions' defaults
    double targetExponent = -1;
};

std::vector<Variant> variants(const Options& o, int sceneMaxLength) {
    Variant base;
    base.maxLength = o.maxLength > 0 ? o.maxLength : sceneMaxLength;
    base.roundSpp = o.roundSpp;
    base.chains = o.chains;
    base.bootstrap = o.bootstrap;
    base.passLength = o.passLength;
    base.probLarge = o.probLarge;
    base.misBeta = o.misBeta;
    base.mmltTarget = o.mmltTarget;
    base.mmltSteps = o.mmltSteps;
    base.mmltDelayed = o.mmltDelayed;
    base.mmltFilm = o.mmltFilm;
    base.targetExponent = o.targetExponent;
    if (o.sweepName.empty()) return {base};
    std::vector<Variant> out;
    for (const std::string& v : o.sweepValues) {
        Variant x = base;
        x.label = o.sweepName + "=" + v;
        if (o.sweepName == "mmlt-target") {  // named values
            x.mmltTarget = parseMmltTarget(v);
            out.push_back(x);
            continue;
        }
        if (o.sweepName == "mmlt-steps") {
            x.mmltSteps = parseMmltSteps(v);
            out.push_back(x);
            continue;
        }
        double d = o.sweepName == "chains" && v == "auto" ? 0 : toNumber(v, "--sweep");  // chains=auto: 0
        if (o.sweepName == "p-large") x.probLarge = d;
        else if (o.sweepName == "chains") x.chains = int(d);
        else if (o.sweepName == "bootstrap") x.bootstrap = int(d);
        else if (o.sweepName == "pass-length") x.passLength = int(d);
        else if (o.sweepName == "mis-beta") x.misBeta = d;
        else if (o.sweepName == "max-length") x.maxLength = int(d);
        else if (o.sweepName == "round-spp") x.roundSpp = int(d);
        else if (o.sweepName == "mmlt-target-exponent") x.targetExponent = d;
        out.push_back(x);
    }
    return out;
}

RenderOptions makeOptions(const SceneDesc& desc, TracerKind tracer, const Variant& v, int threads) {
    RenderOptions opt;
    opt.tracer = tracer;
    opt.threads = threads;
    opt.minPathLength = std::min(desc.settings.minPathLength, v.maxLength);
    opt.maxPathLength = v.maxLength;
    opt.spp = v.roundSpp;
    opt.strataPerAxis = strataForSpp(v.roundSpp);
    opt.probLarge = float(v.probLarge >= 0 ? v.probLarge : desc.settings.probLarge);
    if (v.chains > 0) opt.chains = v.chains;
    if (v.bootstrap >= 0) opt.bootstrap = v.bootstrap;
    if (v.passLength > 0) opt.passLength = v.passLength;
    if (v.misBeta >= 0) opt.misBeta = float(v.misBeta);
    if (v.mmltTarget >= 0) opt.mmltTarget = MmltTarget(v.mmltTarget);
    if (v.mmltSteps >= 0) opt.learnSteps = v.mmltSteps == 1;
    if (v.mmltDelayed >= 0) opt.delayedRejection = v.mmltDelayed == 1;
    if (v.mmltFilm >= 0) opt.filmSteps = FilmSteps(v.mmltFilm);
    if (v.targetExponent > 0) opt.mmltTargetExponent = float(v.targetExponent);
    return opt;
}

double meanOf(const Image& img) {
    double s = 0;
    for (float v : img.rgb) s += v;
    return img.rgb.empty() ? 0 : s / double(img.rgb.size());
}

// Relative MSE: the mean over pixels and channels of (a - b)^2 / (b^2 + 0.01), b the reference.
double relMse(const Image& a, const Image& b) {
    double s = 0;
    for (size_t i = 0; i < a.rgb.size(); ++i) {
        const double d = double(a.rgb[i]) - double(b.rgb[i]), r = double(b.rgb[i]);
        s += d * d / (r * r + 0.01);
    }
    return a.rgb.empty() ? 0 : s / double(a.rgb.size());
}

// Mean squared error over all pixels and channels; NaN or Inf in `a` count as errors
// (they make the result non-finite, which the table then shows).
double mse(const Image& a, const Image& b) {
    if (a.width != b.width || a.height != b.height) throw std::runtime_error("image sizes differ");
    double s = 0;
    for (size_t i = 0; i < a.rgb.size(); ++i) {
        double d = double(a.rgb[i]) - double(b.rgb[i]);
        s += d * d;
    }
    return a.rgb.empty() ? 0 : s / double(a.rgb.size());
}

std::string executableDir() {
    std::error_code ec;
    fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    return ec ? fs::current_path().string() : exe.parent_path().string();
}

struct Reference {
    Image image;
    double mean = 0, noiseRmse = 0, seconds = 0;
    double noiseRelMse = -1;  // < 0: not known (a reference cached before it was recorded)
    int spp = 0;
    std::string path;
    bool cached = false;
};

// The reference for this scene, size and MaxPathLength (BPT unless --ref-tracer says
// otherwise): read from the cache, or rendered (two halves, two seeds) and written there.
Reference reference(const SceneDesc& desc, const std::string& name, int maxLength, int spp, int threads, const std::string& cacheDir,
                    const std::string& tracerName) {
    Reference ref;
    ref.spp = spp;
    TracerKind tracer = TracerKind::BPT;
    parseTracer(tracerName, tracer);
    const std::string tag = tracer == TracerKind::BPT ? "" : tracerName + "-";  // BPT's files keep their names
    char file[512];
    std::snprintf(file, sizeof file, "%s-%dx%d-L%d-%s%dspp", name.c_str(), desc.settings.width, desc.settings.height, maxLength, tag.c_str(), spp);
    ref.path = cacheDir + "/" + file + ".pfm";
    const std::string info = cacheDir + "/" + file + ".txt";
    if (fs::exists(ref.path)) {
        ref.image = readImage(ref.path);
        std::ifstream in(info);
        for (std::string key; in >> key;) {
            if (key == "seconds") in >> ref.seconds;
            else if (key == "noise_rmse") in >> ref.noiseRmse;
            else if (key == "noise_relmse") in >> ref.noiseRelMse;
            else in.ignore(1 << 20, '\n');
        }
        ref.cached = true;
    } else {
        fs::create_directories(cacheDir);
        const int half = std::max(1, spp / 2);
        Variant v;
        v.maxLength = maxLength;
        v.roundSpp = half;
        RenderOptions opt = makeOptions(desc, tracer, v, threads);
        std::printf("reference: rendering %s (%s, %d spp in two halves) ...\n", ref.path.c_str(), tracerName.c_str(), 2 * half);
        std::fflush(stdout);
        auto t0 = Clock::now();
        int lastShown = -1, halfIndex = 0;
        if (isatty(2))
            opt.progress = [&](double f) {
                int pct = int((halfIndex + f) * 50);
                if (pct / 5 != lastShown / 5) {
                    std::fprintf(stderr, "\rreference %3d%% (%.0f s)", pct, std::chrono::duration<double>(Clock::now() - t0).count());
                    lastShown = pct;
                }
            };
        opt.seed = kRefSeedA;
        Image a = render(desc, opt).image;
        halfIndex = 1;
        opt.seed = kRefSeedB;
        Image b = render(desc, opt).image;
        ref.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
        if (isatty(2)) std::fprintf(stderr, "\r%40s\r", "");
        ref.noiseRmse = std::sqrt(mse(a, b)) / 2;  // var(mean of 2) = var(a - b) / 4
        ref.spp = 2 * half;
        ref.image = a;
        for (size_t i = 0; i < a.rgb.size(); ++i) ref.image.rgb[i] = 0.5f * (a.rgb[i] + b.rgb[i]);
        // relMSE of the mean of the halves against the true image: E (a - b)^2 / 4 per pixel,
        // over (ref^2 + 0.01) with the mean as ref, as a run's relMSE is taken
        double s = 0;
        for (size_t i = 0; i < a.rgb.size(); ++i) {
            const double d = double(a.rgb[i]) - double(b.rgb[i]), r = double(ref.image.rgb[i]);
            s += d * d / (r * r + 0.01);
        }
        ref.noiseRelMse = a.rgb.empty() ? 0 : s / double(a.rgb.size()) / 4;
        writeImage(ref.path, ref.image);
        std::ofstream out(info);
        out << "seconds " << ref.seconds << "\nnoise_rmse " << ref.noiseRmse << "\nnoise_relmse " << ref.noiseRelMse << "\nspp " << ref.spp
            << "\ntracer " << tracerName << "\nthreads " << threads << "\n";
    }
    ref.mean = meanOf(ref.image);
    char relNoise[64] = "not recorded";
    if (ref.noiseRelMse >= 0) std::snprintf(relNoise, sizeof relNoise, "%.3g", ref.noiseRelMse);
    std::printf("reference: %s, %s, %s, %d spp, %.0f s to render, mean %.4g, own noise ~ RMSE %.3g (rel %.3g), relMSE %s\n", ref.path.c_str(),
                ref.cached ? "cached" : "rendered now", tracerName.c_str(), ref.spp, ref.seconds, ref.mean, ref.noiseRmse,
                ref.mean > 0 ? ref.noiseRmse / ref.mean : 0.0, relNoise);
    return ref;
}

struct Row {
    std::string scene, tracer, param;
    double budget = 0, seconds = 0, spp = 0, rmse = 0, relRmse = 0, nsPerSample = 0;
    double rmseNet = 0;  // with the reference's own noise taken out: sqrt(MSE - noise^2)
    double rmseMin = INFINITY, rmseMax = 0, relMse = 0, relMseMin = INFINITY, relMseMax = 0;
    double samplesPerSecond = 0;
    double acceptSmall = -1, acceptLarge = -1;  // MMLT, PSSMLT (< 0: none)
};

void benchScene(const std::string& path, const Options& o, std::vector<Row>& rows, const std::string& cacheDir) {
    if (!fs::exists(path)) {
        std::printf("%s: missing (the benchmark reads it from ../shared/scenes/); skipped\n", path.c_str());
        return;
    }
    SceneDesc desc = loadScene(path);
    desc.settings.width = o.width;
    desc.settings.height = o.height;
    // (a Mitsuba scene's file is often scene.xml: then its folder's name)
    const fs::path sp(path);
    const std::string name = sp.stem() == "scene" && sp.has_parent_path() ? sp.parent_path().filename().string() : sp.stem().string();
    std::printf("\n== %s: %dx%d (--size), MaxPathLength %s%d, timed rounds of %d spp, %d rep(s)\n", name.c_str(), o.width, o.height,
                o.maxLength > 0 ? "" : "(the scene's) ", o.maxLength > 0 ? o.maxLength : desc.settings.maxPathLength, o.roundSpp, o.reps);
    int refSpp = o.refSpp;
    if (refSpp <= 0) {
        refSpp = 256;
        for (const RefSpp& r : kRefSpp)
            if (name == r.scene && o.width == r.width && o.height == r.height) refSpp = r.spp;
    }
    const int threadCount = o.threads > 0 ? o.threads : int(std::max(1L, sysconf(_SC_NPROCESSORS_ONLN)));

    std::map<int, Reference> refs;  // by MaxPathLength
    std::vector<Row> sceneRows;
    for (const Variant& v : variants(o, desc.settings.maxPathLength)) {
        if (v.maxLength < 1 || v.maxLength > kMaxPathLength) {
            std::printf("MaxPathLength %d out of range; skipped\n", v.maxLength);
            continue;
        }
        if (!refs.count(v.maxLength)) refs[v.maxLength] = reference(desc, name, v.maxLength, refSpp, o.threads, cacheDir, o.refTracer);
        const Reference& ref = refs[v.maxLength];
        if (o.refOnly) continue;
        std::printf("%-6s %-16s %8s %9s %9s %11s %21s %9s %13s %10s %10s %11s %6s %6s\n", "tracer", "param", "budget s", "seconds", "spp", "RMSE",
                    "(runs: least..most)", "relRMSE", "RMSE-refnoise", "relMSE", "ns/sample", "samples/s", "acc.S", "acc.L");
        for (const std::string& tname : o.tracers) {
            TracerKind tracer;
            if (!parseTracer(tname, tracer)) {
                std::printf("%-6s unknown tracer (pt, lt, bpt, mmlt, pssmlt); skipped\n", tname.c_str());
                ++failedRuns;
                continue;
            }
            RenderOptions opt = makeOptions(desc, tracer, v, o.threads);
            bool failed = false;
            for (double budget : o.budgets) {
                Row row{name, tname, v.label, budget};
                double sumMse = 0;
                for (int rep = 0; rep < o.reps && !failed; ++rep) {
                    opt.timeBudget = budget;
                    opt.seed = o.seed + uint64_t(rep);
                    try {
                        RenderResult r = render(desc, opt);
                        row.seconds += r.stats.seconds / o.reps;
                        row.spp += double(r.stats.spp) / o.reps;
                        const double e = mse(r.image, ref.image), re = relMse(r.image, ref.image);
                        sumMse += e;
                        row.rmseMin = std::min(row.rmseMin, std::sqrt(e));
                        row.rmseMax = std::max(row.rmseMax, std::sqrt(e));
                        row.relMse += re / o.reps;
                        row.relMseMin = std::min(row.relMseMin, re);
                        row.relMseMax = std::max(row.relMseMax, re);
                        const bool mlt = tracer == TracerKind::MMLT || tracer == TracerKind::PSSMLT;
                        const double samples = mlt ? double(r.stats.mmlt.mutations) : double(r.stats.spp) * o.width * o.height;
                        row.samplesPerSecond += (r.stats.seconds > 0 ? samples / r.stats.seconds : 0.0) / o.reps;
                        if (mlt) {  // acceptance of small and large steps, all lengths
                            uint64_t acc[3], prop[3];
                            r.stats.mmlt.stepTotals(acc, prop);
                            row.acceptSmall = std::max(row.acceptSmall, 0.0) + (prop[0] ? double(acc[0]) / prop[0] : 0.0) / o.reps;
                            row.acceptLarge = std::max(row.acceptLarge, 0.0) + (prop[1] ? double(acc[1]) / prop[1] : 0.0) / o.reps;
                        }
                    } catch (const std::exception& e) {
                        std::printf("%-6s %-16s %s; skipped\n", tname.c_str(), v.label.c_str(), e.what());
                        ++failedRuns;
                        failed = true;
                    }
                }
                if (failed) break;
                row.rmse = std::sqrt(sumMse / o.reps);
                row.relRmse = ref.mean > 0 ? row.rmse / ref.mean : 0;
                row.rmseNet = std::sqrt(std::max(0.0, sumMse / o.reps - ref.noiseRmse * ref.noiseRmse));
                row.nsPerSample = row.spp > 0 ? row.seconds / (row.spp * o.width * o.height) * 1e9 : 0;
                char acc[32] = "     -      -";
                if (row.acceptSmall >= 0) std::snprintf(acc, sizeof acc, "%6.3f %6.3f", row.acceptSmall, row.acceptLarge);
                std::printf("%-6s %-16s %8g %9.2f %9.0f %11.4g %10.4g..%-10.4g %9.4f %13.4g %10.4g %10.1f %11.4g %s\n", tname.c_str(),
                            v.label.c_str(), budget, row.seconds, row.spp, row.rmse, row.rmseMin, row.rmseMax, row.relRmse, row.rmseNet, row.relMse,
                            row.nsPerSample, row.samplesPerSecond, acc);
                std::fflush(stdout);
                sceneRows.push_back(row);
            }
        }
    }
    // Equal-time ratios: pt against bpt and mmlt against pssmlt, for each param value and
    // budget both ran.
    for (const auto& [num, den] : {std::pair<std::string, std::string>{"pt", "bpt"}, {"mmlt", "pssmlt"}}) {
        bool header = false;
        for (const Row& p : sceneRows) {
            if (p.tracer != num) continue;
            for (const Row& b : sceneRows) {
                if (b.tracer != den || b.param != p.param || b.budget != p.budget) continue;
                if (!header) std::printf("equal-time RMSE(%s) / RMSE(%s) (%s, %d threads):\n", num.c_str(), den.c_str(), name.c_str(), threadCount);
                header = true;
                std::printf("  %-16s %6gs: %.3f  (without the reference's noise: %.3f; relMSE ratio %.3f)\n", p.param.c_str(), p.budget,
                            b.rmse > 0 ? p.rmse / b.rmse : 0.0, b.rmseNet > 0 ? p.rmseNet / b.rmseNet : 0.0,
                            b.relMse > 0 ? p.relMse / b.relMse : 0.0);
            }
        }
    }
    // The tracer with the least RMSE (and relMSE) at each budget.
    for (double budget : o.budgets)
        for (const Variant& v : variants(o, desc.settings.maxPathLength)) {
            const Row *best = nullptr, *bestRel = nullptr;
            for (const Row& r : sceneRows) {
                if (r.budget != budget || r.param != v.label) continue;
                if (!best || r.rmse < best->rmse) best = &r;
                if (!bestRel || r.relMse < bestRel->relMse) bestRel = &r;
            }
            if (best)
                std::printf("least error at %gs%s%s: RMSE %s, relMSE %s\n", budget, v.label == "-" ? "" : " ", v.label == "-" ? "" : v.label.c_str(),
                            best->tracer.c_str(), bestRel->tracer.c_str());
        }
    rows.insert(rows.end(), sceneRows.begin(), sceneRows.end());
}

void writeCsv(const std::string& path, const std::vector<Row>& rows) {
    std::ofstream out(path);
    if (!out) throw std::runtime_error("cannot write " + path);
    out << "scene,tracer,param,budget_s,seconds,spp,rmse,rel_rmse,rmse_min,rmse_max,relmse,relmse_min,relmse_max,"
           "samples_per_s,accept_small,accept_large\n";
    char buf[1024];
    for (const Row& r : rows) {
        char acc[64] = ",";
        if (r.acceptSmall >= 0) std::snprintf(acc, sizeof acc, "%.4f,%.4f", r.acceptSmall, r.acceptLarge);
        std::snprintf(buf, sizeof buf, "%s,%s,%s,%g,%.4f,%.2f,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%s\n", r.scene.c_str(), r.tracer.c_str(),
                      r.param.c_str(), r.budget, r.seconds, r.spp, r.rmse, r.relRmse, r.rmseMin, r.rmseMax, r.relMse, r.relMseMin, r.relMseMax,
                      r.samplesPerSecond, acc);
        out << buf;
    }
}

}  // namespace

int main(int argc, char** argv) {
    Options o = parseArgs(argc, argv);
    if (o.scenes.empty()) {
        const fs::path root = fs::path(WAVEMMLT_SOURCE_DIR) / ".." / "shared" / "scenes";
        if (!fs::is_directory(root)) {
            std::printf(
                "%s: missing (the benchmark's scenes live in ../shared/scenes/ beside the checkout); "
                "nothing to do\n",
                root.lexically_normal().c_str());
            return 0;
        }
        o.scenes = {(root / "bitterli-cornell/bitterli-cornell-256.xml").lexically_normal().string(),
                    (root / "seed-room/seed-room.xml").lexically_normal().string()};
    }
    const std::string cacheDir = o.cacheDir.empty() ? executableDir() + "/bench-cache" : o.cacheDir;
    if (o.refOnly) std::printf("references only (--ref-only)");
    else {
        std::printf("error vs time: tracers");
        for (const std::string& t : o.tracers) std::printf(" %s", t.c_str());
        std::printf(", budgets");
        for (double b : o.budgets) std::printf(" %gs", b);
    }
    std::printf(", image %dx%d (--size to change), references in %s\n", o.width, o.height, cacheDir.c_str());
    std::vector<Row> rows;
    try {
        for (const std::string& s : o.scenes) benchScene(s, o, rows, cacheDir);
        if (o.refOnly) return 0;
        writeCsv(o.csv, rows);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 2;
    }
    std::printf("\nwrote %s (%zu rows)\n", o.csv.c_str(), rows.size());
    if (failedRuns) {
        std::fprintf(stderr, "error: %d run(s) failed and are not in %s (see above)\n", failedRuns, o.csv.c_str());
        return 1;
    }
    return 0;
}
