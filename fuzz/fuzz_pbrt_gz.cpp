// libFuzzer target for pbrt-v4's .pbrt.gz files: the input as a gzip file (gzip_members.h:
// compressed in two members, or kept when it already is gzip) written as input.pbrt.gz and
// loaded, with the pbrt target's fixtures beside it (a PLY, images, a spectrum). Reaches the
// inflating reader (scene/read_file.h) and the tokenizer across chunk and member boundaries.
#include "fuzz_common.h"
#include "gzip_members.h"
#include "wavemmlt/error.h"
#include "wavemmlt/scene_desc.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    fuzz::writePbrtFixtures();
    const std::string path = fuzz::writeFile("input.pbrt.gz", fuzz::asGzip(data, size));
    try {
        const wmlt::SceneDesc s = wmlt::loadPbrt(path);
        for (const wmlt::ShapeDesc& sh : s.shapes) fuzz::checkMesh(sh.mesh);
    } catch (const wmlt::InputError&) {}
    return 0;
}
