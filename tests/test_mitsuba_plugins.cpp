// The Mitsuba plugins added after the first importer (docs/mitsuba.md): named conductors,
// emitters with BSDFs, textures (bitmap, checkerboard), bumpmap, mask, ply, envmap, point
// lights and area lights on meshes. Importer checks on small hand-written files, bad
// inputs, and the analytic checks that fit in a few seconds; the tracers' agreement on
// each feature is in test_mitsuba_tracers.cpp. The films name the box filter: the closed
// forms are of each pixel's (or block's) plain mean (Mitsuba's default is a Gaussian).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include "kernels/bump.h"
#include "kernels/camera.h"
#include "kernels/envmap.h"
#include "kernels/textured_params.h"
#include "mitsuba_floor.h"
#include "render_stats.h"
#include "scene/scene.h"
#include "wavemmlt/error.h"
#include "wavemmlt/image.h"
#include "wavemmlt/render.h"
#include "wavemmlt/scene_desc.h"

using namespace wmlt;
using floor_test::floorUnder;

namespace {

const std::string kSensor = R"(<sensor type="perspective"><float name="fov" value="40"/>
  <transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
  <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/><rfilter type="box"/></film>
</sensor>
)";

// A scene with the sensor above, `body`, and (unless `light` is false) a rectangle light.
std::string scene(const std::string& body, bool light = true) {
    return "<scene version=\"3.0.0\">\n" + kSensor + body +
           (light ? "\n<shape type=\"rectangle\"><emitter type=\"area\"><rgb name=\"radiance\" value=\"1\"/></emitter></shape>" : "") +
           "\n</scene>\n";
}

SceneDesc load(const std::string& xml, const std::string& dir = ".") { return loadMitsubaFromString(xml, "t.xml", dir); }

std::string errorOf(const std::string& xml, const std::string& dir = ".") {
    try {
        load(xml, dir);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

// Each (body, words) pair: scene(wrap(body)) fails on the body's line (6) with the words.
void expectErrors(const std::vector<std::pair<std::string, std::string>>& cases, const std::string& dir,
                  const std::function<std::string(const std::string&)>& wrap) {
    for (const auto& [body, words] : cases) {
        const std::string e = errorOf(scene(wrap(body)), dir);
        INFO(e);
        CHECK(e.find("t.xml:6:") == 0);
        CHECK(e.find(words) != std::string::npos);
    }
}

}  // namespace

TEST_CASE("Mitsuba plugins: named conductors", "[mitsuba][import]") {
    SceneDesc d = load(scene(R"(
<shape type="cube"><bsdf type="conductor"><string name="material" value="Au"/></bsdf></shape>
<shape type="cube"><bsdf type="roughconductor"><string name="material" value="Cu"/><float name="alpha" value="0.2"/></bsdf></shape>
<shape type="cube"><bsdf type="conductor"/></shape>)"));
    const MaterialDesc& au = d.materials[d.shapes[0].material];
    CHECK(au.kind == MaterialKind::Conductor);
    CHECK(au.conductorEta.z == Approx(1.4424785571f));
    CHECK(au.conductorK.x == Approx(3.9831604247f));
    const MaterialDesc& cu = d.materials[d.shapes[1].material];
    CHECK(cu.kind == MaterialKind::RoughConductor);
    CHECK(cu.conductorEta.x == Approx(0.200438f).epsilon(1e-5));   // veach-mis' copper
    const MaterialDesc& none = d.materials[d.shapes[2].material];  // Mitsuba's default: a mirror
    CHECK(none.conductorEta.x == 0.0f);
    CHECK(none.conductorK.x == 1.0f);
    std::string e = errorOf(scene(R"(<shape type="cube"><bsdf type="conductor"><string name="material" value="Unobtainium"/></bsdf></shape>)"));
    INFO(e);
    CHECK(e.find("t.xml:6:") == 0);
    CHECK(e.find("Unobtainium") != std::string::npos);
    CHECK(e.find("Au") != std::string::npos);  // the names it knows
    e = errorOf(scene(R"(<shape type="cube"><bsdf type="conductor"><string name="material" value="Au"/><rgb name="eta" value="1"/></bsdf></shape>)"));
    CHECK(e.find("not both") != std::string::npos);
}

TEST_CASE("Mitsuba plugins: an emitter keeps its BSDF (Mitsuba's default diffuse when none)", "[mitsuba][import]") {
    SceneDesc d = load(scene(R"(
<shape type="rectangle"><bsdf type="diffuse"><rgb name="reflectance" value="0.7"/></bsdf><emitter type="area"/></shape>
<shape type="sphere"><emitter type="area"/></shape>
<shape type="rectangle"><bsdf type="diffuse"><rgb name="reflectance" value="0"/></bsdf><emitter type="area"/></shape>)",
                             false));
    REQUIRE(d.shapes.size() == 3);
    REQUIRE(d.shapes[0].material >= 0);
    CHECK(d.materials[d.shapes[0].material].diffuse.x == Approx(0.7f));
    REQUIRE(d.shapes[1].material >= 0);
    CHECK(d.materials[d.shapes[1].material].diffuse.x == Approx(0.5f));
    CHECK(!d.materials[d.shapes[1].material].twoSided);
    CHECK(d.shapes[2].material == -1);  // black: an emitter that only absorbs
    for (const ShapeDesc& s : d.shapes) CHECK(s.light >= 0);
}

namespace {

// A w x h image whose texel (x, y) (y = 0: the top row) is c(x, y).
template <class F>
Image texels(int w, int h, F c) {
    Image im(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) im.set(x, y, c(x, y));
    return im;
}

TextureDesc bitmap(const Image& im, bool nearest, TextureWrap wrap) {
    TextureDesc t;
    t.kind = TextureKind::Bitmap;
    t.image = im;
    t.nearest = nearest;
    t.wrap = wrap;
    return t;
}

}  // namespace

TEST_CASE("Mitsuba textures: bitmap lookup conventions (v = 0 the top row, filters, wrap modes, to_uv)", "[mitsuba][texture]") {
    const Image im = texels(4, 2, [](int x, int y) { return Vec3(float(x), float(y), 1.0f); });
    TextureDesc t = bitmap(im, true, TextureWrap::Repeat);
    // Nearest: texel (x, y) covers [x/4, (x+1)/4) x [y/2, (y+1)/2); v = 0 is the top row.
    CHECK(evalTexture(t, 0.1f, 0.1f, Vec3()).x == 0.0f);
    CHECK(evalTexture(t, 0.1f, 0.1f, Vec3()).y == 0.0f);
    CHECK(evalTexture(t, 0.8f, 0.9f, Vec3()).x == 3.0f);
    CHECK(evalTexture(t, 0.8f, 0.9f, Vec3()).y == 1.0f);
    CHECK(evalTexture(t, 1.1f, -0.1f, Vec3()).x == 0.0f);  // repeat
    CHECK(evalTexture(t, 1.1f, -0.1f, Vec3()).y == 1.0f);
    // Bilinear: exact at texel centres, linear between them.
    t.nearest = false;
    CHECK(evalTexture(t, 0.375f, 0.25f, Vec3()).x == Approx(1.0f));
    CHECK(evalTexture(t, 0.5f, 0.25f, Vec3()).x == Approx(1.5f));
    CHECK(evalTexture(t, 0.5f, 0.5f, Vec3()).y == Approx(0.5f));
    // Repeat wraps the last texel into the first: halfway between x = 3 and x = 0.
    CHECK(evalTexture(t, 1.0f, 0.25f, Vec3()).x == Approx(1.5f));
    // Clamp holds the edge texel; mirror reflects about u = 0 and u = 1 (Mitsuba's test03).
    t.wrap = TextureWrap::Clamp;
    CHECK(evalTexture(t, 1.0f, 0.25f, Vec3()).x == Approx(3.0f));
    CHECK(evalTexture(t, -3.0f, 0.25f, Vec3()).x == Approx(0.0f));
    t.wrap = TextureWrap::Mirror;
    for (float u : {0.05f, 0.3f, 0.61f, 0.93f}) {
        CHECK(evalTexture(t, -u, 0.3f, Vec3()).x == Approx(evalTexture(t, u, 0.3f, Vec3()).x));
        CHECK(evalTexture(t, 2.0f - u, 0.3f, Vec3()).x == Approx(evalTexture(t, u, 0.3f, Vec3()).x));
    }
    // to_uv: u' = 2 u (scale), then repeat.
    t.wrap = TextureWrap::Repeat;
    t.nearest = true;
    t.uvTransform[0] = 2;
    CHECK(evalTexture(t, 0.45f, 0.1f, Vec3()).x == 3.0f);
    CHECK(evalTexture(t, 0.55f, 0.1f, Vec3()).x == 0.0f);
    // The luminance gradient of the bilinear bitmap: red grows by 1 per texel across (4
    // texels per unit of u, times 2 from to_uv), green by 1 per row (2 rows per unit of v),
    // weighted as luminance.
    t.nearest = false;
    float du, dv;
    bitmapLuminanceGradient(t, 0.2f, 0.25f, du, dv);
    CHECK(du == Approx(0.2126f * 4 * 2).epsilon(1e-3));
    CHECK(dv == Approx(0.7152f * 2).epsilon(1e-3));
}

TEST_CASE("Mitsuba textures: checkerboard", "[mitsuba][texture]") {
    TextureDesc t;
    t.kind = TextureKind::Checkerboard;
    t.colour1 = Vec3(0.4f);
    t.colour2 = Vec3(0.2f);
    CHECK(evalTexture(t, 0.25f, 0.25f, Vec3()).x == 0.4f);
    CHECK(evalTexture(t, 0.75f, 0.25f, Vec3()).x == 0.2f);
    CHECK(evalTexture(t, 0.25f, 0.75f, Vec3()).x == 0.2f);
    CHECK(evalTexture(t, 0.75f, 0.75f, Vec3()).x == 0.4f);
    CHECK(evalTexture(t, -0.25f, 0.25f, Vec3()).x == 0.2f);
    t.uvTransform[0] = t.uvTransform[4] = 4;  // to_uv scale 4: a 4 x 4 board per unit
    CHECK(evalTexture(t, 0.2f, 0.05f, Vec3()).x == 0.2f);
}

TEST_CASE("Mitsuba textures: importer (bitmap, checkerboard, ref, to_uv) and bad inputs", "[mitsuba][import][texture]") {
    const std::string dir = rstats::tempDir("mitsuba-textures");
    writeImage(dir + "/t.pfm", texels(4, 2, [](int x, int y) { return Vec3(float(x), float(y), 0.5f); }));
    SceneDesc d = load(scene(R"(
<texture type="checkerboard" id="board"><rgb name="color0" value="0.9"/><transform name="to_uv"><scale x="8" y="4"/></transform></texture>
<shape type="rectangle"><bsdf type="diffuse"><texture type="bitmap" name="reflectance"><string name="filename" value="t.pfm"/>
  <string name="filter_type" value="nearest"/><string name="wrap_mode" value="mirror"/></texture></bsdf></shape>
<shape type="rectangle"><bsdf type="roughplastic"><ref name="diffuse_reflectance" id="board"/></bsdf></shape>
<shape type="rectangle"><bsdf type="diffuse"><ref name="reflectance" id="board"/></bsdf></shape>)"),
                       dir);
    REQUIRE(d.textures.size() == 2);
    const MaterialDesc& m0 = d.materials[d.shapes[0].material];
    REQUIRE(m0.texture[MaterialParam::Diffuse] >= 0);
    CHECK(m0.diffuse.x == 1.0f);  // the texture is the colour
    const TextureDesc& bm = d.textures[m0.texture[MaterialParam::Diffuse]];
    CHECK(bm.kind == TextureKind::Bitmap);
    CHECK(bm.nearest);
    CHECK(bm.wrap == TextureWrap::Mirror);
    CHECK(bm.image.width == 4);
    const MaterialDesc& m1 = d.materials[d.shapes[1].material];
    const MaterialDesc& m2 = d.materials[d.shapes[2].material];
    CHECK(m1.texture[MaterialParam::Diffuse] == m2.texture[MaterialParam::Diffuse]);  // one texture, referenced twice
    const TextureDesc& cb = d.textures[m1.texture[MaterialParam::Diffuse]];
    CHECK(cb.kind == TextureKind::Checkerboard);
    CHECK(cb.colour1.x == Approx(0.9f));
    CHECK(cb.colour2.x == Approx(0.2f));  // Mitsuba's default color1
    CHECK(cb.uvTransform[0] == 8.0f);
    CHECK(cb.uvTransform[4] == 4.0f);
    // Bad inputs: a missing file, an unknown filter or wrap mode, a texture where wavemmlt
    // has no textured parameter, an unknown texture type.
    expectErrors(
        {{R"(<texture type="bitmap" name="reflectance"><string name="filename" value="nope.png"/></texture>)", "nope.png"},
         {R"(<texture type="bitmap" name="reflectance"><string name="filename" value="t.pfm"/><string name="filter_type" value="cubic"/></texture>)",
          "cubic"},
         {R"(<texture type="bitmap" name="reflectance"><string name="filename" value="t.pfm"/><string name="wrap_mode" value="tile"/></texture>)",
          "tile"},
         {R"(<texture type="noise" name="reflectance"/>)", "noise"}},
        dir, [](const std::string& b) { return "<shape type=\"cube\"><bsdf type=\"diffuse\">" + b + "</bsdf></shape>"; });
    // A conductor's complex index may be a texture (Mitsuba 3's eta and k are textures).
    const SceneDesc cu =
        load(scene(R"(<shape type="cube"><bsdf type="roughconductor"><texture type="checkerboard" name="eta"/></bsdf></shape>)"), dir);
    CHECK(cu.materials[size_t(cu.shapes[0].material)].texture[MaterialParam::ConductorEta] >= 0);
    CHECK(cu.materials[size_t(cu.shapes[0].material)].conductorEta.x == 1.0f);
    std::filesystem::remove_all(dir);
}

// A bitmap (nearest, 4 x 4 texels) on a rectangle seen face-on, filling a 16 x 16 image,
// under a uniform sky, direct light only: each 4 x 4 block of pixels is one texel's
// albedo times the sky (a diffuse plane under a full hemisphere: L_o = rho L). Mitsuba's
// rectangle has uv = (x + 1, y + 1) / 2 and v = 0 is the bitmap's top row, so the image
// shows the bitmap upside down: block (i, j) from the top is texel (i, 3 - j).
TEST_CASE("Mitsuba textures: a bitmap on a rectangle, end to end (rectangle uv, v = 0 the top row)", "[mitsuba][texture][render]") {
    const std::string dir = rstats::tempDir("mitsuba-bitmap-render");
    auto albedo = [](int x, int y) { return Vec3(0.1f + 0.2f * float(x), 0.1f + 0.2f * float(y), 0.5f); };
    writeImage(dir + "/t.pfm", texels(4, 4, albedo));
    const SceneDesc d = loadMitsubaFromString(R"(<scene version="3.0.0">
  <integrator type="path"><integer name="max_depth" value="2"/></integrator>
  <sensor type="perspective"><float name="fov" value="53.130102"/>
    <transform name="to_world"><lookat origin="0, 0, 2" target="0, 0, 0" up="0, 1, 0"/></transform>
    <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/><rfilter type="box"/></film></sensor>
  <shape type="rectangle"><bsdf type="diffuse"><texture type="bitmap" name="reflectance">
    <string name="filename" value="t.pfm"/><string name="filter_type" value="nearest"/></texture></bsdf></shape>
  <emitter type="constant"><rgb name="radiance" value="2"/></emitter>
</scene>)",
                                              "bitmap.xml", dir);
    rstats::RunStats runs;
    for (int k = 0; k < 8; ++k) {
        const RenderResult r = render(d, rstats::renderOptions(TracerKind::PT, 64, 40 + uint64_t(k), 1, 2));
        std::vector<double> v;
        for (int c = 0; c < 3; ++c) {
            const std::vector<double> b = rstats::blockMeans(r.image, 4, c);
            v.insert(v.end(), b.begin(), b.end());
        }
        runs.add(v);
    }
    std::vector<double> expected;
    for (int c = 0; c < 3; ++c)
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 4; ++i) expected.push_back(2.0 * albedo(i, 3 - j)[c]);
    const rstats::ZTestResult z = rstats::zTest(runs, expected);
    INFO(z.describe());
    CHECK(z.pass);
    std::filesystem::remove_all(dir);
}

