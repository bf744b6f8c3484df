// Scenes of the media tests (test_media.cpp, test_media_mmlt.cpp, test_spectral_tracers.cpp),
// as pbrt-v4 text.
#pragma once
#include <cstdint>
#include <fstream>
#include <string>
#include <utility>

#include "render_stats.h"
#include "wavemmlt/math.h"
#include "wavemmlt/scene_desc.h"

namespace media_scenes {

// The scene of pbrt text `text`, written as `name` in the tests' folder and loaded.
inline wmlt::SceneDesc load(const std::string& name, const std::string& text) {
    static const std::string dir = rstats::tempDir("media");
    const std::string path = dir + "/" + name;
    std::ofstream(path, std::ios::binary) << text;
    return wmlt::loadScene(path);
}

// Fog (sigma_a (0.5, 0.8, 1.2), sigma_s (1, 0.7, 0.3)) in a box [-1, 1]^3 of pbrt interface
// walls under a point light, and no other surface, no material at all: its medium vertices'
// phase samples are the only bounces (MMLT's numbers read, the spectral stage's materials).
inline std::string fogInInterfaceBox(int resolution) {
    const std::string r = std::to_string(resolution);
    return R"(LookAt 0 0.5 -4  0 0 0  0 1 0
Camera "perspective" "float fov" 40
Film "rgb" "integer xresolution" [ )" +
           r + " ] \"integer yresolution\" [ " + r + R"( ]
PixelFilter "box"
Integrator "volpath" "integer maxdepth" [ 6 ]
WorldBegin
LightSource "point" "point3 from" [ 2 3 -2 ] "rgb I" [ 20 20 20 ]
MakeNamedMedium "fog" "string type" "homogeneous" "rgb sigma_a" [ 0.5 0.8 1.2 ] "rgb sigma_s" [ 1 0.7 0.3 ]
MediumInterface "fog" ""
Material "interface"
Shape "trianglemesh" "point3 P" [ -1 -1 -1  1 -1 -1  1 1 -1  -1 1 -1  -1 -1 1  1 -1 1  1 1 1  -1 1 1 ]
  "integer indices" [ 0 2 1 0 3 2  4 5 6 4 6 7  0 1 5 0 5 4  3 7 6 3 6 2  0 4 7 0 7 3  1 2 6 1 6 5 ]
)";
}

// A cube [-h, h]^3 about c as a pbrt trianglemesh, its winding's normals outward (or inward).
inline std::string cube(wmlt::Vec3 c, float h, bool inward) {
    std::string P, idx;
    for (int i = 0; i < 8; ++i)
        P += std::to_string(c.x + ((i & 1) ? h : -h)) + " " + std::to_string(c.y + ((i & 2) ? h : -h)) + " " +
             std::to_string(c.z + ((i & 4) ? h : -h)) + "  ";
    const int quads[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
    auto corner = [&](int i) { return wmlt::Vec3((i & 1) ? h : -h, (i & 2) ? h : -h, (i & 4) ? h : -h); };
    auto triangle = [&](int a, int b, int d) {  // wound so that its normal points as asked
        const wmlt::Vec3 n = cross(corner(b) - corner(a), corner(d) - corner(a));
        const bool out = dot(n, corner(a) + corner(b) + corner(d)) > 0;
        if (out == inward) std::swap(b, d);
        idx += std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(d) + " ";
    };
    for (const auto& q : quads) {
        triangle(q[0], q[1], q[2]);
        triangle(q[0], q[2], q[3]);
    }
    return "Shape \"trianglemesh\" \"point3 P\" [ " + P + "] \"integer indices\" [ " + idx + "]\n";
}

// A furnace: `medium` (pbrt text making a medium named `name`) around the camera, in a
// closed box [-2, 2]^3 of black walls emitting 1 inwards, 8 x 8. The walls are no boundary
// (inside and outside the same medium) and their lights are in the medium: pbrt-v4's rule, a
// light's medium is the MediumInterface in force at its directive.
inline std::string furnace(const std::string& medium, const std::string& name) {
    return medium + R"(
LookAt 0 0 -1.5  0 0 0  0 1 0
MediumInterface "" ")" +
           name + R"("
Camera "perspective" "float fov" [ 60 ]
Film "rgb" "integer xresolution" [ 8 ] "integer yresolution" [ 8 ]
PixelFilter "box"
WorldBegin
MediumInterface ")" +
           name + R"(" ")" + name + R"("
AttributeBegin
Material "diffuse" "rgb reflectance" [ 0 0 0 ]
AreaLightSource "diffuse" "rgb L" [ 1 1 1 ]
)" + cube(wmlt::Vec3(0.0f), 2.0f, true) +
           "AttributeEnd\n";
}

