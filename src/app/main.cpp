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
#include <iomanip>
#include <iostream>
#include <limits>
#include <mutex>
#include <sstream>

#include "app/cli.h"
#include "app/interactive_run.h"
#include "app/progress.h"
#include "app/ranks.h"
#include "app/watchers.h"
#include "scene/features.h"
#include "stages/core/distributed.h"
#include "stages/core/memory.h"
#include "stages/mmlt/mmlt.h"
#include "stages/pssmlt/pssmlt_stages.h"
#include "wavemmlt/error.h"
#include "wavemmlt/render.h"

namespace wmlt {
extern const char* const kDefaultSceneXml;
}

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

// MMLT's chain state must fit in memory: refused before anything is allocated, with the
// memory it would need (every chain counted at MaxPathLength, the largest state). The
// limit is the one renderMmlt applies to the chains it actually runs: 3/4 of the
// machine's physical memory.
void checkChainMemory(long long chains, const wmlt::Settings& s, bool media) {
    const double mem = wmlt::physicalMemoryBytes();
    const uint64_t perChain =
        s.tracer == wmlt::TracerKind::PSSMLT ? wmlt::pssmltChainBytes(s.maxPathLength, media) : wmlt::mmltChainBytes(s.maxPathLength, media);
    const double bytes = double(chains) * double(perChain);
    if (mem > 0 && bytes > 0.75 * mem)
        throw wmlt::InputError("wavemmlt: --chains " + std::to_string(chains) + " would need " + wmlt::bytesText(bytes) + " of chain state (" +
                               std::to_string(perChain) + " bytes per chain at MaxPathLength " + std::to_string(s.maxPathLength) +
                               "), more than 3/4 of this machine's " + wmlt::bytesText(mem) + " of memory");
    if (chains > std::numeric_limits<int>::max())
        throw wmlt::InputError("wavemmlt: --chains " + std::to_string(chains) + " is more than the " +
                               std::to_string(std::numeric_limits<int>::max()) + " chains wavemmlt can run");
}

// The --strategy-images folder: created when missing (its parent must exist).
void prepareFolder(const std::string& dir) {
    std::error_code ec;
    if (!std::filesystem::exists(dir, ec) && !std::filesystem::create_directory(dir, ec))
        throw wmlt::InputError(dir, 0, "cannot create the folder: " + ec.message());
    if (!std::filesystem::is_directory(dir, ec)) throw wmlt::InputError(dir, 0, "not a folder");
    if (access(dir.c_str(), W_OK) != 0) throw wmlt::InputError(dir, 0, std::string("cannot write to the folder: ") + std::strerror(errno));
}

