// Which importer a scene goes to: a .pbrt or .pbrt.gz name to the pbrt-v4 importer
// (pbrt/load_pbrt.cpp); XML whose root is <scene> to the Mitsuba 3 importer
// (mitsuba/load_mitsuba.cpp); other XML to the thesis' format (thesis/load_scene.cpp).
// -D defines are Mitsuba's only.
#include <filesystem>

#include "scene/read_file.h"
#include "scene/thesis/load_thesis.h"
#include "wavemmlt/error.h"
#include "wavemmlt/scene_desc.h"

namespace wmlt {

SceneDesc loadSceneFromString(const std::string& xml, const std::string& name, const std::string& baseDir) {
    if (isMitsubaXml(xml)) return loadMitsubaFromString(xml, name, baseDir);
    return loadThesisFromString(xml, name, baseDir);
}

SceneDesc loadScene(const std::string& path, const Defines& defines, const LoadOptions& options) {
    auto endsWith = [&](const char* e) {
        const std::string s(e);
        return path.size() >= s.size() && path.compare(path.size() - s.size(), s.size(), s) == 0;
    };
    auto noDefines = [&] {
        if (!defines.empty()) throw InputError(path, 0, "-D " + defines[0].first + "=...: -D applies to Mitsuba scene files only");
    };
    if (endsWith(".pbrt") || endsWith(".pbrt.gz")) {
        noDefines();
        return loadPbrt(path, options);
    }
    const std::string xml = readWholeFile(path, "the scene file");  // a regular file only
    const std::string base = std::filesystem::path(path).parent_path().string();
    const bool mitsuba = isMitsubaXml(xml);
    if (!mitsuba) noDefines();
    SceneDesc s = mitsuba ? loadMitsubaFromString(xml, path, base, defines, options) : loadThesisFromString(xml, path, base);
    s.path = path;
    return s;
}

}  // namespace wmlt