TEST_CASE("Mitsuba bumpmap: importer, and the normal of a linear height ramp", "[mitsuba][import][bump]") {
    const std::string dir = rstats::tempDir("mitsuba-bumpmap");
    // Grey ramp: luminance x / 4 in texel column x (8 columns), constant down the rows.
    writeImage(dir + "/h.pfm", texels(8, 2, [](int x, int) { return Vec3(float(x) / 4.0f); }));
    SceneDesc d = load(scene(R"(
<shape type="rectangle"><bsdf type="bumpmap"><texture type="bitmap" name="arbitrary"><string name="filename" value="h.pfm"/></texture>
  <float name="scale" value="0.5"/><bsdf type="twosided"><bsdf type="diffuse"/></bsdf></bsdf></shape>
<shape type="rectangle"><bsdf type="twosided"><bsdf type="bumpmap"><texture type="bitmap"><string name="filename" value="h.pfm"/></texture>
  <bsdf type="roughconductor"/></bsdf></bsdf></shape>)"),
                       dir);
    const MaterialDesc& m0 = d.materials[d.shapes[0].material];
    CHECK(m0.kind == MaterialKind::Matte);
    CHECK(m0.twoSided);
    CHECK(m0.bumpMitsuba);
    CHECK(m0.bumpScale == 0.5f);
    REQUIRE(m0.bump >= 0);
    CHECK(d.textures[m0.bump].kind == TextureKind::Bitmap);
    const MaterialDesc& m1 = d.materials[d.shapes[1].material];
    CHECK(m1.kind == MaterialKind::RoughConductor);
    CHECK(m1.twoSided);
    CHECK(m1.bumpScale == 1.0f);  // Mitsuba's default
    // h = 0.5 * luminance: dh/du = 0.5 * (1/4 per texel) * 8 texels per unit = 1 inside the
    // ramp; with dp/du = x, dp/dv = y and n = z: n' = (-1, 0, 1) / sqrt(2).
    const Vec3 n = bumpedNormalMitsuba(d.textures[m0.bump], 0.5f, 0.4f, 0.3f, Vec3(0, 0, 1), Vec3(0, 0, 1), Vec3(1, 0, 0), Vec3(0, 1, 0));
    CHECK(n.x == Approx(-std::sqrt(0.5f)).epsilon(1e-4));
    CHECK(n.y == Approx(0.0f).margin(1e-5));
    CHECK(n.z == Approx(std::sqrt(0.5f)).epsilon(1e-4));
    // Bad: no texture, a checkerboard (Mitsuba differentiates bitmaps only), no nested BSDF.
    expectErrors(
        {{R"(<bsdf type="bumpmap"><bsdf type="diffuse"/></bsdf>)", "exactly one nested texture"},
         {R"(<bsdf type="bumpmap"><texture type="checkerboard"/><bsdf type="diffuse"/></bsdf>)", "must be a bitmap"},
         {R"(<bsdf type="bumpmap"><texture type="bitmap"><string name="filename" value="h.pfm"/></texture></bsdf>)", "exactly one nested BSDF"}},
        dir, [](const std::string& b) { return "<shape type=\"cube\">" + b + "</shape>"; });
    std::filesystem::remove_all(dir);
}

