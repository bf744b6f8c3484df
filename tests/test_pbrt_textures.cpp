// pbrt-v4's texture mappings and procedural textures (docs/pbrt.md, kernels/texture.h): the
// mappings probed with a bilerp that returns its own (s, t), the noise sums against their
// definitions, the dots' geometry, the marble's spline where sin() pins it, directionmix
// against the normal, imagemap's invert, and a floor textured by position and normal in PT,
// LT and BPT (the texture stage gets the hit's point and normal in every tracer).
#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "chi2.h"
#include "kernels/bump.h"
#include "kernels/texture.h"
#include "mitsuba_floor.h"
#include "render_stats.h"
#include "scene/scene.h"
#include "stages/core/surface.h"
#include "wavemmlt/error.h"
#include "wavemmlt/image.h"
#include "wavemmlt/render.h"
#include "wavemmlt/scene_desc.h"

using namespace wmlt;

namespace {

std::string dir() {
    static const std::string d = rstats::tempDir("pbrt-textures");
    return d;
}
SceneDesc loadText(const std::string& name, const std::string& body) {
    const std::string path = dir() + "/" + name;
    std::ofstream(path, std::ios::binary) << R"(LookAt 0 1 0  0 0 0  0 0 1
Camera "perspective" "float fov" [ 90 ]
Film "rgb" "integer xresolution" [ 16 ] "integer yresolution" [ 16 ]
PixelFilter "box"
WorldBegin
)" << body;
    return loadScene(path);
}
// A 1 x 1 normal map (0.8, 0.5, 0.9) = (n + 1) / 2 for n = (0.6, 0, 0.8) in the tangent frame.
void writeTiltedNormalMap(const std::string& path) {
    std::ofstream f(path, std::ios::binary);
    f << "PF\n1 1\n-1.0\n";
    const float px[3] = {0.8f, 0.5f, 0.9f};
    f.write(reinterpret_cast<const char*>(px), sizeof px);
}
// A scene whose one material's reflectance is texture `name` (defined in `textures`).
SceneDesc withTexture(const std::string& file, const std::string& textures, const std::string& name = "t") {
    return loadText(file, textures + "Material \"diffuse\" \"texture reflectance\" \"" + name + R"("
Shape "trianglemesh" "point3 P" [ -20 0 -20  20 0 -20  20 0 20  -20 0 20 ] "integer indices" [ 0 1 2 0 2 3 ]
LightSource "point" "rgb I" [ 1 1 1 ] "point3 from" [ 0 1 0 ]
)");
}
const TextureDesc& reflectanceTexture(const SceneDesc& d) {
    const int t = d.materials.back().texture[MaterialParam::Diffuse];
    REQUIRE(t >= 0);
    return d.textures[size_t(t)];
}
// bilerp with v00 = 0, v10 = red, v01 = green, v11 = yellow: (s, t, 0) for s, t in [0, 1].
const std::string kProbe = R"("rgb v00" [ 0 0 0 ] "rgb v10" [ 1 0 0 ] "rgb v01" [ 0 1 0 ] "rgb v11" [ 1 1 0 ])";

void checkSt(const TextureDesc& t, float u, float v, Vec3 p, double s, double tt) {
    const Vec3 c = evalTexture(t, u, v, p);
    INFO("u " << u << " v " << v << " p " << p.x << " " << p.y << " " << p.z);
    CHECK(c.x == Approx(s).margin(1e-5));
    CHECK(c.y == Approx(tt).margin(1e-5));
}

}  // namespace

