// The renderable scene: the description, the Embree BVH over every shape, the lights as
// kernel data, the camera, and the feature set. Built once; read-only while rendering.
#pragma once
#include <embree3/rtcore.h>

#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "kernels/bsdf.h"
#include "kernels/camera.h"
#include "kernels/distribution.h"
#include "kernels/envmap.h"
#include "kernels/filter.h"
#include "kernels/lights.h"
#include "scene/features.h"
#include "scene/mesh_light.h"
#include "wavemmlt/scene_desc.h"

namespace wmlt {

// What the stages need to know about the shape an Embree geomID names.
struct GeomRecord {
    ShapeKind kind = ShapeKind::Mesh;
    UvKind uv = UvKind::None;
    int material = -1;  // -1: an emitter
    int light = -1;     // index into Scene::lights, -1: not an emitter
    const TriangleMesh* mesh = nullptr;
    // Smooth meshes: the three vertex normals of each triangle, side by side, so the
    // surface stage reads one cache line per hit instead of an index and three vertices.
    std::vector<Vec3> cornerNormals;
    Vec3 center;
    float radius = 0;
    Affine toLocal, toWorld;
    // Media (ShapeDesc): a boundary's inside and outside medium; passThrough: rays cross it.
    bool mediumBoundary = false, passThrough = false;
    int mediumInside = -1, mediumOutside = -1;
};

// Mitsuba's mask on a shape: what its Embree filter functions read (scene.cpp).
struct MaskRecord {
    const TriangleMesh* mesh = nullptr;  // meshes: (u, v) from the hit's barycentrics
    UvKind uv = UvKind::None;
    Affine toLocal;  // spheres: (u, v) from the local normal
    Vec3 center;
    float opacity = 1;
    // opacity = the luminance of texture `texture` of `textures` at the hit (>= 0; combined
    // textures too: evalTextureOf, with the hit's geometric normal)
    const std::vector<TextureDesc>* textures = nullptr;
    int texture = -1;
    unsigned geomID = 0;
};

class Scene {
public:
    // Takes the description; `threads` is the number of worker threads (0: all).
    static std::unique_ptr<Scene> build(SceneDesc desc, int threads = 0);
    ~Scene();
    Scene(const Scene&) = delete;
    Scene& operator=(const Scene&) = delete;