// MMLT's figures, each an object keyed by path length where it is per length. PSSMLT's the
// same under its own prefix, with one value where MMLT's are per length (its one chain
// group, index 0, holds every length).
void writeMmltStats(std::ostream& o, const wmlt::RenderStats& st, const wmlt::Settings& s) {
    const wmlt::RenderStats::Mmlt& m = st.mmlt;
    const bool whole = st.tracer == "pssmlt";
    const std::string prefix = whole ? "pssmlt_" : "mmlt_";
    auto perLength = [&](const char* name, auto value) {
        o << ",\n  \"" << prefix << (name + 5) << "\": ";  // name without "mmlt_"
        if (whole) {
            o << value(size_t(0));
            return;
        }
        o << "{";
        for (int k = s.minPathLength; k <= s.maxPathLength && k < int(m.b.size()); ++k)
            o << (k == s.minPathLength ? "" : ", ") << '"' << k << "\": " << value(size_t(k));
        o << "}";
    };
    auto rate = [](uint64_t a, uint64_t p) { return p ? double(a) / double(p) : 0.0; };
    perLength("mmlt_b", [&](size_t k) { return m.b[k]; });
    perLength("mmlt_b_bootstrap", [&](size_t k) { return m.bBootstrap[k]; });
    perLength("mmlt_chains", [&](size_t k) { return m.chains[k]; });
    perLength("mmlt_chains_seeded", [&](size_t k) { return m.chainsSeeded[k]; });
    perLength("mmlt_distinct_seeds", [&](size_t k) { return m.distinctSeeds[k]; });
    perLength("mmlt_bootstrap_samples", [&](size_t k) { return m.bootstrapSamples[k]; });
    perLength("mmlt_bootstrap_with_light", [&](size_t k) { return m.bootstrapNonzero[k]; });
    perLength("mmlt_pool_samples", [&](size_t k) { return m.poolSamples[k]; });
    perLength("mmlt_proposals", [&](size_t k) { return m.proposals[k]; });
    perLength("mmlt_acceptance_small", [&](size_t k) { return rate(m.acceptedSmall[k], m.proposedSmall[k]); });
    perLength("mmlt_acceptance_large", [&](size_t k) { return rate(m.acceptedLarge[k], m.proposedLarge[k]); });
    if (m.learnedSteps) perLength("mmlt_small_step_sigma", [&](size_t k) { return m.smallStepSigma[k]; });
    uint64_t acc[2], prop[2];
    m.stepTotals(acc, prop);
    o << ",\n  \"" << prefix << "acceptance\": {\"small\": " << rate(acc[0], prop[0]) << ", \"large\": " << rate(acc[1], prop[1])
      << ", \"all\": " << rate(acc[0] + acc[1], prop[0] + prop[1]) << "}"
      << ",\n  \"" << prefix << "mutations\": " << m.mutations << ",\n  \"" << prefix
      << "mutations_per_second\": " << (st.seconds > 0 ? double(m.mutations) / st.seconds : 0.0) << ",\n  \"" << prefix
      << "iterations\": " << m.iterations << ",\n  \"" << prefix << "passes\": " << m.passes << ",\n  \"" << prefix
      << "pass_length\": " << m.passLength << ",\n  \"" << prefix << "renewals\": " << (m.passes > 0 ? m.passes - 1 : 0) << ",\n  \"" << prefix
      << "tasks_per_round\": " << m.tasksPerRound << ",\n  \"" << prefix << "longest_task_ratio\": " << m.longestTaskRatio << ",\n  \"" << prefix
      << "replay_mismatches\": " << m.replayMismatches << ",\n  \"" << prefix << "chain_state_bytes\": " << m.chainBytes << ",\n  \"" << prefix
      << "chains_asked\": " << (m.chainsAuto ? std::string("\"auto\"") : std::to_string(m.chainsAsked)) << ",\n  \"" << prefix
      << "chains_run\": " << m.chainsRun << ",\n  \"" << prefix << "chains_reason\": \"" << m.chainsReason << "\"";
    o << ",\n  \"" << prefix << "target\": \"" << wmlt::mmltTargetName(m.target) << "\"";
    if (m.target == wmlt::MmltTarget::Relative)
        o << ",\n  \"" << prefix << "target_maps\": " << m.targetMaps << ",\n  \"" << prefix << "target_tile_size\": " << m.targetTileSize
          << ",\n  \"" << prefix << "target_scale\": {\"least\": " << m.targetScaleLeast << ", \"most\": " << m.targetScaleMost << "}";
    if (!m.poolDigestByRank.empty()) o << ",\n  \"" << prefix << "pool_digest\": \"" << std::hex << m.poolDigestByRank[0] << std::dec << "\"";
    if (st.ranks.count > 1) {  // what each rank computed: the same on every rank (docs/mpi.md)
        o << ",\n  \"" << prefix << "b_by_rank\": [";
        for (size_t r = 0; r < m.bByRank.size(); ++r) {
            if (whole) {
                o << (r ? ", " : "") << std::setprecision(17) << m.bByRank[r][0];
                continue;
            }
            o << (r ? ", " : "") << "{";
            for (int k = s.minPathLength; k <= s.maxPathLength && k < int(m.bByRank[r].size()); ++k)
                o << (k == s.minPathLength ? "" : ", ") << '"' << k << "\": " << std::setprecision(17) << m.bByRank[r][size_t(k)];
            o << "}";
        }
        o << std::setprecision(9) << "],\n  \"" << prefix << "pool_digest_by_rank\": [";
        for (size_t r = 0; r < m.poolDigestByRank.size(); ++r) o << (r ? ", " : "") << '"' << std::hex << m.poolDigestByRank[r] << std::dec << '"';
        o << "]";
    }
}

// The ranks of a render split across processes: their count always, the exchanges' cost
// (per rank) when there are several.
void writeRankStats(std::ostream& o, const wmlt::RenderStats& st) {
    o << ",\n  \"ranks\": " << st.ranks.count;
    if (st.ranks.count <= 1) return;
    uint64_t bytes = 0;
    double seconds = 0;
    o << ",\n  \"mpi_bytes_by_rank\": [";
    for (size_t r = 0; r < st.ranks.bytes.size(); ++r) {
        o << (r ? ", " : "") << st.ranks.bytes[r];
        bytes += st.ranks.bytes[r];
    }
    o << "],\n  \"mpi_seconds_by_rank\": [";
    for (size_t r = 0; r < st.ranks.seconds.size(); ++r) {
        o << (r ? ", " : "") << st.ranks.seconds[r];
        seconds = std::max(seconds, st.ranks.seconds[r]);
    }
    o << "],\n  \"mpi_bytes\": " << bytes << ",\n  \"mpi_seconds_max\": " << seconds << ",\n  \"mpi_exchanges\": " << st.ranks.exchanges
      << ",\n  \"mpi_boundaries\": " << st.ranks.boundaries
      << ",\n  \"mpi_bytes_per_boundary\": " << (st.ranks.boundaries ? double(bytes) / double(st.ranks.boundaries) : 0.0)
      << ",\n  \"mpi_seconds_per_boundary\": " << (st.ranks.boundaries ? seconds / double(st.ranks.boundaries) : 0.0);
}