// n numbers in [lo, hi) from a fixed LCG (state h), as pbrt text.
inline std::string randomNumbers(int n, double lo, double hi, uint64_t& h) {
    std::string s;
    for (int i = 0; i < n; ++i) {
        h = h * 6364136223846793005ull + 1442695040888963407ull;
        s += std::to_string(lo + (hi - lo) * (double(h >> 40) / double(1ull << 24))) + " ";
    }
    return s;
}

// A point light (I = 2) at (0.3, 0.2, 2) and the camera at the origin looking along +z, both
// in one homogeneous medium everywhere (sigma_a (0.1, 0.2, 0.4), g 0.4, the given sigma_s), a
// black ball far away the only surface, 16 x 16.
inline std::string pointLightInFog(const std::string& sigmaS) {
    return R"(LookAt 0 0 0  0 0 1  0 1 0
MakeNamedMedium "fog" "string type" "homogeneous" "rgb sigma_a" [ 0.1 0.2 0.4 ] "rgb sigma_s" [ )" +
           sigmaS + R"( ] "float g" 0.4
MediumInterface "" "fog"
Camera "perspective" "float fov" [ 40 ]
Film "rgb" "integer xresolution" [ 16 ] "integer yresolution" [ 16 ]
PixelFilter "box"
WorldBegin
LightSource "point" "rgb I" [ 2 2 2 ] "point3 from" [ 0.3 0.2 2 ]
Material "diffuse" "rgb reflectance" [ 0 0 0 ]
Translate 0 0 1000
Shape "sphere" "float radius" 1
)";
}

// A rough dielectric ball (eta 1.5) filled with a coloured scattering medium (sigma_s
// (2, 1.5, 1), sigma_a (0.05, 0.1, 0.2), g 0.3) on a floor under an area light, the camera
// outside in vacuum, 16 x 16.
inline std::string glassBall() {
    return R"(LookAt 0 1 -4  0 0.6 0  0 1 0
Camera "perspective" "float fov" [ 35 ]
Film "rgb" "integer xresolution" [ 16 ] "integer yresolution" [ 16 ]
PixelFilter "box"
MakeNamedMedium "milk" "string type" "homogeneous" "rgb sigma_a" [ 0.05 0.1 0.2 ] "rgb sigma_s" [ 2 1.5 1 ] "float g" 0.3
WorldBegin
AttributeBegin
AreaLightSource "diffuse" "rgb L" [ 4 4 4 ]
Shape "trianglemesh" "point3 P" [ -1.5 3 -1.5  1.5 3 -1.5  1.5 3 1.5  -1.5 3 1.5 ] "integer indices" [ 0 1 2 0 2 3 ]
AttributeEnd
Material "diffuse" "rgb reflectance" [ 0.6 0.6 0.6 ]
Shape "trianglemesh" "point3 P" [ -5 0 -5  5 0 -5  5 0 5  -5 0 5 ] "integer indices" [ 0 2 1 0 3 2 ]
AttributeBegin
Material "dielectric" "float eta" 1.5 "float roughness" 0.3
MediumInterface "milk" ""
Translate 0 0.7 0
Shape "sphere" "float radius" 0.7
AttributeEnd
)";
}

}  // namespace media_scenes