    SceneDesc desc;
    SceneFeatures features;
    Camera camera;
    // The pixel filter and each column's and row's normalisation (kernels/filter.h).
    PixelFilter filter;
    std::vector<float> filterNormX, filterNormY;
    // Calls add(pixel, weight) for the pixels a light-side contribution at film point
    // (px, py) goes to (forEachFilterPixel; the box filter: the pixel holding it).
    template <class Add>
    void forEachFilmPixel(float px, float py, Add&& add) const {
        forEachFilterPixel(filter, filterNormX.data(), filterNormY.data(), camera.width, camera.height, px, py, add);
    }
    RTCDevice device = nullptr;
    RTCScene rtc = nullptr;
    std::vector<GeomRecord> geoms;  // by geomID: shape i is geomID i, in the top scene or in its group's
    // Shape groups (Mitsuba's shapegroup): one Embree scene each, placed by the instances,
    // instance k being geomID shapes + k of the top scene (a hit's instID[0]).
    std::vector<RTCScene> groupScenes;
    std::vector<InstanceDesc> instances;
    unsigned firstInstanceID = 0;
    std::atomic<int64_t> embreeBytes{0};  // Embree's memory now (its memory monitor)
    uint64_t meshBytes = 0;               // the triangle meshes' arrays (a group's once)
    std::vector<BsdfParams> materials;    // by material index, before textures
    // pbrt's regularize (SceneDesc::regularize): materials[m + regularizedOffset] is material
    // m's regularized version (scene/regularize.h), which the PT and BPT renders use after a
    // path's first non-specular bounce; 0: no such table.
    uint32_t regularizedOffset = 0;
    std::vector<uint8_t> texturedMaterial;  // by material index: it reads a texture (the texture stage)
    // By material index: a blend resolved to one part per hit (blendChoosesPart: pbrt's mix, a
    // blend whose parts perturb the normal), as pbrt-v4 resolves every mix (surface.cpp,
    // choosePart).
    std::vector<uint8_t> choosesPart;
    std::vector<BsdfExtra> bsdfExtras;         // by index into materials: the Mitsuba kinds' constants
    std::vector<BsdfParams> blendParts;        // each Blend's two parts (BsdfExtra::blendParts)
    std::vector<BlendTextures> blendTextures;  // each Blend with textured parts (BsdfExtra::blendTextures)
    std::vector<MaskRecord> masks;             // one per masked shape (Embree's filters point into it)
    // Lights: the scene's emitters, then the environment map (if any) as the last one.
    std::vector<Light> lights;
    std::vector<MeshLight> meshLights;  // Light::mesh indexes it
    std::vector<float> lightPmf;        // probability of choosing each light (in proportion to power)
    // Per light: its rectangle as floats for the flat light-sample loops, zeros (which no
    // sample passes) unless it is a Rect whose radiance is not black; anyRectLight: one is.
    std::vector<RectFloats> lightRects;
    bool anyRectLight = false;
    Distribution1D lightDistribution;
    int envLight = -1;  // index of the environment light, -1: none
    EnvMapSampler env;
    // Participating media (kernels/medium.h), by SceneDesc::media index; the camera's.
    std::vector<Medium> media;
    // The medium each light emits into from its front face (the outside of a boundary
    // shape) and its back face (the inside); a point or spot light, or an emitter that is no
    // boundary, inside a closed boundary: its inside medium; else the camera's, and for
    // directional and environment lights (docs/media.md). By light index.
    std::vector<int> lightMediumFront, lightMediumBack;
    std::vector<std::vector<float>> majorantGrids;  // the grid media's, in their order (Medium::majorants)
    int cameraMedium = -1;
    Vec3 boundsMin, boundsMax, center;
    float radius = 1;            // bounding sphere of the scene's geometry
    float epsilonScale = 1e-4f;  // ray offsets scale with the scene's size

    // Another camera and image size (the interactive mode, between renders): the camera,
    // the filter's normalisation per column and row, the depth-of-field feature. Throws
    // InputError, the scene unchanged, for a camera inside a closed boundary of another
    // medium than the camera's.
    void setView(const CameraDesc& camera, int width, int height);
    // setView's test of a camera position alone (throws InputError, naming the boundary).
    void checkCameraAt(Vec3 position);
    // Each shape's closedness, found when first needed (-1: not yet; the media's enclosure test).
    std::vector<int8_t> closedShapes;

    // A hit's geometric normal in world space (unnormalised; rh must have hit something).
    Vec3 hitNormal(const RTCRayHit& rh) const;

    // Offset along the normal to leave a surface towards w without self-intersection.
    Vec3 offsetRayOrigin(Vec3 p, Vec3 n, Vec3 w) const {
        float mag = std::max(std::max(std::fabs(p.x), std::fabs(p.y)), std::fabs(p.z));
        float eps = 2e-5f * mag + epsilonScale;
        return dot(n, w) >= 0 ? p + n * eps : p - n * eps;
    }

private:
    Scene() = default;
    void setImage(const CameraDesc& camera, int width, int height);
    std::string embreeErrorMessage;
};

// Scene::build's materials, from s.desc's (scene_materials.cpp): Scene::materials,
// bsdfExtras, texturedMaterial, choosesPart, the blends' parts and textures.
void buildMaterials(const SceneDesc& d, Scene& s);

// Each cell of grid medium m's majorant grid (m.mx, my, mz set) the largest voxelMax(i)
// among the voxels i whose trilinear support reaches into it (scene.cpp; the spectral
// majorants of RGB grids: scene_spectra.cpp).
void majorantCells(const Medium& m, const std::function<float(size_t)>& voxelMax, std::vector<float>& cells);

}  // namespace wmlt
