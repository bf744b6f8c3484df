#include "app/cli.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "scene/filter_desc.h"
#include "stages/core/memory.h"
#include "stages/mmlt/mmlt.h"
#include "stages/pssmlt/pssmlt_stages.h"
#include "wavemmlt/error.h"

namespace wmlt {

extern const char* const kDefaultSceneXml;

namespace {

[[noreturn]] void fail(const std::string& msg) { throw InputError("wavemmlt: " + msg); }

// A whole number, written as digits ("65536") or in exponent form ("1e12", "6.5536e4");
// "1.5", "abc", "1e400" and anything beyond 64 bits are not whole numbers.
long long parseInt(const std::string& opt, const std::string& v, long long lo, long long hi) {
    errno = 0;
    char* end = nullptr;
    long long x = std::strtoll(v.c_str(), &end, 10);
    if (!v.empty() && *end != '\0' && v.find_first_of("eE") != std::string::npos) {
        errno = 0;
        const double d = std::strtod(v.c_str(), &end);
        if (*end == '\0' && std::isfinite(d) && d == std::floor(d) && std::fabs(d) < 9.2e18) x = (long long)d;
        else errno = ERANGE;
    }
    if (v.empty() || *end != '\0' || errno == ERANGE) fail(opt + ": '" + v + "' is not a whole number");
    if (x < lo || x > hi) fail(opt + ": " + v + " is out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return x;
}

double parseReal(const std::string& opt, const std::string& v, double lo, double hi) {
    char* end = nullptr;
    double x = std::strtod(v.c_str(), &end);
    if (v.empty() || *end != '\0' || !std::isfinite(x)) fail(opt + ": '" + v + "' is not a number");
    if (x < lo || x > hi) fail(opt + ": " + v + " is out of range");
    return x;
}

// "HOST:PORT", HOST a name, an IPv4 address or an [IPv6] address; PORT 1..65535.
void parseHostPort(const std::string& v, std::string& host, std::string& port) {
    const std::string opt = "--display-server: '" + v + "' ";
    const size_t colon = v.find_last_of(':');
    if (colon == std::string::npos || (v[0] == '[' && colon < v.find(']'))) fail(opt + "has no port (HOST:PORT, e.g. 127.0.0.1:14158)");
    host = v.substr(0, colon);
    port = v.substr(colon + 1);
    const bool digits = !port.empty() && port.size() <= 5 && port.find_first_not_of("0123456789") == std::string::npos;
    if (!digits || std::stoi(port) < 1 || std::stoi(port) > 65535) fail(opt + "has no valid port ('" + port + "': 1 to 65535)");
    if (host.size() > 2 && host.front() == '[' && host.back() == ']') {
        host = host.substr(1, host.size() - 2);
        if (host.find_first_not_of("0123456789abcdefABCDEF:.") == std::string::npos) return;
    } else if (!host.empty() &&
               host.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                      "0123456789.-") == std::string::npos &&
               host.front() != '-' && host.front() != '.') {
        return;
    }
    fail(opt + "has no valid host ('" + host + "': a name, an IPv4 address or an [IPv6] address)");
}

// "X,Y,Z": three finite numbers.
Vec3 parseVec3(const std::string& opt, const std::string& v) {
    float xyz[3];
    size_t start = 0;
    for (int i = 0; i < 3; ++i) {
        const size_t comma = v.find(',', start);
        if ((i < 2) != (comma != std::string::npos)) fail(opt + ": '" + v + "' is not X,Y,Z");
        xyz[i] = float(parseReal(opt, v.substr(start, comma - start), -1e30, 1e30));
        start = comma + 1;
    }
    return {xyz[0], xyz[1], xyz[2]};
}

// --filter NAME[:param=value,...] (filter_desc.h).
FilterDesc parseFilter(const std::string& v) {
    const size_t colon = v.find(':');
    const std::string name = v.substr(0, colon);
    FilterDesc f;
    if (!namedFilter(name, f)) fail("--filter: '" + name + "' is not one of " + kFilterNames);
    std::string rest = colon == std::string::npos ? "" : v.substr(colon + 1);
    while (colon != std::string::npos) {
        const size_t comma = rest.find(',');
        const std::string item = rest.substr(0, comma), param = item.substr(0, item.find('='));
        if (item.find('=') == std::string::npos || param.empty()) fail("--filter: '" + item + "' is not param=value");
        const double x = parseReal("--filter " + param, item.substr(param.size() + 1), -1e30, 1e30);
        const std::string problem = setFilterParameter(f, param, x);
        if (!problem.empty()) fail("--filter: " + name + ": " + problem);
        if (comma == std::string::npos) break;
        rest = rest.substr(comma + 1);
    }
    return f;
}

}  // namespace

std::string usageText() {
    return "usage: wavemmlt [scene.xml] [options]\n"
           "Renders the scene (the built-in default scene when none is given): the thesis' format\n"
           "or a Mitsuba 3 scene file (<scene version=\"3.x\">; see docs/mitsuba.md).\n"
           "Options override the scene's Settings:\n"
           "  --tracer pt|lt|bpt|mmlt|pssmlt  light transport algorithm (default: the scene's, else mmlt;\n"
           "                           pssmlt: Kelemen's PSSMLT over BPT, MMLT's baseline, docs/pssmlt.md)\n"
           "  --mis-beta B             BPT, MMLT, PSSMLT: power-heuristic exponent (1: the balance heuristic;\n"
           "                           default: 1 for MMLT, 2 for BPT and PSSMLT)\n"
           "  --spp N                  samples per pixel (stratified n x n for the largest n*n dividing N);\n"
           "                           MMLT, PSSMLT: mutations per pixel\n"
           "  --chains N|auto          MMLT, PSSMLT: Markov chains in flight (default auto: one per 8000\n"
           "                           mutations the render makes, 4096 to 65536, from --spp alone so\n"
           "                           that a seed gives one image; under --time from the bootstrap's\n"
           "                           rate, at least 1024 and 512 per worker; printed, and in --stats)\n"
           "  --bootstrap N            MMLT: bootstrap samples per path length (PSSMLT: in all; default: automatic)\n"
           "  --pass-length N          MMLT, PSSMLT: iterations of every chain between restarts from the\n"
           "                           sample pools (default: automatic, 2 to 8 passes a render)\n"
           "  --p-large P              MMLT, PSSMLT: probability of a large step, 0 < P <= 1 (default: the scene's)\n"
           "  --mmlt-target luminance|relative   MMLT: the chains' target, a path's luminance or, from the\n"
           "                           second pass on, its luminance over its pixel's brightness so far\n"
           "                           (default: luminance; docs/mmlt-levers.md)\n"
           "  --mmlt-steps fixed|learned   MMLT: small steps of sigma 0.01, or each length's learned between\n"
           "                           passes from its chains' acceptance (default: fixed; docs/mmlt-levers.md)\n"
           "  --mmlt-target-exponent B MMLT: the target is the luminance to the power B in (0, 1], a\n"
           "                           tempered target (default: 1, the luminance; docs/mmlt-levers.md)\n"
           "  --mmlt-delayed-rejection off|on   MMLT: a rejected large step proposes again in the same\n"
           "                           iteration, a small step (delayed rejection; default: off;\n"
           "                           docs/mmlt-levers.md)\n"
           "  --mmlt-film-steps off|learned|always   MMLT: 0.3 of the small steps move only the raster\n"
           "                           point (film steps): learned: from the second pass on, in the\n"
           "                           lengths whose small steps were mostly rejected in the last pass;\n"
           "                           always: in every length (default: learned; docs/mmlt-levers.md)\n"
           "  --spectral, --rgb        render with sampled wavelengths (every tracer; scenes without\n"
           "                           principled materials or Mitsuba blendbsdfs: others render in\n"
           "                           RGB, with a warning), or in RGB (default:\n"
           "                           pbrt-v4 files spectral, as pbrt renders them, Mitsuba files\n"
           "                           that give spectra spectral; others RGB; docs/spectral.md)\n"
           "  --strategy-images DIR    BPT: also write each strategy (s, t) as DIR/s<s>_t<t>_weighted.exr\n"
           "                           and _unweighted.exr (the folder is created)\n"
           "  --time SECONDS           render rounds of --spp samples until the time is spent (the built-in\n"
           "                           scene without --spp or --time: 10 s, with PT unless --tracer is given)\n"
           "  --threads N              worker threads (0: all)\n"
           "  --seed N                 random seed (same seed: same image, for any --threads)\n"
           "  --width N, --height N    image size\n"
           "  --max-length N, --min-length N   path lengths (segments) to render, 1..64\n"
           "  --filter NAME[:P=V,...]  pixel filter: box, tent, gaussian, mitchell, catmullrom, lanczos,\n"
           "                           with parameters radius, stddev, B, C, lobes, tau (e.g.\n"
           "                           gaussian:stddev=0.5; default: the scene's, docs/filters.md)\n"
           "  -o FILE                  output image, .exr/.pfm/.png (repeatable; default: the scene's Output)\n"
           "  --exposure E             PNG exposure: pixels are scaled by 2^E before sRGB\n"
           "  --stats FILE.json        write render statistics\n"
           "  --view                   watch the render in a window: + / - exposure, s saves the outputs now,\n"
           "                           p pauses, q / Esc / closing it stops like Ctrl-C; stays open when done\n"
           "  --interactive            move the camera and change the settings in the window (docs/interactive.md):\n"
           "                           the render restarts at each change; w writes the scene (--scene-out FILE)\n"
           "                           and prints the command line that renders it\n"
           "  --orbit-rate DEGREES     --interactive: a left drag across the window's width turns the camera\n"
           "                           this much about the point at the view's centre (default 60)\n"
           "  --eye X,Y,Z, --look-at X,Y,Z, --up X,Y,Z, --fov DEGREES   the camera, over the scene's\n"
           "  --focus-distance D, --f-stop N   the thin lens (aperture radius D / 2N; --f-stop 0: a pinhole)\n"
           "  --display-server HOST:PORT  stream the render to a running tev (e.g. 127.0.0.1:14158)\n"
           "  -D name=value            Mitsuba scene files: set a <default> parameter ($name)\n"
           "  --describe               print the scene's feature set and exit\n"
           "  --quiet                  no progress or warnings\n"
           "  --help, --version\n"
           "Ctrl-C saves the image so far and exits with status 130. Bad input exits with 2.\n";
}

CommandLine parseCommandLine(int argc, char** argv) {
    CommandLine cl;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) fail(a + " needs a value");
            return argv[++i];
        };
        if (a == "--help" || a == "-h") cl.help = true;
        else if (a == "--version") cl.version = true;
        else if (a == "--describe") cl.describe = true;
        else if (a == "--quiet" || a == "-q") cl.quiet = true;
        else if (a == "--tracer") {
            std::string v = value();
            if (v == "pt") cl.tracer = TracerKind::PT;
            else if (v == "lt") cl.tracer = TracerKind::LT;
            else if (v == "bpt") cl.tracer = TracerKind::BPT;
            else if (v == "mmlt") cl.tracer = TracerKind::MMLT;
            else if (v == "pssmlt") cl.tracer = TracerKind::PSSMLT;
            else fail("--tracer: '" + v + "' is not one of pt, lt, bpt, mmlt, pssmlt");
        } else if (a == "--spp") cl.spp = int(parseInt(a, value(), 1, 1 << 24));
        else if (a == "--time") cl.timeBudget = parseReal(a, value(), 1e-3, 1e9);
        else if (a == "--threads") cl.threads = int(parseInt(a, value(), 0, 4096));
        // Any count is accepted here; main() refuses one that would not fit in memory.
        else if (a == "--chains") {
            const std::string v = value();
            cl.chains = v == "auto" ? 0 : parseInt(a, v, 1, 1000000000000000LL);  // 0: auto
        } else if (a == "--bootstrap") cl.bootstrap = int(parseInt(a, value(), 1, 1 << 30));
        else if (a == "--pass-length") cl.passLength = int(parseInt(a, value(), 1, 1 << 30));
        else if (a == "--p-large") {
            cl.probLarge = float(parseReal(a, value(), 0, 1));
            if (!(*cl.probLarge > 0)) fail("--p-large: must be greater than 0");
        } else if (a == "--mmlt-target") {
            const std::string v = value();
            MmltTarget t;
            if (!parseMmltTarget(v, t)) fail("--mmlt-target: '" + v + "' is not one of luminance, relative");
            cl.mmltTarget = t;
        } else if (a == "--mmlt-target-exponent") {
            cl.targetExponent = float(parseReal(a, value(), 0, 1));
            if (!(*cl.targetExponent > 0)) fail("--mmlt-target-exponent: must be greater than 0");
        } else if (a == "--mmlt-delayed-rejection") {
            const std::string v = value();
            if (v == "on" || v == "off") cl.delayedRejection = v == "on";
            else fail("--mmlt-delayed-rejection: '" + v + "' is not one of off, on");
        } else if (a == "--mmlt-film-steps") {
            const std::string v = value();
            FilmSteps f;
            if (!parseFilmSteps(v, f)) fail("--mmlt-film-steps: '" + v + "' is not one of off, learned, always");
            cl.filmSteps = f;
        } else if (a == "--mmlt-steps") {
            const std::string v = value();
            if (v == "fixed" || v == "learned") cl.learnSteps = v == "learned";
            else fail("--mmlt-steps: '" + v + "' is not one of fixed, learned");
        } else if (a == "--spectral" || a == "--rgb") {
            cl.spectral = a == "--spectral";
        } else if (a == "--strategy-images") cl.strategyImages = value();
        else if (a == "--mis-beta") cl.misBeta = float(parseReal(a, value(), 0.5, 16));
        else if (a == "--seed") cl.seed = uint64_t(parseInt(a, value(), 0, (1LL << 62)));
        else if (a == "--width") cl.width = int(parseInt(a, value(), 1, 16384));
        else if (a == "--height") cl.height = int(parseInt(a, value(), 1, 16384));
        else if (a == "--max-length") cl.maxLength = int(parseInt(a, value(), 1, 64));
        else if (a == "--min-length") cl.minLength = int(parseInt(a, value(), 1, 64));
        else if (a == "--filter") cl.filter = parseFilter(value());
        else if (a == "-o" || a == "--output") cl.outputs.push_back(value());
        else if (a == "-D" || (a.size() > 2 && a.compare(0, 2, "-D") == 0)) {
            const std::string d = a == "-D" ? value() : a.substr(2);
            const size_t eq = d.find('=');
            if (eq == std::string::npos || eq == 0) fail("-D: '" + d + "' is not name=value");
            cl.defines.emplace_back(d.substr(0, eq), d.substr(eq + 1));
        } else if (a == "--exposure") cl.exposure = float(parseReal(a, value(), -64, 64));
        else if (a == "--stats") cl.statsPath = value();
        else if (a == "--view") cl.view = true;
        else if (a == "--interactive") cl.interactive = true;
        else if (a == "--scene-out") cl.sceneOut = value();
        else if (a == "--orbit-rate") {
            const std::string v = value();
            cl.orbitRate = float(parseReal(a, v, -1e30, 1e30));
            if (!(cl.orbitRate > 0)) fail("--orbit-rate: '" + v + "' is not a positive number of degrees per window width (e.g. 60)");
        } else if (a == "--eye") cl.eye = parseVec3(a, value());
        else if (a == "--look-at") cl.lookAt = parseVec3(a, value());
        else if (a == "--up") cl.up = parseVec3(a, value());
        else if (a == "--fov") cl.fov = float(parseReal(a, value(), 1, 170));
        else if (a == "--focus-distance") cl.focusDistance = float(parseReal(a, value(), 1e-30, 1e30));
        else if (a == "--f-stop") cl.fStop = float(parseReal(a, value(), 0, 1e30));
        else if (a == "--display-server") parseHostPort(value(), cl.displayHost, cl.displayPort);
        else if (!a.empty() && a[0] == '-') fail("unknown option '" + a + "' (see --help)");
        else if (cl.scenePath.empty()) cl.scenePath = a;
        else fail("more than one scene given ('" + cl.scenePath + "', '" + a + "')");
    }
    return cl;
}

