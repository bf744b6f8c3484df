// A 4 x 4 affine transform in double precision, as scene files compose them (Mitsuba's
// <transform>, pbrt's transform directives): products, the inverse of the affine part, and
// the elementary transforms both formats name.
#pragma once
#include "wavemmlt/math.h"
#include "wavemmlt/scene_desc.h"

namespace wmlt {

struct Matrix {
    double m[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
    Matrix operator*(const Matrix& b) const;
    double det3() const;
    Matrix inverse() const;  // of the affine part; the caller checks det3() != 0
    Affine affine() const;
    Vec3 point(Vec3 p) const { return affine().point(p); }
    Vec3 vector(Vec3 v) const { return affine().vector(v); }

    static Matrix translate(double x, double y, double z);
    static Matrix scale(double x, double y, double z);
    // Right-handed rotation by `degrees` about the axis (x, y, z), which must not be zero.
    static Matrix rotate(double degrees, double x, double y, double z);
    // Camera to world: columns up x dir, dir x (up x dir), dir (unit), origin. Returns false
    // (M unchanged) when origin equals target or up is zero or parallel to the direction.
    static bool lookAt(const double origin[3], const double target[3], const double up[3], Matrix& M);
};

// Positions by M, vertex normals by its inverse transpose; flip reverses the winding (and
// the vertex normals) so that the geometric normal turns over.
void transformMesh(TriangleMesh& mesh, const Matrix& M, bool flip);

}  // namespace wmlt
