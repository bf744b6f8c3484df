// A scene built once and rendered many times (the interactive mode, src/app/interactive.h):
// render() is Scene::build, then renderScene.
#pragma once
#include "scene/scene.h"
#include "wavemmlt/render.h"

namespace wmlt {

// Renders the built scene with its current camera (Scene::setView) and image size.
// Throws InputError as render() does for options no tracer can render.
RenderResult renderScene(Scene& scene, const RenderOptions& options);

}  // namespace wmlt
