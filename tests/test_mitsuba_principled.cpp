// Mitsuba 3's `principled`: the importer (defaults, eta and specular, textured parameters,
// sidedness, bad input) and a principled floor under a point light against the kernel's f
// in closed form (L = f(wo, wi) I cos / r^2) in PT, LT and BPT, its parameters constant
// and as textures of the same values. The kernel itself: test_bsdf_principled.cpp.
#include <catch2/catch.hpp>

#include <string>

#include "kernels/bsdf.h"
#include "mitsuba_floor.h"
#include "scene/scene.h"
#include "wavemmlt/error.h"
#include "wavemmlt/scene_desc.h"

using namespace wmlt;

namespace {

SceneDesc load(const std::string& body) {
    return loadMitsubaFromString(R"(<scene version="3.0.0">
  <sensor type="perspective"><float name="fov" value="40"/><film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film></sensor><emitter type="point"><point name="position" x="0" y="5" z="0"/></emitter>
  )" + body + "\n</scene>\n",
                                 "t.xml", ".");
}
const MaterialDesc& materialOf(const SceneDesc& d, size_t shape = 0) { return d.materials[size_t(d.shapes[shape].material)]; }

std::string errorOf(const std::string& body) {
    try {
        load(body);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST_CASE("Mitsuba principled: import", "[mitsuba][import][principled]") {
    using P = PrincipledParam;
    {  // Mitsuba 3's defaults: base 0.5, roughness 0.5, specular 0.5 (eta 1.5), the rest 0; one-sided
        const SceneDesc d = load(R"(<shape type="cube"><bsdf type="principled"/></shape>)");
        const MaterialDesc& m = materialOf(d);
        CHECK(m.kind == MaterialKind::Principled);
        CHECK(m.diffuse.y == 0.5f);
        CHECK(m.principled[int(P::Roughness)] == 0.5f);
        CHECK(m.principled[int(P::Metallic)] == 0.0f);
        CHECK(m.iorInside / m.iorOutside == Approx(1.5f).epsilon(1e-6));
        CHECK(!m.twoSided);
        CHECK(!principledTransmits(m));
        CHECK(m.samplingRate[0] == 1.0f);
        CHECK(m.samplingRate[2] == 1.0f);
    }
    {  // every parameter given; specular 0.25 -> eta = 2 / (1 - sqrt(0.02)) - 1
        const SceneDesc d = load(R"(<shape type="cube"><bsdf type="principled"><rgb name="base_color" value="0.9, 0.5, 0.1"/>
  <float name="roughness" value="0.2"/><float name="anisotropic" value="0.6"/><float name="metallic" value="0.7"/>
  <float name="spec_trans" value="0.3"/><float name="specular" value="0.25"/><float name="spec_tint" value="0.4"/>
  <float name="sheen" value="0.5"/><float name="sheen_tint" value="0.6"/><float name="flatness" value="0.1"/>
  <float name="clearcoat" value="0.8"/><float name="clearcoat_gloss" value="0.9"/>
  <float name="diffuse_reflectance_sampling_rate" value="0.5"/><float name="main_specular_sampling_rate" value="2"/>
  <float name="clearcoat_sampling_rate" value="0"/></bsdf></shape>)");
        const MaterialDesc& m = materialOf(d);
        const float expect[kPrincipledParams] = {0.2f, 0.6f, 0.7f, 0.3f, 0.4f, 0.5f, 0.6f, 0.1f, 0.8f, 0.9f};
        for (int i = 0; i < kPrincipledParams; ++i) CHECK(m.principled[i] == expect[i]);
        CHECK(m.diffuse.x == 0.9f);
        CHECK(m.iorInside == Approx(2 / (1 - std::sqrt(0.08 * 0.25)) - 1).epsilon(1e-6));
        CHECK(principledTransmits(m));
        CHECK(m.twoSided);  // a transmitting principled has a back side of its own
        CHECK(isAnisotropic(m));
        CHECK(m.samplingRate[0] == 0.5f);
        CHECK(m.samplingRate[1] == 2.0f);
        CHECK(m.samplingRate[2] == 0.0f);
    }
    {  // eta given; spec_trans with eta 1 becomes 1.001 (Mitsuba 3); twosided over a reflecting one
        const SceneDesc d = load(R"(<shape type="cube"><bsdf type="principled"><float name="eta" value="1.33"/></bsdf></shape>
<shape type="cube"><bsdf type="principled"><float name="eta" value="1"/><float name="spec_trans" value="1"/></bsdf></shape>
<shape type="cube"><bsdf type="twosided"><bsdf type="principled"><float name="metallic" value="1"/></bsdf></bsdf></shape>)");
        CHECK(materialOf(d, 0).iorInside == 1.33f);
        CHECK(materialOf(d, 1).iorInside == 1.001f);
        CHECK(materialOf(d, 2).twoSided);
    }
    {  // textures on the base colour and on float parameters (the constant is then 1)
        const SceneDesc d = load(R"(<shape type="cube"><bsdf type="principled">
  <texture type="checkerboard" name="base_color"/><texture type="checkerboard" name="metallic"/>
  <texture type="checkerboard" name="spec_trans"/></bsdf></shape>)");
        const MaterialDesc& m = materialOf(d);
        CHECK(m.texture[MaterialParam::Diffuse] >= 0);
        CHECK(m.texture[principledParam(P::Metallic)] >= 0);
        CHECK(m.principled[int(P::Metallic)] == 1.0f);
        CHECK(m.texture[principledParam(P::Roughness)] < 0);
        CHECK(principledTransmits(m));  // a texture on spec_trans: it may transmit
    }
    const std::pair<std::string, std::string> bad[] = {
        {R"(<bsdf type="principled"><float name="eta" value="1.5"/><float name="specular" value="0.5"/></bsdf>)", "either eta or specular"},
        {R"(<bsdf type="principled"><float name="roughness" value="1.5"/></bsdf>)", "roughness must be in [0, 1]"},
        {R"(<bsdf type="principled"><float name="metallic" value="-0.1"/></bsdf>)", "metallic must be in [0, 1]"},
        {R"(<bsdf type="principled"><texture type="checkerboard" name="eta"/></bsdf>)", "a texture on \"eta\""},
        {R"(<bsdf type="principled"><float name="main_specular_sampling_rate" value="0"/></bsdf>)", "must be > 0"},
        {R"(<bsdf type="principled"><float name="clearcoat_sampling_rate" value="-1"/></bsdf>)", "must be >= 0"},
        {R"(<bsdf type="principled"><float name="eta" value="0"/></bsdf>)", "eta must be > 0"},
        {R"(<bsdf type="twosided"><bsdf type="principled"><float name="spec_trans" value="0.5"/></bsdf></bsdf>)", "transmitting"},
        {R"(<bsdf type="principled"><float name="subsurface" value="0.5"/></bsdf>)", "subsurface"},
    };
    for (const auto& [bsdf, words] : bad) {
        const std::string e = errorOf("<shape type=\"cube\">\n" + bsdf + "</shape>");
        INFO(bsdf << ": " << e);
        CHECK(e.find("t.xml:4:") == 0);
        CHECK(e.find(words) != std::string::npos);
    }
}

// A principled floor (every reflecting lobe on) under a point light at c: the radiance
// towards the eye is f(wo, wi) I cos / r^2 with f the kernel's at the scene's own
// parameters (Scene::build); then with metallic, clearcoat and the base colour as
// checkerboards of those same values (each texture's luminance or colour at every point).
TEST_CASE("Mitsuba principled: a floor under a point light, in PT, LT and BPT", "[mitsuba][render][principled]") {
    const Vec3 c(0.3f, 1.2f, -0.2f);
    const double I = 2;
    const std::string light = R"(<emitter type="point"><point name="position" x="0.3" y="1.2" z="-0.2"/><rgb name="intensity" value="2"/></emitter>)";
    const std::string lobes = R"(<float name="roughness" value="0.45"/><float name="spec_tint" value="0.3"/><float name="sheen" value="0.6"/>
      <float name="sheen_tint" value="0.4"/><float name="flatness" value="0.2"/><float name="clearcoat_gloss" value="0.3"/>)";
    const std::string constant = R"(<bsdf type="principled"><rgb name="base_color" value="0.7, 0.45, 0.2"/>
      <float name="metallic" value="0.25"/><float name="clearcoat" value="0.6"/>)" +
                                 lobes + "</bsdf>";
    const std::string textured = R"(<bsdf type="principled">
      <texture type="checkerboard" name="base_color"><rgb name="color0" value="0.7, 0.45, 0.2"/><rgb name="color1" value="0.7, 0.45, 0.2"/></texture>
      <texture type="checkerboard" name="metallic"><float name="color0" value="0.25"/><float name="color1" value="0.25"/></texture>
      <texture type="checkerboard" name="clearcoat"><float name="color0" value="0.6"/><float name="color1" value="0.6"/></texture>)" +
                                 lobes + "</bsdf>";
    // f from the constant material as the scene builds it
    SceneDesc d = load("<shape type=\"rectangle\">" + constant + "</shape>");
    const std::unique_ptr<Scene> s = Scene::build(std::move(d), 1);
    const BsdfParams f = s->materials[0];
    REQUIRE(f.kind == MaterialKind::Principled);
    const Frame frame = Frame::fromNormal(Vec3(0, 1, 0));
    auto L = [&](Vec3 p, Vec3 eye) {
        const Vec3 wi = normalize(c - p), wo = normalize(eye - p);
        const double r2 = lengthSquared(c - p);
        return double(principledF(f, frame.toLocal(wo), frame.toLocal(wi)).y) * I * wi.y / r2;
    };
    floor_test::floorRadiance(light, L, "principled", {}, constant);
    floor_test::floorRadiance(light, L, "principled-textured", {}, textured);
}
