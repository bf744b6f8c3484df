#include "kernels/textured_params.h"

namespace wmlt {

void texturedParams(const std::vector<TextureDesc>& tex, const MaterialDesc& m, float u, float v, Vec3 p, Vec3 n, BsdfParams& out) {
    switch (m.kind) {
#define WMLT_TEXTURED_CASE(K) \
    case MaterialKind::K: texturedParamsOf<MaterialKind::K>(tex, m, u, v, p, n, out); break;
        WMLT_TEXTURED_CASE(Matte)
        WMLT_TEXTURED_CASE(Glossy)
        WMLT_TEXTURED_CASE(Reflective)
        WMLT_TEXTURED_CASE(Dielectric)
        WMLT_TEXTURED_CASE(Conductor)
        WMLT_TEXTURED_CASE(RoughConductor)
        WMLT_TEXTURED_CASE(RoughDielectric)
        WMLT_TEXTURED_CASE(ThinDielectric)
        WMLT_TEXTURED_CASE(Plastic)
        WMLT_TEXTURED_CASE(RoughPlastic)
        WMLT_TEXTURED_CASE(Blend)
        WMLT_TEXTURED_CASE(Principled)
        WMLT_TEXTURED_CASE(Coated)
        WMLT_TEXTURED_CASE(DiffuseTransmission)
        WMLT_TEXTURED_CASE(Phase)
#undef WMLT_TEXTURED_CASE
    }
}

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
