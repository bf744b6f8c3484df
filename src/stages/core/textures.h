// The texture stage: the textured parameters of a round's hits, evaluated once the surfaces
// are resolved, kind by kind over structure-of-arrays records (one function per material
// kind, reading only the parameters that kind has), the way the rest of the wavefront runs.
// The surface stage writes every hit's constants (materialAt) and queues the hits whose
// material has a texture (Scene::texturedMaterial); evaluateTextures finishes their
// records. Allocated only for a scene with textures (BatchNeeds::textures): a scene of
// constants runs no part of it.
#pragma once
#include <cstdint>
#include <vector>

#include "kernels/bsdf.h"
#include "scene/scene.h"
#include "stages/core/soa.h"

namespace wmlt {

// Per job: the record to finish (a hit's or a vertex's), its material
// (SceneDesc::materials), the hit's (u, v), position (solid textures) and geometric normal
// (pbrt's directionmix), and the jobs by
// kind (order[kindStart[k] .. kindStart[k + 1])).
#define WMLT_TEXTURE_JOB_ARRAYS(X) \
    X(BsdfParams*, target) X(uint32_t, material) X(float, u) X(float, v) X(Vec3, p) X(Vec3, ng) X(uint32_t, order)

struct TextureJobs {
    size_t n = 0;
    WMLT_TEXTURE_JOB_ARRAYS(WMLT_SOA_ARRAY)
    uint32_t kindStart[kMaterialKinds + 1] = {};

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

// Applies the queued jobs' textures, kind by kind, and empties the queue.
void evaluateTextures(const Scene& scene, TextureJobs& jobs);

}  // namespace wmlt
