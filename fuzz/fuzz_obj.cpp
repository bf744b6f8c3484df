// libFuzzer target for the OBJ loader: the input is written to a temporary .obj file
// (wmlt::loadObj reads files only) and loaded with flat and with smooth shading.
#include "fuzz_common.h"
#include "wavemmlt/error.h"
#include "wavemmlt/scene_desc.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string path = fuzz::writeFile("input.obj", data, size);
    for (bool smooth : {false, true}) {
        try {
            fuzz::checkMesh(wmlt::loadObj(path, smooth));
        } catch (const wmlt::InputError&) {}
    }
    return 0;
}