TEST_CASE("pbrt textures: uv, spherical, cylindrical and planar mappings", "[pbrt][texture]") {
    const SceneDesc uv = withTexture("uv.pbrt",
                                     "Texture \"t\" \"spectrum\" \"bilerp\" \"float uscale\" 2 \"float vscale\" 0.5 "
                                     "\"float udelta\" 0.1 \"float vdelta\" 0.2 " +
                                         kProbe + "\n");
    checkSt(reflectanceTexture(uv), 0.2f, 0.6f, Vec3(5.0f), 0.5, 0.5);
    checkSt(reflectanceTexture(uv), 0.4f, 1.2f, Vec3(5.0f), 0.9, 0.8);
    // The texture's space is the CTM at the directive: centred on (1, 2, 3) here.
    const std::string at = "AttributeBegin\nTranslate 1 2 3\n";
    const SceneDesc sph =
        withTexture("sph.pbrt", at + "Texture \"t\" \"spectrum\" \"bilerp\" \"string mapping\" \"spherical\" " + kProbe + "\nAttributeEnd\n");
    const TextureDesc& ts = reflectanceTexture(sph);
    const Vec3 c(1, 2, 3);
    checkSt(ts, 0, 0, c + Vec3(0, 0, 2), 0, 0);                          // theta 0
    checkSt(ts, 0, 0, c + Vec3(3, 0, 0), 0.5, 0);                        // theta pi / 2, phi 0
    checkSt(ts, 0, 0, c + Vec3(0, 0.5f, 0), 0.5, 0.25);                  // phi pi / 2
    checkSt(ts, 0, 0, c + Vec3(-1, -1, -std::sqrt(2.0f)), 0.75, 0.625);  // theta 3 pi / 4, phi 5 pi / 4
    const SceneDesc cyl =
        withTexture("cyl.pbrt", at + "Texture \"t\" \"spectrum\" \"bilerp\" \"string mapping\" \"cylindrical\" " + kProbe + "\nAttributeEnd\n");
    checkSt(reflectanceTexture(cyl), 0, 0, c + Vec3(2, 0, 0.3f), 0.5, 0.3);
    checkSt(reflectanceTexture(cyl), 0, 0, c + Vec3(0, -1, 0.7f), 0.25, 0.7);
    const SceneDesc pl =
        withTexture("planar.pbrt", at +
                                       "Texture \"t\" \"spectrum\" \"bilerp\" \"string mapping\" \"planar\" \"vector3 v1\" [ 1 0 0 ] "
                                       "\"vector3 v2\" [ 0 0 1 ] \"float udelta\" 0.1 \"float vdelta\" 0.2 " +
                                       kProbe + "\nAttributeEnd\n");
    checkSt(reflectanceTexture(pl), 0, 0, c + Vec3(0.3f, 5, 0.4f), 0.4, 0.6);
    // a rotated texture space: planar along the texture's x, which is world -z after Rotate 90 about y
    const SceneDesc rot =
        withTexture("rot.pbrt", "AttributeBegin\nRotate 90 0 1 0\nTexture \"t\" \"spectrum\" \"bilerp\" \"string mapping\" \"planar\" " + kProbe +
                                    "\nAttributeEnd\n");
    checkSt(reflectanceTexture(rot), 0, 0, Vec3(0.1f, 0.2f, -0.7f), 0.7, 0.2);
}

TEST_CASE("pbrt textures: fbm, wrinkled and windy are pbrt's sums of octaves", "[pbrt][texture]") {
    const Vec3 q(0.37f, 1.91f, -2.23f);
    CHECK(fbm(q, 0.5f, 1) == perlinNoise(q));
    CHECK(fbm(q, 0.7f, 2) == Approx(perlinNoise(q) + 0.7f * perlinNoise(q * 1.99f)).margin(1e-6));
    CHECK(turbulencePbrt(q, 0.6f, 0) == Approx(0.2f));
    CHECK(turbulencePbrt(q, 0.6f, 2) == Approx(std::fabs(perlinNoise(q)) + 0.6f * std::fabs(perlinNoise(q * 1.99f)) + 0.2f * 0.36f).margin(1e-6));
    // the noise is not trivially zero here (the sums above would pass on zeros)
    CHECK(std::fabs(perlinNoise(q)) > 0.01f);
    CHECK(std::fabs(perlinNoise(q * 1.99f)) > 0.01f);
    // as textures, of the point in the texture's space (Scale 2: q = p / 2)
    const SceneDesc d = withTexture("noise.pbrt",
                                    "AttributeBegin\nScale 2 2 2\nTexture \"f\" \"float\" \"fbm\" \"integer octaves\" 3 \"float roughness\" 0.4\n"
                                    "Texture \"w\" \"float\" \"wrinkled\"\nTexture \"y\" \"float\" \"windy\"\nAttributeEnd\n"
                                    "Texture \"t\" \"spectrum\" \"mix\" \"rgb tex1\" [ 0 0 0 ] \"rgb tex2\" [ 1 1 1 ] \"texture amount\" \"f\"\n");
    const Vec3 p = q * 2.0f;
    auto find = [&](TextureKind k) -> const TextureDesc& {
        for (const TextureDesc& t : d.textures)
            if (t.kind == k) return t;
        FAIL("no texture of kind " << int(k));
        return d.textures[0];
    };
    CHECK(evalTexture(find(TextureKind::Fbm), 0, 0, p).y == Approx(fbm(q, 0.4f, 3)).margin(1e-5));
    CHECK(evalTexture(find(TextureKind::Wrinkled), 0, 0, p).y == Approx(turbulencePbrt(q, 0.5f, 8)).margin(1e-5));
    CHECK(evalTexture(find(TextureKind::Windy), 0, 0, p).y == Approx(std::fabs(fbm(q * 0.1f, 0.5f, 3)) * fbm(q, 0.5f, 6)).margin(1e-5));
    // the mix reads fbm as its amount at the same point
    const Vec3 m = evalTextureOf(d.textures, size_t(d.materials.back().texture[MaterialParam::Diffuse]), 0, 0, p, Vec3(0, 1, 0));
    CHECK(m.x == Approx(fbm(q, 0.4f, 3)).margin(1e-5));
}

