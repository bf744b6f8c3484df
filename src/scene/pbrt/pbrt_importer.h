// The pbrt-v4 importer's state (docs/pbrt.md): load_pbrt.cpp reads the directives (the
// graphics state, transforms, objects, camera, film, sampler, integrator, filter);
// pbrt_shapes.cpp the shapes, pbrt_materials.cpp the materials, textures and spectra,
// pbrt_lights.cpp the lights. They fill the scene model every importer fills (SceneDesc).
#pragma once
#include <map>
#include <string>
#include <vector>

#include "scene/matrix.h"
#include "scene/pbrt/pbrt_parser.h"
#include "scene/spectrum.h"
#include "wavemmlt/scene_desc.h"

namespace wmlt::pbrt {

// The material index of pbrt's `interface` (no material: ShapeDesc::passThrough).
constexpr int kInterfaceMaterial = -2;

// How a spectrum parameter becomes RGB (pbrt-v4's SpectrumType).
enum class SpectrumUse { Albedo, Unbounded, Illuminant };

class Importer {
public:
    Importer(const std::string& path, const LoadOptions& options);
    SceneDesc run();

private:
    struct State {
        Matrix ctm;  // pbrt's current transformation matrix (object to world; at Camera, camera from world)
        bool reverse = false;
        int material = -1;  // index into s_.materials, -1: pbrt's default diffuse
        bool areaLight = false;
        Directive areaLightDirective;
        // Attribute "shape" | "light" | "material" | "medium" | "texture": default parameters
        // for the directives of that class (those they do not give themselves)
        std::map<std::string, std::vector<Param>> attributes;
        std::string insideMedium, outsideMedium;  // MediumInterface ("": vacuum)
    };
    // A shape's or a light's medium names, resolved when the file has been read (media may be
    // defined after their use, as pbrt-v4 allows).
    struct PendingMedia {
        int index;  // into s_.shapes (pendingMedia_) or s_.lights (pendingLightMedia_)
        std::string inside, outside;
        Loc at;
    };
    Parser parser_;
    LoadOptions options_;
    std::string path_, base_;
    SceneDesc s_;
    State g_;
    // An open AttributeBegin, TransformBegin or ObjectBegin: the state it saved, its name and line.
    struct Block {
        State state;
        std::string begin;
        Loc at;
    };
    std::vector<Block> stack_;
    std::map<std::string, Matrix> namedCoords_;
    std::map<std::string, int> namedMaterials_;
    std::map<std::string, int> textures_;        // spectrum and float textures by name (SceneDesc::textures)
    std::map<std::string, Vec3> constTextures_;  // "constant" textures: their value
    std::map<std::string, bool> floatTexture_;   // whether a named texture is a float texture
    std::map<std::string, int> objects_;         // ObjectBegin name -> group
    std::map<std::string, int> namedMedia_;      // MakeNamedMedium name -> SceneDesc::media
    std::vector<PendingMedia> pendingMedia_;
    std::map<int, std::string> subsurfaceMedium_;  // a subsurface material (its index) -> the name of its interior medium
    std::vector<PendingMedia> pendingLightMedia_;  // a light's front (outside) and back (inside) media
    std::string cameraMedium_;
    Loc cameraAt_;
    int currentObject_ = -1;
    bool inWorld_ = false, endTimeOnly_ = false, warnedMotion_ = false;
    int defaultMaterial_ = -1;
    float imagingRatio_ = 1;  // film: exposure time * ISO / 100, applied to every emitter
    Directive camera_, film_, sampler_, integrator_, filter_;
    Matrix cameraFromWorld_;
    bool haveCamera_ = false;

    void directive(Directive& d);
    void transform(const Directive& d);
    void finish();
    void camera();
    void film();
    void options();
    std::string resolve(const std::string& f) const;
    void warn(const Loc& at, const std::string& msg);
    void done(Directive& d) { d.params.warnUnused(s_.warnings); }
    // Adds the Attribute defaults of class `target` that d does not give itself.
    void withAttributes(Directive& d, const std::string& target) const;
    // The innermost block, which d (an End) closes: its saved state. pbrt-v4's rule: it must be
    // `begin`'s, else "mismatched nesting".
    State closeBlock(const Directive& d, const std::string& begin);

    // pbrt_shapes.cpp
    void shape(Directive& d);
    // pbrt_materials.cpp
    int material(const std::string& type, Directive& d);
    int currentMaterial();
    void conductorIndices(Params& p, const std::string& prefix, MaterialDesc& m, float outside = 1);
    void texture(Directive& d);
    // `sampled`: the spectrum itself when it is one (pairs, a file, a blackbody), else emptied.
    Vec3 spectrum(Params& p, const std::string& name, Vec3 def, SpectrumUse use, SampledSpectrum* sampled = nullptr);
    // The last spectrum() call's spectrum as the file gave it (an index into SceneDesc::spectra:
    // pairs, a file, a blackbody), or -1 (an RGB, a float, the default, a named metal).
    int lastSpectrum_ = -1;
    int keepSpectrum(const SampledSpectrum& s, float scale, const std::string& source, float kelvin = 0);
    // m's parameter q was the last spectrum() (or colourParam()) read: its spectrum, if the
    // file gave one, times scale, as m.spectra[q].
    void keepParamSpectrum(MaterialDesc& m, MaterialParam q, float scale = 1);
    // A colour parameter: its constant, with `texture` set when it names a texture (the
    // constant is then 1, as MaterialDesc's textured parameters take it).
    Vec3 colourParam(Params& p, const std::string& name, Vec3 def, int& texture, bool floatParam = false);
    float floatParam(Params& p, const std::string& name, float def, int& texture);
    // MakeNamedMedium (pbrt_media.cpp); names to indices at the end (resolveMedia).
    void medium(Directive& d);
    void resolveMedia();
    // pbrt_lights.cpp
    void lightSource(Directive& d);
    void areaLight(const Directive& d, ShapeDesc& sh);
};

// Named spectra of pbrt-v4 this importer knows, as RGB (pbrt_materials.cpp).
bool namedSpectrumRgb(const std::string& name, Vec3& rgb);

}  // namespace wmlt::pbrt
