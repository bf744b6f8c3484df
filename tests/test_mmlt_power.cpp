// MMLT against BPT with stated power (power.h): K = 32 independent runs per side on each
// scene, and per property one test at p = 1e-4: the image's brightness, its blocks, the
// blocks' shape, each path length's brightness (the normalisation b_k of that length)
// and each length's blocks. Each test prints the bias it detects with probability 0.9
// (std::cout; WMLT_TEST_VERBOSE=1 prints every length), and asserts the power it claims:
//  - the image's brightness: an error of 1% on the Cornell box (1.5% for lengths 3..5), 5%
//    in the seed room and the outdoor scene, 6% in the caustic scene (its glass and mirror
//    highlights make a few rare paths carry much of the image: the runs' brightness varies);
//  - a length's brightness: an error of 1% in any length that carries >= 25% of the
//    image (Cornell box), i.e. a 1% error in one length's normalisation fails the test.
// Scenes: the Cornell box with MinPathLength 1, 2 and 3 (the BPT reference of lengths >= 2
// is the sum of its length images, so one set of BPT runs serves all three), the glass
// and mirror caustic scene, the seed room (its light hidden above a drop ceiling), and an
// outdoor scene under an environment map seen through a thin lens, with a bump-mapped floor.
// Tagged [stat]: the sanitizer pass leaves them out (scripts/test.sh).
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

constexpr int K = 32;
constexpr double kP = 1e-4;

RenderOptions bpt(int spp, int minLength, int maxLength) { return rstats::renderOptions(TracerKind::BPT, spp, 0, minLength, maxLength); }

RenderOptions mmlt(int spp, int minLength, int maxLength, int chains, int bootstrap) {
    RenderOptions o = rstats::renderOptions(TracerKind::MMLT, spp, 0, minLength, maxLength);
    o.chains = chains;
    o.bootstrap = bootstrap;
    return o;
}

SceneDesc cornell(int size, int maxLength) {
    SceneDesc d = rstats::cornell64(maxLength);
    d.settings.width = d.settings.height = size;
    return d;
}

// An open scene under the sky with a sun (render_stats.h), seen through a thin lens
// focused on the middle ball, with a bump-mapped (checker) glossy floor, a matte ball and
// a glass ball.
std::string outdoorXml() {
    return R"(<Scene>
  <Settings><Width value="16"/><Height value="16"/><MaxPathLength value="5"/><EnvMap name="sky.pfm"/></Settings>
  <Camera Type="Camera"><Position x="0" y="1.0" z="-3.5"/><LookAt x="0" y="0.4" z="0"/><FOV value="40"/>
    <DOF value="1"/><F-Length value="3.5"/><F-Stop value="4"/></Camera>
  <Texture Type="Checker" ID="1"><Colour1 r="0" g="0" b="0"/><Colour2 r="1" g="1" b="1"/><Repeat u="6" v="6"/></Texture>
  <Shader Type="Glossy" ID="0"><Diffuse r="0.5" g="0.45" b="0.4"/><Specular r="0.3" g="0.3" b="0.3"/>
    <Shininess value="40"/><Bump value="1"/></Shader>
  <Shader Type="Matte" ID="1"><Diffuse r="0.7" g="0.3" b="0.2"/></Shader>
  <Shader Type="Dielectric" ID="2"><Reflect r="1" g="1" b="1"/><Refract r="1" g="1" b="1"/>
    <iIOR value="1.5"/><oIOR value="1"/></Shader>
  <Geometry Type="Plane" ID="floor"><Position x="0" y="0" z="0"/><Width value="6"/><Depth value="6"/><Shader value="0"/></Geometry>
  <Geometry Type="Sphere" ID="ball"><Position x="-0.5" y="0.45" z="0"/><Radius value="0.45"/><Shader value="1"/></Geometry>
  <Geometry Type="Sphere" ID="glass"><Position x="0.6" y="0.35" z="-0.5"/><Radius value="0.35"/><Shader value="2"/></Geometry>
</Scene>
)";
}

}  // namespace

TEST_CASE("MMLT power: Cornell box, MinPathLength 1, 2 and 3, every length against BPT", "[mmlt][stat]") {
    const int L = 5, B = 4;
    const SceneDesc desc = cornell(16, L);
    const std::vector<power::Runs> ref = power::tracerRuns(desc, bpt(64, 1, L), K, 10000, B, {1, 2, 3});
    for (int kMin : {1, 2, 3}) {
        const power::Runs m = power::tracerRuns(desc, mmlt(256, kMin, L, 1024, 65536), K, 11000 + 100 * uint64_t(kMin), B)[0];
        power::compare(m, ref[size_t(kMin - 1)], "MMLT vs BPT", "Cornell box, lengths " + std::to_string(kMin) + ".." + std::to_string(L), kP,
                       power::Claims{kMin < 3 ? 0.01 : 0.015, kMin == 1 ? 0.01 : 0.0});
    }
}

TEST_CASE("MMLT power: glass and mirror caustics against BPT", "[mmlt][stat]") {
    const int L = 6, B = 4;
    const SceneDesc desc = loadSceneFromString(rstats::causticXml(16, L), "caustic.xml", ".");
    const power::Runs ref = power::tracerRuns(desc, bpt(256, 1, L), K, 12000, B)[0];
    const power::Runs m = power::tracerRuns(desc, mmlt(1024, 1, L, 1024, 1 << 16), K, 13000, B)[0];
    power::compare(m, ref, "MMLT vs BPT", "caustic scene", kP, power::Claims{0.06, 0});
}

TEST_CASE("MMLT power: the seed room (light above a drop ceiling) against BPT", "[mmlt][stat]") {
    const int L = 6, B = 4;
    SceneDesc desc = loadScene(std::string(WAVEMMLT_TEST_DATA) + "/scenes/seed-room/seed-room.xml");
    desc.settings.width = desc.settings.height = 16;
    desc.settings.maxPathLength = L;
    const power::Runs ref = power::tracerRuns(desc, bpt(256, 1, L), K, 14000, B)[0];
    const power::Runs m = power::tracerRuns(desc, mmlt(1024, 1, L, 1024, 1 << 14), K, 15000, B)[0];
    power::compare(m, ref, "MMLT vs BPT", "seed room", kP, power::Claims{0.05, 0});
}

TEST_CASE("MMLT power: environment map, thin lens and bump mapping against BPT", "[mmlt][stat]") {
    const int L = 5, B = 4;
    const std::string dir = rstats::tempDir("mmlt-power-outdoor");
    writeImage(dir + "/sky.pfm", rstats::skyWithSun());
    const SceneDesc desc = loadSceneFromString(outdoorXml(), "outdoor.xml", dir);
    const power::Runs ref = power::tracerRuns(desc, bpt(64, 1, L), K, 16000, B)[0];
    const power::Runs m = power::tracerRuns(desc, mmlt(256, 1, L, 1024, 1 << 14), K, 17000, B)[0];
    power::compare(m, ref, "MMLT vs BPT", "outdoor (environment map, thin lens, bump)", kP, power::Claims{0.05, 0});
    std::filesystem::remove_all(dir);
}
