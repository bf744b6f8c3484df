// A pbrt-v4 file against pbrt-v4's own render of it, block by block: K runs of one tracer at
// the reference's size, each block's mean (the three channels summed) as ours / pbrt's and
// as z = (ours - pbrt) / sigma, sigma from the runs' spread (ours: var / K; pbrt's 1024 spp:
// var * spp / 1024, the same estimator assumed), printed as a grid in the image's layout.
//
//   build/wavemmlt_bench_pbrt_blocks [FILE.pbrt REFERENCE.exr] [options]
//     --tracer pt|lt|bpt   [bpt]          --spp N     per run [32]
//     --runs K             [16]           --block B   pixels [25]
//     --coat ours|pbrt|pbrt-bdpt   the coated materials' weighting [ours]:
//       pbrt       pbrt-v4's exit weighting planted (MaterialDesc::Coating::pbrtExitWeight),
//                  f evaluated from the camera's side everywhere, as wavemmlt evaluates it;
//       pbrt-bdpt  BPT as pbrt-v4's BDPT evaluates that (non-reciprocal) f: from the light's
//                  side at a light subpath's vertex. Each run renders twice with the same
//                  seed, once with f from the camera's side and once from the light's
//                  (pbrtWalkFromLight), and adds the strategies' images: t = 1 (light
//                  tracing) from the second, the others from the first. Exact where no
//                  connection with s >= 2 and t >= 2 joins two coated vertices; the MIS
//                  weights are the same in both renders (only f changes).
//     --rgb                render in RGB [spectral, as pbrt-v4 files render by default]
//
// With no file: the caustic glass (../shared/scenes/pbrt-v4/caustic-glass, 175 x 250; says so
// and exits 0 when it is missing) with BPT three times: wavemmlt's coat, pbrt's exit weighting,
// and pbrt's as its BDPT evaluates it. Its only non-specular surface is the coated floor, a
// plane, so every strategy that connects anything is t = 1 or s = 1 and pbrt-bdpt is exact
// there. docs/pbrt.md has the figures.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "image/compare.h"
#include "wavemmlt/image.h"
#include "wavemmlt/render.h"
#include "wavemmlt/scene_desc.h"

using namespace wmlt;

namespace {

struct Config {
    TracerKind tracer = TracerKind::BPT;
    int spp = 32, runs = 16, block = 25;
    std::string coat = "ours";
    bool spectral = true;
};

[[noreturn]] void usage(const std::string& why) {
    std::fprintf(stderr, "wavemmlt_bench_pbrt_blocks: %s (see the comment at the top of bench/bench_pbrt_blocks.cpp)\n", why.c_str());
    std::exit(2);
}

void compareBlocks(const std::string& file, const std::string& reference, const Config& cfg) {
    const Image ref = readImage(reference);
    SceneDesc d = loadScene(file);
    d.settings.width = ref.width;
    d.settings.height = ref.height;
    int coated = 0;
    for (MaterialDesc& m : d.materials)
        if (m.kind == MaterialKind::Coated) {
            m.coating.pbrtExitWeight = cfg.coat != "ours";
            ++coated;
        }
    const bool composite = cfg.coat == "pbrt-bdpt";
    if (composite && cfg.tracer != TracerKind::BPT) usage("--coat pbrt-bdpt needs --tracer bpt");
    const char* tracerName = cfg.tracer == TracerKind::PT ? "pt" : cfg.tracer == TracerKind::LT ? "lt" : "bpt";
    std::printf("== %s: %s, %d runs of %d spp, %s, coat weighting %s (%d coated materials), blocks of %d pixels\n", file.c_str(), tracerName,
                cfg.runs, cfg.spp, cfg.spectral ? "spectral" : "RGB", cfg.coat.c_str(), coated, cfg.block);
    auto renderRun = [&](uint64_t seed, bool fromLight) {
        for (MaterialDesc& m : d.materials) m.coating.pbrtWalkFromLight = fromLight;
        RenderOptions o;
        o.tracer = cfg.tracer;
        o.spp = cfg.spp;
        o.strataPerAxis = strataForSpp(cfg.spp);
        o.seed = seed;
        o.maxPathLength = d.settings.maxPathLength;
        o.spectral = cfg.spectral;
        if (composite) o.strategyImages = "(kept in memory)";  // render() returns them; only the CLI writes the folder
        return render(d, o);
    };
    rstats::RunStats runs[4];  // the three channels and their sum
    for (int k = 0; k < cfg.runs; ++k) {
        const uint64_t seed = 101 + uint64_t(k);
        Image im(ref.width, ref.height);
        if (!composite) im = renderRun(seed, false).image;
        else {  // the strategies' images: t = 1 from f evaluated on the light's side
            const RenderResult camera = renderRun(seed, false), light = renderRun(seed, true);
            for (const RenderResult* r : {&camera, &light})
                for (const StrategyImage& st : r->strategyImages)
                    if ((st.t == 1) == (r == &light))
                        for (size_t i = 0; i < im.rgb.size(); ++i) im.rgb[i] += st.weighted.rgb[i];
        }
        std::vector<double> sum;
        for (int c = 0; c < 3; ++c) {
            const std::vector<double> b = rstats::blockMeans(im, cfg.block, c);
            runs[c].add(b);
            sum.resize(b.size(), 0.0);
            for (size_t i = 0; i < b.size(); ++i) sum[i] += b[i];
        }
        runs[3].add(sum);
    }
    std::vector<double> refSum;
    double ours[3] = {0, 0, 0}, theirs[3] = {0, 0, 0}, var[3] = {0, 0, 0};  // var: of ours[c] - theirs[c]
    for (int c = 0; c < 3; ++c) {
        const std::vector<double> b = rstats::blockMeans(ref, cfg.block, c);
        refSum.resize(b.size(), 0.0);
        for (size_t i = 0; i < b.size(); ++i) {
            refSum[i] += b[i];
            ours[c] += runs[c].mean(i);
            theirs[c] += b[i];
            var[c] += runs[c].variance(i) * (1.0 / cfg.runs + cfg.spp / 1024.0);
        }
    }
    const int bw = (ref.width + cfg.block - 1) / cfg.block;
    int beyond5 = 0, lit = 0;
    double worst = 0;
    for (size_t i = 0; i < refSum.size(); ++i) {
        const double v = runs[3].variance(i), sigma = std::sqrt(v / cfg.runs + v * cfg.spp / 1024.0);
        const double z = (runs[3].mean(i) - refSum[i]) / std::max(sigma, 1e-30);
        const bool isLit = refSum[i] > 1e-3 * theirs[1] / double(refSum.size());
        if (isLit) {
            ++lit;
            beyond5 += std::fabs(z) > 5;
            worst = std::max(worst, std::fabs(z));
        }
        if (isLit) std::printf(" %5.3f(%+5.1f)", runs[3].mean(i) / refSum[i], z);
        else std::printf(" %12s", "dark");
        if ((i + 1) % size_t(bw) == 0) std::printf("\n");
    }
    std::printf("means ours / pbrt (z):");
    for (int c = 0; c < 3; ++c) std::printf(" %.4f (%+.1f)", ours[c] / theirs[c], (ours[c] - theirs[c]) / std::sqrt(std::max(var[c], 1e-300)));
    std::printf("; lit blocks %d, beyond 5 sigma %d, worst |z| %.1f\n\n", lit, beyond5, worst);
}

}  // namespace

