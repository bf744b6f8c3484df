// Emitting media (docs/media.md): the source term sigma_a Le, gathered along the camera
// walks' segments (exactly in a homogeneous medium, by the collision estimator in a grid):
// PT, BPT and MMLT against closed forms. An absorbing, emitting slab behind pass-through
// boundaries in front of a black wall: Le (1 - exp(-sigma_a)) per channel. Furnaces: a closed
// box whose black walls emit L = 1, filled with a medium that scatters, absorbs and emits
// Le = 1 (homogeneous; a grid of random densities with a grid of Lescale; an rgbgrid with an
// Le per voxel): the radiance is 1 everywhere (what the medium absorbs it emits again; the
// grids reach half a voxel past the box, since pbrt's grids, Le among them, fall to 0
// between their outer voxels' centres and their edges). The
// light tracer refuses emitting media; bad emission values name their line.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "media_scenes.h"
#include "render_stats.h"
#include "wavemmlt/error.h"
#include "wavemmlt/render.h"
#include "wavemmlt/scene_desc.h"

using namespace wmlt;

namespace {

RenderOptions optionsFor(TracerKind tracer, int spp, uint64_t seed, int maxLength) {
    RenderOptions o = rstats::renderOptions(tracer, spp, seed, 1, maxLength);
    if (tracer == TracerKind::MMLT) {
        o.chains = 1024;
        o.bootstrap = 4096;
    }
    return o;
}

// The furnace (media_scenes.h) in `medium`, a MakeNamedMedium named "glow".
std::string furnace(const std::string& medium) { return media_scenes::furnace(medium, "glow"); }

std::string repeat(const std::string& s, int n) {
    std::string r;
    for (int i = 0; i < n; ++i) r += s;
    return r;
}

}  // namespace

TEST_CASE("emitting media: an absorbing, emitting slab gives Le (1 - exp(-sigma_a)) in PT, BPT and MMLT", "[media][render]") {
    // An orthographic camera looks along +z through a box 1 deep (interface material) of a
    // medium with sigma_a (0.5, 1, 2), no scattering, Le (1, 2, 3), at a black wall; the
    // scene's light is a small quad behind the camera facing away from everything.
    const SceneDesc d = media_scenes::load("emitting-slab.pbrt", R"(LookAt 0 0 -3  0 0 0  0 1 0
Camera "orthographic"
Film "rgb" "integer xresolution" [ 8 ] "integer yresolution" [ 8 ]
PixelFilter "box"
MakeNamedMedium "glow" "string type" "homogeneous" "rgb sigma_a" [ 0.5 1 2 ] "rgb sigma_s" [ 0 0 0 ] "rgb Le" [ 1 2 3 ]
WorldBegin
AttributeBegin
Material "interface"
MediumInterface "glow" ""
Scale 10 10 1
)" + media_scenes::cube(Vec3(0, 0, 0.5f), 0.5f, false) + R"(AttributeEnd
Material "diffuse" "rgb reflectance" [ 0 0 0 ]
Shape "trianglemesh" "point3 P" [ -9 -9 5  9 -9 5  9 9 5  -9 9 5 ] "integer indices" [ 0 1 2 0 2 3 ]
AttributeBegin
AreaLightSource "diffuse" "rgb L" [ 1 1 1 ]
Shape "trianglemesh" "point3 P" [ -0.1 -0.1 -20  0.1 -0.1 -20  0.1 0.1 -20  -0.1 0.1 -20 ] "integer indices" [ 0 1 2 0 2 3 ]
AttributeEnd
)");
    REQUIRE(d.media.size() == 1);
    CHECK(d.media[0].Le.z == Approx(3.0f));
    // PT's and BPT's estimators are exact here (the emission integrated in closed form, nothing
    // behind the slab): each pixel is the closed form up to float rounding. MMLT's chains
    // spread the same total over the pixels at random: its block means against their errors.
    const auto runs = rstats::channelRuns(6, 2, [&](int k) { return render(d, optionsFor(TracerKind::MMLT, 64, 300 + uint64_t(k), 6)).image; });
    for (int c = 0; c < 3; ++c) {
        const double sigma = c == 0 ? 0.5 : c == 1 ? 1.0 : 2.0, expected = double(c + 1) * (1 - std::exp(-sigma));
        const rstats::ZTestResult z = rstats::zTest(runs[size_t(c)], std::vector<double>(16, expected));
        INFO("MMLT, channel " << c << ": " << z.describe());
        CHECK(z.pass);
    }
    for (TracerKind tr : {TracerKind::PT, TracerKind::BPT}) {
        const Image img = render(d, optionsFor(tr, 16, 300, 6)).image;
        for (int c = 0; c < 3; ++c) {
            const double sigma = c == 0 ? 0.5 : c == 1 ? 1.0 : 2.0, expected = double(c + 1) * (1 - std::exp(-sigma));
            double worst = 0;
            for (size_t i = 0; i < size_t(img.width) * size_t(img.height); ++i)
                worst = std::max(worst, std::fabs(double(img.rgb[3 * i + size_t(c)]) / expected - 1));
            INFO("tracer " << int(tr) << " channel " << c << ": largest relative difference " << worst);
            CHECK(worst < 1e-4);
        }
    }
}