void writeStats(const std::string& path, const wmlt::RenderResult& r, const wmlt::Settings& s) {
    std::ostringstream o;
    o.precision(9);
    const wmlt::RenderStats& st = r.stats;
    o << "{\n  \"tracer\": \"" << st.tracer << "\",\n  \"seconds\": " << st.seconds << ",\n  \"threads\": " << st.threads
      << ",\n  \"spp\": " << st.spp << ",\n  \"width\": " << s.width << ",\n  \"height\": " << s.height
      << ",\n  \"rays_intersect\": " << st.raysIntersect << ",\n  \"rays_occluded\": " << st.raysOccluded
      << ",\n  \"mrays_per_second\": " << st.mraysPerSecond() << ",\n  \"samples_nonfinite_discarded\": " << st.samplesNonfiniteDiscarded
      << ",\n  \"cancelled\": " << (st.cancelled ? "true" : "false") << ",\n  \"spectral\": " << (st.spectral ? "true" : "false")
      << ",\n  \"spectral_reason\": \"" << st.spectralReason << "\",\n  \"mean_luminance_by_length\": {";
    // Path length k (segments) -> the image's mean luminance carried by length-k paths.
    for (int k = s.minPathLength; k <= s.maxPathLength && k < int(st.lengthMeanLuminance.size()); ++k)
        o << (k == s.minPathLength ? "" : ", ") << '"' << k << "\": " << st.lengthMeanLuminance[k];
    o << "}";
    writeRankStats(o, st);
    if (st.tracer == "mmlt" || st.tracer == "pssmlt") writeMmltStats(o, st, s);
    o << ",\n  \"buffers_bytes\": {";
    for (size_t i = 0; i < st.buffers.size(); ++i) o << (i ? ", " : "") << '"' << st.buffers[i].first << "\": " << st.buffers[i].second;
    o << "}";
    o << ",\n  \"scene_features\": " << r.featuresJson << "\n}\n";
    std::string tmp = path + ".tmp-" + std::to_string(getpid());
    {
        std::ofstream f(tmp);
        f << o.str();
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

// The scene file (or the built-in scene) with the command line's settings, filter and camera.
wmlt::SceneDesc loadJobScene(const wmlt::CommandLine& cl) {
    using namespace wmlt;
    SceneDesc scene = cl.scenePath.empty()
                          ? loadSceneFromString(kDefaultSceneXml, "<built-in scene>", ".")
                          : loadScene(cl.scenePath, cl.defines, LoadOptions{cl.tracer.has_value(), cl.tracer.value_or(TracerKind::MMLT)});
    applyCommandLine(cl, scene.settings);
    applyCamera(cl, scene.camera);
    if (cl.filter) scene.filter = *cl.filter;
    return scene;
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
    job.scene = loadJobScene(cl);
    if (root && !cl.quiet)
        for (const std::string& w : job.scene.warnings) std::cerr << "warning: " << w << "\n";
    if (cl.chains && *cl.chains > 0 && (job.scene.settings.tracer == TracerKind::MMLT || job.scene.settings.tracer == TracerKind::PSSMLT))
        checkChainMemory(*cl.chains, job.scene.settings, deriveFeatures(job.scene).media);
    if (cl.describe) {
        if (root) std::cout << deriveFeatures(job.scene).describe();
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
    RenderOptions opt;
    opt.tracer = s.tracer;
    opt.spp = cl.spp ? *cl.spp : s.samples * s.samples;
    opt.strataPerAxis = strataForSpp(opt.spp);
    opt.timeBudget = cl.timeBudget.value_or(0.0);
    opt.threads = s.threads;
    opt.seed = cl.seed;
    if (cl.misBeta) opt.misBeta = *cl.misBeta;
    if (cl.passLength) opt.passLength = *cl.passLength;
    if (cl.mmltTarget) opt.mmltTarget = *cl.mmltTarget;
    if (cl.learnSteps) opt.learnSteps = *cl.learnSteps;
    if (cl.spectral) opt.spectral = *cl.spectral;
    if (cl.chains) opt.chains = int(std::min<long long>(*cl.chains, std::numeric_limits<int>::max()));
    if (cl.bootstrap) opt.bootstrap = *cl.bootstrap;
    opt.probLarge = s.probLarge;
    opt.strategyImages = cl.strategyImages;
    opt.minPathLength = s.minPathLength;
    opt.maxPathLength = s.maxPathLength;
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
    if (root && watchers.interactiveRequested() && !gInterrupted) return interactive(loadJobScene(cl));
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
    }
    for (const std::string& w : renderWarnings(r))  // (an estimator's replay mismatch even with --quiet)
        if (!cl.quiet || r.stats.mmlt.replayMismatches) std::fprintf(stderr, "warning: %s\n", w.c_str());
    // With --view: until the window is closed, or the i key asks for the interactive mode.
    if (watchers.finish(r)) return interactive(loadJobScene(cl));
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
