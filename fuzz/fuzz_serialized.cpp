// libFuzzer target for the serialized mesh reader: the input is written to a temporary
// .serialized file (wmlt::loadSerialized reads files only) and shapes 0 and 1 are loaded
// with flat and with smooth shading.
#include "fuzz_common.h"
#include "wavemmlt/error.h"
#include "wavemmlt/scene_desc.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string path = fuzz::writeFile("input.serialized", data, size);
    for (int shape : {0, 1})
        for (bool smooth : {false, true}) {
            try {
                const wmlt::TriangleMesh m = wmlt::loadSerialized(path, shape, smooth);
                if (m.indices.empty()) __builtin_trap();  // "no triangles" is an InputError
                if (smooth && m.normals.size() != m.positions.size()) __builtin_trap();
                fuzz::checkMesh(m);
            } catch (const wmlt::InputError&) {}
        }
    return 0;
}