TEST_CASE("Mitsuba mask: importer and bad inputs", "[mitsuba][import][mask]") {
    const std::string dir = rstats::tempDir("mitsuba-mask");
    writeImage(dir + "/a.pfm", texels(2, 2, [](int x, int y) { return Vec3((x + y) % 2 ? 1.0f : 0.0f); }));
    SceneDesc d = load(scene(R"(
<shape type="rectangle"><bsdf type="mask"><float name="opacity" value="0.3"/><bsdf type="diffuse"/></bsdf></shape>
<shape type="rectangle"><bsdf type="mask"><texture type="bitmap" name="opacity"><string name="filename" value="a.pfm"/></texture>
  <bsdf type="twosided"><bsdf type="diffuse"/></bsdf></bsdf></shape>
<shape type="rectangle"><bsdf type="mask"><bsdf type="diffuse"/></bsdf></shape>)"),
                       dir);
    CHECK(d.materials[d.shapes[0].material].opacity == Approx(0.3f));
    CHECK(d.materials[d.shapes[1].material].opacityTexture >= 0);
    CHECK(d.materials[d.shapes[1].material].twoSided);
    CHECK(d.materials[d.shapes[2].material].opacity == Approx(0.5f));  // Mitsuba's default
    expectErrors({{R"(<bsdf type="mask"><float name="opacity" value="1.5"/><bsdf type="diffuse"/></bsdf>)", "opacity must be in [0, 1]"},
                  {R"(<bsdf type="mask"><float name="opacity" value="0.5"/></bsdf>)", "exactly one nested BSDF"},
                  {R"(<bsdf type="mask"><bsdf type="diffuse"/></bsdf><emitter type="area"/>)", "emitting"}},
                 dir, [](const std::string& b) { return "<shape type=\"rectangle\">" + b + "</shape>"; });
    std::filesystem::remove_all(dir);
}

// A diffuse plate of opacity 0.3 (and one whose opacity is a 2 x 2 checker of 0 and 1)
// filling the view, under a uniform sky L, direct light only: a pixel is the sky with
// probability 1 - alpha and the plate (rho L) with alpha, so (1 - alpha) L + alpha rho L.
TEST_CASE("Mitsuba mask: a partly transparent plate under a sky, end to end", "[mitsuba][mask][render]") {
    const std::string dir = rstats::tempDir("mitsuba-mask-render");
    writeImage(dir + "/a.pfm", texels(2, 2, [](int x, int y) { return Vec3((x + y) % 2 ? 1.0f : 0.0f); }));
    for (const std::string opacity :
         {R"(<float name="opacity" value="0.3"/>)",
          R"(<texture type="bitmap" name="opacity"><string name="filename" value="a.pfm"/><string name="filter_type" value="nearest"/></texture>)"}) {
        const SceneDesc d = loadMitsubaFromString(R"(<scene version="3.0.0">
  <integrator type="path"><integer name="max_depth" value="2"/></integrator>
  <sensor type="perspective"><float name="fov" value="53.130102"/>
    <transform name="to_world"><lookat origin="0, 0, 2" target="0, 0, 0" up="0, 1, 0"/></transform>
    <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/><rfilter type="box"/></film></sensor>
  <shape type="rectangle"><bsdf type="mask">)" + opacity +
                                                      R"(<bsdf type="diffuse"><rgb name="reflectance" value="0.6"/></bsdf></bsdf></shape>
  <emitter type="constant"><rgb name="radiance" value="2"/></emitter>
</scene>)",
                                                  "mask.xml", dir);
        REQUIRE(Scene::build(d)->features.masks);
        rstats::RunStats runs;
        for (int k = 0; k < 8; ++k) {
            const RenderResult r = render(d, rstats::renderOptions(TracerKind::PT, 64, 60 + uint64_t(k), 1, 2));
            runs.add(rstats::blockMeans(r.image, 4, 1));
        }
        // The checker: texel (x, y) opaque where x + y is odd; the image shows the bitmap
        // upside down (block (i, j) from the top is texel (i, 1 - j)).
        std::vector<double> expected;
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 2; ++i) {
                const double alpha = opacity.find("0.3") != std::string::npos ? 0.3 : (i + (1 - j)) % 2 ? 1.0 : 0.0;
                expected.push_back((1 - alpha) * 2.0 + alpha * 0.6 * 2.0);
            }
        const rstats::ZTestResult z = rstats::zTest(runs, expected);
        INFO(opacity << ": " << z.describe());
        CHECK(z.pass);
    }
    std::filesystem::remove_all(dir);
}

namespace {

// Mitsuba's direction for envmap coordinates (u, v) (its uv_to_direction).
Vec3 mitsubaEnvDirection(double u, double v) {
    const double theta = v * M_PI, phi = u * 2 * M_PI;
    return Vec3(float(std::sin(phi) * std::sin(theta)), float(std::cos(theta)), float(-std::cos(phi) * std::sin(theta)));
}

}  // namespace

// The envmap's orientation, rotation and scale against Mitsuba's formulas: texel (i, j)
// of a W x H map has its centre at u = (i + 1/2) / W, v = j / (H - 1) in Mitsuba's
// direction mapping. Texel values are linear in i and j (Mitsuba's bilinear lookup
// reproduces them exactly between centres); wavemmlt's resampled nearest-pixel map is
// within 1 / 8 texel of it (4 times the resolution): +-0.15 here, and the wrong
// orientation (a turn, a mirror, a flip) would be off by whole units.
TEST_CASE("Mitsuba envmap: orientation, to_world, scale, bad inputs", "[mitsuba][import][envmap]") {
    const std::string dir = rstats::tempDir("mitsuba-envmap");
    const int W = 8, H = 5;
    writeImage(dir + "/env.pfm", texels(W, H, [](int x, int y) { return Vec3(1.0f + float(x), 1.0f + float(y), 1.0f); }));
    auto env = [&](const std::string& params) {
        SceneDesc d = load(scene("<emitter type=\"envmap\"><string name=\"filename\" value=\"env.pfm\"/>" + params + "</emitter>", false), dir);
        CHECK(d.envMap.width == 4 * W);
        EnvMapSampler s;
        s.build(d.envMap);
        return s;
    };
    const EnvMapSampler plain = env("");
    const EnvMapSampler turned = env(R"(<transform name="to_world"><rotate y="1" angle="90"/></transform><float name="scale" value="3"/>)");
    for (int j = 1; j < H - 1; ++j)        // (rows 0 and H - 1 sit on the poles, where u is moot)
        for (int i = 0; i < W - 1; ++i) {  // (the last column's right half blends into the first)
            const Vec3 d = mitsubaEnvDirection((i + 0.5) / W, double(j) / (H - 1));
            INFO("texel " << i << ", " << j);
            CHECK(plain.Le(d).x == Approx(1.0f + float(i)).margin(0.15));
            CHECK(plain.Le(d).y == Approx(1.0f + float(j)).margin(0.15));
            // to_world turns the map (R_y(90) (x, y, z) = (z, y, -x)) and scale multiplies it.
            const Vec3 t(d.z, d.y, -d.x);
            CHECK(turned.Le(t).x == Approx(3.0f * (1.0f + float(i))).margin(0.45));
            CHECK(turned.Le(t).y == Approx(3.0f * (1.0f + float(j))).margin(0.45));
        }
    expectErrors(
        {{R"(<emitter type="envmap"><string name="filename" value="nope.exr"/></emitter>)", "nope.exr"},
         {R"(<emitter type="envmap"/>)", "filename"},
         {R"(<emitter type="envmap"><string name="filename" value="env.pfm"/><transform name="to_world"><scale value="2"/></transform></emitter>)",
          "rotation"},
         {R"(<emitter type="envmap"><string name="filename" value="env.pfm"/></emitter><emitter type="constant"/>)", "second environment"}},
        dir, [](const std::string& b) { return b; });
    std::filesystem::remove_all(dir);
}

// A uniform envmap times scale is a constant sky: a diffuse plate under it, direct light
// only, is rho * scale * L in every pixel, as under Mitsuba's constant emitter.
TEST_CASE("Mitsuba envmap: a uniform map with scale renders as the constant sky", "[mitsuba][envmap][render]") {
    const std::string dir = rstats::tempDir("mitsuba-envmap-render");
    writeImage(dir + "/env.pfm", texels(16, 8, [](int, int) { return Vec3(0.5f); }));
    const SceneDesc d = loadMitsubaFromString(R"(<scene version="3.0.0">
  <integrator type="path"><integer name="max_depth" value="2"/></integrator>
  <sensor type="perspective"><float name="fov" value="40"/>
    <transform name="to_world"><lookat origin="0, 0, 2" target="0, 0, 0" up="0, 1, 0"/></transform>
    <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/><rfilter type="box"/></film></sensor>
  <shape type="rectangle"><bsdf type="diffuse"><rgb name="reflectance" value="0.6"/></bsdf></shape>
  <emitter type="envmap"><string name="filename" value="env.pfm"/><float name="scale" value="4"/>
    <transform name="to_world"><rotate x="1" angle="30"/></transform></emitter>
</scene>)",
                                              "env.xml", dir);
    rstats::RunStats runs;
    for (int k = 0; k < 8; ++k)
        runs.add(rstats::blockMeans(render(d, rstats::renderOptions(TracerKind::PT, 16, 80 + uint64_t(k), 1, 2)).image, 4, 1));
    const rstats::ZTestResult z = rstats::zTest(runs, std::vector<double>(4, 0.6 * 4 * 0.5));
    INFO(z.describe());
    CHECK(z.pass);
    std::filesystem::remove_all(dir);
}

namespace {

void writeFile(const std::string& path, const std::string& bytes) {
    std::ofstream f(path, std::ios::binary);
    f << bytes;
}

// A unit quad (one 4-gon face) with normals, uv, colours (read past), and an extra element.
std::string plyHeader(const std::string& format, const std::string& faceCount = "1") {
    return "ply\nformat " + format +
           " 1.0\ncomment a quad\nelement vertex 4\nproperty float x\nproperty float y\n"
           "property float z\nproperty float nx\nproperty float ny\nproperty float nz\nproperty float u\nproperty float v\n"
           "property uchar red\nelement face " +
           faceCount +
           "\nproperty list uchar int vertex_indices\nproperty uchar flags\n"
           "element edge 1\nproperty int a\nproperty int b\nend_header\n";
}
const float kQuad[4][8] = {{0, 0, 0, 0, 0, 1, 0, 0}, {1, 0, 0, 0, 0, 1, 1, 0}, {1, 1, 0, 0, 0, 1, 1, 1}, {0, 1, 0, 0, 0, 1, 0, 1}};

template <class T>
void put(std::string& s, T v, bool big) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    if (big) std::reverse(b, b + sizeof(T));
    s.append(b, sizeof(T));
}

