// The Mitsuba importer's BSDFs (docs/mitsuba.md, "BSDFs").
#include <cmath>

#include "scene/mitsuba_importer.h"

namespace wmlt::mitsuba {
namespace {

// Mitsuba's named indices of refraction (its dielectric IOR table).
const std::map<std::string, float> kIor = {
    {"vacuum", 1.0f}, {"helium", 1.000036f}, {"hydrogen", 1.000132f}, {"air", 1.000277f},
    {"carbon dioxide", 1.00045f}, {"water", 1.333f}, {"acetone", 1.36f}, {"ethanol", 1.361f},
    {"carbon tetrachloride", 1.461f}, {"glycerol", 1.4729f}, {"benzene", 1.501f},
    {"silicone oil", 1.52045f}, {"bromine", 1.661f}, {"water ice", 1.31f}, {"fused quartz", 1.458f},
    {"pyrex", 1.47f}, {"acrylic glass", 1.49f}, {"polypropylene", 1.49f}, {"bk7", 1.5046f},
    {"sodium chloride", 1.544f}, {"amber", 1.55f}, {"pet", 1.575f}, {"diamond", 2.419f}};

}  // namespace

float Importer::ior(Props& p, const char* name, float def) {
    if (!p.has(name)) return def;
    Node n = p.node().find_child_by_attribute("name", name);
    if (n && std::string(n.name()) == "string") {
        std::string v = p.getString(name, "");
        auto it = kIor.find(v);
        if (it == kIor.end()) p.fail(n, "\"" + v + "\" is not in Mitsuba's table of indices of refraction");
        return it->second;
    }
    const float v = p.getFloat(name, def);
    if (!(v > 0)) p.fail(n, "an index of refraction must be > 0");
    return v;
}

void Importer::materialParams(Props& p, MaterialDesc& m) {
    const std::string t = p.type();
    auto colour = [&](const char* name, Vec3 def) {
        if (Node n = p.node().find_child_by_attribute("name", name); n && std::string(n.name()) == "texture")
            p.fail(n, "textures are not supported by the importer yet (docs/mitsuba.md)");
        Vec3 c = p.getColor(name, def);
        if (!(c.x >= 0 && c.y >= 0 && c.z >= 0)) p.fail(p.node(), std::string(name) + " must be >= 0");
        return c;
    };
    auto rough = [&]() {
        const std::string d = p.getString("distribution", "beckmann");
        if (d == "beckmann") m.distribution = MicrofacetType::Beckmann;
        else if (d == "ggx") m.distribution = MicrofacetType::GGX;
        else p.fail(p.node().find_child_by_attribute("name", "distribution"), "distribution \"" + d + "\" is not beckmann or ggx");
        float a = p.getFloat("alpha", 0.1f);
        if (p.has("alpha_u") || p.has("alpha_v")) {
            const float au = p.getFloat("alpha_u", a), av = p.getFloat("alpha_v", a);
            if (au != av) p.fail(p.node(), "anisotropic roughness (alpha_u != alpha_v) is not supported");
            a = au;
        }
        if (!(a > 0 && a <= 10)) p.fail(p.node(), "alpha must be in (0, 10]");
        m.alpha = std::max(a, 1e-4f);
        p.getBool("sample_visible", true);  // sampling only: every choice gives the same image
    };
    auto iors = [&](float intDef) {
        m.iorInside = ior(p, "int_ior", intDef);
        m.iorOutside = ior(p, "ext_ior", 1.000277f);
    };
    m.twoSided = false;
    if (t == "diffuse") {
        m.kind = MaterialKind::Matte;
        m.diffuse = colour("reflectance", Vec3(0.5f));
    } else if (t == "dielectric" || t == "thindielectric" || t == "roughdielectric") {
        m.kind = t == "dielectric" ? MaterialKind::Dielectric : t == "thindielectric" ? MaterialKind::ThinDielectric : MaterialKind::RoughDielectric;
        iors(1.5046f);
        if (t == "roughdielectric") rough();
        m.reflect = colour("specular_reflectance", Vec3(1.0f));
        m.refract = colour("specular_transmittance", Vec3(1.0f));
        m.twoSided = true;  // both sides scatter by definition
    } else if (t == "conductor" || t == "roughconductor") {
        m.kind = t == "conductor" ? MaterialKind::Conductor : MaterialKind::RoughConductor;
        if (t == "roughconductor") rough();
        const std::string mat = p.getString("material", p.has("eta") || p.has("k") ? "" : "none");
        if (!mat.empty() && mat != "none")
            p.fail(p.node(), "the named conductor \"" + mat + "\" is not in wavemmlt's table (only \"none\"): give eta and k");
        m.conductorEta = colour("eta", Vec3(0.0f));
        m.conductorK = colour("k", Vec3(1.0f));
        m.reflect = colour("specular_reflectance", Vec3(1.0f));
    } else if (t == "plastic" || t == "roughplastic") {
        m.kind = t == "plastic" ? MaterialKind::Plastic : MaterialKind::RoughPlastic;
        iors(1.49f);
        if (t == "roughplastic") rough();
        m.diffuse = colour("diffuse_reflectance", Vec3(0.5f));
        m.reflect = colour("specular_reflectance", Vec3(1.0f));
        m.nonlinear = p.getBool("nonlinear", false);
    } else {
        p.fail(p.node(), "BSDF not supported by wavemmlt's Mitsuba importer (docs/mitsuba.md lists what is)");
    }
    if ((t == "dielectric" || t == "thindielectric" || t == "roughdielectric" || t == "plastic" || t == "roughplastic") &&
        m.iorInside == m.iorOutside)
        p.fail(p.node(), "int_ior equals ext_ior");
}

int Importer::material(Node bsdf) {
    auto it = materialOf_.find(bsdf.internal_object());
    if (it != materialOf_.end()) return it->second;
    Props p = props(bsdf);
    MaterialDesc m;
    if (p.type() == "twosided") {  // one nested BSDF, both faces alike
        std::vector<Node> inner = p.nested("bsdf");
        if (inner.size() != 1) p.fail(bsdf, "twosided needs exactly one nested BSDF (two different faces are not supported)");
        m = s_.materials[material(inner[0])];
        if (m.kind == MaterialKind::Dielectric || m.kind == MaterialKind::ThinDielectric || m.kind == MaterialKind::RoughDielectric)
            p.fail(bsdf, "twosided cannot wrap a transmitting BSDF");
        m.twoSided = true;
    } else {
        materialParams(p, m);
    }
    p.finish();
    m.id = int(s_.materials.size());
    materialOf_[bsdf.internal_object()] = m.id;
    s_.materials.push_back(m);
    return m.id;
}

}  // namespace wmlt::mitsuba
