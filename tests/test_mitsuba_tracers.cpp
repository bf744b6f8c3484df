// The Mitsuba plugins that change how light is emitted or transported, in every tracer:
// PT, LT and MMLT against BPT on small hand-written scenes (power.h: K = 16 runs per
// tracer, one test per property at p = 1e-4: brightness, blocks (max |z|, Bonferroni) and
// the blocks' shape (sum z^2, chi^2)). Each scene uses one feature where it matters:
// emitters that also reflect (their BSDF), point lights, area lights on meshes, masks,
// and the environment map. The analytic checks are in test_mitsuba_plugins.cpp.
// Tagged [stat] (heavy statistical renders, for a pass that leaves those out).
#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "power.h"
#include "render_stats.h"
#include "wavemmlt/image.h"
#include "wavemmlt/render.h"
#include "wavemmlt/scene_desc.h"

using namespace wmlt;

namespace {

constexpr int K = 16;
constexpr double kP = 1e-4;

struct Tracer {
    TracerKind kind;
    int spp;
};

const char* name(TracerKind t) { return t == TracerKind::PT ? "PT" : t == TracerKind::LT ? "LT" : t == TracerKind::BPT ? "BPT" : "MMLT"; }

power::Runs runs(const SceneDesc& d, Tracer t, int block, uint64_t seed0) {
    power::Runs r(block);
    RenderOptions o = rstats::renderOptions(t.kind, t.spp, 0, d.settings.minPathLength, d.settings.maxPathLength);
    if (t.kind == TracerKind::MMLT) {
        o.chains = 1024;
        o.bootstrap = 1 << 14;
    }
    for (int k = 0; k < K; ++k) {
        o.seed = seed0 + uint64_t(k);
        const RenderResult res = render(d, o);
        REQUIRE(res.stats.samplesNonfiniteDiscarded == 0);
        if (t.kind == TracerKind::MMLT) REQUIRE(res.stats.mmlt.replayMismatches == 0);
        r.add(res);
    }
    return r;
}

// Each tracer of `others` against BPT (bptSpp samples per pixel) on the scene `xml`.
void agree(const std::string& what, const std::string& xml, int bptSpp, const std::vector<Tracer>& others, const std::string& dir = ".",
           int block = 4) {
    const SceneDesc d = loadMitsubaFromString(xml, what + ".xml", dir);
    const power::Runs ref = runs(d, {TracerKind::BPT, bptSpp}, block, 5000);
    uint64_t seed = 6000;
    for (const Tracer& t : others) {
        const power::Runs r = runs(d, t, block, seed += 100);
        for (const power::Verdict& v : {power::brightness(r, ref, kP), power::blocks(r, ref, kP), power::scatter(r, ref, kP)}) {
            if (std::getenv("WMLT_TEST_VERBOSE")) std::cout << what << ", " << name(t.kind) << " vs BPT: " << v.text << "\n";
            INFO(what << ", " << name(t.kind) << " vs BPT: " << v.text);
            CHECK(v.pass);
        }
        // Every comparison must be able to see a brightness error of 5 %.
        const power::Verdict b = power::brightness(r, ref, kP);
        INFO(what << ", " << name(t.kind) << ": " << b.text);
        CHECK(b.detectable < 0.05);
    }
}

const std::string kCamera = R"(
  <sensor type="perspective"><float name="fov" value="60"/>
    <transform name="to_world"><lookat origin="0, 1, 3.2" target="0, 1, 0" up="0, 1, 0"/></transform>
    <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/></film>
  </sensor>)";