std::string binaryQuad(bool big) {
    std::string s = plyHeader(big ? "binary_big_endian" : "binary_little_endian");
    for (const auto& v : kQuad) {
        for (float x : v) put(s, x, big);
        put(s, uint8_t(200), big);
    }
    put(s, uint8_t(4), big);
    for (int32_t i : {0, 1, 2, 3}) put(s, i, big);
    put(s, uint8_t(0), big);
    put(s, int32_t(0), big);
    put(s, int32_t(1), big);
    return s;
}

}  // namespace

TEST_CASE("Mitsuba ply: ASCII, binary little and big endian, the same mesh", "[mitsuba][import][ply]") {
    const std::string dir = rstats::tempDir("mitsuba-ply");
    std::string ascii = plyHeader("ascii");
    for (const auto& v : kQuad) {
        for (float x : v) ascii += std::to_string(x) + " ";
        ascii += "200\n";
    }
    ascii += "4 0 1 2 3 0\n0 1\n";
    writeFile(dir + "/a.ply", ascii);
    writeFile(dir + "/le.ply", binaryQuad(false));
    writeFile(dir + "/be.ply", binaryQuad(true));
    for (const char* f : {"a.ply", "le.ply", "be.ply"}) {
        INFO(f);
        const TriangleMesh m = loadPly(dir + "/" + f, true);
        REQUIRE(m.positions.size() == 4);
        REQUIRE(m.indices.size() == 6);  // the 4-gon as a fan of two triangles
        CHECK(m.indices[3] == 0);
        CHECK(m.indices[5] == 3);
        CHECK(m.positions[2].x == 1.0f);
        CHECK(m.positions[2].y == 1.0f);
        REQUIRE(m.uvs.size() == 8);
        CHECK(m.uvs[5] == 1.0f);  // vertex 2's v, as stored
        REQUIRE(m.normals.size() == 4);
        CHECK(m.normals[1].z == 1.0f);
        CHECK(loadPly(dir + "/" + f, false).normals.empty());  // flat: none
    }
    // The importer: a ply shape with to_world (and Mitsuba's face_normals).
    SceneDesc d = load(scene(R"(<shape type="ply"><string name="filename" value="be.ply"/><boolean name="face_normals" value="true"/>
      <transform name="to_world"><translate x="5"/></transform></shape>)"),
                       dir);
    CHECK(d.shapes[0].mesh.positions[0].x == 5.0f);
    CHECK(d.shapes[0].mesh.normals.empty());
    std::filesystem::remove_all(dir);
}

TEST_CASE("Mitsuba ply: bad files name the line (header, ASCII) or the byte (binary)", "[mitsuba][ply][bad-input]") {
    const std::string dir = rstats::tempDir("mitsuba-ply-bad");
    auto errorIn = [&](const std::string& bytes) {
        writeFile(dir + "/x.ply", bytes);
        try {
            loadPly(dir + "/x.ply", true);
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    const std::string p = dir + "/x.ply";
    const std::string tri =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    CHECK(errorIn(tri + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").empty());  // the good one
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"plx\n", p + ":1: not a PLY file"},
        {"ply\nformat ascii 2.0\nend_header\n", p + ":2: PLY version"},
        {"ply\nformat ebcdic 1.0\nend_header\n", p + ":2: unknown format"},
        {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n", p + ":5: the header has no end_header"},
        {"ply\nformat ascii 1.0\nelement vertex 3\nproperty quaternion x\nend_header\n", p + ":4: unknown type"},
        {"ply\nformat ascii 1.0\nwhatever\nend_header\n", p + ":3: unknown header line"},
        {tri + "0 0 0\n1 0x 0\n0 1 0\n3 0 1 2\n", p + ":11: \"0x\" is not a finite number"},
        {tri + "0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n", p + ":13: vertex index 7 is out of range"},
        {tri + "0 0 0\n1 0 0\n0 1 0\n2 0 1\n", p + ":13: a face with 2 vertices"},
        {tri + "0 0 0\n1 0 0\n0 1 0\n3 0 1\n", p + ":13: the data ends early"},
        {tri + "0 0 0\n1 0 0\n", p + ":3: element vertex declares 3 items, more than the file holds"},
        {"ply\nformat binary_little_endian 1.0\nelement vertex 1000000000\nproperty float x\nproperty float y\nproperty float z\nend_header\n",
         p + ":3: element vertex declares 1000000000 items, more than the file holds"},
        {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n0 0\n",
         p + ":3: the vertex element needs properties x, y and z"},
        {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0 1 0 0 0 1 0\n",
         p + ": no faces"},
    };
    for (const auto& [bytes, want] : cases) {
        const std::string e = errorIn(bytes);
        INFO(e);
        CHECK(e.find(want) == 0);
    }
    // Binary: truncated data names the byte offset where it runs out: the vertices, the
    // face's count and two of its four indices.
    std::string le = binaryQuad(false);
    const size_t header = plyHeader("binary_little_endian").size();
    le.resize(header + 4 * (8 * 4 + 1) + 1 + 2 * 4 + 2);
    const std::string e = errorIn(le);
    INFO(e);
    CHECK(e.find(p + ": byte " + std::to_string(header + 4 * 33 + 1 + 2 * 4)) == 0);
    CHECK(e.find("ends early") != std::string::npos);
    // The importer names the scene file's line and the PLY's own message.
    writeFile(dir + "/y.ply", "ply\nformat ascii 1.0\nbogus\nend_header\n");
    const std::string ie = errorOf(scene(R"(<shape type="ply"><string name="filename" value="y.ply"/></shape>)"), dir);
    CHECK(ie.find("t.xml:6:") == 0);
    CHECK(ie.find("y.ply:3: unknown header line") != std::string::npos);
    std::filesystem::remove_all(dir);
}

// A point light of intensity I at height h: E = I cos(theta) / r^2 = I h / r^3.
TEST_CASE("Mitsuba point light: the floor's irradiance I cos / r^2, in PT, LT and BPT", "[mitsuba][render][point]") {
    const Vec3 c(0.7f, 1.5f, -0.4f);
    floorUnder(R"(<emitter type="point"><point name="position" x="0.7" y="1.5" z="-0.4"/><rgb name="intensity" value="3"/></emitter>)",
               [&](Vec3 p) {
                   const Vec3 d = c - p;
                   const double r = length(d);
                   return 3.0 * double(c.y) / (r * r * r);
               },
               "point");
    // The same light given by to_world, and the importer's checks.
    SceneDesc d = load(scene(R"(<emitter type="point"><transform name="to_world"><translate x="1" y="2" z="3"/></transform></emitter>)", false));
    REQUIRE(d.lights.size() == 1);
    CHECK(d.lights[0].kind == LightKind::Point);
    CHECK(d.lights[0].position.z == 3.0f);
    CHECK(d.lights[0].radiance.x == 1.0f);  // Mitsuba's default intensity
    CHECK(errorOf(scene(R"(<emitter type="point"><point name="position" x="0" y="0" z="0"/><transform name="to_world"/></emitter>)"))
              .find("not both") != std::string::npos);
    CHECK(errorOf(scene(R"(<shape type="sphere"><emitter type="point"/></shape>)")).find("cannot be attached") != std::string::npos);
}

// A spot of intensity I at c shining along the unit axis a (Mitsuba's falloff: 1 within the
// beam width, linear in the angle to 0 at the cutoff): E = I falloff(theta) h / r^3.
TEST_CASE("Mitsuba spot light: the floor's irradiance I falloff cos / r^2, in PT, LT and BPT", "[mitsuba][render][point]") {
    const Vec3 c(0.3f, 1.5f, -0.2f);
    const Vec3 a = normalize(Vec3(0.2f, -1.0f, 0.1f));
    const double cutoff = 35 * M_PI / 180, beam = 20 * M_PI / 180;
    floorUnder(R"(<emitter type="spot"><rgb name="intensity" value="3"/><float name="cutoff_angle" value="35"/>
      <float name="beam_width" value="20"/><transform name="to_world"><lookat origin="0.3, 1.5, -0.2" target="0.5, 0.5, -0.1" up="0, 0, 1"/></transform></emitter>)",
               [&](Vec3 p) {
                   const Vec3 d = p - c;
                   const double r = length(d), theta = std::acos(std::clamp(double(dot(d, a)) / r, -1.0, 1.0));
                   const double f = theta >= cutoff ? 0.0 : theta <= beam ? 1.0 : (cutoff - theta) / (cutoff - beam);
                   return 3.0 * f * double(c.y) / (r * r * r);
               },
               "spot");
    // The importer: the axis and angles, Mitsuba's defaults (20 degrees, beam 3/4 of it), bad values.
    SceneDesc d = load(scene(R"(<emitter type="spot"><transform name="to_world"><translate x="1" y="2" z="3"/></transform></emitter>)", false));
    REQUIRE(d.lights.size() == 1);
    CHECK(d.lights[0].kind == LightKind::Point);
    CHECK(d.lights[0].position.y == 2.0f);
    CHECK(d.lights[0].spotAxis.z == 1.0f);
    CHECK(d.lights[0].spotCutoff == Approx(20 * M_PI / 180));
    CHECK(d.lights[0].spotBeam == Approx(15 * M_PI / 180));
    CHECK(errorOf(scene(R"(<emitter type="spot"><float name="cutoff_angle" value="10"/><float name="beam_width" value="12"/></emitter>)"))
              .find("beam_width must be in [0, cutoff_angle]") != std::string::npos);
    CHECK(errorOf(scene(R"(<emitter type="spot"><float name="cutoff_angle" value="0"/></emitter>)")).find("cutoff_angle must be") !=
          std::string::npos);
    CHECK(errorOf(scene(R"(<emitter type="spot"><texture type="bitmap" name="texture"><string name="filename" value="x.png"/></texture></emitter>)"))
              .find("texture") != std::string::npos);
}

// A directional light of irradiance E travelling along the unit d: E_floor = E (-d.y).
TEST_CASE("Mitsuba directional light: the floor's irradiance E cos, in PT, LT and BPT", "[mitsuba][render][point]") {
    const Vec3 d = normalize(Vec3(0.3f, -1.0f, 0.5f));
    floorUnder(R"(<emitter type="directional"><vector name="direction" x="0.3" y="-1" z="0.5"/><rgb name="irradiance" value="2.5"/></emitter>)",
               [&](Vec3) { return 2.5 * double(-d.y); }, "directional", {TracerKind::PT});
    // The importer: direction or to_world (+z), Mitsuba's default irradiance 1, bad values.
    SceneDesc s = load(scene(R"(<emitter type="directional"><transform name="to_world"><rotate x="1" angle="90"/></transform></emitter>)", false));
    REQUIRE(s.lights.size() == 1);
    CHECK(s.lights[0].kind == LightKind::Directional);
    CHECK(s.lights[0].direction.y == Approx(-1.0f));
    CHECK(s.lights[0].radiance.x == 1.0f);
    CHECK(errorOf(scene(R"(<emitter type="directional"><vector name="direction" x="0" y="0" z="0"/></emitter>)")).find("nonzero") !=
          std::string::npos);
    CHECK(errorOf(scene(R"(<emitter type="directional"><vector name="direction" x="0" y="0" z="1"/><transform name="to_world"/></emitter>)"))
              .find("not both") != std::string::npos);
}

// A disk emitter (Mitsuba's disk: a 512-gon here, a triangle mesh light) of radius R and
// radiance L facing down at height h: a parallel receiver at lateral distance q gets
// E = (pi L / 2) (1 - (h^2 + q^2 - R^2) / sqrt((h^2 + q^2 + R^2)^2 - 4 R^2 q^2)).
// (The polygon's area is the disk's to 2.5e-5.)
TEST_CASE("Mitsuba area light on a mesh (a disk): the floor's irradiance, in PT, LT and BPT", "[mitsuba][render][meshlight]") {
    const double R = 0.8, h = 1.2, L = 2.0;
    floorUnder(R"(<shape type="disk"><transform name="to_world"><scale value="0.8"/><rotate x="1" angle="90"/><translate x="0.3" y="1.2"/></transform>
    <bsdf type="diffuse"><rgb name="reflectance" value="0"/></bsdf><emitter type="area"><rgb name="radiance" value="2"/></emitter></shape>)",
               [&](Vec3 p) {
                   const double q2 = (p.x - 0.3) * (p.x - 0.3) + double(p.z) * p.z;
                   const double a = h * h + q2 + R * R;
                   return M_PI * L / 2 * (1 - (h * h + q2 - R * R) / std::sqrt(a * a - 4 * R * R * q2));
               },
               "disk");
}

// A textured area emitter (LightDesc::texture, scene/mesh_light.h): a 1.2 x 1.2 rectangle
// facing down at height h = 1.2 over (0.3, 0), its radiance a checkerboard: L0 = 3 on the
// squares where (x > 0.3) == (z > 0) (u, v > 1/2 or both not), L1 = 0.5 on the others. Each
// square is a uniform parallel rectangle (floor_test::rectangleIrradiance). The same with
// both colours 3 (a constant texture) is the constant emitter's closed form.
TEST_CASE("Mitsuba area light with a textured radiance: the floor's irradiance, in PT, LT and BPT", "[mitsuba][render][meshlight][texture]") {
    auto rect = [&](Vec3 p, double x1, double x2, double z1, double z2) { return floor_test::rectangleIrradiance(p, 1.2, x1, x2, z1, z2); };
    for (double L1 : {0.5, 3.0}) {
        const std::string emitter =
            R"(<shape type="rectangle"><transform name="to_world"><scale value="0.6"/><rotate x="1" angle="90"/><translate x="0.3" y="1.2"/></transform>
    <bsdf type="diffuse"><rgb name="reflectance" value="0"/></bsdf><emitter type="area"><texture type="checkerboard" name="radiance">
    <rgb name="color0" value="3"/><rgb name="color1" value=")" +
            std::to_string(L1) + R"("/></texture></emitter></shape>)";
        floorUnder(
            emitter,
            [&](Vec3 p) {
                return 3.0 * (rect(p, 0.3, 0.9, 0, 0.6) + rect(p, -0.3, 0.3, -0.6, 0)) +
                       L1 * (rect(p, -0.3, 0.3, 0, 0.6) + rect(p, 0.3, 0.9, -0.6, 0));
            },
            L1 == 3.0 ? "constant-texture" : "checkerboard-emitter");
    }
    // The importer: a mesh light holding the texture, L = 1; bad inputs.
    SceneDesc d =
        load(scene(R"(<shape type="rectangle"><emitter type="area"><texture type="checkerboard" name="radiance"/></emitter></shape>)", false));
    REQUIRE(d.lights.size() == 1);
    CHECK(d.lights[0].kind == LightKind::Mesh);
    CHECK(d.lights[0].texture == 0);
    CHECK(d.lights[0].radiance.x == 1.0f);
    CHECK(errorOf(scene(R"(<shape type="sphere"><emitter type="area"><texture type="checkerboard" name="radiance"/></emitter></shape>)", false))
              .find("not supported") != std::string::npos);
    CHECK(
        errorOf(
            scene(
                R"(<shape type="rectangle"><emitter type="area"><texture type="bitmap" name="radiance"><string name="filename" value="missing.png"/></texture></emitter></shape>)",
                false))
            .find("missing.png") != std::string::npos);
    const std::string dir = rstats::tempDir("textured-emitter-no-uv");  // an OBJ without vt
    std::ofstream(dir + "/tri.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    const std::string e = errorOf(scene(R"(<shape type="obj"><string name="filename" value="tri.obj"/>
      <emitter type="area"><texture type="checkerboard" name="radiance"/></emitter></shape>)",
                                        false),
                                  dir);
    INFO(e);
    CHECK(e.find("t.xml:7:") == 0);
    CHECK(e.find("(u, v)") != std::string::npos);
    std::filesystem::remove_all(dir);
}

