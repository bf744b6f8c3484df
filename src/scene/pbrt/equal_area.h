// pbrt-v4's equal-area octahedral parameterisation of the sphere (Clarberg 2008), in which it
// stores environment maps: the square [0, 1]^2 folded onto the octahedron and mapped so that
// equal areas of the square are equal solid angles. Used by the importer to resample such a
// map onto wavemmlt's latitude-longitude grid.
#pragma once
#include <cmath>

#include "wavemmlt/math.h"

namespace wmlt::pbrt {

// The unit direction at (u, v) in [0, 1]^2.
inline Vec3 equalAreaSquareToSphere(double u, double v) {
    const double su = 2 * u - 1, sv = 2 * v - 1, au = std::fabs(su), av = std::fabs(sv);
    const double signedDistance = 1 - (au + av), d = std::fabs(signedDistance), r = 1 - d;
    const double phi = (r == 0 ? 1 : (av - au) / r + 1) * M_PI / 4;
    const double z = std::copysign(1 - r * r, signedDistance);
    const double s = r * std::sqrt(std::max(0.0, 2 - r * r));
    return Vec3(float(std::copysign(std::cos(phi), su) * s), float(std::copysign(std::sin(phi), sv) * s), float(z));
}

// Its inverse: (u, v) in [0, 1]^2 of the unit direction d.
inline void equalAreaSphereToSquare(Vec3 d, double& u, double& v) {
    const double x = std::fabs(d.x), y = std::fabs(d.y), z = std::fabs(d.z);
    const double r = std::sqrt(std::max(0.0, 1 - z));
    const double a = std::max(x, y), b = a == 0 ? 0 : std::min(x, y) / a;
    double phi = std::atan(b) * 2 / M_PI;
    if (x < y) phi = 1 - phi;
    double vv = phi * r, uu = r - vv;
    if (d.z < 0) {  // the southern hemisphere: mirrored across the diagonals
        std::swap(uu, vv);
        uu = 1 - uu;
        vv = 1 - vv;
    }
    uu = std::copysign(uu, double(d.x));
    vv = std::copysign(vv, double(d.y));
    u = 0.5 * (uu + 1);
    v = 0.5 * (vv + 1);
}

}  // namespace wmlt::pbrt