// An open box (floor, back and side walls, diffuse 0.5), the camera at its open side.
const std::string kBox = R"(
  <bsdf type="diffuse" id="white"><rgb name="reflectance" value="0.5"/></bsdf>
  <shape type="rectangle"><transform name="to_world"><rotate x="1" angle="-90"/></transform><ref id="white"/></shape>
  <shape type="rectangle"><transform name="to_world"><translate z="-1"/><translate y="1"/></transform><ref id="white"/></shape>
  <shape type="rectangle"><transform name="to_world"><rotate y="1" angle="90"/><translate x="-1" y="1"/></transform>
    <bsdf type="diffuse"><rgb name="reflectance" value="0.6, 0.2, 0.2"/></bsdf></shape>
  <shape type="rectangle"><transform name="to_world"><rotate y="1" angle="-90"/><translate x="1" y="1"/></transform>
    <bsdf type="diffuse"><rgb name="reflectance" value="0.2, 0.6, 0.2"/></bsdf></shape>)";

std::string scene(const std::string& body, int maxDepth = 5) {
    return "<scene version=\"3.0.0\"><integrator type=\"path\"><integer name=\"max_depth\" value=\"" + std::to_string(maxDepth) +
           "\"/></integrator>" + kCamera + kBox + body + "\n</scene>\n";
}

}  // namespace

// A ceiling light with a white (0.8, twosided) BSDF over a rough copper plate that sends
// its light back up, and a sphere light with Mitsuba's default diffuse 0.5: light that
// reaches an emitter scatters on (PT's and BPT's camera paths go on past the emitter,
// whose s = 0 strategy ends there; light subpaths no longer stop at emitters).
TEST_CASE("Mitsuba tracers: emitters with a BSDF reflect in every tracer", "[mitsuba][render][stat]") {
    agree("reflecting emitters", scene(R"(
  <shape type="rectangle"><transform name="to_world"><scale x="0.4" y="0.4"/><rotate x="1" angle="90"/><translate y="1.9"/></transform>
    <bsdf type="twosided"><bsdf type="diffuse"><rgb name="reflectance" value="0.8"/></bsdf></bsdf>
    <emitter type="area"><rgb name="radiance" value="4"/></emitter></shape>
  <shape type="rectangle"><transform name="to_world"><scale value="0.5"/><rotate x="1" angle="-90"/><translate y="0.4"/></transform>
    <bsdf type="roughconductor"><float name="alpha" value="0.2"/><rgb name="eta" value="0.2, 0.92, 1.1"/><rgb name="k" value="3.9, 2.45, 2.14"/></bsdf></shape>
  <shape type="sphere"><point name="center" x="0.55" y="0.3" z="0.3"/><float name="radius" value="0.2"/>
    <emitter type="area"><rgb name="radiance" value="2, 1.5, 1"/></emitter></shape>
)"),
          64, {{TracerKind::PT, 64}, {TracerKind::LT, 64}, {TracerKind::MMLT, 256}});
}

// A ceiling light casting shadows through masks: a plate whose opacity is a 4 x 4 checker
// bitmap of 0 and 1 (a leaf's cut-out) and one of opacity 0.4 (stochastic transparency),
// both twosided diffuse: light passes through, reflects off them, and their shadows on the
// floor are partial. Every tracer traces the same filtered rays (Embree's filter on the
// masked shapes only).
TEST_CASE("Mitsuba tracers: masks in every tracer", "[mitsuba][render][stat]") {
    const std::string dir = rstats::tempDir("mitsuba-tracers-mask");
    Image im(4, 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) im.set(x, y, Vec3((x + y) % 2 ? 1.0f : 0.0f));
    writeImage(dir + "/leaf.pfm", im);
    agree("masks", scene(R"(
  <shape type="rectangle"><transform name="to_world"><scale x="0.4" y="0.4"/><rotate x="1" angle="90"/><translate y="1.9"/></transform>
    <emitter type="area"><rgb name="radiance" value="6"/></emitter></shape>
  <shape type="rectangle"><transform name="to_world"><scale value="0.45"/><rotate x="1" angle="-45"/><translate x="-0.45" y="1.1"/></transform>
    <bsdf type="mask"><texture type="bitmap" name="opacity"><string name="filename" value="leaf.pfm"/><string name="filter_type" value="nearest"/></texture>
      <bsdf type="twosided"><bsdf type="diffuse"><rgb name="reflectance" value="0.2, 0.7, 0.2"/></bsdf></bsdf></bsdf></shape>
  <shape type="rectangle"><transform name="to_world"><scale value="0.4"/><rotate x="1" angle="-90"/><translate x="0.45" y="0.35"/></transform>
    <bsdf type="mask"><float name="opacity" value="0.4"/><bsdf type="twosided"><bsdf type="diffuse"><rgb name="reflectance" value="0.8"/></bsdf></bsdf></bsdf></shape>
)"),
          64, {{TracerKind::PT, 64}, {TracerKind::LT, 64}, {TracerKind::MMLT, 256}}, dir);
    std::filesystem::remove_all(dir);
}