int main(int argc, char** argv) {
    Config cfg;
    std::vector<std::string> files;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) usage(a + " needs a value");
            return argv[++i];
        };
        auto count = [&]() {
            const int n = std::atoi(value().c_str());
            if (n < 1) usage(a + " needs a positive number");
            return n;
        };
        if (a == "--tracer") {
            const std::string t = value();
            if (t != "pt" && t != "lt" && t != "bpt") usage("--tracer is pt, lt or bpt");
            cfg.tracer = t == "pt" ? TracerKind::PT : t == "lt" ? TracerKind::LT : TracerKind::BPT;
        } else if (a == "--spp") cfg.spp = count();
        else if (a == "--runs") cfg.runs = std::max(2, count());
        else if (a == "--block") cfg.block = count();
        else if (a == "--coat") {
            cfg.coat = value();
            if (cfg.coat != "ours" && cfg.coat != "pbrt" && cfg.coat != "pbrt-bdpt") usage("--coat is ours, pbrt or pbrt-bdpt");
        } else if (a == "--rgb") cfg.spectral = false;
        else if (!a.empty() && a[0] == '-') usage("unknown option " + a);
        else files.push_back(a);
    }
    try {
        if (files.size() == 2) {
            compareBlocks(files[0], files[1], cfg);
            return 0;
        }
        if (!files.empty()) usage("give a pbrt file and pbrt-v4's render of it, or neither");
        const std::string dir = std::string(WAVEMMLT_SOURCE_DIR) + "/../shared/scenes/pbrt-v4/caustic-glass/";
        const std::string file = dir + "caustic-glass-v4.pbrt", reference = dir + "reference/pbrt-caustic-glass-v4-175x250-1024spp.exr";
        if (!std::filesystem::exists(file) || !std::filesystem::exists(reference)) {
            std::printf("%s is missing: nothing measured\n", dir.c_str());
            return 0;
        }
        Config c = cfg;
        c.tracer = TracerKind::BPT;
        for (const char* coat : {"ours", "pbrt", "pbrt-bdpt"}) {
            c.coat = coat;
            compareBlocks(file, reference, c);
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "wavemmlt_bench_pbrt_blocks: %s\n", e.what());
        return 2;
    }
    return 0;
}