namespace {

// The scene of the test below seen through `sensor` (its opening tag and to_world), the
// blocks checked: PT's exactly, LT's, BPT's and MMLT's by z-tests over 8 seeds from seed0.
void checkerboardEmitterFillingFilm(const std::string& sensor, const std::string& name, uint64_t seed0, bool ortho) {
    const SceneDesc d = loadMitsubaFromString(R"(<scene version="3.0.0">
  <integrator type="path"><integer name="max_depth" value="1"/></integrator>
  )" + sensor + R"(
    <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/><rfilter type="box"/></film></sensor>
  <shape type="rectangle"><emitter type="area"><texture type="checkerboard" name="radiance">
    <rgb name="color0" value="3"/><rgb name="color1" value="0.5"/></texture></emitter></shape>
</scene>)",
                                              name, ".");
    REQUIRE(d.camera.orthographic == ortho);
    const std::vector<double> expected = {0.5, 3.0, 3.0, 0.5};  // blocks (0, 0), (1, 0), (0, 1), (1, 1)
    const std::vector<double> pt = rstats::blockMeans(render(d, rstats::renderOptions(TracerKind::PT, 4, 1, 1, 1)).image, 8, 1);
    for (size_t i = 0; i < 4; ++i) CHECK(pt[i] == Approx(expected[i]).epsilon(1e-5));
    for (TracerKind t : {TracerKind::LT, TracerKind::BPT, TracerKind::MMLT}) {
        rstats::RunStats runs;
        for (int k = 0; k < 8; ++k) {
            RenderOptions o = rstats::renderOptions(t, 16, seed0 + uint64_t(k), 1, 1);
            if (t == TracerKind::MMLT) {
                o.chains = 256;
                o.bootstrap = 1 << 12;
            }
            runs.add(rstats::blockMeans(render(d, o).image, 8, 1));
        }
        const rstats::ZTestResult z = rstats::zTest(runs, expected);
        INFO(name << ", tracer " << int(t) << ": " << z.describe());
        CHECK(z.pass);
    }
}

}  // namespace

// A textured emitter seen directly, filling the 16 x 16 film (the rectangle [-1, 1]^2 at
// z = 0 seen from (0, 0, 2), fov 2 atan(1/2)): its radiance a checkerboard whose 2 x 2
// squares are the image's 8 x 8 pixel blocks: 3 where (u > 1/2) == (v > 1/2), 0.5
// elsewhere (v = 1/2 at the image's middle row, the top half v > 1/2). PT sees each
// block's value exactly; LT only by light tracing (s = 1, t = 1); BPT and MMLT weigh that
// with the camera's hits (s = 0), each reading T where its strategy finds the point.
TEST_CASE("Mitsuba area light with a textured radiance: seen directly, in every tracer", "[mitsuba][render][meshlight][texture]") {
    checkerboardEmitterFillingFilm(R"(<sensor type="perspective"><float name="fov" value="53.130102"/>
    <transform name="to_world"><lookat origin="0, 0, 2" target="0, 0, 0" up="0, 1, 0"/></transform>)",
                                   "seen.xml", 70, false);
}