// A point light (a delta in position: PT's and BPT's next-event estimation alone find it,
// light subpaths start at it, it is never seen) and a small glowing cube (a triangle mesh
// light: area-uniform over its 12 triangles), over a rough plastic floor patch.
TEST_CASE("Mitsuba tracers: point lights and mesh lights in every tracer", "[mitsuba][render][stat]") {
    agree("point and mesh lights", scene(R"(
  <emitter type="point"><point name="position" x="-0.3" y="1.6" z="0.2"/><rgb name="intensity" value="2, 1.8, 1.5"/></emitter>
  <shape type="cube"><transform name="to_world"><scale value="0.12"/><rotate y="1" angle="30"/><translate x="0.5" y="0.12" z="0.1"/></transform>
    <emitter type="area"><rgb name="radiance" value="3, 4, 6"/></emitter></shape>
  <shape type="rectangle"><transform name="to_world"><scale value="0.5"/><rotate x="1" angle="-90"/><translate x="-0.3" y="0.01"/></transform>
    <bsdf type="roughplastic"><float name="alpha" value="0.15"/><rgb name="diffuse_reflectance" value="0.3, 0.3, 0.6"/></bsdf></shape>
)"),
          64, {{TracerKind::PT, 64}, {TracerKind::LT, 64}, {TracerKind::MMLT, 256}});
}

// Anisotropic roughness (alpha_u != alpha_v) under a ceiling light: a rough copper plate
// turned 30 degrees about its normal (its u direction, the highlight's, off the box's axes)
// and a rough glass sphere. Every tracer must turn the shading frames alike (x along
// dp/du, stages/core/surface.h) for the connections and the sampled directions to agree.
TEST_CASE("Mitsuba tracers: anisotropic roughness in every tracer", "[mitsuba][render][stat][aniso]") {
    agree("anisotropic roughness", scene(R"(
  <shape type="rectangle"><transform name="to_world"><scale x="0.4" y="0.4"/><rotate x="1" angle="90"/><translate y="1.9"/></transform>
    <emitter type="area"><rgb name="radiance" value="5"/></emitter></shape>
  <shape type="rectangle"><transform name="to_world"><scale value="0.5"/><rotate z="1" angle="30"/><rotate x="1" angle="-90"/><translate x="-0.3" y="0.01"/></transform>
    <bsdf type="roughconductor"><float name="alpha_u" value="0.05"/><float name="alpha_v" value="0.4"/><string name="distribution" value="ggx"/>
      <rgb name="eta" value="0.2, 0.92, 1.1"/><rgb name="k" value="3.9, 2.45, 2.14"/></bsdf></shape>
  <shape type="sphere"><point name="center" x="0.45" y="0.35" z="0.2"/><float name="radius" value="0.3"/>
    <bsdf type="roughdielectric"><float name="alpha_u" value="0.3"/><float name="alpha_v" value="0.08"/></bsdf></shape>
)"),
          64, {{TracerKind::PT, 64}, {TracerKind::LT, 64}, {TracerKind::MMLT, 256}});
}

