// The Mitsuba importer's BSDFs (docs/mitsuba.md, "BSDFs").
#include <cmath>
#include <filesystem>

#include "scene/features.h"
#include "scene/mitsuba/mitsuba_importer.h"
#include "scene/read_file.h"
#include "wavemmlt/error.h"
#include "wavemmlt/image.h"

namespace wmlt::mitsuba {
namespace {

// Mitsuba's named indices of refraction (its dielectric IOR table).
const std::map<std::string, float> kIor = {{"vacuum", 1.0f},      {"helium", 1.000036f},        {"hydrogen", 1.000132f},
                                           {"air", 1.000277f},    {"carbon dioxide", 1.00045f}, {"water", 1.333f},
                                           {"acetone", 1.36f},    {"ethanol", 1.361f},          {"carbon tetrachloride", 1.461f},
                                           {"glycerol", 1.4729f}, {"benzene", 1.501f},          {"silicone oil", 1.52045f},
                                           {"bromine", 1.661f},   {"water ice", 1.31f},         {"fused quartz", 1.458f},
                                           {"pyrex", 1.47f},      {"acrylic glass", 1.49f},     {"polypropylene", 1.49f},
                                           {"bk7", 1.5046f},      {"sodium chloride", 1.544f},  {"amber", 1.55f},
                                           {"pet", 1.575f},       {"diamond", 2.419f}};

// Named conductors: the complex index eta + i k of each metal as RGB, Mitsuba 3's own
// projection of its spectra (against E, no D65: scene/spectrum.h; Bitterli's veach-mis
// copper and veach-bidir VN are these). Other names of Mitsuba's table are refused.
struct ComplexIor {
    Vec3 eta, k;
};
const std::map<std::string, ComplexIor> kConductors = {
    {"Ag", {{0.1552646489f, 0.1167232965f, 0.1383806959f}, {4.8283433224f, 3.1222459278f, 2.1469504455f}}},
    {"Al", {{1.6574599595f, 0.8803689579f, 0.5212287346f}, {9.2238691996f, 6.2695232477f, 4.8370012281f}}},
    {"Au", {{0.1431189557f, 0.3749570432f, 1.4424785571f}, {3.9831604247f, 2.3857207478f, 1.6032152899f}}},
    {"Cr", {{4.3696828663f, 2.9167024892f, 1.6547005413f}, {5.2064337956f, 4.2313645277f, 3.7549467933f}}},
    {"Cu", {{0.2004376970f, 0.9240334304f, 1.1022119527f}, {3.9129485033f, 2.4528477015f, 2.1421879552f}}},
    {"VN", {{2.8656011588f, 2.1191817791f, 1.9400767149f}, {3.0323264950f, 2.0561075580f, 1.6162930914f}}}};

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

// A <texture> (bitmap, checkerboard) into SceneDesc::textures, once per element.
int Importer::texture(Node n) {
    auto it = textureOf_.find(n.internal_object());
    if (it != textureOf_.end()) return it->second;
    Props p = props(n);
    const std::string t = p.type();
    TextureDesc tex;
    auto toUv = [&]() {
        const Matrix M = p.getTransform("to_uv");  // Mitsuba reads its 2D part: rows 0-1, columns 0, 1, 3
        const double a[6] = {M.m[0][0], M.m[0][1], M.m[0][3], M.m[1][0], M.m[1][1], M.m[1][3]};
        for (int i = 0; i < 6; ++i) tex.uvTransform[i] = float(a[i]);
    };
    if (t == "bitmap") {
        tex.kind = TextureKind::Bitmap;
        if (!p.has("filename")) p.fail(n, "a bitmap needs a filename");
        const std::string path = resolve(p.getString("filename", ""));
        try {
            tex.image = readSceneImage(path);
        } catch (const InputError& e) {
            p.fail(n, e.what());
        }
        const std::string filter = p.getString("filter_type", "bilinear");
        if (filter == "nearest") tex.nearest = true;
        else if (filter != "bilinear") p.fail(n, "filter_type \"" + filter + "\" is not bilinear or nearest");
        const std::string wrap = p.getString("wrap_mode", "repeat");
        if (wrap == "repeat") tex.wrap = TextureWrap::Repeat;
        else if (wrap == "mirror") tex.wrap = TextureWrap::Mirror;
        else if (wrap == "clamp") tex.wrap = TextureWrap::Clamp;
        else p.fail(n, "wrap_mode \"" + wrap + "\" is not repeat, mirror or clamp");
        // raw: the file's values as stored. readImage linearises 8-bit sRGB files (PNG,
        // JPEG); raw undoes that (exactly, up to float rounding).
        const std::string ext = std::filesystem::path(path).extension().string();
        const bool encoded = ext == ".png" || ext == ".PNG" || ext == ".jpg" || ext == ".JPG" || ext == ".jpeg" || ext == ".JPEG";
        if (p.getBool("raw", false) && encoded)
            for (float& v : tex.image.rgb) v = linearToSrgb(v);
        toUv();
    } else if (t == "checkerboard") {
        tex.kind = TextureKind::Checkerboard;
        for (const char* c : {"color0", "color1"})
            if (Node x = p.node().find_child_by_attribute("name", c); x && (std::string(x.name()) == "texture" || std::string(x.name()) == "ref"))
                p.fail(x, "a texture inside a checkerboard is not supported (a colour is)");
        tex.colour1 = p.getColor("color0", Vec3(0.4f));
        tex.colour2 = p.getColor("color1", Vec3(0.2f));
        toUv();
    } else {
        p.fail(n, "texture not supported by wavemmlt's Mitsuba importer (bitmap and checkerboard are)");
    }
    p.finish();
    tex.id = int(s_.textures.size());
    textureOf_[n.internal_object()] = tex.id;
    s_.textures.push_back(std::move(tex));
    return int(s_.textures.size()) - 1;
}

// The texture a parameter names (<texture name=...> or <ref name=... id=...> of one), or
// a null node when the parameter is a plain value or absent.
Node Importer::textureParam(Props& p, const std::string& name) {
    Node c = p.node().find_child_by_attribute("name", name.c_str());
    if (!c) return Node();
    const std::string tag = c.name();
    if (tag == "texture") return p.getNested("texture", name);
    if (tag == "ref") {
        Node r = ids_.count(c.attribute("id").value()) ? ids_.at(c.attribute("id").value()) : Node();
        if (r && std::string(r.name()) == "texture") return p.getNested("texture", name);
    }
    return Node();
}

// Mitsuba 3's `principled` (not base_color: materialParams reads that): each float
// parameter a number in [0, 1] or a texture (its luminance); eta or specular (not both;
// eta = 2 / (1 - sqrt(0.08 specular)) - 1); the three sampling rates. It transmits when
// spec_trans is given and not 0 (then eta 1 becomes 1.001 and specular 0 becomes 1e-3, as
// Mitsuba 3 does); only then is it two-sided by itself.
void Importer::principledParams(Props& p, MaterialDesc& m) {
    m.kind = MaterialKind::Principled;
    static const char* kNames[kPrincipledParams] = {"roughness", "anisotropic", "metallic", "spec_trans", "spec_tint",
                                                    "sheen",     "sheen_tint",  "flatness", "clearcoat",  "clearcoat_gloss"};
    for (int i = 0; i < kPrincipledParams; ++i) {
        if (Node tx = textureParam(p, kNames[i])) {
            m.texture[principledParam(PrincipledParam(i))] = texture(tx);
            m.principled[i] = 1;
            continue;
        }
        m.principled[i] = p.getFloat(kNames[i], i == int(PrincipledParam::Roughness) ? 0.5f : 0.0f);
        if (!(m.principled[i] >= 0 && m.principled[i] <= 1))
            p.fail(p.node().find_child_by_attribute("name", kNames[i]), std::string(kNames[i]) + " must be in [0, 1]");
    }
    const bool transmits = principledTransmits(m);
    for (const char* name : {"eta", "specular"})
        if (Node tx = textureParam(p, name)) p.fail(tx, std::string("a texture on \"") + name + "\" is not supported (Mitsuba 3 reads a number)");
    if (p.has("eta") && p.has("specular")) p.fail(p.node(), "give either eta or specular, not both");
    float eta;
    if (p.has("eta")) {
        eta = p.getFloat("eta", 1.5f);
        if (!(eta > 0)) p.fail(p.node().find_child_by_attribute("name", "eta"), "eta must be > 0");
        if (transmits && eta == 1) eta = 1.001f;
    } else {
        float specular = p.getFloat("specular", 0.5f);
        if (!(specular >= 0 && specular < 12.5f)) p.fail(p.node().find_child_by_attribute("name", "specular"), "specular must be in [0, 12.5)");
        if (transmits && specular == 0) specular = 1e-3f;
        eta = 2.0f / (1.0f - std::sqrt(0.08f * specular)) - 1.0f;
    }
    m.iorInside = eta;
    m.iorOutside = 1;
    static const char* kRates[3] = {"diffuse_reflectance_sampling_rate", "main_specular_sampling_rate", "clearcoat_sampling_rate"};
    for (int i = 0; i < 3; ++i) {
        m.samplingRate[i] = p.getFloat(kRates[i], 1.0f);
        if (!(m.samplingRate[i] >= 0 && m.samplingRate[i] < 1e6f) || (i == 1 && !(m.samplingRate[i] > 0)))
            p.fail(p.node().find_child_by_attribute("name", kRates[i]), std::string(kRates[i]) + (i == 1 ? " must be > 0" : " must be >= 0"));
    }
    m.twoSided = transmits;
}

void Importer::materialParams(Props& p, MaterialDesc& m) {
    const std::string t = p.type();
    // A colour parameter: a constant, or a texture that scales a constant 1 (the parameter
    // it is, `param`).
    auto colour = [&](const char* name, Vec3 def, MaterialParam param, Props::ColorUse use = Props::ColorUse::Reflectance) {
        if (Node tx = textureParam(p, name)) {
            m.texture[param] = texture(tx);
            return Vec3(1.0f);
        }
        Vec3 c = p.getColor(name, def, use);
        if (!(c.x >= 0 && c.y >= 0 && c.z >= 0)) p.fail(p.node(), std::string(name) + " must be >= 0");
        m.spectra[param] = p.lastSpectrum();  // (a <spectrum>: kept for spectral renders)
        return c;
    };
    // anisotropic: alpha_u != alpha_v accepted (Mitsuba 3's roughconductor and
    // roughdielectric), else refused as Mitsuba's roughplastic refuses it.
    auto rough = [&](bool anisotropic) {
        const std::string d = p.getString("distribution", "beckmann");
        if (d == "beckmann") m.distribution = MicrofacetType::Beckmann;
        else if (d == "ggx") m.distribution = MicrofacetType::GGX;
        else p.fail(p.node().find_child_by_attribute("name", "distribution"), "distribution \"" + d + "\" is not beckmann or ggx");
        // A roughness: a number, or a texture whose luminance at the hit is the alpha there
        // (rough conductors and dielectrics; roughplastic's tables are made for one alpha).
        auto roughness = [&](const char* name, float def, int& tex) {
            if (Node tx = textureParam(p, name)) {
                if (!anisotropic)
                    p.fail(p.node().find_child_by_attribute("name", name),
                           std::string("a texture on \"") + name + "\" is not supported by roughplastic (its tables are made for one alpha)");
                tex = texture(tx);
                return 1.0f;
            }
            return p.getFloat(name, def);
        };
        int ta = -1, tav = -1;
        float a = roughness("alpha", 0.1f, ta), av = a;
        tav = ta;
        if (p.has("alpha_u") || p.has("alpha_v")) {  // Mitsuba 3's rules: both, and not with alpha
            if (!p.has("alpha_u") || !p.has("alpha_v")) p.fail(p.node(), "give both alpha_u and alpha_v");
            if (p.has("alpha")) p.fail(p.node(), "give either alpha or alpha_u and alpha_v, not both");
            a = roughness("alpha_u", a, ta);
            av = roughness("alpha_v", a, tav);
            if (a != av && !anisotropic)
                p.fail(p.node(), "anisotropic roughness (alpha_u != alpha_v) is not supported by roughplastic (as in Mitsuba 3)");
        }
        m.texture[MaterialParam::AlphaU] = ta;
        m.texture[MaterialParam::AlphaV] = tav;
        for (float x : {a, av})
            if (!(x > 0 && x <= 10)) p.fail(p.node(), "alpha must be in (0, 10]");
        m.alpha = std::max(a, 1e-4f);
        if (av != a) m.alphaV = std::max(av, 1e-4f);  // else isotropic: alphaV stays unset
        p.getBool("sample_visible", true);            // sampling only: every choice gives the same image
    };
    auto iors = [&](float intDef) {
        m.iorInside = ior(p, "int_ior", intDef);
        m.iorOutside = ior(p, "ext_ior", 1.000277f);
    };
    m.twoSided = false;
    if (t == "diffuse") {
        m.kind = MaterialKind::Matte;
        m.diffuse = colour("reflectance", Vec3(0.5f), MaterialParam::Diffuse);
    } else if (t == "dielectric" || t == "thindielectric" || t == "roughdielectric") {
        m.kind = t == "dielectric" ? MaterialKind::Dielectric : t == "thindielectric" ? MaterialKind::ThinDielectric : MaterialKind::RoughDielectric;
        iors(1.5046f);
        if (t == "roughdielectric") rough(true);
        m.reflect = colour("specular_reflectance", Vec3(1.0f), MaterialParam::Reflect);
        m.refract = colour("specular_transmittance", Vec3(1.0f), MaterialParam::Refract);
        m.twoSided = true;  // both sides scatter by definition
    } else if (t == "conductor" || t == "roughconductor") {
        m.kind = t == "conductor" ? MaterialKind::Conductor : MaterialKind::RoughConductor;
        if (t == "roughconductor") rough(true);
        // Mitsuba 3: eta and k, or a named material; "none" (the default) is eta 0, k 1.
        const std::string mat = p.getString("material", "none");
        if (mat == "none") {
            m.conductorEta = colour("eta", Vec3(0.0f), MaterialParam::ConductorEta, Props::ColorUse::Unbounded);
            m.conductorK = colour("k", Vec3(1.0f), MaterialParam::ConductorK, Props::ColorUse::Unbounded);
        } else {
            if (p.has("eta") || p.has("k")) p.fail(p.node(), "give either eta and k or material, not both");
            auto it = kConductors.find(mat);
            if (it == kConductors.end()) {
                std::string names;
                for (const auto& c : kConductors) names += " " + c.first;
                p.fail(p.node().find_child_by_attribute("name", "material"),
                       "the conductor \"" + mat + "\" is not in wavemmlt's table (none" + names +
                           "): give eta and k (numbers, rgb, or spectra such as <spectrum name=\"eta\" filename=\"" + mat + ".eta.spd\"/>)");
            }
            m.conductorEta = it->second.eta;
            m.conductorK = it->second.k;
        }
        m.reflect = colour("specular_reflectance", Vec3(1.0f), MaterialParam::Reflect);
    } else if (t == "plastic" || t == "roughplastic") {
        m.kind = t == "plastic" ? MaterialKind::Plastic : MaterialKind::RoughPlastic;
        iors(1.49f);
        if (t == "roughplastic") rough(false);
        m.diffuse = colour("diffuse_reflectance", Vec3(0.5f), MaterialParam::Diffuse);
        m.reflect = colour("specular_reflectance", Vec3(1.0f), MaterialParam::Reflect);
        m.nonlinear = p.getBool("nonlinear", false);
    } else if (t == "principled") {
        principledParams(p, m);
        m.diffuse = colour("base_color", Vec3(0.5f), MaterialParam::Diffuse);
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
    auto inner = [&](const char* what) {  // the one nested BSDF of a wrapper
        std::vector<Node> b = p.nested("bsdf");
        if (b.size() != 1) p.fail(bsdf, std::string(what) + " needs exactly one nested BSDF");
        return s_.materials[material(b[0])];
    };
    if (p.type() == "twosided") {  // one nested BSDF, both faces alike
        std::vector<Node> b = p.nested("bsdf");
        if (b.size() != 1) p.fail(bsdf, "twosided needs exactly one nested BSDF (two different faces are not supported)");
        m = s_.materials[material(b[0])];
        if (m.kind == MaterialKind::Dielectric || m.kind == MaterialKind::ThinDielectric || m.kind == MaterialKind::RoughDielectric ||
            principledTransmits(m))
            p.fail(bsdf, "twosided cannot wrap a transmitting BSDF");
        m.twoSided = true;
    } else if (p.type() == "bumpmap") {  // a height texture (any name) over the nested BSDF
        m = inner("bumpmap");
        if (m.normalMap >= 0) p.fail(bsdf, "a bumpmap over a normalmap is not supported");
        std::vector<Node> tx;
        for (Node c : p.node().children())
            if (c.type() == pugi::node_element && std::string(c.name()) == "texture") tx.push_back(c);
        for (Node c : p.node().children())
            if (c.type() == pugi::node_element && std::string(c.name()) == "ref" && ids_.count(c.attribute("id").value()) &&
                std::string(ids_.at(c.attribute("id").value()).name()) == "texture")
                tx.push_back(c);
        if (tx.size() != 1) p.fail(bsdf, "bumpmap needs exactly one nested texture (the height)");
        const std::string tname = tx[0].attribute("name").value();
        Node tn = tname.empty() ? p.nested("texture").at(0) : p.getNested("texture", tname);
        if (m.bump >= 0) p.fail(bsdf, "a bumpmap inside a bumpmap is not supported");
        m.bump = texture(tn);
        if (s_.textures[m.bump].kind != TextureKind::Bitmap) p.fail(tx[0], "a bumpmap's height must be a bitmap (Mitsuba differentiates only those)");
        m.bumpMitsuba = true;
        m.bumpScale = p.getFloat("scale", 1.0f);
    } else if (p.type() == "normalmap") {  // the `normalmap` texture over the nested BSDF
        m = inner("normalmap");
        if (m.bump >= 0 || m.normalMap >= 0) p.fail(bsdf, "a normalmap over a bumpmap or normalmap is not supported");
        Node tn = textureParam(p, "normalmap");
        if (!tn) p.fail(bsdf, "normalmap needs a texture named \"normalmap\"");
        m.normalMap = texture(tn);
    } else if (p.type() == "mask") {  // opacity: a float or a texture's luminance
        m = inner("mask");
        if (m.opacity < 1 || m.opacityTexture >= 0) p.fail(bsdf, "a mask inside a mask is not supported");
        if (Node tx = textureParam(p, "opacity")) {
            m.opacityTexture = texture(tx);
        } else {
            m.opacity = p.getFloat("opacity", 0.5f);
            if (!(m.opacity >= 0 && m.opacity <= 1)) p.fail(bsdf, "opacity must be in [0, 1]");
        }
    } else if (p.type() == "blendbsdf") {  // f = (1 - weight) f_0 + weight f_1
        std::vector<Node> b = p.nested("bsdf");
        if (b.size() != 2) p.fail(bsdf, "blendbsdf needs exactly two nested BSDFs");
        m.kind = MaterialKind::Blend;
        for (int k = 0; k < 2; ++k) {
            const int part = material(b[size_t(k)]);
            const MaterialDesc& q = s_.materials[size_t(part)];
            // (bump- or normal-mapped parts: one of them per hit, Scene::choosesPart)
            const char* why = q.kind == MaterialKind::Blend            ? "a blendbsdf inside a blendbsdf"
                              : q.opacity < 1 || q.opacityTexture >= 0 ? "a mask"
                                                                       : nullptr;
            if (why) p.fail(b[size_t(k)], std::string(why) + " inside a blendbsdf is not supported");
            m.blendPart[k] = part;
        }
        if (s_.materials[size_t(m.blendPart[0])].twoSided != s_.materials[size_t(m.blendPart[1])].twoSided)
            p.fail(bsdf, "a blendbsdf of a twosided and a one-sided BSDF is not supported (wrap the blendbsdf in twosided)");
        m.twoSided = s_.materials[size_t(m.blendPart[0])].twoSided;
        if (Node tx = textureParam(p, "weight")) {
            m.texture[MaterialParam::BlendWeight] = texture(tx);
            m.blendWeight = 1;
        } else {
            m.blendWeight = p.getFloat("weight", 0.5f);
            if (!(m.blendWeight >= 0 && m.blendWeight <= 1)) p.fail(bsdf, "weight must be in [0, 1]");
        }
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
