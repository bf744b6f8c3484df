// libFuzzer target for the pbrt-v4 importer: the input is written to a temporary .pbrt file
// (wmlt::loadPbrt reads files: Include and mesh names resolve beside it) in a per-process
// folder that also holds the fixtures of fuzz_common.h (a PLY, images, a spectrum), so a scene
// may load them; every other file name fails cleanly (InputError).
#include "fuzz_common.h"
#include "wavemmlt/error.h"
#include "wavemmlt/scene_desc.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    fuzz::writePbrtFixtures();
    const std::string path = fuzz::writeFile("input.pbrt", data, size);
    try {
        const wmlt::SceneDesc s = wmlt::loadPbrt(path);
        for (const wmlt::ShapeDesc& sh : s.shapes) fuzz::checkMesh(sh.mesh);
        for (const wmlt::InstanceDesc& in : s.instances)
            if (in.group < 0 || in.group >= s.groups) __builtin_trap();
    } catch (const wmlt::InputError&) {}
    return 0;
}
