// The texture stage (src/stages/core/textures.h) with the combining textures (Scale, Mix) the
// pbrt-v4 importer fills: a floor whose reflectance is a Scale of a checkerboard by 0.5
// renders as the same floor with the constant 0.5 times the checkerboard, bit for bit (a
// product by 0.5 is exact), in every tracer; and Scene::build refuses a combining texture
// where the stage does not evaluate it, or one whose operand comes after it.
#include <catch2/catch.hpp>

#include <cstring>
#include <string>

#include "render_stats.h"
#include "scene/scene.h"
#include "wavemmlt/error.h"
#include "wavemmlt/render.h"
#include "wavemmlt/scene_desc.h"

using namespace wmlt;

namespace {

SceneDesc floorScene() {
    return loadMitsubaFromString(R"(<scene version="3.0.0">
  <integrator type="path"><integer name="max_depth" value="3"/></integrator>
  <sensor type="perspective"><float name="fov" value="60"/>
    <transform name="to_world"><lookat origin="0, 1.5, 2" target="0, 0, 0" up="0, 1, 0"/></transform>
    <film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="16"/><rfilter type="box"/></film></sensor>
  <shape type="rectangle"><transform name="to_world"><scale value="2"/><rotate x="1" angle="-90"/></transform>
    <bsdf type="diffuse"><texture type="checkerboard" name="reflectance"><rgb name="color0" value="0.8, 0.3, 0.1"/>
      <rgb name="color1" value="0.1, 0.4, 0.9"/><transform name="to_uv"><scale value="4"/></transform></texture></bsdf></shape>
  <shape type="rectangle"><transform name="to_world"><scale value="0.4"/><rotate x="1" angle="90"/><translate y="1.2"/></transform>
    <emitter type="area"><rgb name="radiance" value="6"/></emitter></shape>
</scene>)",
                                 "floor.xml", ".");
}

}  // namespace

TEST_CASE("Texture stage: a Scale texture renders as its constant folded in, in every tracer", "[texture][render]") {
    SceneDesc constant = floorScene(), scaled = floorScene();
    MaterialDesc& mc = constant.materials[size_t(constant.shapes[0].material)];
    REQUIRE(mc.texture[MaterialParam::Diffuse] >= 0);
    mc.diffuse = mc.diffuse * 0.5f;  // 0.5 x the checkerboard
    MaterialDesc& ms = scaled.materials[size_t(scaled.shapes[0].material)];
    TextureDesc s;  // the checkerboard times 0.5, as pbrt's "scale" texture
    s.kind = TextureKind::Scale;
    s.operand[0] = ms.texture[MaterialParam::Diffuse];
    s.colour2 = Vec3(0.5f);
    s.id = int(scaled.textures.size());
    scaled.textures.push_back(s);
    ms.texture[MaterialParam::Diffuse] = s.id;
    for (TracerKind t : {TracerKind::PT, TracerKind::LT, TracerKind::BPT, TracerKind::MMLT}) {
        RenderOptions o = rstats::renderOptions(t, 16, 11, 1, 3);
        if (t == TracerKind::MMLT) o.chains = 256;
        const Image a = render(constant, o).image, b = render(scaled, o).image;
        INFO("tracer " << int(t));
        REQUIRE(a.rgb.size() == b.rgb.size());
        CHECK(std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0);
        double sum = 0;
        for (float x : a.rgb) sum += x;
        CHECK(sum > 0);
    }
}

TEST_CASE("Texture stage: combining textures only where it evaluates them", "[texture]") {
    auto errorOf = [](SceneDesc d) -> std::string {
        try {
            Scene::build(std::move(d), 1);
        } catch (const InputError& e) {
            return e.what();
        }
        return "";
    };
    SceneDesc d = floorScene();
    TextureDesc s;
    s.kind = TextureKind::Mix;
    s.operand[0] = d.materials[size_t(d.shapes[0].material)].texture[MaterialParam::Diffuse];
    s.id = int(d.textures.size());
    d.textures.push_back(s);
    {  // as a bump map (the thesis' and pbrt's heights are any texture's luminance): accepted
        SceneDesc b = d;
        b.materials[size_t(b.shapes[0].material)].bump = s.id;
        CHECK(errorOf(b).empty());
    }
    {  // as a normal map or an opacity: accepted
        SceneDesc b = d;
        b.materials[size_t(b.shapes[0].material)].normalMap = s.id;
        b.materials[size_t(b.shapes[0].material)].opacityTexture = s.id;
        CHECK(errorOf(b).empty());
    }
    {  // as a Mitsuba bump map (the gradient of a bitmap): refused
        SceneDesc b = d;
        b.materials[size_t(b.shapes[0].material)].bump = s.id;
        b.materials[size_t(b.shapes[0].material)].bumpMitsuba = true;
        CHECK(errorOf(b).find("Mitsuba bump map") != std::string::npos);
    }
    {  // an operand after the texture itself: refused
        SceneDesc b = d;
        b.textures.back().operand[1] = s.id;
        CHECK(errorOf(b).find("an operand must be an earlier texture") != std::string::npos);
    }
    {  // on the reflectance: accepted
        SceneDesc b = d;
        b.materials[size_t(b.shapes[0].material)].texture[MaterialParam::Diffuse] = s.id;
        CHECK(errorOf(b).empty());
    }
}
