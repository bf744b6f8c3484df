// Test helper for test_mpi.cpp: one mpirun renders K seeds of each tracer asked for (the
// statistical tests need many runs; a launch costs about a second), through render() with
// the ranks that wavemmlt itself uses. Every rank loads the scene; rank 0 writes, per tracer
// and seed, OUT/<tracer>-<seed>.pfm and OUT/<tracer>-<seed>.txt (MMLT: b_k and the pools'
// digest as each rank had them, one line per rank).
//   mpirun -np N wavemmlt_mpi_runner SCENE.xml OUT WIDTH MAXLENGTH THREADS SEED0 RUNS TRACER:SPP[:CHAINS]... (CHAINS 0: auto)
// TRACER mmlt-levers: MMLT with its levers on (the relative target, learned step sizes).
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <string>

#include "stages/core/distributed.h"
#include "wavemmlt/error.h"
#include "wavemmlt/image.h"
#include "wavemmlt/render.h"
#include "wavemmlt/scene_desc.h"

using namespace wmlt;

int main(int argc, char** argv) {
    std::unique_ptr<Distributed> ranks = startRanks(argc, argv);
    if (argc < 9) {
        std::cerr << "usage: wavemmlt_mpi_runner SCENE OUT WIDTH MAXLENGTH THREADS SEED0 RUNS TRACER:SPP[:CHAINS]...\n";
        return 2;
    }
    try {
        SceneDesc desc = loadScene(argv[1]);
        const std::string out = argv[2];
        desc.settings.width = desc.settings.height = std::atoi(argv[3]);
        const int maxLength = std::atoi(argv[4]), threads = std::atoi(argv[5]);
        const uint64_t seed0 = std::strtoull(argv[6], nullptr, 10);
        const int runs = std::atoi(argv[7]);
        for (int a = 8; a < argc; ++a) {
            const std::string spec = argv[a];
            const size_t c1 = spec.find(':'), c2 = spec.find(':', c1 + 1);
            const std::string tracer = spec.substr(0, c1);
            RenderOptions o;
            o.tracer = tracer == "pt"       ? TracerKind::PT
                       : tracer == "lt"     ? TracerKind::LT
                       : tracer == "bpt"    ? TracerKind::BPT
                       : tracer == "pssmlt" ? TracerKind::PSSMLT
                                            : TracerKind::MMLT;
            if (tracer == "mmlt-levers") {
                o.mmltTarget = MmltTarget::Relative;
                o.learnSteps = true;
                o.filmSteps = FilmSteps::Always;
            }
            o.spp = std::atoi(spec.c_str() + c1 + 1);
            if (c2 != std::string::npos) o.chains = std::atoi(spec.c_str() + c2 + 1);
            o.strataPerAxis = strataForSpp(o.spp);
            o.threads = threads;
            o.maxPathLength = maxLength;
            o.ranks = ranks->many() ? ranks.get() : nullptr;
            for (int i = 0; i < runs; ++i) {
                o.seed = seed0 + uint64_t(i);
                const RenderResult r = render(desc, o);
                if (!ranks->root()) continue;
                const std::string stem = out + "/" + tracer + "-" + std::to_string(o.seed);
                writeImage(stem + ".pfm", r.image, 0);
                std::ofstream f(stem + ".txt");
                f << std::setprecision(17);
                for (size_t rk = 0; rk < r.stats.mmlt.bByRank.size(); ++rk) {
                    f << "rank " << rk << " digest " << std::hex << r.stats.mmlt.poolDigestByRank[rk] << std::dec << " b";
                    for (double b : r.stats.mmlt.bByRank[rk]) f << ' ' << b;
                    f << '\n';
                }
                f << "ranks " << r.stats.ranks.count << " bytes";
                for (uint64_t b : r.stats.ranks.bytes) f << ' ' << b;
                f << "\nnonfinite " << r.stats.samplesNonfiniteDiscarded << " mismatches " << r.stats.mmlt.replayMismatches << "\nchains "
                  << r.stats.mmlt.chainsRun << '\n';
            }
        }
    } catch (const std::exception& e) {
        std::cerr << "error: " << e.what() << "\n";
        abortRanks(2);
    }
    return 0;
}
