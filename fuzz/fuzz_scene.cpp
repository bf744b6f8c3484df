// libFuzzer target for the XML scene loader: wmlt::loadSceneFromString on the input, with
// the base directory a per-process temporary folder holding a small OBJ ("m.obj") and
// small images ("t.pfm", "t.hdr"), so a scene may load them; every other relative file
// name fails cleanly (InputError: cannot open).
#include "fuzz_common.h"
#include "wavemmlt/error.h"
#include "wavemmlt/scene_desc.h"

namespace {

const std::string& baseDir() {
    static const std::string dir = [] {
        fuzz::writeFile("m.obj",
                        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\n"
                        "f 1/1/1 2/2/1 3/3/1\nf 2 4 3\n");
        const std::string pfm = std::string("PF\n2 1\n-1.0\n") + std::string(24, '\0');
        fuzz::writeFile("t.pfm", pfm);
        fuzz::writeFile("t.hdr",
                        std::string("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 2\n") + std::string("\x80\x40\x20\x81\x10\x10\x10\x80", 8));
        return fuzz::tempDir();
    }();
    return dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string& base = baseDir();
    try {
        wmlt::SceneDesc s = wmlt::loadSceneFromString(std::string(reinterpret_cast<const char*>(data), size), "fuzz.xml", base);
        for (const wmlt::ShapeDesc& sh : s.shapes)
            for (uint32_t i : sh.mesh.indices)
                if (i >= sh.mesh.positions.size()) __builtin_trap();
    } catch (const wmlt::InputError&) {}
    return 0;
}
