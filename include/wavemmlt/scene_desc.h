// The scene as the XML file describes it (../shared/spec/scene-format.md), after
// validation, with meshes loaded and transformed to world space and images read.
// Plain data; src/scene/ builds the renderable Scene from it.
#pragma once
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "wavemmlt/image.h"
#include "wavemmlt/math.h"

namespace wmlt {

enum class TracerKind : uint8_t { MMLT, BPT, LT, PT, PSSMLT };

struct Settings {
    int width = 512, height = 512;
    int samples = 4;  // N: N x N samples (MMLT: mutations) per pixel
    int threads = 0;  // 0: all hardware threads
    TracerKind tracer = TracerKind::MMLT;
    int maxPathLength = 10;  // segments, camera to light
    int minPathLength = 1;
    float probLarge = 0.3f;
    // The format's rendering mode by default (--spectral, --rgb choose): pbrt-v4 files render
    // spectrally, as pbrt does; the thesis format and Mitsuba files in RGB (docs/spectral.md).
    bool spectral = false;
    std::string output = "render.exr";  // as written in the file (quotes stripped)
    std::string envMap;                 // resolved path, empty when none
};

// The pixel reconstruction filter (kernels/filter.h, docs/filters.md): each pixel is the
// filter-weighted mean of the image plane about its centre. Box of radius 1/2 is each
// pixel's plain average (the thesis format's default); Mitsuba's default is Gaussian.
// Separable: f(x, y) = f(x) f(y). Catmull-Rom is Mitchell with B = 0, C = 1/2.
enum class FilterKind : uint8_t { Box, Tent, Gaussian, Mitchell, Lanczos };
struct FilterDesc {
    FilterKind kind = FilterKind::Box;
    float radius = 0.5f;               // pixels, > 0: f = 0 beyond it
    float stddev = 0.5f;               // Gaussian: exp(-x^2 / 2 stddev^2) - its value at the radius
    float B = 1 / 3.0f, C = 1 / 3.0f;  // Mitchell-Netravali's cubic at 2 |x| / radius
    float tau = 3;                     // Lanczos: sinc(x) sinc(x / tau)
};

struct CameraDesc {
    Vec3 position{0, 0, 0}, lookAt{0, 0, 1}, up{0, 1, 0};
    float fovDegrees = 45;  // full angle across the shorter image side
    bool dof = false;
    float focalLength = 1;  // focus distance
    float fStop = 1;        // aperture radius = focalLength / (2 fStop)
    bool flipX = false;     // image right = up x forward instead (a mirroring Mitsuba to_world)
    // Mitsuba's orthographic sensor: rays along the view direction from the film rectangle
    // through `position` (half extents in world units; fovDegrees and dof unused), starting
    // nearClip in front of it.
    bool orthographic = false;
    float orthoHalfWidth = 1, orthoHalfHeight = 1, nearClip = 0;
    // The part of the whole film this image is (pbrt's cropwindow): x0, x1, y0, y1 as
    // fractions of the film's width and height, y from the top. The image's pixels span
    // only that window; fovDegrees (and the orthographic half extents) are the whole film's.
    float window[4] = {0, 1, 0, 1};
};

// Every material kind, once: X(Kind, "name for --describe"). The enum, the kind count, the
// names, the dispatch by kind (kernels/bsdf.h, bsdfF/Pdf/Sample through BsdfOf<Kind>,
// kernels/bsdf_kinds.h) and the stages' loop over kinds (forEachMaterialKind) are made from
// it (docs/adding-a-material-kind.md). The thesis' four materials, then the Mitsuba 3 ones
// (docs/mitsuba.md: smooth and rough conductor, rough and thin dielectric, smooth and rough
// plastic, the blend of two (blendbsdf: f = (1 - w) f_0 + w f_1), principled), pbrt-v4's
// coated and diffusetransmission (docs/pbrt.md), and Phase: not a material of any file, the
// phase function of a scattering event in a medium, run by the stages as the BSDF of a
// medium vertex (kernels/medium.h).
// clang-format off
#define WMLT_MATERIAL_KINDS(X)                                                                               \
    X(Matte, "matte") X(Glossy, "glossy") X(Reflective, "reflective") X(Dielectric, "dielectric")             \
    X(Conductor, "conductor") X(RoughConductor, "rough-conductor") X(RoughDielectric, "rough-dielectric")     \
    X(ThinDielectric, "thin-dielectric") X(Plastic, "plastic") X(RoughPlastic, "rough-plastic") X(Blend, "blend") \
    X(Principled, "principled") X(Coated, "coated") X(DiffuseTransmission, "diffuse-transmission") X(Phase, "phase")
// clang-format on

#define WMLT_KIND_ENUM(K, name) K,
enum class MaterialKind : uint8_t { WMLT_MATERIAL_KINDS(WMLT_KIND_ENUM) };
#undef WMLT_KIND_ENUM
#define WMLT_KIND_COUNT(K, name) +1
constexpr int kMaterialKinds = 0 WMLT_MATERIAL_KINDS(WMLT_KIND_COUNT);
#undef WMLT_KIND_COUNT
#define WMLT_KIND_NAME(K, name) name,
inline constexpr const char* kMaterialKindNames[kMaterialKinds] = {WMLT_MATERIAL_KINDS(WMLT_KIND_NAME)};
#undef WMLT_KIND_NAME

enum class MicrofacetType : uint8_t { Beckmann, GGX };

// The principled BSDF's float parameters (Mitsuba 3's names: roughness, anisotropic,
// metallic, spec_trans, spec_tint, sheen, sheen_tint, flatness, clearcoat, clearcoat_gloss).
enum class PrincipledParam : uint8_t { Roughness, Anisotropic, Metallic, SpecTrans, SpecTint, Sheen, SheenTint, Flatness, Clearcoat, ClearcoatGloss };
constexpr int kPrincipledParams = 10;

// Every material parameter a texture may drive (MaterialDesc::texture), and what the
// texture's value at a hit does to the parameter's constant there (kernels/textured_params.h;
// which kinds read which: readsParam, scene/features.h):
enum class MaterialParam : uint8_t {
    Diffuse,
    Specular,
    Reflect,
    Refract,  // colours (Kd, Ks, specular reflectance, transmittance): RGB times them
    AlphaU,
    AlphaV,  // roughness (rough kinds, a coat's interface): luminance (sqrt: alphaRemap) times it
    BaseAlphaU,
    BaseAlphaV,  // a coated conductor's base roughness: the same
    ConductorEta,
    ConductorK,            // a conductor's complex index (a coated one's base): RGB times it
    ConductorReflectance,  // pbrt's conductor reflectance r: k = 2 sqrt(r) / sqrt(1 - r) times k
    Albedo,                // a coating's medium albedo: RGB times it
    Scale,                 // pbrt's diffusetransmission scale: luminance times Kd and transmittance
    BlendWeight,           // a blend's weight: luminance times it, in [0, 1]
    Principled             // the first of kPrincipledParams: luminance times each, in [0, 1]
};
constexpr int kMaterialParams = int(MaterialParam::Principled) + kPrincipledParams;
constexpr MaterialParam principledParam(PrincipledParam q) { return MaterialParam(int(MaterialParam::Principled) + int(q)); }

// A material's textures by parameter: an index into SceneDesc::textures, -1: a constant.
struct ParamTextures {
    int index[kMaterialParams];
    constexpr ParamTextures() : index{} {
        for (int& i : index) i = -1;
    }
    int& operator[](MaterialParam q) { return index[int(q)]; }
    int operator[](MaterialParam q) const { return index[int(q)]; }
};

// A spectrum as a file gave it (wavelength-value pairs or an .spd file, a blackbody
// temperature, a named glass), kept beside the RGB the importer projects it to: RGB rendering
// reads the RGB, spectral rendering (docs/spectral.md) this.
struct SpectrumDesc {
    enum class Kind : uint8_t { Tabulated, Blackbody, Sellmeier };
    Kind kind = Kind::Tabulated;
    std::vector<float> lambda, value;              // Tabulated: nm, increasing; linear between, 0 outside
    float kelvin = 0;                              // Blackbody: Planck's law normalised to 1 at its peak
    float sellmeierB[3] = {}, sellmeierC[3] = {};  // Sellmeier: an index of refraction (C in um^2)
    float scale = 1;                               // the spectrum is this times the above
    std::string source;                            // "spds/Au.eta.spd", "blackbody 5500 K", "glass-BK7"
};

// A material's spectra by parameter (MaterialParam): an index into SceneDesc::spectra, -1:
// its RGB constant (a colour given as RGB, or not given).
using ParamSpectra = ParamTextures;

struct MaterialDesc {
    int id = 0;
    MaterialKind kind = MaterialKind::Matte;
    Vec3 diffuse{0.5f};                         // Matte, Glossy
    Vec3 specular{0.0f};                        // Glossy
    float shininess = 0;                        // Glossy exponent n
    Vec3 reflect{1.0f};                         // Reflective, Dielectric
    Vec3 refract{1.0f};                         // Dielectric; DiffuseTransmission: its transmittance (diffuse its reflectance)
    float iorInside = 1.5f, iorOutside = 1.0f;  // Dielectric (iIOR, oIOR)
    // The textures of its parameters (MaterialParam): each drives its constant at a hit; the
    // thesis' <Texture> is the Diffuse one; an importer that maps a texture alone sets the
    // constant to 1 (a roughness's too: alpha 1, scaled by the texture).
    ParamTextures texture;
    ParamSpectra spectra;  // the colours given as spectra
    int etaSpectrum = -1;  // Dielectric kinds: the index given as a spectrum (SceneDesc::spectra, -1: none)
    int bump = -1;         // index into SceneDesc::textures, -1: none
    // Mitsuba materials: `diffuse` is diffuse_reflectance, `reflect` specular_reflectance,
    // `refract` specular_transmittance, iorInside/iorOutside int_ior/ext_ior.
    MicrofacetType distribution = MicrofacetType::Beckmann;
    float alpha = 0.1f;  // rough kinds (anisotropic: the roughness along u, alpha_u)
    float alphaV = -1;   // rough kinds: the roughness along v (alpha_v); < 0: alpha
    // A textured roughness (texture[AlphaU], [AlphaV], [BaseAlphaU], [BaseAlphaV]): its
    // luminance r at the hit scales alpha by r itself, or by sqrt(r) with alphaRemap (pbrt's
    // remaproughness: the texture is a roughness, alpha = sqrt(roughness)); a textured `alpha`
    // sets both to the same texture (isotropic).
    bool alphaRemap = false;
    Vec3 conductorEta{0.0f}, conductorK{1.0f};  // Conductor, RoughConductor (relative index)
    bool nonlinear = false;                     // Plastic, RoughPlastic
    bool twoSided = true;                       // false: black seen from below the shading normal
    bool bumpMitsuba = false;                   // bump is Mitsuba's bumpmap: height = bumpScale * luminance
    bool bumpPbrt = false;                      // bump is pbrt-v4's displacement: height = luminance, world units
    // Mitsuba's normalmap: a texture whose RGB at the hit is the shading normal in the
    // tangent frame (x along dp/du, z the interpolated normal) as (n + 1) / 2 (index into
    // SceneDesc::textures, -1: none; kernels/bump.h, normalMapped).
    int normalMap = -1;
    float bumpScale = 1;
    // Mitsuba's mask: the surface is there with probability opacity (or the texture's
    // luminance at the hit), else rays pass straight through (an any-hit test).
    float opacity = 1;
    int opacityTexture = -1;  // index into SceneDesc::textures, -1: none
    // Blend: its two parts (indices into SceneDesc::materials: kinds other than Blend,
    // without a mask) and the weight w of part 1, a constant in [0, 1] or
    // (texture[BlendWeight]) that texture's luminance at the hit. blendPerHit: one part per
    // hit, part 1 with probability w (pbrt-v4's mix), instead of f = (1 - w) f_0 + w f_1
    // (Mitsuba's blendbsdf); blendChoosesPart.
    int blendPart[2] = {-1, -1};
    float blendWeight = 0.5f;
    bool blendPerHit = false;
    // Principled (Mitsuba's `principled`): base_color is `diffuse` (its texture the Diffuse
    // one), eta iorInside / iorOutside; its float parameters below, each a constant or
    // (texture[principledParam(q)]) that texture's luminance at the hit; sampling rates of
    // the diffuse, main specular and clearcoat lobes.
    float principled[kPrincipledParams] = {0.5f, 0, 0, 0, 0, 0, 0, 0, 0, 0};
    float samplingRate[3] = {1, 1, 1};
    // Coated (pbrt-v4's coateddiffuse and coatedconductor, kernels/bsdf_coated.cpp): the
    // interface's index iorInside / iorOutside and GGX alphas alpha, alphaV; the base a
    // diffuse `diffuse` (its texture the Diffuse one) or a conductor conductorEta/K times
    // `reflect` with its own alphas; the slab between them.
    struct Coating {
        bool conductorBase = false;
        float baseAlpha = 0, baseAlphaV = 0;
        float thickness = 0.01f, g = 0;
        Vec3 albedo{0.0f};
        int maxDepth = 10, nSamples = 1;
        // pbrt-v4's own weight of a direction sampled inside the slab against next-event
        // estimation through the exit: the exit's density of wi given that direction, where
        // the strategy's density is that of the direction given wi (kernels/bsdf_coated.cpp).
        // Biased (f then integrates above the walk's albedo) and off; on, the coated gold
        // killeroo and the caustic glass render what pbrt-v4 renders (tests/test_pbrt_scenes.cpp).
        bool pbrtExitWeight = false;
        // With pbrtExitWeight, f(wo, wi) is pbrt-v4's f(wi, wo) in TransportMode::Importance: that
        // weighting makes f non-reciprocal, and pbrt evaluates a light subpath's vertex so (its
        // walk starts on the light's side: BDPT's and light tracing's connections to the camera).
        // Off; bench/bench_pbrt_blocks.cpp sets it for BPT's t = 1 strategies (docs/pbrt.md).
        bool pbrtWalkFromLight = false;
    } coating;
};

// Whether a principled material transmits (spec_trans given: a texture or a number > 0, as
// Mitsuba 3 decides): it then has a back side of its own; else it reflects only, one-sided
// unless wrapped in twosided.
inline bool principledTransmits(const MaterialDesc& m) {
    const int t = int(PrincipledParam::SpecTrans);
    return m.kind == MaterialKind::Principled && (m.principled[t] > 0 || m.texture[principledParam(PrincipledParam::SpecTrans)] >= 0);
}

// Whether blend m is resolved to one of its parts at each hit (Scene::choosesPart, chosen by
// a hash of the point): pbrt-v4's mix always (so its parts' colours render spectrally, as
// pbrt's), and any blend of a bump- or normal-mapped part (the parts' shading normals differ).
inline bool blendChoosesPart(const std::vector<MaterialDesc>& materials, const MaterialDesc& m) {
    if (m.kind != MaterialKind::Blend) return false;
    if (m.blendPerHit) return true;
    for (int part : m.blendPart) {
        const MaterialDesc& q = materials[size_t(part)];
        if (q.bump >= 0 || q.normalMap >= 0) return true;
    }
    return false;
}

// A rough kind's roughness along v (alphaV, or alpha where none was given), and whether it
// differs from the u one (or is scaled by another texture): the material is anisotropic,
// its shading frame's x axis follows dp/du (stages/core/surface.h).
inline float alphaVOf(const MaterialDesc& m) { return m.alphaV < 0 ? m.alpha : m.alphaV; }
inline bool isAnisotropic(const MaterialDesc& m) {
    const bool rough = m.kind == MaterialKind::RoughConductor || m.kind == MaterialKind::RoughDielectric || m.kind == MaterialKind::RoughPlastic;
    const int a = int(PrincipledParam::Anisotropic);
    if (m.kind == MaterialKind::Principled) return m.principled[a] != 0 || m.texture[principledParam(PrincipledParam::Anisotropic)] >= 0;
    if (m.kind == MaterialKind::Coated) return alphaVOf(m) != m.alpha || m.coating.baseAlpha != m.coating.baseAlphaV;
    return rough && (alphaVOf(m) != m.alpha || m.texture[MaterialParam::AlphaU] != m.texture[MaterialParam::AlphaV]);
}

// The thesis' three textures, Mitsuba's bitmap and checkerboard (docs/mitsuba.md), and two
// that combine others (pbrt's scale and mix): see TextureDesc::operand.
// pbrt-v4's procedural textures (docs/pbrt.md): Dots (operand 0 inside a dot, operand 1
// outside, as Scale's and Mix's), DirectionMix (a |n . direction| operand 0 + (1 - a)
// operand 1, n the hit's geometric normal), Bilerp (colour1..4 = v00, v01, v10, v11 over (s, t)), the
// float noises Fbm, Wrinkled and Windy, and PbrtMarble (pbrt's marble, colour from its
// spline); the noises and PbrtMarble are solid textures of the point textureFromWorld p.
enum class TextureKind : uint8_t {
    Checker,
    ImageFile,
    Marble,
    Bitmap,
    Checkerboard,
    Scale,
    Mix,
    Dots,
    DirectionMix,
    Bilerp,
    Fbm,
    Wrinkled,
    Windy,
    PbrtMarble
};
enum class TextureWrap : uint8_t { Repeat, Mirror, Clamp };
// How a texture turns a hit into its (s, t) before uvTransform (pbrt-v4's mappings): UV the
// shape's (u, v); the others a function of q = textureFromWorld p: Spherical (theta / pi,
// phi / 2 pi) of q's direction, Cylindrical ((pi + atan2(q.y, q.x)) / 2 pi, q.z), Planar
// (q . planarS, q . planarT).
enum class TextureMapping : uint8_t { UV, Spherical, Cylindrical, Planar };

struct TextureDesc {
    int id = 0;
    TextureKind kind = TextureKind::Checker;
    Vec3 colour1{0.0f}, colour2{1.0f}, colour3{0.5f};  // Checkerboard: color0, color1
    float repeatU = 1, repeatV = 1;
    Image image;  // ImageFile, Bitmap: linear RGB
    // Bitmap and Checkerboard: Mitsuba's to_uv, (u, v) -> (a u + b v + c, d u + e v + f)
    // as {a, b, c, d, e, f}, applied first; v = 0 is the image's TOP row (Mitsuba's).
    float uvTransform[6] = {1, 0, 0, 0, 1, 0};
    bool nearest = false;                    // Bitmap: filter_type nearest (else bilinear)
    TextureWrap wrap = TextureWrap::Repeat;  // Bitmap: wrap_mode
    // Scale: operand 0 times operand 1. Mix: (1 - a) operand 0 + a operand 1, a the
    // luminance of operand 2 or, without one, `amount`. An operand is a texture (an index
    // into SceneDesc::textures below this one's: no cycles) or, when -1, colour1 (operand 0)
    // or colour2 (operand 1). They combine on material parameters only (the texture stage,
    // evalTextureOf); Scene::build refuses them elsewhere (bump, normal map, opacity, emission).
    int operand[3] = {-1, -1, -1};
    float amount = 0.5f;
    TextureMapping mapping = TextureMapping::UV;
    // The texture's space (a 3 x 4 row-major affine map from world space): for the mappings
    // other than UV and for the solid kinds.
    float textureFromWorld[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    Vec3 planarS{1, 0, 0}, planarT{0, 1, 0};
    Vec3 colour4{1.0f};       // Bilerp: v11
    Vec3 direction{0, 0, 1};  // DirectionMix: unit, world space
    // Fbm, Wrinkled, PbrtMarble: octaves and roughness (omega, each octave's weight relative
    // to the one before); PbrtMarble's scale and variation.
    int octaves = 8;
    float roughness = 0.5f, noiseScale = 1, variation = 0.2f;
};

// How a shape maps surface points to (u, v) (scene-format.md, "UV coordinates").
// SphereMitsuba: Mitsuba's (u, v) = (phi / 2 pi, theta / pi) about the local +z pole,
// phi from +x towards +y.
enum class UvKind : uint8_t { None, Plane, Sphere, Mesh, SphereMitsuba };

struct TriangleMesh {
    std::vector<Vec3> positions;    // world space
    std::vector<Vec3> normals;      // world space, per vertex; empty: use face normals
    std::vector<float> uvs;         // 2 per vertex; empty: (0, 0)
    std::vector<uint32_t> indices;  // 3 per triangle
};

enum class ShapeKind : uint8_t { Mesh, Sphere };

struct ShapeDesc {
    std::string id;  // the element's ID
    int line = 0;    // line of the element in the scene file
    ShapeKind kind = ShapeKind::Mesh;
    UvKind uv = UvKind::None;
    int material = -1;  // index into SceneDesc::materials; -1: an emitter that only absorbs
    int light = -1;     // index into SceneDesc::lights; -1 for non-emitters
    TriangleMesh mesh;  // Mesh (planes and rectangle lights are two triangles)
    Vec3 center;        // Sphere, world space
    float radius = 0;   // Sphere, world space
    Affine toWorld;     // object to world (for sphere and plane uv)
    Affine toLocal;     // world to object
    // >= 0: a shape of that group (Mitsuba's shapegroup), in the group's coordinates, placed
    // only by the instances of the group (SceneDesc::instances); a triangle mesh without
    // emitter or mask.
    int group = -1;
    // Media (docs/media.md): a boundary between the medium inside (the side its geometric
    // normal points away from) and outside (indices into SceneDesc::media, -1: vacuum); a
    // shape that is no boundary leaves a ray in the medium it travels in. `passThrough`: an
    // index-matched boundary (pbrt's interface material, Mitsuba's null BSDF): rays cross
    // it without scattering, and it takes no material.
    bool mediumBoundary = false;
    int mediumInside = -1, mediumOutside = -1;
    bool passThrough = false;
};

// A participating medium (docs/media.md): absorption and scattering coefficients per unit
// length (RGB, >= 0) and the Henyey-Greenstein phase function's mean cosine g in (-1, 1)
// (0: isotropic). Homogeneous, or (density or the RGB grids non-empty) heterogeneous: the coefficients times
// a density grid of nx x ny x nz values (x fastest, >= 0) over the unit cube of grid space
// (worldToGrid), interpolated trilinearly between voxel centres, outside the cube 0 (pbrt's
// grids) or the nearest voxel (clampEdges: Mitsuba's).
struct MediumDesc {
    std::string name;
    int line = 0;
    Vec3 sigmaA{0.0f}, sigmaS{0.0f};
    float g = 0;
    int nx = 0, ny = 0, nz = 0;
    std::vector<float> density;
    // Or RGB grids of the coefficients themselves (pbrt's rgbgrid; sigmaA and sigmaS then
    // unused), the same size and interpolation.
    std::vector<Vec3> sigmaAGrid, sigmaSGrid;
    Affine worldToGrid;
    bool clampEdges = false;
    // Emission: the radiance Le the medium emits (RGB, >= 0; the source term is sigma_a Le per
    // unit length), or per voxel (LeGrid, the grid's size: pbrt's Le times a Lescale grid, or
    // an rgbgrid's Le).
    Vec3 Le{0.0f};
    std::vector<Vec3> LeGrid;
    // A density grid's albedo per voxel (Mitsuba's albedo gridvolume): sigma_s = albedo
    // sigma_t there, trilinear as the density (sigmaA + sigmaS is then sigma_t; their split unused).
    std::vector<Vec3> albedoGrid;
    // Mitsuba's constant albedo (sigma_s = albedo sigma_t; -1: none, pbrt's coefficients),
    // kept for spectral renders, which multiply its reflectance spectrum by sigma_t's as
    // Mitsuba 3's scalar_spectral does (docs/spectral.md).
    Vec3 albedo{-1.0f};
};

// One placement of a group of shapes (Mitsuba's instance of a shapegroup): stored once,
// traced through an Embree instance with this transform.
struct InstanceDesc {
    int group = 0;
    Affine toWorld, toLocal;  // group to world, and back
    int line = 0;             // of the element in the scene file
};

// Mesh: any triangle mesh emitting on its winding's side (Mitsuba's area on obj, ply,
// cube, disk); Point: Mitsuba's point light (no shape).
enum class LightKind : uint8_t { Rect, Sphere, Mesh, Point, Directional };

struct LightDesc {
    LightKind kind = LightKind::Rect;
    Vec3 radiance{1.0f};  // Intensity * Colour (Point: the intensity I, W / sr; Directional: the irradiance E, W / m^2)
    int shape = -1;       // index into SceneDesc::shapes (-1 for Point)
    Vec3 position;        // Point
    // Point as Mitsuba's spot: the unit axis (world) it shines along, and its angles in
    // radians (cutoff: 0 beyond; beam width: full intensity within); spotCutoff 0: a
    // point light.
    Vec3 spotAxis{0, 0, 1};
    float spotCutoff = 0, spotBeam = 0;
    bool spotSmoothstep = false;  // pbrt-v4's spot: smoothstep in the cosine from cutoff to beam

