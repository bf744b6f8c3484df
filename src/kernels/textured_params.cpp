#include "kernels/textured_params.h"

namespace wmlt {

void textureBlendPart(const BsdfParams& blend, int k, BsdfParams& part) {
    const BsdfExtra& x = *blend.x;
    const MaterialDesc* m = x.blendTextures->part[k];
    if (!m) return;  // a constant part
    float u, v;
    Vec3 p, n;
    blendPoint(blend, u, v, p, n);
    texturedParams(*x.blendTextures->textures, *m, u, v, p, n, part);
}

}  // namespace wmlt
