// stb_image's decoder compiled into the fuzz build (the same header Debian's libstb-dev
// ships, so the same code as libstb.so), so that libFuzzer gets coverage from inside the
// PNG/JPEG decoder and ASan/UBSan check it. The main build links libstb.so instead.
#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>