// blendbsdf: (1 - w) f_0 + w f_1. Two diffuse parts, 0.3 and 0.8 with w = 0.6, are a
// diffuse 0.6: the floor under a point light has the point light's closed form, with w a
// constant and with w a texture (a checkerboard of 0.6 and 0.6), in PT, LT and BPT.
TEST_CASE("Mitsuba blendbsdf: two diffuse parts are their weighted mean, in PT, LT and BPT", "[mitsuba][render][blend]") {
    const Vec3 c(0.2f, 1.3f, -0.1f);
    auto E = [&](Vec3 p) {
        const Vec3 d = c - p;
        const double r = length(d);
        return 2.0 * double(c.y) / (r * r * r);
    };
    const std::string light = R"(<emitter type="point"><point name="position" x="0.2" y="1.3" z="-0.1"/><rgb name="intensity" value="2"/></emitter>)";
    const std::string parts =
        R"(<bsdf type="diffuse"><rgb name="reflectance" value="0.3"/></bsdf><bsdf type="diffuse"><rgb name="reflectance" value="0.8"/></bsdf>)";
    floorUnder(light, E, "blend", {}, R"(<bsdf type="blendbsdf"><float name="weight" value="0.6"/>)" + parts + "</bsdf>");
    floorUnder(
        light, E, "blend-textured", {},
        R"(<bsdf type="blendbsdf"><texture type="checkerboard" name="weight"><rgb name="color0" value="0.6"/><rgb name="color1" value="0.6"/></texture>)" +
            parts + "</bsdf>");
    // The importer: the parts, the weight, twosided over a blend; bad inputs.
    SceneDesc d = load(scene(R"(<shape type="cube"><bsdf type="twosided"><bsdf type="blendbsdf"><float name="weight" value="0.25"/>
      <bsdf type="roughconductor"/><bsdf type="diffuse"/></bsdf></bsdf></shape>)"));
    const MaterialDesc& m = d.materials[size_t(d.shapes[0].material)];
    CHECK(m.kind == MaterialKind::Blend);
    CHECK(m.twoSided);
    CHECK(m.blendWeight == 0.25f);
    CHECK(d.materials[size_t(m.blendPart[0])].kind == MaterialKind::RoughConductor);
    CHECK(d.materials[size_t(m.blendPart[1])].kind == MaterialKind::Matte);
    expectErrors(
        {{R"(<shape type="cube"><bsdf type="blendbsdf"><bsdf type="diffuse"/></bsdf></shape>)", "exactly two"},
         {R"(<shape type="cube"><bsdf type="blendbsdf"><float name="weight" value="1.5"/><bsdf type="diffuse"/><bsdf type="diffuse"/></bsdf></shape>)",
          "weight must be in [0, 1]"},
         {R"(<shape type="cube"><bsdf type="blendbsdf"><bsdf type="blendbsdf"><bsdf type="diffuse"/><bsdf type="diffuse"/></bsdf><bsdf type="diffuse"/></bsdf></shape>)",
          "inside a blendbsdf"},
         {R"(<shape type="cube"><bsdf type="blendbsdf"><bsdf type="bumpmap"><texture type="bitmap" name="map"><string name="filename" value="none.png"/></texture><bsdf type="diffuse"/></bsdf><bsdf type="diffuse"/></bsdf></shape>)",
          "none.png"},
         {R"(<shape type="cube"><bsdf type="blendbsdf"><bsdf type="twosided"><bsdf type="diffuse"/></bsdf><bsdf type="diffuse"/></bsdf></shape>)",
          "twosided and a one-sided"}},
        ".", [](const std::string& b) { return b; });
}

// blendbsdf with textured parts: each part's textures applied at the hit (the blend keeps
// the hit's (u, v) and point for them; BPT's vertices carry them between rounds). A floor of
// half a checkerboard diffuse (0.2 / 1.0 in the quadrants of the floor's (u, v) square:
// color0 where u > 1/2 is v > 1/2, i.e. x > 0 is z < 0) and half a constant 0.6 has
// reflectance (c(p) + 0.6) / 2 under the point light, in PT, LT and BPT; and with a
// constant-valued texture on a part it is the constant blend.
TEST_CASE("Mitsuba blendbsdf: textured parts, in PT, LT and BPT", "[mitsuba][render][blend]") {
    const Vec3 c(0.2f, 1.3f, -0.1f);
    auto E = [&](Vec3 p) {
        const Vec3 d = c - p;
        const double r = length(d);
        return 2.0 * double(c.y) / (r * r * r);
    };
    const std::string light = R"(<emitter type="point"><point name="position" x="0.2" y="1.3" z="-0.1"/><rgb name="intensity" value="2"/></emitter>)";
    floorUnder(
        light, E, "blend-textured-part-constant", {},
        R"(<bsdf type="blendbsdf"><float name="weight" value="0.6"/><bsdf type="diffuse"><texture type="checkerboard" name="reflectance"><rgb name="color0" value="0.3"/><rgb name="color1" value="0.3"/></texture></bsdf>
               <bsdf type="diffuse"><rgb name="reflectance" value="0.8"/></bsdf></bsdf>)");
    floor_test::floorRadiance(
        light, [&](Vec3 p, Vec3) { return (((p.x > 0) == (p.z < 0) ? 0.2 : 1.0) + 0.6) / 2 / M_PI * E(p); }, "blend-textured-part", {},
        R"(<bsdf type="blendbsdf"><float name="weight" value="0.5"/><bsdf type="diffuse"><texture type="checkerboard" name="reflectance"><rgb name="color0" value="0.2"/><rgb name="color1" value="1.0"/></texture></bsdf>
               <bsdf type="diffuse"><rgb name="reflectance" value="0.6"/></bsdf></bsdf>)");
}

// The kernel: a blend of a textured rough conductor and a textured principled is, at each
// point, the weighted mean of the two parts made with their textures there (f, pdf, and the
// sample's f and pdf), and a blend of constant parts reads no texture.
TEST_CASE("blendbsdf kernel: textured parts at the hit's point", "[mitsuba][blend]") {
    const SceneDesc d = load(scene(R"(<shape type="cube"><bsdf type="blendbsdf"><float name="weight" value="0.3"/>
      <bsdf type="roughconductor"><string name="distribution" value="ggx"/><float name="alpha_u" value="0.2"/><float name="alpha_v" value="0.2"/>
        <texture type="checkerboard" name="specular_reflectance"><rgb name="color0" value="0.9, 0.5, 0.2"/><rgb name="color1" value="0.1, 0.3, 0.7"/></texture></bsdf>
      <bsdf type="principled"><texture type="checkerboard" name="base_color"><rgb name="color0" value="0.8"/><rgb name="color1" value="0.2, 0.4, 0.1"/></texture>
        <texture type="checkerboard" name="metallic"><rgb name="color0" value="0.1"/><rgb name="color1" value="0.9"/></texture></bsdf></bsdf></shape>
    <shape type="sphere"><bsdf type="blendbsdf"><bsdf type="diffuse"/><bsdf type="conductor"/></bsdf></shape>)"));
    const auto s = Scene::build(d, 1);
    const int blend = d.shapes[0].material;
    REQUIRE(s->texturedMaterial[size_t(blend)] == 1);
    CHECK(s->texturedMaterial[size_t(d.shapes[1].material)] == 0);
    CHECK(s->materials[size_t(d.shapes[1].material)].x->blendTextures == nullptr);
    const MaterialDesc& m = d.materials[size_t(blend)];
    const Vec3 wo = normalize(Vec3(0.3f, -0.2f, 0.9f)), wi = normalize(Vec3(-0.4f, 0.1f, 0.8f));
    for (const auto& [u, v] : std::vector<std::pair<float, float>>{{0.2f, 0.3f}, {0.7f, 0.3f}, {0.7f, 0.9f}}) {
        BsdfParams b = s->materials[size_t(blend)];
        setBlendPoint(b, u, v, Vec3(0.0f), Vec3(0, 0, 1));
        BsdfParams part[2];
        for (int k = 0; k < 2; ++k) {
            part[k] = s->materials[size_t(m.blendPart[k])];
            texturedParams(d.textures, d.materials[size_t(m.blendPart[k])], u, v, Vec3(0.0f), Vec3(0, 0, 1), part[k]);
        }
        INFO("u " << u << " v " << v);
        const Vec3 f = blendF(b, wo, wi), want = bsdfF(part[0], wo, wi) * 0.7f + bsdfF(part[1], wo, wi) * 0.3f;
        CHECK(f.x == Approx(want.x).epsilon(1e-6));
        CHECK(f.z == Approx(want.z).epsilon(1e-6));
        CHECK(blendPdf(b, wo, wi) == Approx(bsdfPdf(part[0], wo, wi) * 0.7f + bsdfPdf(part[1], wo, wi) * 0.3f).epsilon(1e-6));
        BsdfSample smp;
        REQUIRE(blendSample(b, wo, 0.5f, 0.3f, 0.6f, TransportMode::Radiance, smp));
        const Vec3 fs = bsdfF(part[0], wo, smp.wi) * 0.7f + bsdfF(part[1], wo, smp.wi) * 0.3f;
        CHECK(smp.f.y == Approx(fs.y).epsilon(1e-6));
        CHECK(smp.pdf == Approx(bsdfPdf(part[0], wo, smp.wi) * 0.7f + bsdfPdf(part[1], wo, smp.wi) * 0.3f).epsilon(1e-6));
    }
    // The two corners differ: the textures are read at the point.
    BsdfParams a = s->materials[size_t(blend)], b = a;
    setBlendPoint(a, 0.2f, 0.3f, Vec3(0.0f), Vec3(0, 0, 1));
    setBlendPoint(b, 0.7f, 0.3f, Vec3(0.0f), Vec3(0, 0, 1));
    CHECK(std::fabs(blendF(a, wo, wi).x - blendF(b, wo, wi).x) > 0.01f);
}

// Mitsuba's orthographic sensor (a delta in direction: rays along the view direction from
// the film rectangle, CameraDesc::orthographic). Looking down at the floor at 35 degrees
// from the vertical (the film's density projected with that cosine) over a 1.6 x 1.6 film
// (to_world scaled by 0.8) under a point light: each block's radiance
// rho / pi E with E = I h / r^3, in PT, LT (connections along -forward, We = 1 / A) and BPT
// (the film's density projected at the first hit, and at t = 1).
TEST_CASE("Mitsuba orthographic sensor: a floor under a point light, in PT, LT and BPT", "[mitsuba][render][ortho]") {
    const Vec3 c(0.3f, 1.4f, -0.2f);
    floorUnder(
        R"(<emitter type="point"><point name="position" x="0.3" y="1.4" z="-0.2"/><rgb name="intensity" value="2"/></emitter>)",
        [&](Vec3 p) {
            const Vec3 d = c - p;
            const double r = length(d);
            return 2.0 * double(c.y) / (r * r * r);
        },
        "ortho", {}, R"(<bsdf type="diffuse"><rgb name="reflectance" value="0.6"/></bsdf>)", ".",
        R"(<sensor type="orthographic"><transform name="to_world"><scale value="0.8"/><lookat origin="0.2, 1, 0.7" target="0.2, 0, 0" up="0, 0, 1"/></transform>)");
}

// An orthographic view of a textured emitter filling the film (the rectangle [-1, 1]^2 at
// z = 0, the film to_world's unit square at z = 2): the blocks of the seen-directly test
// above, PT exactly, LT, BPT and MMLT within noise. And the importer: extents (y by the
// film's aspect), near_clip, bad inputs.
TEST_CASE("Mitsuba orthographic sensor: an emitter seen directly in every tracer, and the importer", "[mitsuba][render][ortho]") {
    checkerboardEmitterFillingFilm(R"(<sensor type="orthographic">
    <transform name="to_world"><lookat origin="0, 0, 2" target="0, 0, 0" up="0, 1, 0"/></transform>)",
                                   "ortho-seen.xml", 80, true);
    const std::string head = R"(<scene version="3.0.0"><sensor type="orthographic">)";
    const std::string film = R"(<film type="hdrfilm"><integer name="width" value="40"/><integer name="height" value="20"/></film></sensor>
      <shape type="sphere"><emitter type="area"/></shape></scene>)";
    const SceneDesc e = load(head + R"(<float name="near_clip" value="0.5"/><transform name="to_world"><scale x="3" y="2"/></transform>)" + film);
    CHECK(e.camera.orthoHalfWidth == Approx(3.0f));
    CHECK(e.camera.orthoHalfHeight == Approx(1.0f));  // 2 * 20 / 40
    CHECK(e.camera.nearClip == 0.5f);
    CHECK(errorOf(head + R"(<float name="fov" value="40"/>)" + film).find("fov") != std::string::npos);
    CHECK(errorOf(head + R"(<float name="near_clip" value="-1"/>)" + film).find("near_clip must be >= 0") != std::string::npos);
    CHECK(errorOf(head + R"(<transform name="to_world"><scale x="0" y="1"/></transform>)" + film).find("no area") != std::string::npos);
}

