// A floor under one emitter, seen from above, against its closed form in PT, LT and BPT
// (shared by the Mitsuba plugin tests).
#pragma once
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "kernels/camera.h"
#include "render_stats.h"
#include "wavemmlt/render.h"
#include "wavemmlt/scene_desc.h"

namespace floor_test {
using namespace wmlt;

const std::string kLookingDown = R"(<sensor type="perspective"><float name="fov" value="90"/>
    <transform name="to_world"><lookat origin="0, 1, 0" target="0, 0, 0" up="0, 0, 1"/></transform>)";

// A floor (y = 0, floorBsdf) seen from y = 1 (below the light, which would hide it) by a
// 16 x 16 camera looking down (or `sensor`), lit by `emitter` only, direct light only: the
// exact 4 x 4 block means of the green channel of radiance(p, o), the floor's radiance at p
// towards the camera ray's origin o, averaged over 8 x 8 points per pixel, against K runs
// of each of PT, LT and BPT (rstats::zTest, p = 1e-4).
// `exact`: tracers whose estimate has no variance here (next-event estimation of a
// directional light on a diffuse floor): their block means equal the expected ones to
// float rounding instead.
inline void floorRadianceOf(const SceneDesc& d, const std::function<double(Vec3, Vec3)>& radiance, const std::string& what,
                            const std::vector<TracerKind>& exact);
inline void floorRadiance(const std::string& emitter, const std::function<double(Vec3, Vec3)>& radiance, const std::string& what,
                          const std::vector<TracerKind>& exact, const std::string& floorBsdf, const std::string& dir = ".",
                          const std::string& sensor = kLookingDown) {
    const SceneDesc d = loadMitsubaFromString(R"(<scene version="3.0.0">
  <integrator type="path"><integer name="max_depth" value="2"/></integrator>
  )" + sensor + R"(
    <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/><rfilter type="box"/></film></sensor>
  <shape type="rectangle"><transform name="to_world"><scale value="20"/><rotate x="1" angle="-90"/></transform>
    )" + floorBsdf + R"(</shape>
)" + emitter + "\n</scene>",
                                              what + ".xml", dir);
    floorRadianceOf(d, radiance, what, exact);
}

// The same for a scene already loaded (any format): an image of the floor y = 0 (16 x 16,
// or the scene's size when a multiple of 4 in both directions: its 4 x 4 blocks).
inline void floorRadianceOf(const SceneDesc& d, const std::function<double(Vec3, Vec3)>& radiance, const std::string& what,
                            const std::vector<TracerKind>& exact) {
    const int W = d.settings.width, H = d.settings.height;
    REQUIRE(W % 4 == 0);
    REQUIRE(H % 4 == 0);
    const Camera cam = makeCamera(d.camera, W, H);
    std::vector<double> expected(size_t(W / 4) * size_t(H / 4), 0.0);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            for (int j = 0; j < 8; ++j)
                for (int i = 0; i < 8; ++i) {
                    Vec3 o, dir;
                    generateCameraRay(cam, float(x) + (float(i) + 0.5f) / 8, float(y) + (float(j) + 0.5f) / 8, 0.5f, 0.5f, o, dir);
                    const Vec3 p = o + dir * (-o.y / dir.y);
                    expected[size_t(y / 4) * size_t(W / 4) + size_t(x / 4)] += radiance(p, o) / (16 * 64);
                }
    for (TracerKind t : {TracerKind::PT, TracerKind::LT, TracerKind::BPT}) {
        if (std::find(exact.begin(), exact.end(), t) != exact.end()) {
            const std::vector<double> m = rstats::blockMeans(render(d, rstats::renderOptions(t, 64, 90, 1, 2)).image, 4, 1);
            for (size_t i = 0; i < m.size(); ++i) CHECK(m[i] == Approx(expected[i]).epsilon(1e-5));
            continue;
        }
        rstats::RunStats runs;
        for (int k = 0; k < 8; ++k) runs.add(rstats::blockMeans(render(d, rstats::renderOptions(t, 64, 90 + uint64_t(k), 1, 2)).image, 4, 1));
        const rstats::ZTestResult z = rstats::zTest(runs, expected);
        INFO(what << ", tracer " << int(t) << ": " << z.describe());
        CHECK(z.pass);
    }
}

// The irradiance at p on the floor from a uniform rectangle [x1, x2] x [z1, z2] of unit
// radiance facing it at height h: with G(a, b) = (1 / 2) (A atan(b / sqrt(a^2 + h^2)) +
// B atan(a / sqrt(b^2 + h^2))), A = a / sqrt(a^2 + h^2), B = b / sqrt(b^2 + h^2), the
// irradiance below the corner of an a x b rectangle (odd in a and in b), the rectangle's
// is G(x2, z2) - G(x1, z2) - G(x2, z1) + G(x1, z1) in coordinates relative to p.
inline double rectangleIrradiance(Vec3 p, double h, double x1, double x2, double z1, double z2) {
    auto G = [&](double a, double b) {
        const double ra = std::sqrt(a * a + h * h), rb = std::sqrt(b * b + h * h);
        return 0.5 * (a / ra * std::atan(b / ra) + b / rb * std::atan(a / rb));
    };
    x1 -= p.x, x2 -= p.x, z1 -= p.z, z2 -= p.z;
    return G(x2, z2) - G(x1, z2) - G(x2, z1) + G(x1, z1);
}

// A diffuse floor (reflectance rho = 0.6 unless floorBsdf says otherwise): rho / pi E(p),
// E the floor's irradiance at p.
inline void floorUnder(const std::string& emitter, const std::function<double(Vec3)>& irradiance, const std::string& what,
                       const std::vector<TracerKind>& exact = {},
                       const std::string& floorBsdf = R"(<bsdf type="diffuse"><rgb name="reflectance" value="0.6"/></bsdf>)",
                       const std::string& dir = ".", const std::string& sensor = kLookingDown) {
    const double rho = 0.6;
    floorRadiance(
        emitter, [&](Vec3 p, Vec3) { return rho / M_PI * irradiance(p); }, what, exact, floorBsdf, dir, sensor);
}

}  // namespace floor_test
