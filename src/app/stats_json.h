// The --stats JSON of a render: what the command line writes to its --stats file and the
// Python module returns as a dict (Render.stats), the same keys in both (tests/test_cli.cpp,
// "--stats writes JSON with the documented keys"; the README's "Using it" describes them).
#pragma once
#include <string>

#include "wavemmlt/render.h"
#include "wavemmlt/scene_desc.h"

namespace wmlt {

// `settings` are the render's: the image size and the path lengths reported.
std::string statsJson(const RenderResult& r, const Settings& settings);

}  // namespace wmlt
