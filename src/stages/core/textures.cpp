#include "stages/core/textures.h"

#include "kernels/textured_params.h"

namespace wmlt {

void evaluateTextures(const Scene& scene, TextureJobs& j) {
    for (size_t k = 0; k < j.n; ++k)
        texturedParams(scene.desc.textures, scene.desc.materials[j.material[k]], j.u[k], j.v[k], j.p[k], j.ng[k], *j.target[k]);
    j.n = 0;
}

}  // namespace wmlt
