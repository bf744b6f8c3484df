// A scene's feature set: decided once when the scene is built, it selects which stages
// and kernels run and which per-path state exists ("model only what a scene requires").
#pragma once
#include <string>

#include "wavemmlt/scene_desc.h"

namespace wmlt {

struct SceneFeatures {
    bool material[kMaterialKinds] = {};  // indexed by MaterialKind
    bool textures = false;               // some Matte/Glossy/plastic has a Texture
    bool bump = false;                   // some shader has a Bump
    bool envMap = false;
    bool depthOfField = false;
    bool rectLights = false, sphereLights = false, meshLights = false, pointLights = false, directionalLights = false;
    bool smoothNormals = false;               // some mesh interpolates vertex normals
    bool spheres = false;                     // sphere geometry (not lights)
    bool needUv = false;                      // textures or bump: the surface stage computes (u, v)
    bool delta = false;                       // a material with a delta lobe exists
    bool oneSided = false;                    // some material is black from below (Mitsuba without twosided)
    bool masks = false;                       // some shape is partly transparent (Mitsuba's mask: Embree filters)
    bool anisotropic = false;                 // some rough material has alpha_u != alpha_v: frames follow dp/du
    bool texturedEmitters = false;            // some mesh light's radiance is a texture (LightDesc::texture)
    bool media = false;                       // participating media or pass-through boundaries (the media stages run)
    bool passThrough = false;                 // pass-through boundaries: shadow rays are traced through them one by one
    bool emissiveMedia = false;               // a medium emits (the walks gather its emission)
    std::string filter = "box (radius 0.5)";  // the pixel filter (describeFilter)

    bool has(MaterialKind k) const { return material[int(k)]; }
    // Human-readable listing for `wavemmlt --describe`.
    std::string describe() const;
    // The same as a JSON object (for --stats).
    std::string json() const;
};

SceneFeatures deriveFeatures(const SceneDesc& desc);
// Whether m's kind reads one of its textured parameters (MaterialDesc::texture; which it
// reads: readsParam, kernels/textured_params.h).
bool readsParamTexture(const MaterialDesc& m);
// That, or a blend one of whose parts reads a texture.
bool readsTexture(const SceneDesc& d, const MaterialDesc& m);

}  // namespace wmlt
