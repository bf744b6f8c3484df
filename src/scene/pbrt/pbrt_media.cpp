// pbrt-v4's participating media (docs/pbrt.md, docs/media.md): MakeNamedMedium's
// homogeneous medium onto the scene model's MediumDesc, and the medium names of shapes
// (MediumInterface) and of the camera resolved once the whole file is read.
#include "scene/pbrt/pbrt_importer.h"

namespace wmlt::pbrt {

void Importer::medium(Directive& d) {
    Params& p = d.params;
    const std::string& name = d.strings[0];
    if (name.empty()) fail(d.at, "MakeNamedMedium needs a name (\"\" is the vacuum)");
    if (namedMedia_.count(name)) fail(d.at, "MakeNamedMedium \"" + name + "\" defined twice");
    const std::string type = p.getString("type", "");
    if (type.empty()) fail(d.at, "MakeNamedMedium \"" + name + "\" needs a \"string type\"");
    if (type != "homogeneous")
        fail(d.at, "MakeNamedMedium type \"" + type + "\" is not supported yet (homogeneous is; docs/pbrt.md)");
    if (const Param* q = p.find("preset")) fail(q->at, "medium presets (measured media) are not supported: give sigma_a and sigma_s");
    MediumDesc m;
    m.name = name;
    m.line = d.at.line;
    // pbrt-v4's defaults: sigma_a = sigma_s = 1 per unit, times scale; g 0
    const float scale = float(p.getFloat("scale", 1));
    m.sigmaA = spectrum(p, "sigma_a", Vec3(1.0f), SpectrumUse::Unbounded) * scale;
    m.sigmaS = spectrum(p, "sigma_s", Vec3(1.0f), SpectrumUse::Unbounded) * scale;
    m.g = float(p.getFloat("g", 0));
    const Vec3 Le = spectrum(p, "Le", Vec3(0.0f), SpectrumUse::Illuminant) * float(p.getFloat("Lescale", 1));
    if (Le.x != 0 || Le.y != 0 || Le.z != 0) fail(p.find("Le")->at, "an emitting medium (Le) is not supported yet");
    auto bad = [](Vec3 v) { return !isFinite(v) || v.x < 0 || v.y < 0 || v.z < 0; };
    if (bad(m.sigmaA) || bad(m.sigmaS)) fail(d.at, "medium \"" + name + "\": sigma_a and sigma_s (times scale) must be finite and >= 0");
    if (!(m.g > -1 && m.g < 1)) fail(p.has("g") ? p.find("g")->at : d.at, "medium \"" + name + "\": g must be in (-1, 1)");
    namedMedia_[name] = int(s_.media.size());
    s_.media.push_back(m);
}

void Importer::resolveMedia() {
    auto index = [&](const std::string& n, const Loc& at) {
        if (n.empty()) return -1;
        auto it = namedMedia_.find(n);
        if (it == namedMedia_.end()) fail(at, "no medium named \"" + n + "\" (MakeNamedMedium)");
        return it->second;
    };
    for (const PendingMedia& pm : pendingMedia_) {
        ShapeDesc& sh = s_.shapes[size_t(pm.shape)];
        sh.mediumBoundary = true;
        sh.mediumInside = index(pm.inside, pm.at);
        sh.mediumOutside = index(pm.outside, pm.at);
    }
    s_.cameraMedium = index(cameraMedium_, cameraAt_);
}

}  // namespace wmlt::pbrt