TEST_CASE("emitting media: furnaces (homogeneous, a density grid with a Lescale grid, an rgbgrid's Le) are 1", "[media][render][stat]") {
    uint64_t h = 99;
    const SceneDesc homogeneous = media_scenes::load(
        "glow-a.pbrt",
        furnace(
            R"(MakeNamedMedium "glow" "string type" "homogeneous" "rgb sigma_a" [ 0.3 0.6 0.9 ] "rgb sigma_s" [ 0.9 0.6 0.3 ] "float g" 0.3 "rgb Le" [ 1 1 1 ])"));
    const SceneDesc grid = media_scenes::load(
        "glow-b.pbrt",
        furnace(R"(MakeNamedMedium "glow" "string type" "uniformgrid" "rgb sigma_a" [ 0.3 0.6 0.9 ] "rgb sigma_s" [ 0.9 0.6 0.3 ] "float g" -0.2
  "integer nx" 3 "integer ny" 3 "integer nz" 3 "point3 p0" [ -3 -3 -3 ] "point3 p1" [ 3 3 3 ] "rgb Le" [ 0.5 0.5 0.5 ]
  "float density" [ )" +
                media_scenes::randomNumbers(27, 0, 2, h) + "] \"float Lescale\" [ " + repeat("2 ", 27) + "]"));
    const SceneDesc rgb = media_scenes::load(
        "glow-c.pbrt", furnace(R"(MakeNamedMedium "glow" "string type" "rgbgrid" "float g" 0.5 "integer nx" 2 "integer ny" 2 "integer nz" 2
  "point3 p0" [ -4 -4 -4 ] "point3 p1" [ 4 4 4 ] "rgb sigma_a" [ )" +
                               media_scenes::randomNumbers(24, 0, 1.5, h) + "] \"rgb sigma_s\" [ " + media_scenes::randomNumbers(24, 0, 1.5, h) +
                               "] \"rgb Le\" [ " + repeat("1 ", 24) + "]"));
    REQUIRE(grid.media[0].LeGrid.size() == 27);
    REQUIRE(rgb.media[0].LeGrid.size() == 8);
    for (const SceneDesc* d : {&homogeneous, &grid, &rgb})
        for (TracerKind tr : {TracerKind::PT, TracerKind::BPT, TracerKind::MMLT}) {
            rstats::RunStats runs;
            for (int k = 0; k < 6; ++k) runs.add(rstats::blockMeans(render(*d, optionsFor(tr, 16, 310 + uint64_t(k), kMaxPathLength)).image, 2, 1));
            const rstats::ZTestResult z = rstats::zTest(runs, std::vector<double>(16, 1.0));
            INFO((d == &homogeneous ? "homogeneous" : d == &grid ? "grid" : "rgbgrid") << ", tracer " << int(tr) << ": " << z.describe());
            CHECK(z.pass);
        }
}

TEST_CASE("emitting media: the light tracer refuses them, bad emission values name their line", "[media][bad-input]") {
    const SceneDesc d = media_scenes::load("glow-lt.pbrt", furnace(R"(MakeNamedMedium "glow" "string type" "homogeneous" "rgb Le" [ 1 1 1 ])"));
    CHECK_THROWS_WITH(render(d, rstats::renderOptions(TracerKind::LT, 1, 1, 1, 2)), Catch::Contains("emitting medium"));
    auto errorOf = [](const std::string& name, const std::string& text) -> std::string {
        try {
            media_scenes::load(name, text);
        } catch (const InputError& e) {
            return e.what();
        }
        return "no error";
    };
    const std::string head = "Camera \"perspective\"\nWorldBegin\nLightSource \"point\"\n";
    CHECK_THAT(errorOf("le1.pbrt", head + "MakeNamedMedium \"f\" \"string type\" \"homogeneous\" \"float Lescale\" -1 \"rgb Le\" [ 1 1 1 ]\n"),
               Catch::Contains("le1.pbrt:4") && Catch::Contains("Lescale"));
    CHECK_THAT(errorOf("le2.pbrt", head + "MakeNamedMedium \"f\" \"string type\" \"uniformgrid\" \"integer nx\" 2 \"float density\" [ 1 1 ] "
                                          "\"rgb Le\" [ 1 1 1 ] \"float Lescale\" [ 1 2 3 ]\n"),
               Catch::Contains("le2.pbrt:4") && Catch::Contains("3 Lescale values for a 2 x 1 x 1 grid"));
    CHECK_THAT(
        errorOf("le3.pbrt", head + "MakeNamedMedium \"f\" \"string type\" \"uniformgrid\" \"float density\" [ 1 ] \"float temperature\" [ 900 ]\n"),
        Catch::Contains("le3.pbrt:4") && Catch::Contains("temperature"));
}
