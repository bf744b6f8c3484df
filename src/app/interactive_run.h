// main()'s interactive mode: builds the scene once, runs the session in the window until
// it closes, then writes the outputs (the image shown). Returns the exit status: 0 when the
// user closed the window or pressed q, 130 after Ctrl-C.
#pragma once
#include <atomic>
#include <functional>

#include "app/cli.h"
#include "app/watchers.h"

namespace wmlt {

int runInteractive(const CommandLine& cl, SceneDesc scene, const RenderOptions& base, Watchers& watchers, const std::atomic<bool>& interrupted,
                   std::function<void(const Snapshot&, float)> writeOutputs);

}  // namespace wmlt
