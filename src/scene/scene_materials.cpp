// Scene::build's materials: each MaterialDesc as the kernels' data, its constants in a
// BsdfParams (Scene::materials) and its tables in a BsdfExtra (Scene::bsdfExtras), and under
// pbrt's regularize a second such table of their regularized versions
// (Scene::regularizedOffset); the blends' parts, their textures, and which blends are
// resolved to one part per hit (Scene::choosesPart).
#include "kernels/texture.h"
#include "scene/regularize.h"
#include "scene/scene.h"

namespace wmlt {

namespace {

// A principled material's constants: its weights and alphas in b (setPrincipled),
// whether it transmits, its sampling rates.
void principledConstants(const MaterialDesc& m, BsdfParams& b, BsdfExtra& x) {
    setPrincipled(b, m.principled);
    x.dist = Microfacet(MicrofacetType::GGX, b.alphaX, b.alphaY);
    x.transmits = principledTransmits(m);
    for (int i = 0; i < 3; ++i) x.samplingRate[i] = m.samplingRate[i];
}

}  // namespace

void buildMaterials(const SceneDesc& d, Scene& s) {
    // The materials, then (pbrt's regularize) each one's regularized version, built alike:
    // index n + i is material i's (Scene::regularizedOffset).
    const size_t n = d.materials.size();
    std::vector<MaterialDesc> regularized;
    if (d.regularize)
        for (const MaterialDesc& m : d.materials) regularized.push_back(regularizedMaterial(m));
    s.regularizedOffset = regularized.empty() ? 0 : uint32_t(n);
    const size_t tables = n + regularized.size();
    auto descOf = [&](size_t i) -> const MaterialDesc& { return i < n ? d.materials[i] : regularized[i - n]; };
    s.bsdfExtras.resize(tables);  // not resized again: materials point into it
    s.choosesPart.assign(n, 0);
    for (size_t i = 0; i < tables; ++i) {
        const MaterialDesc& m = descOf(i);
        BsdfParams b;
        b.kind = m.kind;
        b.diffuse = m.diffuse;
        b.specular = m.specular;
        b.shininess = m.shininess;
        b.reflect = m.reflect;
        b.refract = m.refract;
        b.eta = m.iorInside / m.iorOutside;
        if (int(m.kind) >= int(MaterialKind::Conductor)) {
            BsdfExtra& x = s.bsdfExtras[i];
            x.dist = Microfacet(m.distribution, m.alpha, alphaVOf(m));  // alphaX along u (the frame's x)
            x.anisotropic = isAnisotropic(m);
            x.nonlinear = m.nonlinear;
            // Mitsuba's specular sampling weight: mean(Ks) / (mean(Kd) + mean(Ks)), each
            // parameter with its texture's mean (as Mitsuba's roughplastic takes it); a
            // sampling choice only, so an approximate mean costs noise, never bias.
            auto withMean = [&](MaterialParam c, Vec3 v) {
                const int t = m.texture[c];
                return t >= 0 ? v * textureMeanOf(d.textures, size_t(t)) : v;
            };
            const Vec3 Ks = withMean(MaterialParam::Reflect, m.reflect), Kd = withMean(MaterialParam::Diffuse, m.diffuse);
            const float ks = (Ks.x + Ks.y + Ks.z) / 3, kd = (Kd.x + Kd.y + Kd.z) / 3;
            x.specularWeight = ks + kd > 0 ? ks / (ks + kd) : 0.5f;
            if (m.kind == MaterialKind::Plastic || m.kind == MaterialKind::RoughPlastic)
                preparePlastic(x, b.eta, m.kind == MaterialKind::RoughPlastic);
            if (m.kind == MaterialKind::Principled) principledConstants(m, b, x);
            if (m.kind == MaterialKind::Conductor || m.kind == MaterialKind::RoughConductor) setConductorIndex(b, m.conductorEta, m.conductorK);
            x.regularized = i >= n;
            b.x = &x;
        }
        b.blendWeight = m.blendWeight;
        if (m.kind == MaterialKind::Coated) {  // the interface's alphas, the albedo and the base in b; the slab in x
            BsdfExtra& x = s.bsdfExtras[i];
            b.alphaX = m.alpha;
            b.alphaY = alphaVOf(m);
            if (m.coating.conductorBase) setConductorIndex(b, m.conductorEta, m.conductorK);
            setCoatingAlbedo(b, m.coating.albedo);
            setCoatBaseAlphas(b, m.coating.baseAlpha, m.coating.baseAlphaV);
            static_cast<MaterialDesc::Coating&>(x.coating) = m.coating;  // (the base's Fresnel scale: b.reflect, m.reflect)
        }
        s.materials.push_back(b);
        // (by the material's index: the regularized table reads the same textures)
        if (i < n) s.texturedMaterial.push_back(readsTexture(d, m) ? 1 : 0);
    }
    // Blends: their parts' constants side by side (reserved once: the extras point into it),
    // a regularized blend's from the regularized table.
    size_t blends = 0;
    for (size_t i = 0; i < tables; ++i) blends += descOf(i).kind == MaterialKind::Blend ? 1 : 0;
    s.blendParts.reserve(2 * blends);
    s.blendTextures.reserve(blends);
    for (size_t i = 0; i < tables; ++i) {
        const MaterialDesc& m = descOf(i);
        if (m.kind != MaterialKind::Blend) continue;
        s.bsdfExtras[i].blendParts = s.blendParts.data() + s.blendParts.size();
        for (int part : m.blendPart) s.blendParts.push_back(s.materials[size_t(part) + (i < n ? 0 : n)]);
        BlendTextures t;  // the textured parts, read where the blend's kernel needs them
        t.textures = &s.desc.textures;
        for (int k = 0; k < 2; ++k) {
            const MaterialDesc& q = s.desc.materials[size_t(m.blendPart[k])];
            if (readsParamTexture(q)) t.part[k] = &q;
        }
        if (t.part[0] || t.part[1]) {
            s.blendTextures.push_back(t);
            s.bsdfExtras[i].blendTextures = &s.blendTextures.back();
        }
        // anisotropic parts: the blend's frame follows dp/du for them (shadingFrame)
        for (int part : m.blendPart) s.bsdfExtras[i].anisotropic |= isAnisotropic(d.materials[size_t(part)]);
        if (i < n && blendChoosesPart(d.materials, m)) s.choosesPart[i] = 1;
    }
}

}  // namespace wmlt
