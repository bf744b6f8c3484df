// The feature set of a scene (deriveFeatures: the material kinds its shapes use, and those
// of their regularized versions under pbrt's regularize; lights, textures, media...) and its
// listing for --describe and --stats.
#include "scene/features.h"

#include <sstream>

#include "kernels/bsdf.h"
#include "kernels/textured_params.h"
#include "scene/filter_desc.h"
#include "scene/regularize.h"

namespace wmlt {

bool readsParamTexture(const MaterialDesc& m) {
    for (int q = 0; q < kMaterialParams; ++q)
        if (m.texture.index[q] >= 0 && readsParam(m.kind, MaterialParam(q))) return true;
    return false;
}

bool readsTexture(const SceneDesc& d, const MaterialDesc& m) {
    if (readsParamTexture(m)) return true;
    if (m.kind == MaterialKind::Blend)
        for (int part : m.blendPart)
            if (part >= 0 && readsParamTexture(d.materials[size_t(part)])) return true;
    return false;
}

SceneFeatures deriveFeatures(const SceneDesc& d) {
    SceneFeatures f;
    // Only materials that some shape uses count: an unused shader costs nothing.
    for (const ShapeDesc& s : d.shapes) {
        if (s.material < 0) continue;
        const MaterialDesc& m = d.materials[s.material];
        f.material[int(m.kind)] = true;
        if (d.regularize) f.material[int(regularizedMaterial(m).kind)] = true;  // its regularized version's (Scene::regularizedOffset)
        if (readsTexture(d, m)) f.textures = true;
        if (!m.twoSided) f.oneSided = true;
        if (m.bump >= 0 || m.normalMap >= 0) f.bump = true;  // both perturb the normal in surfaceAt
        if (m.opacity < 1 || m.opacityTexture >= 0) f.masks = true;
        if (isAnisotropic(m)) f.anisotropic = true;
        if (m.kind == MaterialKind::Blend) {  // a part's delta lobes and anisotropy count as the blend's
            for (int part : m.blendPart) {
                const MaterialDesc& q = d.materials[size_t(part)];
                if (isDeltaMaterial(q.kind) || q.kind == MaterialKind::Plastic || q.kind == MaterialKind::Coated)
                    f.delta = true;  // (a smooth coat's mirror)
                if (isAnisotropic(q)) f.anisotropic = true;
            }
            if (blendChoosesPart(d.materials, m)) {  // one part at each hit (Scene::choosesPart): the stages meet the parts themselves
                f.bump = true;
                for (int part : m.blendPart) {
                    const MaterialDesc& q = d.materials[size_t(part)];
                    f.material[int(q.kind)] = true;
                    if (d.regularize) f.material[int(regularizedMaterial(q).kind)] = true;
                }
            }
        }
        if (s.kind == ShapeKind::Sphere) f.spheres = true;
        if (s.kind == ShapeKind::Mesh && !s.mesh.normals.empty()) f.smoothNormals = true;
    }
    for (const LightDesc& l : d.lights)
        (l.kind == LightKind::Rect          ? f.rectLights
         : l.kind == LightKind::Sphere      ? f.sphereLights
         : l.kind == LightKind::Mesh        ? f.meshLights
         : l.kind == LightKind::Directional ? f.directionalLights
                                            : f.pointLights) = true;
    for (const LightDesc& l : d.lights)
        if (l.texture >= 0) f.texturedEmitters = true;
    f.envMap = d.envMap.width > 0;
    f.media = !d.media.empty();
    for (const MediumDesc& m : d.media)
        if (!m.LeGrid.empty() || m.Le.x != 0 || m.Le.y != 0 || m.Le.z != 0) f.emissiveMedia = true;
    for (const ShapeDesc& s : d.shapes) {
        if (s.passThrough || s.mediumBoundary) f.media = true;
        if (s.passThrough) f.passThrough = true;
    }
    f.depthOfField = d.camera.dof;
    f.filter = describeFilter(d.filter);
    f.needUv = f.textures || f.bump;
    for (int k = 0; k < kMaterialKinds; ++k)
        if (f.material[k] && (isDeltaMaterial(MaterialKind(k)) || MaterialKind(k) == MaterialKind::Plastic ||
                              MaterialKind(k) == MaterialKind::Coated))  // a smooth coat's mirror
            f.delta = true;
    return f;
}

std::string SceneFeatures::describe() const {
    std::ostringstream o;
    o << "materials:";
    for (int k = 0; k < kMaterialKinds; ++k)
        if (material[k]) o << ' ' << kMaterialKindNames[k];
    o << "\nlights:" << (rectLights ? " rect" : "") << (sphereLights ? " sphere" : "") << (meshLights ? " mesh" : "") << (pointLights ? " point" : "")
      << (directionalLights ? " directional" : "") << (envMap ? " environment-map" : "") << "\n";
    o << "textures: " << (textures ? "yes" : "no") << "\n";
    o << "textured emitters: " << (texturedEmitters ? "yes" : "no") << "\n";
    o << "bump mapping: " << (bump ? "yes" : "no") << "\n";
    o << "depth of field: " << (depthOfField ? "yes" : "no") << "\n";
    o << "smooth normals: " << (smoothNormals ? "yes" : "no") << "\n";
    o << "sphere geometry: " << (spheres ? "yes" : "no") << "\n";
    o << "delta lobes: " << (delta ? "yes" : "no") << "\n";
    o << "one-sided materials: " << (oneSided ? "yes" : "no") << "\n";
    o << "masks (opacity): " << (masks ? "yes" : "no") << "\n";
    o << "participating media: " << (media ? "yes" : "no") << "\n";
    o << "anisotropic roughness: " << (anisotropic ? "yes" : "no") << "\n";
    o << "pixel filter: " << filter << "\n";
    return o.str();
}

std::string SceneFeatures::json() const {
    std::ostringstream o;
    o << "{\"materials\": [";
    bool first = true;
    for (int k = 0; k < kMaterialKinds; ++k)
        if (material[k]) {
            o << (first ? "" : ", ") << '"' << kMaterialKindNames[k] << '"';
            first = false;
        }
    auto b = [](bool v) { return v ? "true" : "false"; };
    o << "], \"rect_lights\": " << b(rectLights) << ", \"sphere_lights\": " << b(sphereLights) << ", \"mesh_lights\": " << b(meshLights)
      << ", \"point_lights\": " << b(pointLights) << ", \"directional_lights\": " << b(directionalLights) << ", \"environment_map\": " << b(envMap)
      << ", \"textures\": " << b(textures) << ", \"textured_emitters\": " << b(texturedEmitters) << ", \"bump\": " << b(bump)
      << ", \"depth_of_field\": " << b(depthOfField) << ", \"smooth_normals\": " << b(smoothNormals) << ", \"masks\": " << b(masks)
      << ", \"media\": " << b(media) << ", \"pixel_filter\": \"" << filter << "\"}";
    return o.str();
}

}  // namespace wmlt
