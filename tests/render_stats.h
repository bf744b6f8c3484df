// Test helpers for renders: options as the command line makes them, temporary folders,
// small scenes. The statistics that compare Monte Carlo renders (RunStats, zTest,
// compareRuns, blockMeans) are in src/image/compare.h, shared with the Python module.
#pragma once
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "chi2.h"
#include "image/compare.h"
#include "wavemmlt/image.h"
#include "wavemmlt/render.h"
#include "wavemmlt/scene_desc.h"

namespace rstats {

// Each channel's block means (B x B pixels) of K images, image(k) for k = 0..K-1, each
// rendered once for all three channels: channelRuns(K, B, image)[c] is what a channel-by-
// channel test compares (the same runs as rendering the same seeds again for each channel).
template <class ImageOf>
std::array<RunStats, 3> channelRuns(int K, int B, ImageOf&& image) {
    std::array<RunStats, 3> runs;
    for (int k = 0; k < K; ++k) {
        const wmlt::Image img = image(k);
        for (int c = 0; c < 3; ++c) runs[size_t(c)].add(blockMeans(img, B, c));
    }
    return runs;
}

// Options for a test render: spp samples per pixel stratified as the CLI does, 2 threads.
inline wmlt::RenderOptions renderOptions(wmlt::TracerKind tracer, int spp, uint64_t seed, int minLength, int maxLength, int threads = 2) {
    wmlt::RenderOptions o;
    o.tracer = tracer;
    o.spp = spp;
    o.strataPerAxis = wmlt::strataForSpp(spp);
    o.threads = threads;
    o.seed = seed;
    o.minPathLength = minLength;
    o.maxPathLength = maxLength;
    return o;
}

// The number after "key": in a --stats JSON file's text (NaN when missing).
inline double jsonNumber(const std::string& json, const std::string& key) {
    const size_t at = json.find("\"" + key + "\": ");
    return at == std::string::npos ? std::nan("") : std::atof(json.c_str() + at + key.size() + 4);
}

// A fresh folder for a test's files: $TMPDIR (or /tmp)/wmlt-<name>-<pid>.
inline std::string tempDir(const std::string& name) {
    const char* tmp = std::getenv("TMPDIR");
    std::string dir = std::string(tmp ? tmp : "/tmp") + "/wmlt-" + name + "-" + std::to_string(getpid());
    std::filesystem::create_directories(dir);
    return dir;
}

// A 16 x 8 sky: a blue gradient above the horizon, dark ground below, a small bright sun.
inline wmlt::Image skyWithSun() {
    wmlt::Image sky(16, 8);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 16; ++x) sky.set(x, y, y < 4 ? wmlt::Vec3(0.4f + 0.1f * y, 0.6f, 0.9f - 0.1f * y) : wmlt::Vec3(0.2f, 0.15f, 0.1f));
    sky.set(5, 1, wmlt::Vec3(40.0f, 36.0f, 30.0f));
    return sky;
}

// A glass ball and a mirror ball above a glossy floor, lit by a sphere light: caustics
// (light through glass onto the floor), glossy reflections, and specular chains seen
// directly by the camera (sampled by s = 0 and s = 1 only).
inline std::string causticXml(int size, int maxLength, const std::string& intensity = "8", const std::string& lightY = "2.4") {
    return R"(<Scene>
  <Settings><Width value=")" +
           std::to_string(size) + R"("/><Height value=")" + std::to_string(size) + R"("/><MaxPathLength value=")" + std::to_string(maxLength) +
           R"("/></Settings>
  <Camera Type="Camera"><Position x="0" y="0.9" z="-2.5"/><LookAt x="0" y="0.3" z="0"/><FOV value="45"/></Camera>
  <Shader Type="Glossy" ID="0"><Diffuse r="0.4" g="0.35" b="0.3"/><Specular r="0.4" g="0.4" b="0.4"/>
    <Shininess value="30"/></Shader>
  <Shader Type="Dielectric" ID="1"><Reflect r="1" g="1" b="1"/><Refract r="1" g="1" b="1"/>
    <iIOR value="1.5"/><oIOR value="1"/></Shader>
  <Shader Type="Reflective" ID="2"><Reflect r="0.9" g="0.9" b="0.9"/></Shader>
  <Geometry Type="Plane" ID="floor"><Position x="0" y="0" z="0"/><Width value="6"/><Depth value="6"/><Shader value="0"/></Geometry>
  <Geometry Type="Sphere" ID="glass"><Position x="-0.3" y="0.6" z="0"/><Radius value="0.35"/><Shader value="1"/></Geometry>
  <Geometry Type="Sphere" ID="mirror"><Position x="0.55" y="0.35" z="0.3"/><Radius value="0.3"/><Shader value="2"/></Geometry>
  <Light Type="Area" ID="light"><Position x="-0.2" y=")" +
           lightY + R"(" z="0.2"/><Radius value="0.3"/>
    <Intensity value=")" +
           intensity + R"("/><Colour r="1" g="0.9" b="0.8"/></Light>
</Scene>
)";
}

// The Cornell box test copy (Tungsten's reference scene) at 64 x 64, paths up to maxLength.
inline wmlt::SceneDesc cornell64(int maxLength) {
    wmlt::SceneDesc d = wmlt::loadScene(std::string(WAVEMMLT_TEST_DATA) + "/scenes/bitterli-cornell/bitterli-cornell-256.xml");
    d.settings.width = 64;
    d.settings.height = 64;
    d.settings.maxPathLength = maxLength;
    return d;
}

}  // namespace rstats