TEST_CASE("pbrt textures: dots are discs of radius 0.35 in about half of the cells", "[pbrt][texture]") {
    // Per cell (s, t) in [i - 0.5, i + 0.5) x [j - 0.5, j + 0.5): either no point inside, or
    // the points inside make a disc: area pi 0.35^2 (to the 64 x 64 grid's resolution), its
    // centroid within 0.15 of the cell's centre and every inside point within 0.35 of it.
    int cellsWithDots = 0;
    const int n = 64;
    for (int i = -8; i < 8; ++i)
        for (int j = -8; j < 8; ++j) {
            int inside = 0;
            double cs = 0, ct = 0;
            for (int a = 0; a < n; ++a)
                for (int b = 0; b < n; ++b) {
                    const float s = float(i) - 0.5f + (float(a) + 0.5f) / n, t = float(j) - 0.5f + (float(b) + 0.5f) / n;
                    if (!insidePolkaDot(s, t)) continue;
                    ++inside;
                    cs += s;
                    ct += t;
                }
            if (inside == 0) continue;
            ++cellsWithDots;
            cs /= inside;
            ct /= inside;
            CHECK(double(inside) / (n * n) == Approx(M_PI * 0.35 * 0.35).margin(0.01));
            CHECK(std::hypot(cs - i, ct - j) <= 0.15 + 1e-3);
        }
    // 256 cells, each with a dot when a noise value is positive: about half
    CHECK(cellsWithDots > 80);
    CHECK(cellsWithDots < 176);
    // the texture: inside and outside, constants or textures
    const SceneDesc d = withTexture("dots.pbrt", "Texture \"in\" \"spectrum\" \"bilerp\" " + kProbe +
                                                     "\nTexture \"t\" \"spectrum\" \"dots\" \"texture inside\" \"in\" \"rgb outside\" [ 0.1 0.2 0.3 ]"
                                                     " \"float uscale\" 4 \"float vscale\" 4\n");
    const size_t t = size_t(d.materials.back().texture[MaterialParam::Diffuse]);
    for (float u = 0.01f; u < 1; u += 0.037f)
        for (float v = 0.02f; v < 1; v += 0.041f) {
            const Vec3 c = evalTextureOf(d.textures, t, u, v, Vec3(0.0f), Vec3(0, 1, 0));
            if (insidePolkaDot(4 * u, 4 * v)) {
                CHECK(c.x == Approx(u).margin(1e-5));  // the operand at the hit's own (u, v)
                CHECK(c.y == Approx(v).margin(1e-5));
            } else {
                CHECK(c.z == Approx(0.3f));
            }
        }
}

TEST_CASE("pbrt textures: marble's spline where sin() pins it", "[pbrt][texture]") {
    // variation 0: t = 0.5 + 0.5 sin(scale q.y): the spline's ends and middle control points, times 1.5
    const SceneDesc d = withTexture("marble.pbrt", "Texture \"t\" \"spectrum\" \"marble\" \"float variation\" 0 \"float scale\" 2\n");
    const TextureDesc& m = reflectanceTexture(d);
    auto at = [&](float y) { return evalTexture(m, 0, 0, Vec3(0.3f, y / 2, -0.8f)); };
    CHECK(at(-float(M_PI) / 2).z == Approx(1.5 * 0.6).margin(1e-5));  // t = 0: c[0]
    CHECK(at(float(M_PI) / 2).z == Approx(1.5 * 0.6).margin(1e-5));   // t = 1: c[8]
    CHECK(at(0).x == Approx(1.5 * 0.5).margin(1e-5));                 // t = 0.5: c[3]
    // t = 5/6 exactly is the start of the last segment: c[5]; between, a blend of the blue c[7]
    const Vec3 blue = at(std::asin(2 * 0.92f - 1));
    CHECK(blue.z - blue.x > 0.05f);
    // variation bends the bands with fbm of the scaled point
    const SceneDesc dv = withTexture("marble2.pbrt", "Texture \"t\" \"spectrum\" \"marble\" \"float variation\" 1 \"integer octaves\" 4\n");
    const Vec3 q(0.3f, 0.2f, 0.9f);
    const float t = 0.5f + 0.5f * std::sin(q.y + fbm(q, 0.5f, 4));
    TextureDesc pinned = reflectanceTexture(dv);
    pinned.variation = 0;
    const Vec3 got = evalTexture(reflectanceTexture(dv), 0, 0, q), want = evalTexture(pinned, 0, 0, Vec3(0, std::asin(2 * t - 1), 0));
    CHECK(got.x == Approx(want.x).margin(1e-4));
    CHECK(got.z == Approx(want.z).margin(1e-4));
}