void applyCommandLine(const CommandLine& cl, Settings& s) {
    if (cl.tracer) s.tracer = *cl.tracer;
    if (cl.threads) s.threads = *cl.threads;
    if (cl.width) s.width = *cl.width;
    if (cl.height) s.height = *cl.height;
    if (cl.maxLength) s.maxPathLength = *cl.maxLength;
    if (cl.minLength) s.minPathLength = *cl.minLength;
    if (cl.probLarge) s.probLarge = *cl.probLarge;
    if (!cl.strategyImages.empty() && s.tracer != TracerKind::BPT) fail("--strategy-images needs --tracer bpt");
    if (s.minPathLength > s.maxPathLength)
        fail("the minimum path length " + std::to_string(s.minPathLength) + " exceeds the maximum " + std::to_string(s.maxPathLength));
}

void applyCamera(const CommandLine& cl, CameraDesc& c) {
    if (cl.eye) c.position = *cl.eye;
    if (cl.lookAt) c.lookAt = *cl.lookAt;
    if (cl.up) c.up = *cl.up;
    if (cl.fov) c.fovDegrees = *cl.fov;
    if (cl.focusDistance) c.focalLength = *cl.focusDistance;
    if (cl.fStop) {
        c.dof = *cl.fStop > 0;
        if (c.dof) c.fStop = *cl.fStop;
    }
    if (!(cl.eye || cl.lookAt || cl.up)) return;
    const Vec3 d = c.lookAt - c.position;
    if (!(length(d) > 0)) fail("--eye and --look-at: the camera must look somewhere (they are the same point)");
    if (!(length(cross(d, c.up)) > 0)) fail("--up: must not be parallel to the view direction");
}