// Textured colour parameters (MaterialDesc::texture). A rectangle filling a 16 x 16
// image (as above) under a uniform sky, its BSDF's parameter a checkerboard whose 2 x 2
// squares are 8 x 8 pixel blocks: every pixel sees one square only, and a path through it
// does what the same path does with that square's colour as the constant, so each block
// is bit for bit the render of its constant, for PT, LT and BPT (one bounce: no Russian
// roulette, and the densities do not read the colours).
namespace {

SceneDesc texturedPlate(const std::string& bsdf) {
    return loadMitsubaFromString(R"(<scene version="3.0.0">
  <integrator type="path"><integer name="max_depth" value="3"/></integrator>
  <sensor type="perspective"><float name="fov" value="53.130102"/>
    <transform name="to_world"><lookat origin="0, 0, 2" target="0, 0, 0" up="0, 1, 0"/></transform>
    <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/><rfilter type="box"/></film></sensor>
  <shape type="rectangle">)" + bsdf + R"(</shape>
  <emitter type="constant"><rgb name="radiance" value="2"/></emitter>
</scene>)",
                                 "plate.xml", ".");
}

// The image of block (bx, by) of 8 x 8 pixels.
std::vector<float> block(const Image& im, int bx, int by) {
    std::vector<float> v;
    for (int y = 8 * by; y < 8 * by + 8; ++y)
        for (int x = 8 * bx; x < 8 * bx + 8; ++x)
            for (int c = 0; c < 3; ++c) v.push_back(im.rgb[(size_t(y) * im.width + x) * 3 + c]);
    return v;
}

}  // namespace

TEST_CASE("Mitsuba textured parameters: each block of a checkerboard renders its constant bit for bit", "[mitsuba][texture][render]") {
    const std::string a = "0.9, 0.6, 0.3", b = "0.2, 0.4, 0.8";
    auto board = [&](const std::string& name) {
        return "<texture type=\"checkerboard\" name=\"" + name + "\"><rgb name=\"color0\" value=\"" + a + "\"/><rgb name=\"color1\" value=\"" + b +
               "\"/></texture>";
    };
    auto rgb = [](const std::string& name, const std::string& v) { return "<rgb name=\"" + name + "\" value=\"" + v + "\"/>"; };
    struct Case {
        const char* what;
        std::string head, param, tail;
    };
    const std::vector<Case> cases = {
        {"roughconductor specular_reflectance", R"(<bsdf type="roughconductor"><float name="alpha" value="0.3"/>)", "specular_reflectance",
         "</bsdf>"},
        {"conductor specular_reflectance", R"(<bsdf type="conductor"><string name="material" value="Au"/>)", "specular_reflectance", "</bsdf>"},
        {"diffuse reflectance", R"(<bsdf type="diffuse">)", "reflectance", "</bsdf>"},
        {"roughdielectric specular_transmittance", R"(<bsdf type="roughdielectric"><float name="alpha" value="0.2"/>)", "specular_transmittance",
         "</bsdf>"},
        {"thindielectric specular_reflectance", R"(<bsdf type="thindielectric">)", "specular_reflectance", "</bsdf>"},
    };
    for (const Case& c : cases) {
        const SceneDesc textured = texturedPlate(c.head + board(c.param) + c.tail);
        const SceneDesc constA = texturedPlate(c.head + rgb(c.param, a) + c.tail);
        const SceneDesc constB = texturedPlate(c.head + rgb(c.param, b) + c.tail);
        for (TracerKind tr : {TracerKind::PT, TracerKind::LT, TracerKind::BPT}) {
            DYNAMIC_SECTION(c.what << ", tracer " << int(tr)) {
                const RenderOptions o = rstats::renderOptions(tr, 16, 77, 1, 3);
                const Image t = render(textured, o).image, ia = render(constA, o).image, ib = render(constB, o).image;
                // (The light tracer sees no delta surface: its images are black.)
                const bool black = std::all_of(ia.rgb.begin(), ia.rgb.end(), [](float v) { return v == 0; });
                CHECK(black == (tr == TracerKind::LT && std::string(c.what).find("rough") == std::string::npos &&
                                std::string(c.what).find("diffuse") == std::string::npos));
                if (!black) CHECK(t.rgb != ia.rgb);
                // Checkerboard: color0 where floor(2u) + floor(2v) is even; the image's top
                // row is v = 1 (the rectangle's uv, the test above), so blocks (0, 1) and
                // (1, 0) from the top left are color0.
                CHECK(block(t, 0, 1) == block(ia, 0, 1));
                CHECK(block(t, 1, 0) == block(ia, 1, 0));
                CHECK(block(t, 0, 0) == block(ib, 0, 0));
                CHECK(block(t, 1, 1) == block(ib, 1, 1));
            }
        }
    }
}

TEST_CASE("Mitsuba textured parameters: a constant texture renders what its constant renders, bit for bit", "[mitsuba][texture][render]") {
    // color0 = color1 = the constant: the texture returns it exactly, and 1 * c = c.
    const std::string c = "0.7, 0.5, 0.25";
    const std::string board = "<texture type=\"checkerboard\" name=\"specular_reflectance\"><rgb name=\"color0\" value=\"" + c +
                              "\"/><rgb name=\"color1\" value=\"" + c + "\"/></texture>";
    const std::string head = R"(<bsdf type="roughconductor"><string name="distribution" value="ggx"/><float name="alpha" value="0.2"/>)";
    // The plastics too: their lobe choice weighs the parameters by their textures' means
    // (textureMean, as Mitsuba's roughplastic), here the constant itself.
    auto boardOf = [&](const std::string& name) {
        return "<texture type=\"checkerboard\" name=\"" + name + "\"><rgb name=\"color0\" value=\"" + c + "\"/><rgb name=\"color1\" value=\"" + c +
               "\"/></texture>";
    };
    const std::string plastic = R"(<bsdf type="roughplastic"><float name="alpha" value="0.2"/>)";
    const std::vector<std::pair<std::string, std::string>> pairs = {
        {head + board + "</bsdf>", head + "<rgb name=\"specular_reflectance\" value=\"" + c + "\"/></bsdf>"},
        {plastic + boardOf("diffuse_reflectance") + "</bsdf>", plastic + "<rgb name=\"diffuse_reflectance\" value=\"" + c + "\"/></bsdf>"},
        {plastic + boardOf("specular_reflectance") + "</bsdf>", plastic + "<rgb name=\"specular_reflectance\" value=\"" + c + "\"/></bsdf>"},
        {R"(<bsdf type="plastic">)" + boardOf("diffuse_reflectance") + "</bsdf>",
         R"(<bsdf type="plastic"><rgb name="diffuse_reflectance" value=")" + c + "\"/></bsdf>"}};
    for (const auto& [tex, con] : pairs) {
        const SceneDesc textured = texturedPlate(tex), constant = texturedPlate(con);
        for (TracerKind tr : {TracerKind::PT, TracerKind::LT, TracerKind::BPT, TracerKind::MMLT}) {
            INFO(tex << "\ntracer " << int(tr));
            RenderOptions o = rstats::renderOptions(tr, 16, 5, 1, 3);
            if (tr == TracerKind::MMLT) o.chains = 1024;
            CHECK(render(textured, o).image.rgb == render(constant, o).image.rgb);
        }
    }
}

TEST_CASE("Mitsuba perspective sensor: focus_distance is read (a pinhole: no depth of field)", "[mitsuba][import]") {
    const std::string sensor = R"(<sensor type="perspective"><float name="fov" value="40"/><float name="focus_distance" value="%"/>
  <transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
  <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/><rfilter type="box"/></film></sensor>)";
    auto with = [&](const std::string& f) {
        std::string s = sensor;
        s.replace(s.find('%'), 1, f);
        return "<scene version=\"3.0.0\">\n" + s + "\n<emitter type=\"constant\"/>\n</scene>\n";
    };
    const SceneDesc d = load(with("3.5"));
    CHECK_FALSE(d.camera.dof);
    CHECK(d.camera.fovDegrees == Approx(40.0f));
    const std::string e = errorOf(with("0"));
    CHECK(e.find("t.xml:2:") == 0);
    CHECK(e.find("focus_distance must be > 0") != std::string::npos);
}

