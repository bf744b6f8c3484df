// libFuzzer target for the PLY reader: the input is written to a temporary .ply file
// (wmlt::loadPly reads files only) and loaded with flat and with smooth shading.
#include "fuzz_common.h"
#include "wavemmlt/error.h"
#include "wavemmlt/scene_desc.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string path = fuzz::writeFile("input.ply", data, size);
    for (bool smooth : {false, true}) {
        try {
            wmlt::TriangleMesh m = wmlt::loadPly(path, smooth);
            if (m.indices.empty() || m.indices.size() % 3) __builtin_trap();
            for (uint32_t i : m.indices)
                if (i >= m.positions.size()) __builtin_trap();  // an index past the vertices
            if (!m.normals.empty() && m.normals.size() != m.positions.size()) __builtin_trap();
            if (!m.uvs.empty() && m.uvs.size() != 2 * m.positions.size()) __builtin_trap();
        } catch (const wmlt::InputError&) {
        }
    }
    return 0;
}