SceneDesc loadCommandLineScene(const CommandLine& cl) {
    SceneDesc scene = cl.scenePath.empty()
                          ? loadSceneFromString(kDefaultSceneXml, "<built-in scene>", ".")
                          : loadScene(cl.scenePath, cl.defines, LoadOptions{cl.tracer.has_value(), cl.tracer.value_or(TracerKind::MMLT)});
    applyToScene(cl, scene);
    return scene;
}

void applyToScene(const CommandLine& cl, SceneDesc& scene) {
    applyCommandLine(cl, scene.settings);
    applyCamera(cl, scene.camera);
    if (cl.filter) scene.filter = *cl.filter;
}

RenderOptions renderOptionsFor(const CommandLine& cl, const Settings& s) {
    RenderOptions opt;
    opt.tracer = s.tracer;
    opt.spp = cl.spp ? *cl.spp : s.samples * s.samples;
    opt.strataPerAxis = strataForSpp(opt.spp);
    opt.timeBudget = cl.timeBudget.value_or(0.0);
    // The built-in scene asked for no sample count and no time: the first render a newcomer
    // makes (the README's first command), given the seconds that make it clean enough to show,
    // with the tracer whose image is the cleanest in that time unless one is asked for
    // (docs/benchmarks.md, "The first render": PT's relMSE 0.036, BPT's 0.040, MMLT's 0.125).
    if (cl.scenePath.empty() && !cl.spp && !cl.timeBudget) {
        opt.timeBudget = kFirstRenderSeconds;
        if (!cl.tracer) opt.tracer = TracerKind::PT;
    }
    opt.threads = s.threads;
    opt.seed = cl.seed;
    if (cl.misBeta) opt.misBeta = *cl.misBeta;
    if (cl.passLength) opt.passLength = *cl.passLength;
    if (cl.mmltTarget) opt.mmltTarget = *cl.mmltTarget;
    if (cl.learnSteps) opt.learnSteps = *cl.learnSteps;
    if (cl.delayedRejection) opt.delayedRejection = *cl.delayedRejection;
    if (cl.filmSteps) opt.filmSteps = *cl.filmSteps;
    if (cl.targetExponent) opt.mmltTargetExponent = *cl.targetExponent;
    opt.spectral = cl.spectral ? *cl.spectral : s.spectral;
    opt.spectralByDefault = !cl.spectral && s.spectral;
    if (cl.chains) opt.chains = int(std::min<long long>(*cl.chains, std::numeric_limits<int>::max()));
    if (cl.bootstrap) opt.bootstrap = *cl.bootstrap;
    opt.probLarge = s.probLarge;
    opt.strategyImages = cl.strategyImages;
    opt.minPathLength = s.minPathLength;
    opt.maxPathLength = s.maxPathLength;
    return opt;
}

void checkChainMemory(long long chains, const Settings& s, bool media) {
    const double mem = physicalMemoryBytes();
    // (as a spectral render's chains, one number more: a bound either way)
    const uint64_t perChain =
        s.tracer == TracerKind::PSSMLT ? pssmltChainBytes(s.maxPathLength, media, true) : mmltChainBytes(s.maxPathLength, media, true);
    const double bytes = double(chains) * double(perChain);
    if (mem > 0 && bytes > 0.75 * mem)
        throw InputError("wavemmlt: --chains " + std::to_string(chains) + " would need " + bytesText(bytes) + " of chain state (" +
                         std::to_string(perChain) + " bytes per chain at MaxPathLength " + std::to_string(s.maxPathLength) +
                         "), more than 3/4 of this machine's " + bytesText(mem) + " of memory");
    if (chains > std::numeric_limits<int>::max())
        throw InputError("wavemmlt: --chains " + std::to_string(chains) + " is more than the " + std::to_string(std::numeric_limits<int>::max()) +
                         " chains wavemmlt can run");
}

}  // namespace wmlt