// A textured roughness (issue 25): the luminance of the texture at the hit is the alpha
// there. A checkerboard of two greys on alpha (alpha_u) renders, block by block, what the
// constant alpha of its square renders, bit for bit (the constant written as the float the
// texture's luminance gives); a constant texture renders its constant in all four tracers.
TEST_CASE("Mitsuba textured roughness: a checkerboard alpha renders each square's constant bit for bit", "[mitsuba][texture][render]") {
    const Vec3 greyA(0.1f), greyB(0.45f);
    auto num = [](float v) {
        char s[32];
        std::snprintf(s, sizeof s, "%.9g", double(v));
        return std::string(s);
    };
    const std::string la = num(luminance(greyA)), lb = num(luminance(greyB));
    auto board = [&](const std::string& name, Vec3 c0, Vec3 c1) {
        return "<texture type=\"checkerboard\" name=\"" + name + "\"><float name=\"color0\" value=\"" + num(c0.x) +
               "\"/><float name=\"color1\" value=\"" + num(c1.x) + "\"/></texture>";
    };
    auto flt = [](const std::string& name, const std::string& v) { return "<float name=\"" + name + "\" value=\"" + v + "\"/>"; };
    struct Case {
        const char* what;
        std::string head, param, tail;
    };
    const std::vector<Case> cases = {
        {"roughconductor alpha", R"(<bsdf type="roughconductor"><string name="distribution" value="ggx"/>)", "alpha", "</bsdf>"},
        {"roughdielectric alpha", R"(<bsdf type="roughdielectric">)", "alpha", "</bsdf>"},
        {"roughconductor alpha_u (alpha_v 0.05)", R"(<bsdf type="roughconductor"><float name="alpha_v" value="0.05"/>)", "alpha_u", "</bsdf>"},
    };
    for (const Case& c : cases) {
        const SceneDesc textured = texturedPlate(c.head + board(c.param, greyA, greyB) + c.tail);
        const SceneDesc constA = texturedPlate(c.head + flt(c.param, la) + c.tail);
        const SceneDesc constB = texturedPlate(c.head + flt(c.param, lb) + c.tail);
        REQUIRE(textured.materials[0].texture[MaterialParam::AlphaU] >= 0);
        for (TracerKind tr : {TracerKind::PT, TracerKind::LT, TracerKind::BPT}) {
            DYNAMIC_SECTION(c.what << ", tracer " << int(tr)) {
                const RenderOptions o = rstats::renderOptions(tr, 16, 78, 1, 3);
                const Image t = render(textured, o).image, ia = render(constA, o).image, ib = render(constB, o).image;
                CHECK(t.rgb != ia.rgb);
                CHECK(ia.rgb != ib.rgb);
                CHECK(block(t, 0, 1) == block(ia, 0, 1));
                CHECK(block(t, 1, 0) == block(ia, 1, 0));
                CHECK(block(t, 0, 0) == block(ib, 0, 0));
                CHECK(block(t, 1, 1) == block(ib, 1, 1));
            }
        }
        // The same squares both greyA: the constant's image in MMLT too.
        const SceneDesc flat = texturedPlate(c.head + board(c.param, greyA, greyA) + c.tail);
        for (TracerKind tr : {TracerKind::PT, TracerKind::LT, TracerKind::BPT, TracerKind::MMLT}) {
            INFO(c.what << ", constant texture, tracer " << int(tr));
            RenderOptions o = rstats::renderOptions(tr, 16, 6, 1, 3);
            if (tr == TracerKind::MMLT) o.chains = 1024;
            CHECK(render(flat, o).image.rgb == render(constA, o).image.rgb);
        }
    }
}

TEST_CASE("Mitsuba textured roughness: importer and bad inputs", "[mitsuba][import][texture]") {
    auto plate = [](const std::string& bsdf) {
        return R"(<scene version="3.0.0"><sensor type="perspective"><float name="fov" value="40"/></sensor>
<emitter type="constant"/>
<shape type="sphere"><bsdf type=")" +
               bsdf + "</bsdf></shape></scene>";
    };
    const std::string board = R"(<texture type="checkerboard" name="alpha"/>)";
    const SceneDesc d = loadMitsubaFromString(plate("roughconductor\">" + board), "t.xml", ".");
    CHECK(d.materials[0].texture[MaterialParam::AlphaU] >= 0);
    CHECK(d.materials[0].texture[MaterialParam::AlphaV] == d.materials[0].texture[MaterialParam::AlphaU]);
    CHECK(d.materials[0].alpha == 1.0f);
    CHECK_FALSE(isAnisotropic(d.materials[0]));
    const SceneDesc u = loadMitsubaFromString(
        plate("roughdielectric\">" + std::string(R"(<texture type="checkerboard" name="alpha_u"/><float name="alpha_v" value="0.3"/>)")), "t.xml",
        ".");
    CHECK(
        (u.materials[0].texture[MaterialParam::AlphaU] >= 0 && u.materials[0].texture[MaterialParam::AlphaV] == -1 && u.materials[0].alphaV == 0.3f));
    CHECK(isAnisotropic(u.materials[0]));
    CHECK(errorOf(plate("roughplastic\">" + board)) ==
          "t.xml:3: <texture type=\"checkerboard\" name=\"alpha\">: a texture on \"alpha\" is not supported by roughplastic "
          "(its tables are made for one alpha)");
}

// Mitsuba's normalmap (issue 25): a constant map tilting the floor's shading normal by 30
// degrees about v, n' = (sin 30, 0, cos 30) in the tangent frame (x along dp/du: the
// rectangle's u is world +x here). A diffuse floor under a directional light then has
// radiance rho / pi E (n' . -d) everywhere: PT exactly (next-event estimation alone), LT
// and BPT within their noise: their adjoint shading-normal corrections must give the same
// image as PT's radiance transport.
TEST_CASE("Mitsuba normalmap: a tilted constant map under a directional light, in PT, LT and BPT", "[mitsuba][render][bump]") {
    const std::string dir = rstats::tempDir("mitsuba-normalmap");
    const double s = 0.5, c = std::sqrt(0.75);
    writeImage(dir + "/n.pfm", texels(2, 2, [&](int, int) { return Vec3(float((s + 1) / 2), 0.5f, float((c + 1) / 2)); }));
    const std::string bsdf = R"(<bsdf type="normalmap"><texture type="bitmap" name="normalmap"><string name="filename" value="n.pfm"/>
      <boolean name="raw" value="true"/></texture><bsdf type="diffuse"><rgb name="reflectance" value="0.6"/></bsdf></bsdf>)";
    const Vec3 d = normalize(Vec3(-0.4f, -1.0f, 0.2f));  // towards -x: the tilted normal faces it more
    // The map's normal as the renderer decodes it (2 rgb - 1 in floats, normalised).
    const Vec3 m = normalize(Vec3(float((s + 1) / 2), 0.5f, float((c + 1) / 2)) * 2.0f - Vec3(1.0f));
    const Vec3 n(m.x, m.z, -m.y);  // tangent frame (x, y, z) = world (+x, -z, +y) on the floor
    const double cosine = -double(dot(n, d));
    REQUIRE(cosine > -double(d.y) * 1.05);  // the tilt matters: 6 % more than the flat floor's
    floorUnder(R"(<emitter type="directional"><vector name="direction" x="-0.4" y="-1" z="0.2"/><rgb name="irradiance" value="2"/></emitter>)",
               [&](Vec3) { return 2.0 * cosine; }, "normalmap", {TracerKind::PT}, bsdf, dir);
    std::filesystem::remove_all(dir);
}

TEST_CASE("Mitsuba normalmap: importer and bad inputs", "[mitsuba][import][bump]") {
    const std::string dir = rstats::tempDir("mitsuba-normalmap-import");
    writeImage(dir + "/n.pfm", texels(2, 2, [](int, int) { return Vec3(0.5f, 0.5f, 1.0f); }));
    const std::string map = R"(<texture type="bitmap" name="normalmap"><string name="filename" value="n.pfm"/></texture>)";
    SceneDesc d = load(scene(R"(<shape type="sphere"><bsdf type="normalmap">)" + map + R"(<bsdf type="roughconductor"/></bsdf></shape>)"), dir);
    const MaterialDesc& mm = d.materials[d.shapes[0].material];
    CHECK(mm.kind == MaterialKind::RoughConductor);
    REQUIRE(mm.normalMap >= 0);
    CHECK(d.textures[mm.normalMap].kind == TextureKind::Bitmap);
    // (0.5, 0.5, 1): the normal itself.
    const Vec3 ns = normalize(Vec3(0.1f, 0.2f, 1.0f));
    const Vec3 n = normalMapped(d.textures, size_t(mm.normalMap), 0.3f, 0.6f, Vec3(0.0f), ns, Vec3(0, 0, 1), Vec3(1, 0, 0));
    CHECK(n.x == Approx(ns.x).margin(1e-6));
    CHECK(n.y == Approx(ns.y).margin(1e-6));
    CHECK(n.z == Approx(ns.z).margin(1e-6));
    // A mesh without (u, v), no texture, a bumpmap inside.
    { std::ofstream(dir + "/tri.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"; }
    CHECK(errorOf(scene(R"(<shape type="obj"><string name="filename" value="tri.obj"/><bsdf type="normalmap">)" + map +
                        R"(<bsdf type="diffuse"/></bsdf></shape>)"),
                  dir)
              .find("a normalmap needs the mesh's (u, v), and this mesh has none") != std::string::npos);
    CHECK(errorOf(scene(R"(<shape type="sphere"><bsdf type="normalmap"><bsdf type="diffuse"/></bsdf></shape>)"), dir)
              .find("normalmap needs a texture named \"normalmap\"") != std::string::npos);
    CHECK(
        errorOf(
            scene(
                R"(<shape type="sphere"><bsdf type="normalmap">)" + map +
                R"(<bsdf type="bumpmap"><texture type="bitmap"><string name="filename" value="n.pfm"/></texture><bsdf type="diffuse"/></bsdf></bsdf></shape>)"),
            dir)
            .find("not supported") != std::string::npos);
    std::filesystem::remove_all(dir);
}
