// Writing a thesis-format scene back with the camera and settings an interactive session
// set (scene/thesis/write_scene.cpp, issue 28): loading the result gives exactly that camera
// and those settings, and the same scene otherwise.
#include <catch2/catch.hpp>

#include <string>

#include "app/camera_control.h"
#include "scene/read_file.h"
#include "wavemmlt/error.h"
#include "wavemmlt/scene_desc.h"

using namespace wmlt;

TEST_CASE("the thesis format written back: the camera and settings reload exactly", "[scene][write]") {
    const std::string dir = std::string(WAVEMMLT_TEST_DATA) + "/scenes/seed-room";
    const std::string path = dir + "/seed-room.xml";
    const std::string xml = readWholeFile(path, "the scene file");
    const SceneDesc original = loadScene(path);
    CameraDesc cam = orbit(original.camera, 0.4f, 0.15f);
    cam = zoom(dolly(cam, 0.3f), 0.2f);
    cam.dof = true;
    cam.focalLength = 3.1234567f;
    cam.fStop = 2.7182817f;
    Settings st = original.settings;
    st.width = 123;
    st.height = 45;
    st.samples = 3;
    st.tracer = TracerKind::BPT;
    st.maxPathLength = 7;
    st.minPathLength = 2;
    st.probLarge = 0.123456789f;
    const SceneDesc back = loadSceneFromString(thesisSceneWithView(xml, path, cam, st), "back.xml", dir);
    for (int a = 0; a < 3; ++a) {
        CHECK(back.camera.position[a] == cam.position[a]);
        CHECK(back.camera.lookAt[a] == cam.lookAt[a]);
        CHECK(back.camera.up[a] == cam.up[a]);
    }
    CHECK(back.camera.fovDegrees == cam.fovDegrees);
    CHECK(back.camera.dof);
    CHECK(back.camera.focalLength == cam.focalLength);
    CHECK(back.camera.fStop == cam.fStop);
    CHECK(back.settings.width == 123);
    CHECK(back.settings.height == 45);
    CHECK(back.settings.samples == 3);
    CHECK(back.settings.tracer == TracerKind::BPT);
    CHECK(back.settings.maxPathLength == 7);
    CHECK(back.settings.minPathLength == 2);
    CHECK(back.settings.probLarge == st.probLarge);
    // the rest of the scene as it was
    CHECK(back.shapes.size() == original.shapes.size());
    CHECK(back.materials.size() == original.materials.size());
    CHECK(back.lights.size() == original.lights.size());
    CHECK(back.settings.output == original.settings.output);
    CHECK(back.settings.envMap == original.settings.envMap);
    // not a thesis-format scene
    CHECK_THROWS_AS(thesisSceneWithView("<scene version=\"3.0.0\"/>", "m.xml", cam, st), InputError);
}
