#include "app/interactive_run.h"

#include <tbb/global_control.h>
#include <tbb/info.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "app/interactive.h"
#include "scene/read_file.h"
#include "scene/scene_spectra.h"
#include "wavemmlt/error.h"

namespace wmlt {

extern const char* const kDefaultSceneXml;

namespace {

bool endsWith(const std::string& s, const char* end) {
    const size_t n = std::strlen(end);
    return s.size() >= n && s.compare(s.size() - n, n, end) == 0;
}

// Where the w key writes: --scene-out, else beside the scene file (so that the files it
// names are found from it) as <stem>-interactive.xml; the built-in scene's in the folder
// wavemmlt runs in.
std::string sceneOutPath(const CommandLine& cl) {
    if (!cl.sceneOut.empty()) return cl.sceneOut;
    if (cl.scenePath.empty()) return "wavemmlt-interactive.xml";
    const std::filesystem::path p(cl.scenePath);
    std::string stem = p.filename().string();
    for (const char* ext : {".xml", ".pbrt.gz", ".pbrt"})
        if (stem.size() > std::strlen(ext) && endsWith(stem, ext)) {
            stem.resize(stem.size() - std::strlen(ext));
            break;
        }
    return (p.parent_path() / (stem + "-interactive.xml")).string();
}

void writeText(const std::string& path, const std::string& text) {
    const std::string tmp = path + ".tmp-" + std::to_string(getpid());
    {
        std::ofstream f(tmp);
        f << text;
        if (!f) {
            std::remove(tmp.c_str());
            throw InputError(path, 0, "cannot write the scene file");
        }
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        std::remove(tmp.c_str());
        throw InputError(path, 0, "cannot write the scene file");
    }
}

}  // namespace

int runInteractive(const CommandLine& cl, SceneDesc scene, const RenderOptions& base, Watchers& watchers, const std::atomic<bool>& interrupted,
                   std::function<void(const Snapshot&, float)> writeOutputs) {
    ViewHub& hub = *watchers.hub();
    const ViewSettings initial = viewSettingsOf(scene.camera, base, cl.exposure);
    const Settings fileSettings = scene.settings;
    const int width = scene.settings.width, height = scene.settings.height;
    const std::vector<std::string> outputs = cl.outputs.empty() ? std::vector<std::string>{scene.settings.output} : cl.outputs;
    // The scene's text, for writing it back (the thesis format only; docs/interactive.md).
    std::string text;
    bool thesis = true;
    if (cl.scenePath.empty()) text = kDefaultSceneXml;
    else if (endsWith(cl.scenePath, ".pbrt") || endsWith(cl.scenePath, ".pbrt.gz")) thesis = false;
    else text = readWholeFile(cl.scenePath, "scene file"), thesis = !isMitsubaXml(text);

    const int threads = base.threads > 0 ? base.threads : tbb::info::default_concurrency();
    std::unique_ptr<Scene> built;
    if (base.spectral) resolveBlendsForSpectral(scene);  // (its linear blends, one part per hit)
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
        built = Scene::build(std::move(scene), threads);
    }
    RenderOptions opt = base;
    opt.view = nullptr;
    opt.notice = nullptr;
    opt.progress = nullptr;
    const std::string scenePath = cl.scenePath;

    hub.setSessionRunning(true);
    InteractiveSession session(std::move(built), opt, initial, hub);
    ControlsOptions controls;
    controls.orbitRate = cl.orbitRate;
    controls.commandLine = [&](const ViewSettings& s) {
        const std::string cmd = commandLineFor(scenePath, s, opt, width, height, outputs);
        std::printf("%s\n", cmd.c_str());
        std::fflush(stdout);
        return cmd;
    };
    controls.keep = [&, thesis, text](const ViewSettings& s) -> std::string {
        const std::string cmd = controls.commandLine(s);
        if (!thesis)
            return "printed the command line that renders this view (the scene file is Mitsuba's or pbrt's: "
                   "wavemmlt writes only the thesis format back)";
        Settings st = fileSettings;
        st.tracer = s.tracer;
        st.minPathLength = s.minPathLength;
        st.maxPathLength = s.maxPathLength;
        st.probLarge = s.probLarge;
        const std::string path = sceneOutPath(cl);
        try {
            writeText(path, thesisSceneWithView(text, scenePath.empty() ? "<built-in scene>" : scenePath, s.camera, st));
        } catch (const std::exception& e) {
            return std::string("not written: ") + e.what();
        }
        return "wrote " + path + "; printed the command line that renders this view";
    };
    watchers.window()->attach(session, controls);
    watchers.window()->waitClosed();
    session.stop();
    hub.setSessionRunning(false);
    const ViewHub::Frame f = hub.latest();
    if (f.snapshot) {
        writeOutputs(*f.snapshot, session.settings().exposure);
        if (!cl.quiet) std::fprintf(stderr, "saved the image shown (%llu spp)\n", (unsigned long long)f.snapshot->spp);
        hub.finish(*f.snapshot);  // tev's last frame: the image written
    }
    watchers.waitFinalSent();
    return interrupted ? 130 : 0;
}

}  // namespace wmlt
