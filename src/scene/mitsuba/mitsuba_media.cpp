// Mitsuba 3's participating media (docs/mitsuba.md, docs/media.md): `homogeneous` (sigma_t,
// albedo, scale) with an `isotropic` or `hg` phase, referenced as a shape's `interior` and
// `exterior` and as the sensor's medium; the `null` BSDF makes a shape an index-matched
// boundary (ShapeDesc::passThrough).
#include "scene/mitsuba/mitsuba_importer.h"

namespace wmlt::mitsuba {

int Importer::medium(Node n) {
    auto it = mediumOf_.find(n.internal_object());
    if (it != mediumOf_.end()) return it->second;
    Props p = props(n);
    if (p.type() != "homogeneous")
        p.fail(n, "medium \"" + p.type() + "\" is not supported yet (homogeneous is; docs/mitsuba.md)");
    MediumDesc m;
    m.name = n.attribute("id").value();
    m.line = files_.line(n);
    // Mitsuba 3: sigma_s = albedo sigma_t, sigma_a = sigma_t - sigma_s, both times scale
    const Vec3 sigmaT = p.getColor("sigma_t", Vec3(1.0f), Props::ColorUse::Unbounded);
    const Vec3 albedo = p.getColor("albedo", Vec3(0.75f));
    const float scale = p.getFloat("scale", 1.0f);
    p.getBool("sample_emitted", true);
    m.sigmaS = albedo * sigmaT * scale;
    m.sigmaA = (sigmaT * scale) - m.sigmaS;
    for (Node ph : p.nested("phase")) {
        Props pp = props(ph);
        if (pp.type() == "hg") m.g = pp.getFloat("g", 0.8f);
        else if (pp.type() != "isotropic") pp.fail(ph, "phase \"" + pp.type() + "\" is not supported (isotropic and hg are)");
        pp.finish();
    }
    p.finish();
    auto bad = [](Vec3 v) { return !isFinite(v) || v.x < 0 || v.y < 0 || v.z < 0; };
    if (bad(m.sigmaA) || bad(m.sigmaS)) p.fail(n, "sigma_t (times scale) must be finite and >= 0, albedo in [0, 1]");
    if (!(m.g > -1 && m.g < 1)) p.fail(n, "the phase function's g must be in (-1, 1)");
    const int index = int(s_.media.size());
    s_.media.push_back(m);
    mediumOf_[n.internal_object()] = index;
    return index;
}

void Importer::shapeMedia(Props& p, ShapeDesc& sh) {
    const Node in = p.getNested("medium", "interior"), out = p.getNested("medium", "exterior");
    if (!in && !out) return;
    sh.mediumBoundary = true;
    sh.mediumInside = in ? medium(in) : -1;
    sh.mediumOutside = out ? medium(out) : -1;
}

}  // namespace wmlt::mitsuba
