// The thesis' XML format alone (load_scene.cpp): loadScene and loadSceneFromString
// (scene/load_by_format.cpp) call it for the files that are neither pbrt nor Mitsuba.
#pragma once
#include <string>

#include "wavemmlt/scene_desc.h"

namespace wmlt {

// Reads and validates thesis-format XML text (named `name` in messages, its relative file
// names resolved against `baseDir`). Throws InputError("file:line: <element>: problem").
SceneDesc loadThesisFromString(const std::string& xml, const std::string& name, const std::string& baseDir);

}  // namespace wmlt
