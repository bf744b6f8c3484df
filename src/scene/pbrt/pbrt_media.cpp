// pbrt-v4's participating media (docs/pbrt.md, docs/media.md): MakeNamedMedium's
// homogeneous and uniformgrid media onto the scene model's MediumDesc, and the medium names of shapes
// (MediumInterface) and of the camera resolved once the whole file is read.
#include <cmath>

#include "scene/pbrt/pbrt_importer.h"

namespace wmlt::pbrt {

void Importer::medium(Directive& d) {
    Params& p = d.params;
    const std::string& name = d.strings[0];
    if (name.empty()) fail(d.at, "MakeNamedMedium needs a name (\"\" is the vacuum)");
    if (namedMedia_.count(name)) fail(d.at, "MakeNamedMedium \"" + name + "\" defined twice");
    const std::string type = p.getString("type", "");
    if (type.empty()) fail(d.at, "MakeNamedMedium \"" + name + "\" needs a \"string type\"");
    if (type != "homogeneous" && type != "uniformgrid" && type != "rgbgrid")
        fail(d.at, "MakeNamedMedium type \"" + type + "\" is not supported yet (homogeneous, uniformgrid and rgbgrid are; docs/pbrt.md)");
    if (const Param* q = p.find("preset")) fail(q->at, "medium presets (measured media) are not supported: give sigma_a and sigma_s");
    MediumDesc m;
    m.name = name;
    m.line = d.at.line;
    // pbrt-v4's defaults: sigma_a = sigma_s = 1 per unit, times scale; g 0
    const float scale = float(p.getFloat("scale", 1));
    if (type != "rgbgrid") {  // (an rgbgrid's sigma_a and sigma_s are its grids, below)
        m.sigmaA = spectrum(p, "sigma_a", Vec3(1.0f), SpectrumUse::Unbounded) * scale;
        m.sigmaS = spectrum(p, "sigma_s", Vec3(1.0f), SpectrumUse::Unbounded) * scale;
    }
    m.g = float(p.getFloat("g", 0));
    // Emission (pbrt-v4: the source term sigma_a Le; Le an illuminant spectrum times Lescale;
    // a uniformgrid's Lescale may be a grid of the density's size, an rgbgrid's Le one RGB per voxel)
    const std::vector<double> LeScale = p.has("Lescale") ? p.getNumbers("Lescale") : std::vector<double>{1.0};
    for (double x : LeScale)
        if (!(x >= 0) || !std::isfinite(x)) fail(p.find("Lescale")->at, "Lescale must be finite and >= 0");
    if (type != "rgbgrid") {
        m.Le = spectrum(p, "Le", Vec3(0.0f), SpectrumUse::Illuminant);
        if (LeScale.size() == 1) m.Le = m.Le * float(LeScale[0]);
    }
    if (LeScale.size() != 1 && type != "uniformgrid") fail(p.find("Lescale")->at, "Lescale: one number (a grid of them: a uniformgrid's)");
    auto bad = [](Vec3 v) { return !isFinite(v) || v.x < 0 || v.y < 0 || v.z < 0; };
    if (bad(m.sigmaA) || bad(m.sigmaS)) fail(d.at, "medium \"" + name + "\": sigma_a and sigma_s (times scale) must be finite and >= 0");
    if (!(m.g > -1 && m.g < 1)) fail(p.has("g") ? p.find("g")->at : d.at, "medium \"" + name + "\": g must be in (-1, 1)");
    if (type == "uniformgrid" || type == "rgbgrid") {  // pbrt-v4: grids (nx ny nz, x fastest) over [p0, p1] in the medium's space
        m.nx = p.getInt("nx", 1), m.ny = p.getInt("ny", 1), m.nz = p.getInt("nz", 1);
        if (m.nx < 1 || m.ny < 1 || m.nz < 1 || double(m.nx) * m.ny * m.nz > 1e9)
            fail(d.at, type + ": nx, ny, nz must be >= 1 (and their product at most 1e9)");
        const size_t n = size_t(m.nx) * size_t(m.ny) * size_t(m.nz);
        // a grid parameter: `per` numbers per voxel, finite and >= 0
        auto grid = [&](const char* name, int per) {
            const Param* q = p.find(name);
            if (!q) fail(d.at, type + " needs \"" + name + "\"");
            const std::vector<double> v = p.getNumbers(name);
            if (v.size() != n * size_t(per))
                fail(q->at, type + ": " + std::to_string(v.size() / size_t(per)) + " " + name + " values for a " + std::to_string(m.nx) + " x " +
                                std::to_string(m.ny) + " x " + std::to_string(m.nz) + " grid");
            for (double x : v)
                if (!(x >= 0) || !std::isfinite(x)) fail(q->at, type + ": " + name + " values must be finite and >= 0");
            return v;
        };
        if (type == "uniformgrid") {
            const std::vector<double> v = grid("density", 1);
            m.density.assign(v.begin(), v.end());
            if (LeScale.size() != 1) {  // Le times a grid of scales
                const std::vector<double> ls = grid("Lescale", 1);
                for (double x : ls) m.LeGrid.push_back(m.Le * float(x));
                m.Le = Vec3(0.0f);
            }
        } else {  // rgbgrid: the coefficients themselves, times scale
            const std::vector<double> a = grid("sigma_a", 3), s = grid("sigma_s", 3);
            for (size_t i = 0; i < n; ++i) {
                m.sigmaAGrid.push_back(Vec3(float(a[3 * i]), float(a[3 * i + 1]), float(a[3 * i + 2])) * scale);
                m.sigmaSGrid.push_back(Vec3(float(s[3 * i]), float(s[3 * i + 1]), float(s[3 * i + 2])) * scale);
            }
            if (p.has("Le")) {  // an RGB radiance per voxel, times Lescale
                const std::vector<double> e = grid("Le", 3);
                for (size_t i = 0; i < n; ++i)
                    m.LeGrid.push_back(Vec3(float(e[3 * i]), float(e[3 * i + 1]), float(e[3 * i + 2])) * float(LeScale[0]));
            }
        }
        const Vec3 p0 = p.getPoint3("p0", Vec3(0.0f)), p1 = p.getPoint3("p1", Vec3(1.0f));
        const Vec3 e = p1 - p0;
        if (!(e.x > 0 && e.y > 0 && e.z > 0)) fail(d.at, type + ": p1 must exceed p0 in x, y and z");
        if (g_.ctm.det3() == 0) fail(d.at, type + ": the current transformation is singular");
        const Matrix toGrid = Matrix::scale(1 / e.x, 1 / e.y, 1 / e.z) * Matrix::translate(-p0.x, -p0.y, -p0.z) * g_.ctm.inverse();
        m.worldToGrid = toGrid.affine();
        for (const char* k : {"temperature", "temperaturescale", "temperatureoffset", "temperaturecutoff"})
            if (p.has(k)) fail(p.find(k)->at, std::string(k) + ": emission from a temperature grid (blackbody) is not supported: give Le");
    }
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
        ShapeDesc& sh = s_.shapes[size_t(pm.index)];
        sh.mediumBoundary = true;
        sh.mediumInside = index(pm.inside, pm.at);
        sh.mediumOutside = index(pm.outside, pm.at);
    }
    s_.cameraMedium = index(cameraMedium_, cameraAt_);
    // pbrt-v4's rules: the media are what the file declares (an open pass-through boundary is
    // legal; a light's media are the MediumInterface in force at its directive)
    s_.mediaAsDeclared = true;
    for (const PendingMedia& pm : pendingLightMedia_) {
        LightDesc& l = s_.lights[size_t(pm.index)];
        l.mediumFront = index(pm.outside, pm.at);
        l.mediumBack = index(pm.inside, pm.at);
    }
}

}  // namespace wmlt::pbrt