TEST_CASE("pbrt textures: directionmix follows the geometric normal", "[pbrt][texture]") {
    const SceneDesc d = withTexture("dm.pbrt",
                                    "AttributeBegin\nRotate 90 1 0 0\nTexture \"t\" \"spectrum\" \"directionmix\" "
                                    "\"rgb tex1\" [ 0.8 0.8 0.8 ] \"rgb tex2\" [ 0.2 0.2 0.2 ] \"vector3 dir\" [ 0 1 0 ]\nAttributeEnd\n");
    // dir (0, 1, 0) in the texture's space is world (0, 0, 1)
    const size_t t = size_t(d.materials.back().texture[MaterialParam::Diffuse]);
    auto at = [&](Vec3 n) { return evalTextureOf(d.textures, t, 0.3f, 0.4f, Vec3(1.0f), n).x; };
    CHECK(at(Vec3(0, 0, 1)) == Approx(0.8f));
    CHECK(at(Vec3(0, 0, -3)) == Approx(0.8f));  // |cos|, any length
    CHECK(at(Vec3(0, 1, 0)) == Approx(0.2f));
    CHECK(at(Vec3(0, std::sqrt(3.0f) / 2, 0.5f)) == Approx(0.5 * 0.8 + 0.5 * 0.2));
}

TEST_CASE("pbrt textures: imagemap's invert is 1 - scale texel, at least 0", "[pbrt][texture]") {
    const std::string img = dir() + "/ramp.pfm";
    {
        std::ofstream f(img, std::ios::binary);
        f << "PF\n2 1\n-1.0\n";
        const float px[6] = {0.25f, 0.5f, 0.75f, 2.0f, 0.1f, 0.0f};
        f.write(reinterpret_cast<const char*>(px), sizeof px);
    }
    const SceneDesc d = withTexture("invert.pbrt",
                                    "Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"ramp.pfm\" "
                                    "\"bool invert\" true \"float scale\" 2 \"string filter\" \"point\"\n");
    const TextureDesc& t = reflectanceTexture(d);
    const Vec3 a = evalTexture(t, 0.25f, 0.5f, Vec3(0.0f)), b = evalTexture(t, 0.75f, 0.5f, Vec3(0.0f));
    CHECK(a.x == Approx(0.5f));
    CHECK(a.y == Approx(0.0f));
    CHECK(a.z == Approx(0.0f));  // 1 - 1.5, clamped
    CHECK(b.x == Approx(0.0f));
    CHECK(b.y == Approx(0.8f));
    CHECK(b.z == Approx(1.0f));
}

TEST_CASE("pbrt textures: a floor textured by position and normal, in PT, LT and BPT", "[pbrt][texture][render]") {
    // Reflectance: directionmix(marble, 0.05) along +y on the floor y = 0, so the marble
    // whenever the texture stage has the hit's normal; the marble's bands run along world z
    // (Rotate: the texture's y is world z), wide against the pixels (two octaves of noise:
    // the expected means' 8 x 8 points per pixel resolve them). Lit by a point light:
    // L = rho(p) / pi I cos / r^2, rho the texture's green at p. (Planted: a zero normal in
    // the texture jobs fails all three tracers.)
    const SceneDesc d = loadText("floor-tex.pbrt", R"(AttributeBegin
Rotate -90 1 0 0
Texture "m" "spectrum" "marble" "float scale" 1.5 "float variation" 0.3 "integer octaves" 2
AttributeEnd
Texture "t" "spectrum" "directionmix" "texture tex1" "m" "rgb tex2" [ 0.05 0.05 0.05 ] "vector3 dir" [ 0 1 0 ]
Material "diffuse" "texture reflectance" "t"
Shape "trianglemesh" "point3 P" [ -20 0 -20  20 0 -20  20 0 20  -20 0 20 ] "integer indices" [ 0 1 2 0 2 3 ]
LightSource "point" "rgb I" [ 2 2 2 ] "point3 from" [ 0.2 1.3 -0.1 ]
)");
    const size_t t = size_t(d.materials.back().texture[MaterialParam::Diffuse]);
    const Vec3 c(0.2f, 1.3f, -0.1f);
    floor_test::floorRadianceOf(d,
                                [&](Vec3 p, Vec3) {
                                    const double r2 = double(lengthSquared(c - p));
                                    const double rho = evalTextureOf(d.textures, t, 0, 0, p, Vec3(0, 1, 0)).y;
                                    return rho / M_PI * 2 * c.y / std::sqrt(r2) / r2;
                                },
                                "pbrt-textured-floor", {});
}

