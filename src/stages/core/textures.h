// The texture stage: the textured parameters of a round's hits, evaluated once the surfaces
// are resolved, over structure-of-arrays records, one rule per parameter for every kind
// (kernels/textured_params.h). The surface stage writes every hit's constants (materialAt)
// and queues the hits whose material has a texture (Scene::texturedMaterial);
// evaluateTextures finishes their records. Allocated only for a scene with textures
// (BatchNeeds::textures): a scene of constants runs no part of it.
#pragma once
#include <cstdint>
#include <vector>

#include "kernels/bsdf.h"
#include "scene/scene.h"
#include "stages/core/soa.h"

namespace wmlt {

// Per job: the record to finish (a hit's or a vertex's), its material
// (SceneDesc::materials), the hit's (u, v), position (solid textures) and geometric normal
// (pbrt's directionmix).
// clang-format off
#define WMLT_TEXTURE_JOB_ARRAYS(X) \
    X(BsdfParams*, target) X(uint32_t, material) X(float, u) X(float, v) X(Vec3, p) X(Vec3, ng)
// clang-format on

struct TextureJobs {
    size_t n = 0;
    WMLT_TEXTURE_JOB_ARRAYS(WMLT_SOA_ARRAY)

    void resize(size_t n) { WMLT_TEXTURE_JOB_ARRAYS(WMLT_SOA_RESIZE) }
    void add(BsdfParams* t, int m, float su, float sv, Vec3 sp, Vec3 sn) {
        target[n] = t;
        material[n] = uint32_t(m);
        u[n] = su;
        v[n] = sv;
        p[n] = sp;
        ng[n] = sn;
        ++n;
    }
};

// Applies the queued jobs' textures and empties the queue.
void evaluateTextures(const Scene& scene, TextureJobs& jobs);

}  // namespace wmlt