// A Mitchell filter (B = C = 1/3: negative lobes) on a 16 x 16 film whose every pixel is
// within the filter's radius of an edge or of the light: PT's importance-sampled camera
// samples (signed weights) and LT's and MMLT's splats over the footprint against BPT's
// mix of both, each pixel renormalised at the film's edges alike (docs/filters.md).
TEST_CASE("Mitsuba tracers: a Mitchell filter in every tracer", "[mitsuba][render][stat][filter]") {
    std::string xml = scene(R"(
  <shape type="rectangle"><transform name="to_world"><scale x="0.3" y="0.3"/><rotate x="1" angle="90"/><translate y="1.9"/></transform>
    <emitter type="area"><rgb name="radiance" value="8"/></emitter></shape>
  <shape type="sphere"><point name="center" x="0.3" y="0.4" z="0.1"/><float name="radius" value="0.35"/>
    <bsdf type="roughconductor"><float name="alpha" value="0.2"/></bsdf></shape>
)");
    const std::string film = "</film>";
    xml.replace(xml.find(film), film.size(), "<rfilter type=\"mitchell\"/></film>");
    agree("Mitchell filter", xml, 64, {{TracerKind::PT, 64}, {TracerKind::LT, 64}, {TracerKind::MMLT, 256}});
}

// A ceiling panel whose radiance is a 4 x 4 bitmap (bright and dim texels, bilinear: a
// textured mesh light sampled by its luminance, scene/mesh_light.h) and that reflects
// (twosided diffuse 0.6), seen by the camera, over the box: every tracer reads T at the
// points it samples (next-event estimation, light subpaths) and at the points it hits
// (s = 0, PT's emission), and weighs both with the same density.
TEST_CASE("Mitsuba tracers: a textured area light in every tracer", "[mitsuba][render][stat][meshlight]") {
    const std::string dir = rstats::tempDir("mitsuba-tracers-textured-light");
    Image im(4, 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) im.set(x, y, x == 3 && y < 2 ? Vec3(20.0f, 16.0f, 10.0f) : Vec3(0.5f * float(x + y), 0.4f, 0.3f));
    writeImage(dir + "/panel.pfm", im);
    agree("textured light", scene(R"(
  <shape type="rectangle"><transform name="to_world"><scale x="0.6" y="0.5"/><rotate x="1" angle="70"/><translate y="1.6" z="-0.3"/></transform>
    <bsdf type="twosided"><bsdf type="diffuse"><rgb name="reflectance" value="0.6"/></bsdf></bsdf>
    <emitter type="area"><texture type="bitmap" name="radiance"><string name="filename" value="panel.pfm"/></texture></emitter></shape>
)"),
          64, {{TracerKind::PT, 64}, {TracerKind::LT, 64}, {TracerKind::MMLT, 256}}, dir);
    std::filesystem::remove_all(dir);
}

