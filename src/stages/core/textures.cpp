#include "stages/core/textures.h"

#include <algorithm>

#include "kernels/textured_params.h"
#include "stages/core/bsdf_dispatch.h"

namespace wmlt {

void evaluateTextures(const Scene& scene, TextureJobs& j) {
    if (j.n == 0) return;
    groupByMaterialKind([&](size_t k) { return j.target[k]->kind; }, j.n, j.order.data(), j.kindStart);
    forEachMaterialKind([&](auto kind) {
        constexpr MaterialKind K = decltype(kind)::value;
        for (uint32_t r = j.kindStart[int(K)]; r < j.kindStart[int(K) + 1]; ++r) {
            const uint32_t k = j.order[r];
            texturedParamsOf<K>(scene.desc.textures, scene.desc.materials[j.material[k]], j.u[k], j.v[k], j.p[k], j.ng[k], *j.target[k]);
        }
    });
    j.n = 0;
}

}  // namespace wmlt
