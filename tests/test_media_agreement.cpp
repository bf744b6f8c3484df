// Media where no closed form exists, judged by agreement (docs/media.md): a heterogeneous
// grid whose density is constant tracks to what the homogeneous medium of that density
// renders; multiple scattering of a point light in an infinite medium, PT against BPT and
// MMLT (the camera is in the medium: not the light tracer, whose estimator has infinite
// variance there). Differences of K-run block means against their standard errors.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "media_scenes.h"
#include "render_stats.h"
#include "wavemmlt/render.h"
#include "wavemmlt/scene_desc.h"

using namespace wmlt;

namespace {

// K-run block means (4 x 4 blocks of a 16 x 16 image) of scene d, per channel.
std::vector<rstats::RunStats> blockRuns(const SceneDesc& d, TracerKind tr, int spp, uint64_t seed, int maxLength) {
    std::vector<rstats::RunStats> runs(3);
    for (int k = 0; k < 6; ++k) {
        RenderOptions o = rstats::renderOptions(tr, spp, seed + uint64_t(k), 1, maxLength);
        if (tr == TracerKind::MMLT) o.chains = 1024;
        const Image img = render(d, o).image;
        for (int c = 0; c < 3; ++c) runs[size_t(c)].add(rstats::blockMeans(img, 4, c));
    }
    return runs;
}

void checkAgree(const std::vector<rstats::RunStats>& a, const std::vector<rstats::RunStats>& b, const std::string& what) {
    for (int c = 0; c < 3; ++c) {
        double ratio = 0;
        const rstats::ZTestResult z = rstats::compareRuns(a[size_t(c)], b[size_t(c)], 1e-4, &ratio);
        INFO(what << ", channel " << c << ": " << z.describe() << ", ratio of means " << ratio);
        CHECK(z.pass);
    }
}

// A closed diffuse box [-2, 2]^3 lit by an area light under its ceiling, the camera inside
// in `medium` (a MakeNamedMedium named "m"); the walls no boundary ("m" on both sides) and
// the light in "m" (pbrt-v4's rule: the MediumInterface in force at its directive).
std::string box(const std::string& medium) {
    return medium + R"(
LookAt 0 0 -1.8  0 0 0  0 1 0
MediumInterface "" "m"
Camera "perspective" "float fov" [ 70 ]
Film "rgb" "integer xresolution" [ 16 ] "integer yresolution" [ 16 ]
PixelFilter "box"
WorldBegin
MediumInterface "m" "m"
Material "diffuse" "rgb reflectance" [ 0.7 0.6 0.5 ]
Shape "trianglemesh" "point3 P" [ -2 -2 -2  2 -2 -2  2 -2 2  -2 -2 2  -2 2 -2  2 2 -2  2 2 2  -2 2 2 ]
  "integer indices" [ 0 2 1 0 3 2  4 5 6 4 6 7  3 6 2 3 7 6  0 4 7 0 7 3  1 2 6 1 6 5  0 1 5 0 5 4 ]
AttributeBegin
AreaLightSource "diffuse" "rgb L" [ 6 6 6 ]
Shape "trianglemesh" "point3 P" [ -0.5 1.99 -0.5  0.5 1.99 -0.5  0.5 1.99 0.5  -0.5 1.99 0.5 ] "integer indices" [ 0 1 2 0 2 3 ]
AttributeEnd
)";
}

}  // namespace

TEST_CASE("media: a constant grid tracks to what the homogeneous medium renders", "[media][render][grid][stat]") {
    // density 1.5 in every voxel of a 4 x 4 x 4 grid over [-8, 8]^3 (its fall to 0 past the outer
    // voxels' centres is far outside the box) against the homogeneous medium of 1.5 times its
    // coefficients.
    std::string dens;
    for (int i = 0; i < 64; ++i) dens += "1.5 ";
    const SceneDesc grid = media_scenes::load(
        "const-grid.pbrt",
        box(R"(MakeNamedMedium "m" "string type" "uniformgrid" "rgb sigma_a" [ 0.05 0.1 0.2 ] "rgb sigma_s" [ 0.3 0.25 0.2 ] "float g" 0.4
  "integer nx" 4 "integer ny" 4 "integer nz" 4 "point3 p0" [ -8 -8 -8 ] "point3 p1" [ 8 8 8 ] "float density" [ )" +
            dens + "]"));
    const SceneDesc homogeneous = media_scenes::load(
        "const-homogeneous.pbrt",
        box(R"(MakeNamedMedium "m" "string type" "homogeneous" "rgb sigma_a" [ 0.075 0.15 0.3 ] "rgb sigma_s" [ 0.45 0.375 0.3 ] "float g" 0.4)"));
    REQUIRE(grid.media[0].density.size() == 64);
    for (TracerKind tr : {TracerKind::PT, TracerKind::BPT})
        checkAgree(blockRuns(grid, tr, 64, 600, 10), blockRuns(homogeneous, tr, 64, 610, 10), "tracer " + std::to_string(int(tr)));
}

TEST_CASE("media: multiple scattering of a point light in an infinite medium, PT against BPT and MMLT", "[media][render][stat]") {
    const SceneDesc d = media_scenes::load("multiple.pbrt", media_scenes::pointLightInFog("0.9 0.7 0.5"));
    const std::vector<rstats::RunStats> pt = blockRuns(d, TracerKind::PT, 256, 700, 30);
    checkAgree(blockRuns(d, TracerKind::BPT, 64, 710, 30), pt, "BPT against PT");
    checkAgree(blockRuns(d, TracerKind::MMLT, 256, 720, 30), pt, "MMLT against PT");
}
