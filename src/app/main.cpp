// wavemmlt: the command-line renderer.
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <mutex>

#include "app/cli.h"
#include "app/interactive_run.h"
#include "app/progress.h"
#include "app/ranks.h"
#include "app/stats_json.h"
#include "app/watchers.h"
#include "scene/features.h"
#include "scene/scene_spectra.h"
#include "stages/core/distributed.h"
#include "wavemmlt/error.h"
#include "wavemmlt/render.h"

namespace {

std::atomic<bool> gCancel{false};
std::atomic<bool> gInterrupted{false};  // Ctrl-C (or mpirun's SIGTERM), not q

void onInterrupt(int signal) {
    gCancel = true;
    gInterrupted = true;
    std::signal(signal, SIG_DFL);  // a second Ctrl-C ends the process at once
}

// The folder of an output path must exist and be writable before hours of rendering.
void checkOutputPath(const std::string& path, bool image) {
    if (image && !wmlt::isWritableImageExtension(path)) throw wmlt::InputError(path, 0, "unknown image format (use .exr, .pfm or .png)");
    size_t slash = path.find_last_of('/');
    std::string dir = slash == std::string::npos ? "." : (slash == 0 ? "/" : path.substr(0, slash));
    std::error_code ec;
    if (access(dir.c_str(), W_OK) != 0) throw wmlt::InputError(path, 0, "cannot write to folder '" + dir + "': " + std::strerror(errno));
    if (!std::filesystem::is_directory(dir, ec)) throw wmlt::InputError(path, 0, "cannot write to folder '" + dir + "': not a folder");
    if (std::filesystem::is_directory(path, ec)) throw wmlt::InputError(path, 0, "cannot write the file: a folder of that name exists");
}

// The --strategy-images folder: created when missing (its parent must exist).
void prepareFolder(const std::string& dir) {
    std::error_code ec;
    if (!std::filesystem::exists(dir, ec) && !std::filesystem::create_directory(dir, ec))
        throw wmlt::InputError(dir, 0, "cannot create the folder: " + ec.message());
    if (!std::filesystem::is_directory(dir, ec)) throw wmlt::InputError(dir, 0, "not a folder");
    if (access(dir.c_str(), W_OK) != 0) throw wmlt::InputError(dir, 0, std::string("cannot write to the folder: ") + std::strerror(errno));
}

void writeStats(const std::string& path, const wmlt::RenderResult& r, const wmlt::Settings& s) {
    const std::string json = wmlt::statsJson(r, s);
    std::string tmp = path + ".tmp-" + std::to_string(getpid());
    {
        std::ofstream f(tmp);
        f << json;
        if (!f) throw wmlt::InputError(path, 0, "cannot write statistics");
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        std::remove(tmp.c_str());
        throw wmlt::InputError(path, 0, std::string("cannot write statistics: ") + std::strerror(errno));
    }
}

// What the command line asks for, loaded and checked before any rendering.
struct Job {
    wmlt::CommandLine cl;
    wmlt::SceneDesc scene;
    std::vector<std::string> outputs;
};

// What to try after the built-in scene: real scenes (those found from here), the
// interactive mode, Python and the docs.
std::string nextStepsText() {
    std::string t = "next:\n";
    const char* const scenes[] = {"../shared/scenes/pbrt-v4/veach-ajar/veach-ajar.pbrt", "tests/data/scenes/pbrt-v4/cornell-box/cornell-box.pbrt",
                                  "tests/data/scenes/mitsuba/veach-bidir/scene.xml"};
    std::error_code ec;
    for (const char* s : scenes)
        if (std::filesystem::is_regular_file(s, ec)) t += "  build/wavemmlt " + std::string(s) + " --time 30 -o scene.png\n";
    t += "  build/wavemmlt SCENE --interactive   a window: drag to orbit, change the tracer and settings\n"
         "  build/wavemmlt --help                every option; thesis, Mitsuba 3 and pbrt-v4 files load\n"
         "  import wavemmlt                      from Python (PYTHONPATH=build/python; docs/python.md)\n"
         "  README.md, docs/                     the docs\n";
    return t;
}

// --describe's last line: whether a render with these options is spectral, and why not
// (the reasons the tracers give in --stats' spectral_reason).
std::string spectralLine(const wmlt::SceneDesc& scene, const wmlt::RenderOptions& opt) {
    if (!opt.spectral)
        return scene.settings.spectral ? "spectral: no (RGB, asked for with --rgb)\n"
                                       : "spectral: no (RGB, the format's default; --spectral asks for sampled wavelengths)\n";
    const std::string why = wmlt::spectralUnsupported(scene);
    if (!why.empty()) return "spectral: no: the scene has " + why + " (not spectral yet)\n";
    return std::string("spectral: yes (") + wmlt::tracerName(opt.tracer) + (opt.spectralByDefault ? ", the format's default" : "") +
           ", sampled wavelengths: docs/spectral.md)\n";
}

// Parses, loads and checks (throws InputError). Returns false when the job ends here
// (--help, --version, --describe). Only rank 0 prints, opens viewers and checks the output
// paths (they are its files); the other ranks load the scene themselves, quietly.
bool prepare(int argc, char** argv, const wmlt::Distributed& ranks, Job& job) {
    using namespace wmlt;
    const bool root = ranks.root();
    CommandLine& cl = job.cl;
    cl = parseCommandLine(argc, argv);
    if (cl.help || cl.version) {
        if (root) std::cout << (cl.help ? usageText() : std::string("wavemmlt ") + WAVEMMLT_VERSION + "\n");
        return false;
    }
    if (cl.interactive && ranks.many())
        throw InputError("wavemmlt: --interactive needs one process (run it without mpirun; --view watches a render across ranks)");
    if (cl.interactive && !cl.statsPath.empty())
        throw InputError("wavemmlt: --stats is not written by --interactive (render the printed command line with --stats)");
    if (cl.interactive && !cl.strategyImages.empty()) throw InputError("wavemmlt: --strategy-images is not made by --interactive");
    if (root && (cl.view || cl.interactive) && !cl.describe) checkViewPossible(cl.interactive ? "--interactive" : "--view");
    if (ranks.many() && !cl.strategyImages.empty())
        throw InputError("wavemmlt: --strategy-images is made by one process only (run it without mpirun)");

    if (cl.scenePath.empty() && !cl.defines.empty()) throw InputError("wavemmlt: -D needs a Mitsuba scene file");
    job.scene = loadCommandLineScene(cl);
    if (root && !cl.quiet)
        for (const std::string& w : job.scene.warnings) std::cerr << "warning: " << w << "\n";
    if (cl.chains && *cl.chains > 0 && (job.scene.settings.tracer == TracerKind::MMLT || job.scene.settings.tracer == TracerKind::PSSMLT))
        wmlt::checkChainMemory(*cl.chains, job.scene.settings, deriveFeatures(job.scene).media);
    if (cl.describe) {
        if (root) std::cout << deriveFeatures(job.scene).describe() << spectralLine(job.scene, renderOptionsFor(cl, job.scene.settings));
        return false;
    }
    job.outputs = cl.outputs;
    if (job.outputs.empty()) job.outputs.push_back(job.scene.settings.output);
    if (!root) return true;
    for (const std::string& o : job.outputs) checkOutputPath(o, true);
    if (!cl.statsPath.empty()) checkOutputPath(cl.statsPath, false);
    if (!cl.strategyImages.empty()) prepareFolder(cl.strategyImages);
    return true;
}

int run(int argc, char** argv, wmlt::Distributed& ranks) {
    using namespace wmlt;
    Job job;
    const int early = prepareOnRanks(ranks, [&] { return prepare(argc, argv, ranks, job) ? -1 : 0; });
    if (early >= 0) return early;
    const CommandLine& cl = job.cl;
    const std::vector<std::string>& outputs = job.outputs;
    const bool root = ranks.root();

    const Settings& s = job.scene.settings;
    RenderOptions opt = renderOptionsFor(cl, s);
    opt.cancel = &gCancel;
    if (ranks.many()) opt.ranks = &ranks;
    if (root && !cl.quiet) opt.notice = [](const std::string& n) { std::fprintf(stderr, "%s\n", n.c_str()); };
    std::signal(SIGINT, onInterrupt);
    // Open MPI's mpirun turns a Ctrl-C into SIGTERM to every rank (then SIGKILL after
    // odls_base_sigkill_timeout, 1 s by default): the ranks agree to stop at the next
    // boundary and rank 0 writes the image so far (docs/mpi.md).
    if (ranks.many()) std::signal(SIGTERM, onInterrupt);

    // The outputs (rank 0's): at the end, and from the --view window's s key (its own thread).
    std::mutex outputsMutex;
    auto writeOutputs = [&](const Image& image, float exposure) {
        std::lock_guard<std::mutex> lock(outputsMutex);
        for (const std::string& o : outputs) writeImage(o, image, exposure);
    };
    auto saveNow = [&](const Snapshot& snap, float exposure) {
        try {
            writeOutputs(snap.image, exposure);
            if (!cl.quiet) std::fprintf(stderr, "\nsaved the image so far (%llu spp)\n", (unsigned long long)snap.spp);
        } catch (const std::exception& e) {
            std::fprintf(stderr, "\nwarning: %s\n", e.what());
        }
    };
    const std::string imageName = std::filesystem::path(outputs[0]).filename().string() + " (" + std::to_string(getpid()) + ")";
    CommandLine viewers = cl;  // rank 0 watches the job; the other ranks have no viewers
    if (!root) viewers.view = viewers.interactive = false, viewers.displayHost.clear();
    Watchers watchers(viewers, tracerName(opt.tracer), s.width, s.height, imageName, &gCancel, saveNow, !ranks.many());
    opt.view = watchers.view();
    // The interactive mode (--interactive, or the i key in --view): the scene built once and
    // rendered again at each change, until the window closes (interactive_run.cpp).
    auto interactive = [&](SceneDesc scene) {
        gCancel = false;
        return runInteractive(cl, std::move(scene), opt, watchers, gInterrupted,
                              [&](const Snapshot& snap, float exposure) { writeOutputs(snap.image, exposure); });
    };
    if (cl.interactive) return interactive(std::move(job.scene));
    Progress progress(cl.quiet || !root);
    if (root)
        opt.progress = [&](double f) {
            progress.update(f);
            watchers.progress(f);
        };

    Settings settings = s;
    RenderResult r;
    try {
        r = render(std::move(job.scene), opt);
    } catch (const std::exception& e) {
        // Split across ranks, the others may be waiting in an exchange: the job ends here.
        if (ranks.many()) failRanks(ranks, dynamic_cast<const InputError*>(&e) ? 2 : 1, e.what());
        throw;
    }
    progress.finish();
    if (root && watchers.interactiveRequested() && !gInterrupted) return interactive(loadCommandLineScene(cl));
    if (!root) return r.stats.cancelled ? 130 : 0;
    writeOutputs(r.image, cl.exposure);
    for (const StrategyImage& si : r.strategyImages) {
        const std::string stem = opt.strategyImages + "/s" + std::to_string(si.s) + "_t" + std::to_string(si.t);
        writeImage(stem + "_weighted.exr", si.weighted, 0);
        writeImage(stem + "_unweighted.exr", si.unweighted, 0);
    }
    if (!cl.statsPath.empty()) writeStats(cl.statsPath, r, settings);
    if (!cl.quiet) {
        const std::string across = ranks.many() ? " on " + std::to_string(ranks.size()) + " ranks" : "";
        std::fprintf(stderr, "%s: %llu spp in %.2f s%s, %.2f Mrays/s%s\n", tracerName(opt.tracer), (unsigned long long)r.stats.spp, r.stats.seconds,
                     across.c_str(), r.stats.mraysPerSecond(), r.stats.cancelled ? " (interrupted: image so far saved)" : "");
        std::string written;
        for (const std::string& o : outputs) written += (written.empty() ? "" : ", ") + o;
        std::fprintf(stderr, "wrote %s\n", written.c_str());
        if (cl.scenePath.empty()) std::fputs(nextStepsText().c_str(), stderr);  // the first render a newcomer makes
    }
    for (const std::string& w : renderWarnings(r))  // (an estimator's replay mismatch even with --quiet)
        if (!cl.quiet || r.stats.mmlt.replayMismatches) std::fprintf(stderr, "warning: %s\n", w.c_str());
    // With --view: until the window is closed, or the i key asks for the interactive mode.
    if (watchers.finish(r)) return interactive(loadCommandLineScene(cl));
    return r.stats.cancelled ? 130 : 0;
}

}  // namespace

int main(int argc, char** argv) {
    // Under mpirun: MPI_Init here, MPI_Finalize when `ranks` goes (before main returns).
    std::unique_ptr<wmlt::Distributed> ranks = wmlt::startRanks(argc, argv);
    try {
        return run(argc, argv, *ranks);
    } catch (const wmlt::InputError& e) {
        std::cerr << "error: " << e.what() << "\n";
        return 2;
    } catch (const std::bad_alloc&) {
        std::cerr << "error: out of memory\n";
        return 1;
    } catch (const std::exception& e) {
        std::cerr << "error: " << e.what() << "\n";
        return 1;
    }
}
