// Where the camera and the lights are (docs/media.md, "the model"): a point light inside a
// closed ball of fog with the camera outside emits into the fog (the light and
// bidirectional tracers start its paths there; they agree with PT, which never asks), and a
// camera inside a closed boundary whose inside is another medium than the camera's is
// refused with the boundary's line.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "media_scenes.h"
#include "render_stats.h"
#include "wavemmlt/error.h"
#include "wavemmlt/render.h"
#include "wavemmlt/scene_desc.h"

using namespace wmlt;

TEST_CASE("media: a point light inside a closed fog ball emits into the fog", "[media][render][stat]") {
    // The ball (radius 1, interface material) holds fog (sigma_s 1.2, sigma_a 0.2, g 0.3) and
    // a point light at its centre; the camera is outside in vacuum; a diffuse floor below.
    const SceneDesc d = media_scenes::load("lamp-in-fog.pbrt", R"(LookAt 0 0.5 -4  0 0 0  0 1 0
Camera "perspective" "float fov" [ 45 ]
Film "rgb" "integer xresolution" [ 16 ] "integer yresolution" [ 16 ]
PixelFilter "box"
MakeNamedMedium "fog" "string type" "homogeneous" "rgb sigma_a" [ 0.2 0.2 0.2 ] "rgb sigma_s" [ 1.2 1.2 1.2 ] "float g" 0.3
WorldBegin
LightSource "point" "rgb I" [ 3 3 3 ] "point3 from" [ 0 0 0 ]
Material "diffuse" "rgb reflectance" [ 0.6 0.6 0.6 ]
Shape "trianglemesh" "point3 P" [ -6 -1.5 -6  6 -1.5 -6  6 -1.5 6  -6 -1.5 6 ] "integer indices" [ 0 2 1 0 3 2 ]
AttributeBegin
Material "interface"
MediumInterface "fog" ""
Shape "sphere" "float radius" 1
AttributeEnd
)");
    REQUIRE(d.cameraMedium == -1);
    const TracerKind tracers[3] = {TracerKind::PT, TracerKind::LT, TracerKind::BPT};
    std::vector<rstats::RunStats> runs(3);
    for (int tr = 0; tr < 3; ++tr)
        for (int k = 0; k < 6; ++k)
            runs[size_t(tr)].add(rstats::blockMeans(render(d, rstats::renderOptions(tracers[tr], 256, 400 + uint64_t(k), 1, 12)).image, 4, 1));
    for (int tr = 1; tr < 3; ++tr) {
        double ratio = 0;
        const rstats::ZTestResult z = rstats::compareRuns(runs[size_t(tr)], runs[0], 1e-4, &ratio);
        INFO("tracer " << int(tracers[tr]) << " against PT: " << z.describe() << ", ratio of means " << ratio);
        CHECK(z.pass);
    }
}

TEST_CASE("media: a camera inside a closed boundary of another medium is refused", "[media][bad-input]") {
    // The camera (in vacuum: no MediumInterface before Camera) inside a fog ball.
    const SceneDesc d = media_scenes::load("camera-in-ball.pbrt", R"(LookAt 0 0 0  0 0 1  0 1 0
Camera "perspective"
MakeNamedMedium "fog" "string type" "homogeneous"
WorldBegin
LightSource "point" "point3 from" [ 0 0 0.5 ]
AttributeBegin
Material "interface"
MediumInterface "fog" ""
Shape "sphere" "float radius" 2
AttributeEnd
)");
    try {
        render(d, rstats::renderOptions(TracerKind::PT, 1, 1, 1, 2));
        FAIL("rendered a camera in the wrong medium");
    } catch (const InputError& e) {
        CHECK_THAT(std::string(e.what()), Catch::Contains("camera-in-ball.pbrt:9") && Catch::Contains("the camera is inside") &&
                                              Catch::Contains("medium \"fog\"") && Catch::Contains("vacuum"));
    }
}
