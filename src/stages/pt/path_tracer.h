// The path tracer (PT): next-event estimation and BSDF sampling combined with the power
// heuristic, run as wavefront stages over batches of tiles (pt_stages.h).
#pragma once
#include "scene/scene.h"
#include "wavemmlt/render.h"

namespace wmlt {

RenderResult renderPathTracing(const Scene& scene, const RenderOptions& options);

}  // namespace wmlt