// blendbsdf on the floor patch and a sphere: a rough copper and a diffuse part weighted by a
// checkerboard (w 0.2 and 0.9), and two rough glasses (alpha 0.2, eta 1.5 and alpha 0.5,
// eta 1.33; w 0.4): the mixture's f and pdf (its adjoint on light subpaths). Then a smooth
// glass (delta lobes) with a rough one: the blend's sample takes the part's delta lobe,
// and BPT connects at its vertices as at a plastic's; LT is left out there (the camera sees
// the delta lobe directly, which light tracing cannot).
TEST_CASE("Mitsuba tracers: blendbsdf in every tracer", "[mitsuba][render][stat][blend]") {
    agree("blendbsdf", scene(R"(
  <shape type="rectangle"><transform name="to_world"><scale x="0.4" y="0.4"/><rotate x="1" angle="90"/><translate y="1.9"/></transform>
    <emitter type="area"><rgb name="radiance" value="5"/></emitter></shape>
  <shape type="rectangle"><transform name="to_world"><scale value="0.5"/><rotate x="1" angle="-90"/><translate x="-0.3" y="0.01"/></transform>
    <bsdf type="blendbsdf"><texture type="checkerboard" name="weight"><rgb name="color0" value="0.2"/><rgb name="color1" value="0.9"/>
      <transform name="to_uv"><scale value="3"/></transform></texture>
      <bsdf type="roughconductor"><float name="alpha" value="0.15"/><rgb name="eta" value="0.2, 0.92, 1.1"/><rgb name="k" value="3.9, 2.45, 2.14"/></bsdf>
      <bsdf type="diffuse"><rgb name="reflectance" value="0.2, 0.3, 0.7"/></bsdf></bsdf></shape>
  <shape type="sphere"><point name="center" x="0.45" y="0.35" z="0.2"/><float name="radius" value="0.3"/>
    <bsdf type="blendbsdf"><float name="weight" value="0.4"/><bsdf type="roughdielectric"><float name="alpha" value="0.2"/></bsdf>
      <bsdf type="roughdielectric"><float name="alpha" value="0.5"/><float name="int_ior" value="1.33"/></bsdf></bsdf></shape>
)"),
          64, {{TracerKind::PT, 64}, {TracerKind::LT, 64}, {TracerKind::MMLT, 256}});
    agree("blendbsdf with a delta part", scene(R"(
  <shape type="rectangle"><transform name="to_world"><scale x="0.4" y="0.4"/><rotate x="1" angle="90"/><translate y="1.9"/></transform>
    <emitter type="area"><rgb name="radiance" value="5"/></emitter></shape>
  <shape type="sphere"><point name="center" x="0.2" y="0.35" z="0.2"/><float name="radius" value="0.3"/>
    <bsdf type="blendbsdf"><float name="weight" value="0.4"/><bsdf type="dielectric"/>
      <bsdf type="roughdielectric"><float name="alpha" value="0.2"/></bsdf></bsdf></shape>
)"),
          64, {{TracerKind::PT, 64}, {TracerKind::MMLT, 256}});
}

// principled: a floor patch with every reflecting lobe (anisotropic: its frame follows
// dp/du; clearcoat, sheen, metallic, textured base colour) and a sphere that transmits
// (spec_trans 0.7: rough refraction tinted by sqrt(base), its adjoint on light subpaths,
// reflection only from inside), under a ceiling light.
TEST_CASE("Mitsuba tracers: principled in every tracer", "[mitsuba][render][stat][principled]") {
    agree("principled", scene(R"(
  <shape type="rectangle"><transform name="to_world"><scale x="0.4" y="0.4"/><rotate x="1" angle="90"/><translate y="1.9"/></transform>
    <emitter type="area"><rgb name="radiance" value="5"/></emitter></shape>
  <shape type="rectangle"><transform name="to_world"><scale value="0.5"/><rotate z="1" angle="30"/><rotate x="1" angle="-90"/><translate x="-0.3" y="0.01"/></transform>
    <bsdf type="principled"><texture type="checkerboard" name="base_color"><rgb name="color0" value="0.8, 0.5, 0.2"/><rgb name="color1" value="0.2, 0.4, 0.8"/>
      <transform name="to_uv"><scale value="3"/></transform></texture>
      <float name="roughness" value="0.4"/><float name="anisotropic" value="0.7"/><float name="metallic" value="0.4"/>
      <float name="clearcoat" value="0.7"/><float name="clearcoat_gloss" value="0.3"/><float name="sheen" value="0.5"/><float name="spec_tint" value="0.3"/></bsdf></shape>
  <shape type="sphere"><point name="center" x="0.45" y="0.35" z="0.2"/><float name="radius" value="0.3"/>
    <bsdf type="principled"><rgb name="base_color" value="0.9, 0.8, 0.6"/><float name="roughness" value="0.35"/>
      <float name="spec_trans" value="0.7"/><float name="eta" value="1.4"/></bsdf></shape>
)"),
          64, {{TracerKind::PT, 64}, {TracerKind::LT, 64}, {TracerKind::MMLT, 256}});
}