    Vec3 direction{0, 0, 1};  // Directional: the unit direction its light travels (world)
    // Mesh: a texture (index into SceneDesc::textures, -1: none) whose value at the point's
    // (u, v) multiplies radiance (Mitsuba's area with a textured radiance); light sampling
    // then follows its luminance (scene/mesh_light.h).
    int texture = -1;
    // Mesh: emits alike from both faces (pbrt-v4's `twosided` area light), each face as a
    // one-sided emitter would; else from the front face only.
    bool twoSided = false;
    // The media its light leaves into from its front and back (index into SceneDesc::media,
    // -1: vacuum), as the file declares them (pbrt-v4: the MediumInterface in force at its
    // directive); kMediumUndeclared: found by the scene model's rule (docs/media.md).
    static constexpr int kMediumUndeclared = -2;
    int mediumFront = kMediumUndeclared, mediumBack = kMediumUndeclared;
    // Its emission as a spectrum (index into SceneDesc::spectra, -1: radiance is RGB), stored
    // with a luminance of 1 (Y against E): the spectral radiance is it times luminance(radiance).
    int spectrum = -1;
};

struct SceneDesc {
    std::string path;  // the scene file, "" for the built-in scene
    Settings settings;
    CameraDesc camera;
    FilterDesc filter;
    std::vector<MaterialDesc> materials;
    std::vector<TextureDesc> textures;
    std::vector<ShapeDesc> shapes;
    std::vector<LightDesc> lights;
    int groups = 0;                       // shape groups (ShapeDesc::group)
    std::vector<InstanceDesc> instances;  // their placements
    std::vector<MediumDesc> media;
    std::vector<SpectrumDesc> spectra;  // the spectra the file gave (MaterialDesc::spectra, LightDesc::spectrum)
    int cameraMedium = -1;              // the medium the camera is in (index into media, -1: vacuum)
    // pbrt-v4's and Mitsuba's rules (their importers set it): a pass-through boundary may be an
    // open mesh (a ray's medium is set by the side it leaves through), and the camera's medium
    // is not checked against a closed boundary around it: what the file declares is rendered,
    // as their renderers do. The thesis format keeps both checks.
    bool mediaAsDeclared = false;
    // pbrt-v4's path regularisation (Integrator "bool regularize", docs/pbrt.md): after a
    // path's first non-specular bounce its BSDFs are roughened (scene/regularize.h). Applied by
    // the PT and BPT renders; the light tracer and the Metropolis tracers render without it.
    // regularizeAt: where the file asks for it ("file:line" of the parameter).
    bool regularize = false;
    std::string regularizeAt;
    Image envMap;                       // empty (0 x 0) when none
    std::vector<std::string> warnings;  // "file:line: ..." ready to print
};

// Loads and validates a scene file: the thesis' format, or a Mitsuba 3 file (a root
// <scene version="...">, load_mitsuba.cpp) with `defines` overriding its <default>s
// (-D name=value). Throws InputError("file:line: problem").
using Defines = std::vector<std::pair<std::string, std::string>>;
// What the command line decides that an importer must know: with a tracer given (--tracer),
// a pbrt or Mitsuba file's integrator that wavemmlt lacks is replaced by it, with a warning
// naming the integrator's line, instead of refused; and what a pbrt file's integrator asks
// for is judged by that tracer (regularize: applied by PT and BPT, else a warning).
struct LoadOptions {
    bool tracerGiven = false;
    TracerKind tracer = TracerKind::MMLT;  // the tracer given (when tracerGiven)
};
SceneDesc loadScene(const std::string& path, const Defines& defines = {}, const LoadOptions& options = {});
bool isMitsubaXml(const std::string& xml);
SceneDesc loadMitsubaFromString(const std::string& xml, const std::string& name, const std::string& baseDir, const Defines& defines = {},
                                const LoadOptions& options = {});
// The same from XML text in memory; `name` is used in messages, `baseDir` resolves
// relative file names (OBJ, images).
SceneDesc loadSceneFromString(const std::string& xml, const std::string& name, const std::string& baseDir);
// The thesis-format text `xml` (named `name` in messages) with its camera and the settings
// an interactive session sets (size, samples, tracer, path lengths, ProbLarge) replaced by
// cam and st, the rest as it was (scene/thesis/write_scene.cpp). Throws InputError when the
// text is not a thesis-format scene.
std::string thesisSceneWithView(const std::string& xml, const std::string& name, const CameraDesc& cam, const Settings& st);
// Loads a pbrt-v4 scene file (.pbrt, or gzipped .pbrt.gz; docs/pbrt.md). loadScene calls
// it for those names. Throws InputError("file:line: problem").
SceneDesc loadPbrt(const std::string& path, const LoadOptions& options = {});

// Loads a Wavefront OBJ (triangulating polygons) in its own coordinates.
// Throws InputError("file:line: problem") on a missing file, bad data, indices out
// of range, or no faces.
TriangleMesh loadObj(const std::string& path, bool smoothShading);

// Loads a Stanford PLY mesh (ASCII or binary, load_ply.cpp; gzipped when the name ends in
// .gz) in its own coordinates, uv as stored; smoothShading without the file's normals:
// area-weighted ones when computeMissingNormals (Mitsuba), none (pbrt). Throws
// InputError("file:line: problem" or "file: byte N: problem").
TriangleMesh loadPly(const std::string& path, bool smoothShading, bool computeMissingNormals = true);

// Loads shape `shapeIndex` (0 the first) of a Mitsuba serialized file (zlib-compressed
// meshes, load_serialized.cpp) in its own coordinates, uv as stored. Throws
// InputError("file: problem", "file: byte N: problem" or "file: shape I: problem").
TriangleMesh loadSerialized(const std::string& path, int shapeIndex, bool smoothShading);

}  // namespace wmlt
