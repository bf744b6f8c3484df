// Bidirectional path tracing (--tracer bpt): stages in bpt_stages.h, state in bpt_state.h.
#pragma once
#include "scene/scene.h"
#include "wavemmlt/render.h"

namespace wmlt {

RenderResult renderBidirectional(const Scene& scene, const RenderOptions& opt);

}  // namespace wmlt
