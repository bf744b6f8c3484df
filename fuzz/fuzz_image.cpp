// libFuzzer target for one image reader: the input is written to a temporary file with the
// extension FUZZ_IMAGE_EXT (".png", ".jpg", ".exr", ".hdr", ".pfm"; set by fuzz/CMakeLists.txt)
// and read with wmlt::readImage, which dispatches on the extension. The readers take a path
// only (OpenEXR opens the file itself), hence the file.
#include "fuzz_common.h"
#include "wavemmlt/error.h"
#include "wavemmlt/image.h"

#ifndef FUZZ_IMAGE_EXT
#error "define FUZZ_IMAGE_EXT"
#endif

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string path = fuzz::writeFile(std::string("input") + FUZZ_IMAGE_EXT, data, size);
    try {
        wmlt::Image img = wmlt::readImage(path);
        if (img.width <= 0 || img.height <= 0 || img.rgb.size() != size_t(img.width) * size_t(img.height) * 3)
            __builtin_trap();  // a reader returned a malformed image
    } catch (const wmlt::InputError&) {}
    return 0;
}
