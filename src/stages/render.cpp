// render(): builds the scene once and hands it to the chosen tracer.
#include <tbb/global_control.h>
#include <tbb/info.h>

#include "stages/bidirectional.h"
#include "stages/light_tracer.h"
#include "stages/mmlt.h"
#include "stages/path_tracer.h"
#include "wavemmlt/error.h"
#include "wavemmlt/render.h"

namespace wmlt {

int strataForSpp(int spp) {
    int n = 1;
    for (int k = 1; k * k <= spp; ++k)
        if (spp % (k * k) == 0) n = k;
    return n;
}

RenderResult render(SceneDesc desc, const RenderOptions& opt) {
    if (!opt.strategyImages.empty() && opt.tracer != TracerKind::BPT)
        throw InputError("strategy images need the BPT tracer");
    if (opt.tracer == TracerKind::MMLT && !(opt.probLarge > 0 && opt.probLarge <= 1))
        throw InputError("ProbLarge must be in (0, 1]");
    int threads = opt.threads > 0 ? opt.threads : tbb::info::default_concurrency();
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
    std::unique_ptr<Scene> scene = Scene::build(std::move(desc), threads);
    RenderResult r = opt.tracer == TracerKind::MMLT  ? renderMmlt(*scene, opt)
                     : opt.tracer == TracerKind::LT  ? renderLightTracing(*scene, opt)
                     : opt.tracer == TracerKind::BPT ? renderBidirectional(*scene, opt)
                                                     : renderPathTracing(*scene, opt);
    r.stats.threads = threads;
    return r;
}

}  // namespace wmlt
