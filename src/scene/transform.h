// The object transform of scene-format.md ("Coordinates and units"):
//   toWorld = translate(Position) * Rz * Ry * Rx * scale,
// rotations in degrees, counter-clockwise seen from the positive end of each axis
// (the standard right-handed matrices), so Rz(90) turns +y into -x.
// Composed and inverted in double precision; multiples of 90 degrees are exact.
#pragma once
#include <cmath>

#include "wavemmlt/math.h"

namespace wmlt {

struct Mat3d {
    double m[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
};

inline Mat3d mul(const Mat3d& a, const Mat3d& b) {
    Mat3d r;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) r.m[i][j] = a.m[i][0] * b.m[0][j] + a.m[i][1] * b.m[1][j] + a.m[i][2] * b.m[2][j];
    return r;
}

// sin and cos of an angle in degrees, exact for multiples of 90 (no 6e-17 noise that
// would tilt an axis-aligned wall).
inline void sinCosDegrees(double deg, double& s, double& c) {
    double q = std::fmod(deg, 360.0);
    if (q < 0) q += 360.0;
    if (q == 0) {
        s = 0;
        c = 1;
        return;
    }
    if (q == 90) {
        s = 1;
        c = 0;
        return;
    }
    if (q == 180) {
        s = 0;
        c = -1;
        return;
    }
    if (q == 270) {
        s = -1;
        c = 0;
        return;
    }
    const double r = deg * 3.14159265358979323846 / 180.0;
    s = std::sin(r);
    c = std::cos(r);
}

// Right-handed rotation about axis 0 (x), 1 (y) or 2 (z).
inline Mat3d rotationDegrees(int axis, double deg) {
    double s, c;
    sinCosDegrees(deg, s, c);
    Mat3d r;
    const int i = (axis + 1) % 3, j = (axis + 2) % 3;  // x: (y, z), y: (z, x), z: (x, y)
    r.m[i][i] = c;
    r.m[i][j] = -s;
    r.m[j][i] = s;
    r.m[j][j] = c;
    return r;
}

inline Affine toAffine(const Mat3d& l, const double t[3]) {
    Affine a;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) a.m[i][j] = float(l.m[i][j]);
        a.m[i][3] = float(t[i]);
    }
    return a;
}

// toWorld = T(position) * Rz * Ry * Rx * S(scale); toLocal is its inverse.
// Scale components must be non-zero (the loader requires > 0).
inline void objectTransform(Vec3 position, Vec3 rotationDeg, Vec3 scale, Affine& toWorld, Affine& toLocal) {
    Mat3d rot = mul(rotationDegrees(2, rotationDeg.z), mul(rotationDegrees(1, rotationDeg.y), rotationDegrees(0, rotationDeg.x)));
    Mat3d l = rot;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) l.m[i][j] *= double(scale[j]);
    const double t[3] = {position.x, position.y, position.z};
    toWorld = toAffine(l, t);
    // Inverse: S^-1 * R^T, translation -(S^-1 R^T) t.
    Mat3d inv;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) inv.m[i][j] = rot.m[j][i] / double(scale[i]);
    double ti[3];
    for (int i = 0; i < 3; ++i) ti[i] = -(inv.m[i][0] * t[0] + inv.m[i][1] * t[1] + inv.m[i][2] * t[2]);
    toLocal = toAffine(inv, ti);
}

// A normal from object to world space: the transpose of toLocal's linear part
// (the inverse transpose of toWorld's), not normalised.
inline Vec3 normalToWorld(const Affine& toLocal, Vec3 n) {
    return {toLocal.m[0][0] * n.x + toLocal.m[1][0] * n.y + toLocal.m[2][0] * n.z,
            toLocal.m[0][1] * n.x + toLocal.m[1][1] * n.y + toLocal.m[2][1] * n.z,
            toLocal.m[0][2] * n.x + toLocal.m[1][2] * n.y + toLocal.m[2][2] * n.z};
}

// Positions by toWorld, normals by the inverse transpose (renormalised).
template <class Mesh>
void meshToWorld(Mesh& mesh, const Affine& toWorld, const Affine& toLocal) {
    for (Vec3& p : mesh.positions) p = toWorld.point(p);
    for (Vec3& n : mesh.normals) {
        Vec3 w = normalToWorld(toLocal, n);
        float l = length(w);
        n = l > 0 && std::isfinite(l) ? w / l : Vec3(0, 1, 0);
    }
}

}  // namespace wmlt
