// libFuzzer target for the pbrt-v4 importer: the input is written to a temporary .pbrt file
// (wmlt::loadPbrt reads files: Include and mesh names resolve beside it) in a per-process
// folder that also holds a small PLY ("m.ply"), a tiny image ("t.pfm") and a spectrum
// ("s.spd"), so a scene may load them; every other file name fails cleanly (InputError).
#include "fuzz_common.h"
#include "wavemmlt/error.h"
#include "wavemmlt/scene_desc.h"

namespace {

void writeFixtures() {
    static const bool done = [] {
        fuzz::writeFile("m.ply", std::string("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                             "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                             "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"));
        fuzz::writeFile("t.pfm", std::string("PF\n2 1\n-1.0\n") + std::string(24, '\0'));
        fuzz::writeFile("s.spd", std::string("400 1.5\n500 1.2\n600 0.9\n700 0.5\n"));
        return true;
    }();
    (void)done;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    writeFixtures();
    const std::string path = fuzz::writeFile("input.pbrt", data, size);
    try {
        const wmlt::SceneDesc s = wmlt::loadPbrt(path);
        for (const wmlt::ShapeDesc& sh : s.shapes) fuzz::checkMesh(sh.mesh);
        for (const wmlt::InstanceDesc& in : s.instances)
            if (in.group < 0 || in.group >= s.groups) __builtin_trap();
    } catch (const wmlt::InputError&) {
    }
    return 0;
}
