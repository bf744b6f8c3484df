// render(): builds the scene once and hands it to the chosen tracer.
#include <tbb/global_control.h>
#include <tbb/info.h>

#include "scene/scene_spectra.h"
#include "stages/bpt/bidirectional.h"
#include "stages/core/distributed.h"
#include "stages/core/memory.h"
#include "stages/core/strategy_films.h"
#include "stages/lt/light_tracer.h"
#include "stages/mmlt/mmlt.h"
#include "stages/pssmlt/pssmlt.h"
#include "stages/pt/path_tracer.h"
#include "stages/render_scene.h"
#include "wavemmlt/error.h"
#include "wavemmlt/render.h"

namespace wmlt {

int strataForSpp(int spp) {
    int n = 1;
    for (int k = 1; k * k <= spp; ++k)
        if (spp % (k * k) == 0) n = k;
    return n;
}

namespace {

// The films a tracer keeps, in bytes (MMLT adds its chain state: mmlt.cpp checks it).
std::vector<std::pair<std::string, uint64_t>> filmBuffers(const RenderOptions& opt, int w, int h) {
    const uint64_t px = uint64_t(w) * uint64_t(h), image = 12 * px;
    const uint64_t film = 24 * px + 4 * px, splats = 24 * px;  // Film (sums, counts), SplatFilm
    switch (opt.tracer) {
        case TracerKind::PT: return {{"film", film}, {"image", image}};
        case TracerKind::LT: return {{"splat film", splats}, {"image", image}};
        case TracerKind::BPT: {
            std::vector<std::pair<std::string, uint64_t>> b = {{"film", film}, {"splat film", splats}, {"image", image}};
            if (!opt.strategyImages.empty() || opt.lengthImages) b.push_back({"strategy films", StrategyFilms::bytes(w, h, opt.maxPathLength)});
            return b;
        }
        case TracerKind::MMLT:
        case TracerKind::PSSMLT:
            return {{"film", splats}, {"length films", opt.lengthImages ? splats * uint64_t(opt.maxPathLength) : 0}, {"image", image}};
    }
    return {};
}

}  // namespace

namespace {

// What no tracer can render, refused before the scene is built: bad path lengths, options
// of the wrong tracer, films that would not fit (with the figure).
std::vector<std::pair<std::string, uint64_t>> checkOptions(const RenderOptions& opt, int width, int height) {
    if (opt.maxPathLength < 1 || opt.maxPathLength > kMaxPathLength || opt.minPathLength < 1 || opt.minPathLength > opt.maxPathLength)
        throw InputError("path lengths must satisfy 1 <= min <= max <= " + std::to_string(kMaxPathLength));
    if (!opt.strategyImages.empty() && opt.tracer != TracerKind::BPT) throw InputError("strategy images need the BPT tracer");
    const bool metropolis = opt.tracer == TracerKind::MMLT || opt.tracer == TracerKind::PSSMLT;
    if (!misBetaValid(opt.misBeta)) throw InputError(kMisBetaRange);
    if (metropolis && !(opt.probLarge > 0 && opt.probLarge <= 1)) throw InputError("ProbLarge must be in (0, 1]");
    if (opt.lengthImages && opt.tracer != TracerKind::BPT && opt.tracer != TracerKind::MMLT)
        throw InputError("length images need the BPT or MMLT tracer (PSSMLT's chains carry every length at once)");
    if (opt.ranks && opt.ranks->many() && (!opt.strategyImages.empty() || opt.lengthImages))
        throw InputError("strategy and length images are made by one process only (run without mpirun)");
    const auto buffers = filmBuffers(opt, width, height);
    double bytes = 0;
    for (const auto& b : buffers) bytes += double(b.second);
    const double mem = physicalMemoryBytes();
    if (mem > 0 && bytes > 0.75 * mem)
        throw InputError("a " + std::to_string(width) + " x " + std::to_string(height) + " render needs " + bytesText(bytes) +
                         " of films, more than 3/4 of this machine's " + bytesText(mem));
    return buffers;
}

int threadCount(const RenderOptions& opt) { return opt.threads > 0 ? opt.threads : tbb::info::default_concurrency(); }

}  // namespace

RenderResult renderScene(Scene& scene, const RenderOptions& asked) {
    const auto buffers = checkOptions(asked, scene.camera.width, scene.camera.height);
    RenderOptions opt = asked;
    opt.misBeta = misBetaOf(asked);  // the tracers read the exponent itself
    const int threads = threadCount(opt);
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
    if (scene.features.emissiveMedia && opt.tracer == TracerKind::LT)
        throw InputError(scene.desc.path, 0,
                         "the light tracer cannot start paths in an emitting medium: render it with --tracer pt, bpt or mmlt (docs/media.md)");
    RenderResult r = opt.tracer == TracerKind::MMLT     ? renderMmlt(scene, opt)
                     : opt.tracer == TracerKind::PSSMLT ? renderPssmlt(scene, opt)
                     : opt.tracer == TracerKind::LT     ? renderLightTracing(scene, opt)
                     : opt.tracer == TracerKind::BPT    ? renderBidirectional(scene, opt)
                                                        : renderPathTracing(scene, opt);
    r.stats.threads = threads;
    if (opt.tracer == TracerKind::BPT || opt.tracer == TracerKind::MMLT || opt.tracer == TracerKind::PSSMLT) r.stats.misBeta = opt.misBeta;
    r.stats.spectralByDefault = opt.spectralByDefault;
    for (const MaterialDesc& m : scene.desc.materials) r.stats.dispersionAsIndex |= !r.stats.spectral && m.etaSpectrum >= 0;
    if (opt.spectralByDefault && !r.stats.spectralReason.empty())
        r.stats.spectralReason = "spectral by the format's default, but " + r.stats.spectralReason;
    if (r.stats.buffers.empty()) r.stats.buffers = buffers;
    // The scene: its triangle meshes' arrays (a shape group's once, however many instances)
    // and what Embree holds (BVHs, instances), from Embree's memory monitor.
    r.stats.buffers.push_back({"meshes", scene.meshBytes});
    r.stats.buffers.push_back({"embree", uint64_t(std::max<int64_t>(0, scene.embreeBytes.load()))});
    return r;
}

std::vector<std::string> renderWarnings(const RenderResult& r) {
    std::vector<std::string> w;
    const RenderStats& s = r.stats;
    if (!s.spectralReason.empty() && !s.spectralByDefault) w.push_back("--spectral: " + s.spectralReason);
    if (s.dispersionAsIndex)
        w.push_back("a dispersive glass rendered in RGB, with its index at 550 nm (a spectral render disperses it: docs/spectral.md)");
    if (s.samplesNonfiniteDiscarded) w.push_back(std::to_string(s.samplesNonfiniteDiscarded) + " samples were NaN or infinite and were discarded");
    if (s.mmlt.chainsRun < s.mmlt.chainsAsked)
        w.push_back("ran " + std::to_string(s.mmlt.chainsRun) + " chains, not " + std::to_string(s.mmlt.chainsAsked) +
                    ": one iteration of them all costs at most 2% of --time (a longer budget runs them all)");
    if (s.mmlt.replayMismatches)
        w.push_back(std::to_string(s.mmlt.replayMismatches) + " of " + std::to_string(s.mmlt.replayed) +
                    " replayed MMLT seeds evaluated differently from their pool entries (F, target or film point): an estimator "
                    "bug, the image may be biased; please report it with the scene and the command line");
    return w;
}

RenderResult render(SceneDesc desc, const RenderOptions& opt) {
    // Films that would not fit are refused before the scene is built.
    checkOptions(opt, desc.settings.width, desc.settings.height);
    const int threads = threadCount(opt);
    if (opt.spectral) resolveBlendsForSpectral(desc);  // (its linear blends, one part per hit)
    std::unique_ptr<Scene> scene;
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
        scene = Scene::build(std::move(desc), threads);
    }
    return renderScene(*scene, opt);
}

}  // namespace wmlt
