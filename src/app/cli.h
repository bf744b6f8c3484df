// The command line of `wavemmlt`: parsed into plain options, checked before any work.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "app/camera_control.h"
#include "wavemmlt/render.h"
#include "wavemmlt/scene_desc.h"

namespace wmlt {

struct CommandLine {
    std::string scenePath;  // empty: the built-in default scene
    std::optional<TracerKind> tracer;
    std::optional<int> spp, threads, width, height, maxLength, minLength;
    std::optional<double> timeBudget;
    std::optional<float> misBeta;          // BPT's, MMLT's and PSSMLT's power-heuristic exponent
    std::optional<long long> chains;       // MMLT, 0: auto; checked against memory in main()
    std::optional<int> bootstrap;          // MMLT
    std::optional<int> passLength;         // MMLT
    std::optional<float> probLarge;        // MMLT
    std::optional<MmltTarget> mmltTarget;  // MMLT: --mmlt-target
    std::optional<bool> learnSteps;        // MMLT: --mmlt-steps learned
    std::optional<bool> delayedRejection;  // MMLT: --mmlt-delayed-rejection on
    std::optional<FilmSteps> filmSteps;    // MMLT: --mmlt-film-steps
    std::optional<float> targetExponent;   // MMLT: --mmlt-target-exponent beta
    std::optional<bool> spectral;          // --spectral / --rgb
    std::string strategyImages;            // BPT: folder for per-strategy EXRs
    std::optional<FilterDesc> filter;      // --filter NAME[:param=value,...]
    uint64_t seed = 0;
    std::vector<std::string> outputs;
    Defines defines;  // -D name=value (Mitsuba scene files)
    std::string statsPath;
    float exposure = 0;
    bool view = false;                    // --view: the SDL2 window
    bool interactive = false;             // --interactive: the window, the camera and settings changed in it
    std::string sceneOut;                 // --scene-out: where the interactive mode writes the scene
    float orbitRate = kOrbitRateDefault;  // --orbit-rate: the interactive orbit, degrees per window width
    // The camera, over the scene's (the interactive mode prints them): --eye, --look-at, --up,
    // --fov, --focus-distance, --f-stop (0: a pinhole).
    std::optional<Vec3> eye, lookAt, up;
    std::optional<float> fov, focusDistance, fStop;
    std::string displayHost, displayPort;  // --display-server HOST:PORT (tev); empty: none
    bool describe = false, quiet = false, help = false, version = false;
};

// The tracer's name on the command line (--tracer) and in titles.
inline const char* tracerName(TracerKind t) {
    static const char* const names[] = {"mmlt", "bpt", "lt", "pt", "pssmlt"};  // TracerKind's order
    return names[int(t)];
}

// Throws InputError("wavemmlt: ...") on an unknown option or a bad value.
CommandLine parseCommandLine(int argc, char** argv);
std::string usageText();

// Applies the command line over the scene's Settings and checks the result.
void applyCommandLine(const CommandLine& cl, Settings& s);
// Applies --eye, --look-at, --up, --fov, --focus-distance, --f-stop over the scene's camera
// and checks the result (a view direction, an up not along it).
void applyCamera(const CommandLine& cl, CameraDesc& c);

// The scene file (the built-in scene when none is given) with the command line's settings,
// filter and camera applied.
SceneDesc loadCommandLineScene(const CommandLine& cl);
// The command line's settings, camera and filter over a loaded scene's (the Python module's
// render() over the scene it loaded).
void applyToScene(const CommandLine& cl, SceneDesc& scene);
// The seconds the built-in scene renders for when neither --spp nor --time is given (with
// PT unless --tracer says otherwise).
constexpr double kFirstRenderSeconds = 10;
// The render's options from the command line over the scene's settings: what `wavemmlt`
// and the Python module (src/python) render with, so a seed gives both the same image.
RenderOptions renderOptionsFor(const CommandLine& cl, const Settings& s);
// MMLT's and PSSMLT's chain state must fit in memory: refused before anything is allocated,
// with the memory it would need (every chain counted at MaxPathLength, the largest state).
// The limit is the one renderMmlt applies to the chains it actually runs: 3/4 of the
// machine's physical memory.
void checkChainMemory(long long chains, const Settings& s, bool media);

}  // namespace wmlt