// Every textured parameter (issue 43: the texture stage applies one rule per parameter,
// MaterialParam): a coated material's interface roughness, a remapped roughness, a coated
// conductor's base roughness and albedo, a conductor's eta, k and reflectance (plain and
// coated), diffusetransmission's scale. A checkerboard of two equal values is the constant
// seen through the texture stage: the floor under a point light renders as with the
// constant (6 PT runs a side, p = 1e-4, with their own seeds). A checkerboard of two
// different values is not (the same test fails on it), so the texture is read.
TEST_CASE("pbrt textures: every textured parameter equals its constant through a constant texture", "[pbrt][texture][render]") {
    // float texture "r" and spectrum texture "c", each a checkerboard of its two values
    auto floorOf = [](const std::string& file, const std::string& material, const std::string& r, const std::string& c) {
        return loadText(file, "Texture \"r\" \"float\" \"checkerboard\" \"float uscale\" 8 \"float vscale\" 8 " + r +
                                  "\nTexture \"c\" \"spectrum\" \"checkerboard\" \"float uscale\" 8 \"float vscale\" 8 " + c + "\n" + material + R"(
Shape "trianglemesh" "point3 P" [ -20 0 -20  20 0 -20  20 0 20  -20 0 20 ] "point2 uv" [ 0 0 1 0 1 1 0 1 ] "integer indices" [ 0 1 2 0 2 3 ]
LightSource "point" "rgb I" [ 2 2 2 ] "point3 from" [ 0.2 1.3 -0.1 ]
)");
    };
    const std::string rSame = "\"float tex1\" 0.3 \"float tex2\" 0.3", rDiffer = "\"float tex1\" 0.02 \"float tex2\" 0.6";
    auto rgbPair = [](const std::string& a, const std::string& b) { return "\"rgb tex1\" [ " + a + " ] \"rgb tex2\" [ " + b + " ]"; };
    struct Case {
        const char* what;
        std::string textured, constant;
        MaterialParam param;
        std::string cSame, cDiffer;  // the spectrum texture's values (the float one: rSame, rDiffer)
    };
    // (a spectrum texture's RGB is read as a reflectance, at most 1, as pbrt-v4 reads it)
    const std::string eta = "0.2 0.9 0.95", k = "0.9 0.8 0.6", refl = "0.7 0.5 0.3", alb = "0.8 0.6 0.4";
    const std::string coatCu = "Material \"coatedconductor\" \"float interface.roughness\" 0.05 \"float thickness\" 0.2 ";
    const std::vector<Case> cases = {
        {"coateddiffuse roughness", "Material \"coateddiffuse\" \"texture roughness\" \"r\" \"rgb reflectance\" [ 0.5 0.4 0.3 ]",
         "Material \"coateddiffuse\" \"float roughness\" 0.3 \"rgb reflectance\" [ 0.5 0.4 0.3 ]", MaterialParam::AlphaU, "", ""},
        {"conductor roughness, remapped", "Material \"conductor\" \"texture roughness\" \"r\"", "Material \"conductor\" \"float roughness\" 0.3",
         MaterialParam::AlphaU, "", ""},
        {"coatedconductor conductor.roughness", coatCu + "\"texture conductor.roughness\" \"r\"", coatCu + "\"float conductor.roughness\" 0.3",
         MaterialParam::BaseAlphaU, "", ""},
        {"coatedconductor albedo", coatCu + "\"texture albedo\" \"c\"", coatCu + "\"rgb albedo\" [ " + alb + " ]", MaterialParam::Albedo,
         rgbPair(alb, alb), rgbPair(alb, "0.1 0.1 0.1")},
        {"conductor eta", "Material \"conductor\" \"float roughness\" 0.2 \"texture eta\" \"c\" \"rgb k\" [ " + k + " ]",
         "Material \"conductor\" \"float roughness\" 0.2 \"rgb eta\" [ " + eta + " ] \"rgb k\" [ " + k + " ]", MaterialParam::ConductorEta,
         rgbPair(eta, eta), rgbPair(eta, "0.6 0.6 0.6")},
        {"conductor k", "Material \"conductor\" \"float roughness\" 0.2 \"rgb eta\" [ " + eta + " ] \"texture k\" \"c\"",
         "Material \"conductor\" \"float roughness\" 0.2 \"rgb eta\" [ " + eta + " ] \"rgb k\" [ " + k + " ]", MaterialParam::ConductorK,
         rgbPair(k, k), rgbPair(k, "0.1 0.1 0.1")},
        {"conductor reflectance", "Material \"conductor\" \"float roughness\" 0.2 \"texture reflectance\" \"c\"",
         "Material \"conductor\" \"float roughness\" 0.2 \"rgb reflectance\" [ " + refl + " ]", MaterialParam::ConductorReflectance,
         rgbPair(refl, refl), rgbPair(refl, "0.05 0.05 0.05")},
        {"coatedconductor reflectance", coatCu + "\"texture reflectance\" \"c\"", coatCu + "\"rgb reflectance\" [ " + refl + " ]",
         MaterialParam::ConductorReflectance, rgbPair(refl, refl), rgbPair(refl, "0.05 0.05 0.05")},
        {"diffusetransmission scale", "Material \"diffusetransmission\" \"texture scale\" \"r\" \"rgb reflectance\" [ 0.9 0.7 0.5 ]",
         "Material \"diffusetransmission\" \"float scale\" 0.3 \"rgb reflectance\" [ 0.9 0.7 0.5 ]", MaterialParam::Scale, "", ""},
    };
    auto runs = [](const SceneDesc& d, uint64_t seed) {
        rstats::RunStats r;
        for (int k = 0; k < 6; ++k)
            r.add(rstats::blockMeans(render(d, rstats::renderOptions(TracerKind::PT, 64, seed + uint64_t(k), 1, 8)).image, 4, 1));
        return r;
    };
    const std::string cNone = rgbPair("0.5 0.5 0.5", "0.5 0.5 0.5");
    for (const Case& c : cases) {
        DYNAMIC_SECTION(c.what) {
            const std::string cSame = c.cSame.empty() ? cNone : c.cSame, cDiffer = c.cDiffer.empty() ? cNone : c.cDiffer;
            const bool floatTexture = c.cSame.empty();
            const SceneDesc textured = floorOf("tex-t.pbrt", c.textured, rSame, cSame), constant = floorOf("tex-c.pbrt", c.constant, rSame, cSame);
            const MaterialDesc& m = textured.materials.back();
            REQUIRE(m.texture[c.param] >= 0);
            if (c.param == MaterialParam::AlphaU) CHECK(m.alphaRemap);
            const rstats::RunStats a = runs(textured, 100), b = runs(constant, 200);
            double ratio = 0;
            const rstats::ZTestResult z = rstats::compareRuns(a, b, 1e-4, &ratio);
            INFO(c.what << ", the constant texture: " << z.describe() << ", ratio of means " << ratio);
            CHECK(z.pass);
            const SceneDesc differ = floorOf("tex-d.pbrt", c.textured, floatTexture ? rDiffer : rSame, floatTexture ? cSame : cDiffer);
            const rstats::ZTestResult w = rstats::compareRuns(runs(differ, 300), b, 1e-4, &ratio);
            INFO(c.what << ", a checkerboard of two values: " << w.describe() << ", ratio of means " << ratio);
            CHECK_FALSE(w.pass);
        }
    }
}

