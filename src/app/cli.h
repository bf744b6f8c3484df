// The command line of `wavemmlt`: parsed into plain options, checked before any work.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "wavemmlt/scene_desc.h"

namespace wmlt {

struct CommandLine {
    std::string scenePath;  // empty: the built-in default scene
    std::optional<TracerKind> tracer;
    std::optional<int> spp, threads, width, height, maxLength, minLength;
    std::optional<double> timeBudget;
    std::optional<float> misBeta;  // BPT's power-heuristic exponent
    std::optional<long long> chains;       // MMLT, 0: auto; checked against memory in main()
    std::optional<int> bootstrap;          // MMLT
    std::optional<int> passLength;         // MMLT
    std::optional<float> probLarge;        // MMLT
    std::string strategyImages;            // BPT: folder for per-strategy EXRs
    std::optional<FilterDesc> filter;      // --filter NAME[:param=value,...]
    uint64_t seed = 0;
    std::vector<std::string> outputs;
    Defines defines;                       // -D name=value (Mitsuba scene files)
    std::string statsPath;
    float exposure = 0;
    bool view = false;                     // --view: the SDL2 window
    std::string displayHost, displayPort;  // --display-server HOST:PORT (tev); empty: none
    bool describe = false, quiet = false, help = false, version = false;
};

// Throws InputError("wavemmlt: ...") on an unknown option or a bad value.
CommandLine parseCommandLine(int argc, char** argv);
std::string usageText();

// Applies the command line over the scene's Settings and checks the result.
void applyCommandLine(const CommandLine& cl, Settings& s);

}  // namespace wmlt
