#include "scene/matrix.h"

#include <cmath>
#include <utility>

namespace wmlt {

Matrix Matrix::operator*(const Matrix& b) const {
    Matrix r;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            double s = 0;
            for (int k = 0; k < 4; ++k) s += m[i][k] * b.m[k][j];
            r.m[i][j] = s;
        }
    return r;
}
double Matrix::det3() const {
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}
Matrix Matrix::inverse() const {
    const double d = det3();
    Matrix r;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {  // adjugate: cofactor of (j, i)
            const int a = (i + 1) % 3, b = (i + 2) % 3, c = (j + 1) % 3, e = (j + 2) % 3;
            r.m[i][j] = (m[c][a] * m[e][b] - m[c][b] * m[e][a]) / d;
        }
    for (int i = 0; i < 3; ++i) r.m[i][3] = -(r.m[i][0] * m[0][3] + r.m[i][1] * m[1][3] + r.m[i][2] * m[2][3]);
    return r;
}
Affine Matrix::affine() const {
    Affine a;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 4; ++j) a.m[i][j] = float(m[i][j]);
    return a;
}

Matrix Matrix::translate(double x, double y, double z) {
    Matrix T;
    T.m[0][3] = x;
    T.m[1][3] = y;
    T.m[2][3] = z;
    return T;
}
Matrix Matrix::scale(double x, double y, double z) {
    Matrix T;
    T.m[0][0] = x;
    T.m[1][1] = y;
    T.m[2][2] = z;
    return T;
}
Matrix Matrix::rotate(double degrees, double ax, double ay, double az) {  // Rodrigues
    const double len = std::sqrt(ax * ax + ay * ay + az * az);
    const double ang = degrees * M_PI / 180;
    const double c = std::cos(ang), s = std::sin(ang), x = ax / len, y = ay / len, z = az / len;
    const double r[3][3] = {{c + x * x * (1 - c), x * y * (1 - c) - z * s, x * z * (1 - c) + y * s},
                            {y * x * (1 - c) + z * s, c + y * y * (1 - c), y * z * (1 - c) - x * s},
                            {z * x * (1 - c) - y * s, z * y * (1 - c) + x * s, c + z * z * (1 - c)}};
    Matrix T;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) T.m[i][j] = r[i][j];
    return T;
}
bool Matrix::lookAt(const double o[3], const double tg[3], const double up[3], Matrix& M) {
    double d[3] = {tg[0] - o[0], tg[1] - o[1], tg[2] - o[2]};
    auto norm = [](double* v) {
        const double l = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        if (l > 0)
            for (int i = 0; i < 3; ++i) v[i] /= l;
        return l;
    };
    if (!(norm(d) > 0)) return false;
    double l[3] = {up[1] * d[2] - up[2] * d[1], up[2] * d[0] - up[0] * d[2], up[0] * d[1] - up[1] * d[0]};
    if (!(norm(l) > 1e-12)) return false;
    const double u[3] = {d[1] * l[2] - d[2] * l[1], d[2] * l[0] - d[0] * l[2], d[0] * l[1] - d[1] * l[0]};
    Matrix T;
    for (int i = 0; i < 3; ++i) {
        T.m[i][0] = l[i];
        T.m[i][1] = u[i];
        T.m[i][2] = d[i];
        T.m[i][3] = o[i];
    }
    M = T;
    return true;
}

void transformMesh(TriangleMesh& mesh, const Matrix& M, bool flip) {
    const Matrix inv = M.inverse();
    for (Vec3& p : mesh.positions) p = M.point(p);
    for (Vec3& n : mesh.normals) {
        Vec3 w(float(inv.m[0][0] * n.x + inv.m[1][0] * n.y + inv.m[2][0] * n.z), float(inv.m[0][1] * n.x + inv.m[1][1] * n.y + inv.m[2][1] * n.z),
               float(inv.m[0][2] * n.x + inv.m[1][2] * n.y + inv.m[2][2] * n.z));
        const float l = length(w);
        n = l > 0 && std::isfinite(l) ? (flip ? -w : w) / l : Vec3(0, 0, 1);
    }
    if (flip)
        for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) std::swap(mesh.indices[t + 1], mesh.indices[t + 2]);
}

}  // namespace wmlt
