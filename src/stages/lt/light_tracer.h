// The light tracer (--tracer lt): light subpaths connected to the camera (t = 1).
#pragma once
#include "scene/scene.h"
#include "wavemmlt/render.h"

namespace wmlt {

RenderResult renderLightTracing(const Scene& scene, const RenderOptions& options);

}  // namespace wmlt