TEST_CASE("pbrt textures: normalmap tilts a floor's shading normal, in PT, LT and BPT", "[pbrt][texture][render][bump]") {
    // A 1 x 1 normal map (0.8, 0.5, 0.9) = (n + 1) / 2 for n = (0.6, 0, 0.8) in the tangent
    // frame (x along dp/du = world +x, z the normal +y): the floor's shading normal is
    // (0.6, 0.8, 0) and a distant light from l gives rho / pi E (n . l).
    writeTiltedNormalMap(dir() + "/n.pfm");
    for (const double lx : {0.5, -0.5}) {
        const double ly = std::sqrt(1 - lx * lx);
        const SceneDesc d =
            loadText(lx > 0 ? "nmap-a.pbrt" : "nmap-b.pbrt", R"(Material "diffuse" "rgb reflectance" [ 0.6 0.6 0.6 ] "string normalmap" "n.pfm"
Shape "trianglemesh" "point3 P" [ -20 0 -20  20 0 -20  20 0 20  -20 0 20 ] "integer indices" [ 0 2 1 0 3 2 ] "point2 uv" [ 0 0  1 0  1 1  0 1 ]
LightSource "distant" "rgb L" [ 1 1 1 ] "point3 from" [ )" + std::to_string(lx) +
                                                                 " " + std::to_string(ly) + R"( 0 ] "point3 to" [ 0 0 0 ] "float illuminance" 2
)");
        REQUIRE(d.materials.back().normalMap >= 0);
        const double cosN = 0.6 * lx + 0.8 * ly;
        floor_test::floorRadianceOf(d, [&](Vec3, Vec3) { return 0.6 / M_PI * 2 * cosN; }, "pbrt-normalmap", {TracerKind::PT, TracerKind::BPT});
    }
    // An 8-bit normal map is read linearly (its bytes / 255), as pbrt reads normal maps.
    Image png(1, 1);
    png.rgb = {0.6f, 0.2f, 0.9f};  // written sRGB-encoded: bytes round(255 srgb(v))
    writeImage(dir() + "/n.png", png);
    const SceneDesc d = loadText("nmap-png.pbrt", R"(Material "diffuse" "string normalmap" "n.png"
Shape "trianglemesh" "point3 P" [ -20 0 -20  20 0 -20  20 0 20  -20 0 20 ] "integer indices" [ 0 2 1 0 3 2 ] "point2 uv" [ 0 0  1 0  1 1  0 1 ]
LightSource "point" "rgb I" [ 1 1 1 ] "point3 from" [ 0 1 0 ]
)");
    const Vec3 c = evalTexture(d.textures[size_t(d.materials.back().normalMap)], 0.5f, 0.5f, Vec3(0.0f));
    CHECK(c.x == Approx(linearToSrgb(0.6f)).margin(1.0 / 255));  // not 0.6: the decoded value
    CHECK(c.y == Approx(linearToSrgb(0.2f)).margin(1.0 / 255));
    CHECK(c.z == Approx(linearToSrgb(0.9f)).margin(1.0 / 255));
}

