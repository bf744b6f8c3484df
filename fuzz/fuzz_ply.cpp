// libFuzzer target for the PLY reader: the input is written to a temporary .ply file
// (wmlt::loadPly reads files only) and loaded with flat and with smooth shading.
#include "fuzz_common.h"
#include "wavemmlt/error.h"
#include "wavemmlt/scene_desc.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string path = fuzz::writeFile("input.ply", data, size);
    for (bool smooth : {false, true}) {
        try {
            const wmlt::TriangleMesh m = wmlt::loadPly(path, smooth);
            if (m.indices.empty()) __builtin_trap();  // "no faces" is an InputError
            fuzz::checkMesh(m);
        } catch (const wmlt::InputError&) {}
    }
    return 0;
}
