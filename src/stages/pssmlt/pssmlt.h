// Primary-sample-space MLT over bidirectional path tracing (Kelemen et al. 2002; --tracer
// pssmlt): the baseline MMLT (Hachisuka et al. 2014) was made to beat. One primary sample
// drives a whole BPT sample (every strategy of every length, MIS-weighted), its target the
// luminance of the sum. It runs on MMLT's driver and stages (mmlt_render.h) with one chain
// group of whole samples (pssmlt_stages.h): the same pools, bootstrap, passes, rounds, large
// and small steps, expected-value splats, replay and thread-count invariance; --chains,
// --p-large and --bootstrap mean what they mean for MMLT (docs/pssmlt.md).
#pragma once
#include "scene/scene.h"
#include "wavemmlt/render.h"

namespace wmlt {

// Throws InputError when no light reaches the camera or the chains would not fit in memory.
RenderResult renderPssmlt(const Scene& scene, const RenderOptions& opt);

}  // namespace wmlt