TEST_CASE("pbrt textures: displacement bumps by the texture's slope in world units", "[pbrt][texture][bump]") {
    // displacement k u (a float bilerp): dp/du' = dp/du + k ns, so on a patch with dp/du =
    // (2, 0, 0), dp/dv = (0, 0, -3), ns = ng = +y the normal is (-3 k, 6, 0) normalised; k =
    // 0.5 given directly, or (issue 43, the pbrt book's) as a scale texture of 0.25 times 2.
    const char* kBilerp = "Texture \"h\" \"float\" \"bilerp\" \"float v00\" 0 \"float v01\" 0 ";
    for (const std::string& textures :
         {std::string(kBilerp) + "\"float v10\" 0.5 \"float v11\" 0.5\n",
          std::string(kBilerp) +
              "\"float v10\" 0.25 \"float v11\" 0.25\nTexture \"h2\" \"float\" \"scale\" \"texture tex\" \"h\" \"float scale\" 2\n"}) {
        const bool scaled = textures.find("scale") != std::string::npos;
        const SceneDesc d = loadText(scaled ? "disp-scale.pbrt" : "disp.pbrt",
                                     textures + "Material \"diffuse\" \"texture displacement\" " + (scaled ? "\"h2\"" : "\"h\"") + R"(
Shape "trianglemesh" "point3 P" [ -20 0 -20  20 0 -20  20 0 20  -20 0 20 ] "integer indices" [ 0 2 1 0 3 2 ] "point2 uv" [ 0 0  1 0  1 1  0 1 ]
LightSource "point" "rgb I" [ 1 1 1 ] "point3 from" [ 0 1 0 ]
)");
        INFO((scaled ? "a scale texture" : "a bilerp"));
        const MaterialDesc& m = d.materials.back();
        REQUIRE(m.bump >= 0);
        CHECK(m.bumpPbrt);
        CHECK((d.textures[size_t(m.bump)].kind == TextureKind::Scale) == scaled);
        const Vec3 n = bumpedNormalPbrt(heightOf(d.textures, size_t(m.bump), Vec3(0, 1, 0)), Vec3(0.1f, 0, 0.2f), 0.3f, 0.6f, Vec3(0, 1, 0),
                                        Vec3(0, 1, 0), Vec3(2, 0, 0), Vec3(0, 0, -3));
        const Vec3 want = normalize(Vec3(-1.5f, 6, 0));
        CHECK(n.x == Approx(want.x).margin(1e-3));
        CHECK(n.y == Approx(want.y).margin(1e-3));
        CHECK(std::fabs(n.z) < 1e-3f);
        CHECK(Scene::build(d, 1) != nullptr);
    }
}

TEST_CASE("pbrt textures: bad parameters name file and line", "[pbrt][texture][bad-input]") {
    auto error = [&](const std::string& body) {
        try {
            withTexture("bad-tex.pbrt", body);
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    CHECK_THAT(error("Texture \"t\" \"spectrum\" \"bilerp\" \"string mapping\" \"sphere\"\n"),
               Catch::Contains("bad-tex.pbrt:6") && Catch::Contains("mapping \"sphere\""));
    CHECK_THAT(error("Texture \"t\" \"spectrum\" \"fbm\"\n"), Catch::Contains("bad-tex.pbrt:6") && Catch::Contains("float texture"));
    CHECK_THAT(error("Texture \"t\" \"float\" \"wrinkled\" \"integer octaves\" 100\n"), Catch::Contains("octaves"));
    CHECK_THAT(error("Texture \"t\" \"spectrum\" \"directionmix\" \"vector3 dir\" [ 0 0 0 ]\n"), Catch::Contains("nonzero"));
    CHECK_THAT(error("Scale 1 0 1\nTexture \"t\" \"spectrum\" \"bilerp\"\n"), Catch::Contains("singular"));
}

// A mix whose parts perturb the normal (issue 43) is one part per hit, as pbrt-v4 chooses
// every mix's material: part 1 where a hash of the point is below amount. A floor of a
// normal-mapped diffuse (its shading normal (0.6, 0.8, 0), as in the normalmap test) and a
// plain one under a distant light renders as amount of the one and 1 - amount of the other
// in PT, LT and BPT (a z-test over 8 runs: the choice varies with the point); the choice's frequency over 20 000 points is amount within 5 standard
// deviations. A mix of an anisotropic part loads, and the mix's frame follows dp/du.
TEST_CASE("pbrt textures: a mix of bump-mapped or anisotropic parts", "[pbrt][texture][blend]") {
    writeTiltedNormalMap(dir() + "/nm.pfm");
    const double amount = 0.3, lx = 0.5, ly = std::sqrt(1 - lx * lx);
    const SceneDesc d =
        loadText("mix-bump.pbrt", R"(MakeNamedMaterial "tilted" "string type" "diffuse" "rgb reflectance" [ 0.6 0.6 0.6 ] "string normalmap" "nm.pfm"
MakeNamedMaterial "flat" "string type" "diffuse" "rgb reflectance" [ 0.6 0.6 0.6 ]
Material "mix" "string materials" [ "flat" "tilted" ] "float amount" )" +
                                      std::to_string(amount) + R"(
Shape "trianglemesh" "point3 P" [ -20 0 -20  20 0 -20  20 0 20  -20 0 20 ] "integer indices" [ 0 2 1 0 3 2 ] "point2 uv" [ 0 0  1 0  1 1  0 1 ]
LightSource "distant" "rgb L" [ 1 1 1 ] "point3 from" [ )" +
                                      std::to_string(lx) + " " + std::to_string(ly) + R"( 0 ] "point3 to" [ 0 0 0 ] "float illuminance" 2
)");
    const int mix = d.shapes[0].material;
    REQUIRE(d.materials[size_t(mix)].kind == MaterialKind::Blend);
    {
        const std::unique_ptr<Scene> s = Scene::build(d, 1);
        REQUIRE(s->choosesPart[size_t(mix)] == 1);
        CHECK(s->features.bump);
        chi2::Pcg32 rng(7);
        const int n = 20000;
        int ones = 0;
        for (int i = 0; i < n; ++i) {
            SurfacePoint sp;
            sp.material = mix;
            sp.p = Vec3(40 * rng.uniform() - 20, 0, 40 * rng.uniform() - 20);
            sp.ng = Vec3(0, 1, 0);
            ones += choosePart(*s, sp) == d.materials[size_t(mix)].blendPart[1] ? 1 : 0;
        }
        const double sd = std::sqrt(amount * (1 - amount) / n);
        INFO("part 1 chosen at " << ones << " of " << n << " points");
        CHECK(std::fabs(double(ones) / n - amount) < 5 * sd);
    }
    const double cosN = 0.6 * lx + 0.8 * ly;
    floor_test::floorRadianceOf(d, [&](Vec3, Vec3) { return 0.6 / M_PI * 2 * (amount * cosN + (1 - amount) * ly); }, "pbrt-mix-bump", {});

    const SceneDesc a =
        loadText("mix-aniso.pbrt", R"(MakeNamedMaterial "brushed" "string type" "conductor" "float uroughness" 0.05 "float vroughness" 0.3
MakeNamedMaterial "flat" "string type" "diffuse"
Material "mix" "string materials" [ "flat" "brushed" ] "float amount" 0.5
Shape "trianglemesh" "point3 P" [ -20 0 -20  20 0 -20  20 0 20  -20 0 20 ] "integer indices" [ 0 2 1 0 3 2 ] "point2 uv" [ 0 0  1 0  1 1  0 1 ]
LightSource "distant" "rgb L" [ 1 1 1 ] "point3 from" [ 0 1 0 ] "point3 to" [ 0 0 0 ]
)");
    const std::unique_ptr<Scene> s = Scene::build(a, 1);
    CHECK(s->features.anisotropic);
    CHECK(s->materials[size_t(a.shapes[0].material)].x->anisotropic);
}

// A combined texture as a shape's alpha (issue 43): pbrt's cut-out by a scale texture of a
// constant bilerp 0.6 times 0.5, opacity 0.3 everywhere. A diffuse floor (rho 0.6) that fills
// the view under a uniform sky L = 2 is the sky with probability 0.7 and rho L with 0.3:
// 0.7 L + 0.3 rho L = 1.76, in PT and BPT (z-tests over 8 runs; the light tracer's image of
// a cut-out under a sky is heavy-tailed, with a constant alpha too).
TEST_CASE("pbrt textures: a scale texture as alpha", "[pbrt][texture][mask]") {
    const SceneDesc d = loadText("alpha-scale.pbrt", R"(Texture "b" "float" "bilerp" "float v00" 0.6 "float v01" 0.6 "float v10" 0.6 "float v11" 0.6
Texture "a" "float" "scale" "texture tex" "b" "float scale" 0.5
Material "diffuse" "rgb reflectance" [ 0.6 0.6 0.6 ]
Shape "trianglemesh" "point3 P" [ -20 0 -20  20 0 -20  20 0 20  -20 0 20 ] "integer indices" [ 0 2 1 0 3 2 ] "point2 uv" [ 0 0  1 0  1 1  0 1 ] "texture alpha" "a"
LightSource "infinite" "rgb L" [ 2 2 2 ]
)");
    const MaterialDesc& m = d.materials[size_t(d.shapes[0].material)];
    REQUIRE(m.opacityTexture >= 0);
    REQUIRE(d.textures[size_t(m.opacityTexture)].kind == TextureKind::Scale);
    for (TracerKind t : {TracerKind::PT, TracerKind::BPT}) {
        rstats::RunStats runs;
        for (int k = 0; k < 8; ++k) runs.add(rstats::blockMeans(render(d, rstats::renderOptions(t, 64, 70 + uint64_t(k), 1, 2)).image, 4, 1));
        const rstats::ZTestResult z = rstats::zTest(runs, std::vector<double>(16, 0.7 * 2 + 0.3 * 0.6 * 2));
        INFO("tracer " << int(t) << ": " << z.describe());
        CHECK(z.pass);
    }
}
