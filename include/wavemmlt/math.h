// Small vector math shared by every layer: plain structs, inline, no allocation.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>

namespace wmlt {

constexpr float kPi = 3.14159265358979323846f;
constexpr float kInvPi = 0.31830988618379067154f;
constexpr float kInv2Pi = 0.15915494309189533577f;

struct Vec3 {
    float x = 0, y = 0, z = 0;
    constexpr Vec3() = default;
    constexpr Vec3(float x_, float y_, float z_) : x(x_), y(y_), z(z_) {}
    constexpr explicit Vec3(float v) : x(v), y(v), z(v) {}
    float operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
    float& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
};

static_assert(sizeof(Vec3) == 12, "Vec3 arrays are shared with Embree as FLOAT3");

inline Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3 operator-(Vec3 a) { return {-a.x, -a.y, -a.z}; }
inline Vec3 operator*(Vec3 a, Vec3 b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
inline Vec3 operator*(Vec3 a, float s) { return {a.x * s, a.y * s, a.z * s}; }
inline Vec3 operator*(float s, Vec3 a) { return {a.x * s, a.y * s, a.z * s}; }
inline Vec3 operator/(Vec3 a, float s) {
    float r = 1.0f / s;
    return a * r;
}
inline Vec3& operator+=(Vec3& a, Vec3 b) {
    a = a + b;
    return a;
}
inline Vec3& operator*=(Vec3& a, Vec3 b) {
    a = a * b;
    return a;
}
inline Vec3& operator*=(Vec3& a, float s) {
    a = a * s;
    return a;
}

inline float dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 cross(Vec3 a, Vec3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
inline float length(Vec3 a) { return std::sqrt(dot(a, a)); }
inline float lengthSquared(Vec3 a) { return dot(a, a); }
inline Vec3 normalize(Vec3 a) { return a / length(a); }
inline float maxComponent(Vec3 a) { return std::max(a.x, std::max(a.y, a.z)); }
inline Vec3 vmin(Vec3 a, Vec3 b) { return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)}; }
inline Vec3 vmax(Vec3 a, Vec3 b) { return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)}; }
inline bool isBlack(Vec3 a) { return a.x == 0 && a.y == 0 && a.z == 0; }
inline bool isFinite(Vec3 a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }
// Rec. 709 luminance of linear RGB.
inline float luminance(Vec3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

// Orthonormal basis around a unit normal n (Duff et al. 2017, "Building an
// orthonormal basis, revisited"), as floats: the form loops that vectorise use (a Frame
// read from memory is a group of nine floats, which GCC 12 does not vectorise), and the
// one Frame::fromNormal makes its vectors with.
struct FrameFloats {
    float sx, sy, sz, tx, ty, tz, nx, ny, nz;
};
inline FrameFloats frameFromNormal(float nx, float ny, float nz) {
    const float sign = std::copysign(1.0f, nz);
    const float a = -1.0f / (sign + nz);
    const float b = nx * ny * a;
    return {1.0f + sign * nx * nx * a, sign * b, -sign * nx, b, sign + ny * ny * a, -ny, nx, ny, nz};
}
// normalize(s x + t y + n z) (Frame::toWorld, then a / |a| as a * (1 / |a|)).
inline void toWorldUnit(const FrameFloats& f, float x, float y, float z, float& dx, float& dy, float& dz) {
    const float vx = (f.sx * x + f.tx * y) + f.nx * z, vy = (f.sy * x + f.ty * y) + f.ny * z, vz = (f.sz * x + f.tz * y) + f.nz * z;
    const float r = 1.0f / std::sqrt(vx * vx + vy * vy + vz * vz);
    dx = vx * r;
    dy = vy * r;
    dz = vz * r;
}

struct Frame {
    Vec3 s, t, n;
    static Frame fromFloats(const FrameFloats& f) { return {{f.sx, f.sy, f.sz}, {f.tx, f.ty, f.tz}, {f.nx, f.ny, f.nz}}; }
    static Frame fromNormal(Vec3 n) { return fromFloats(frameFromNormal(n.x, n.y, n.z)); }
    // s along tangent's part orthogonal to n (Gram-Schmidt), t = n x s (right-handed, as
    // fromNormal's); fromNormal where the tangent is (nearly) parallel to n or zero.
    static Frame fromNormalTangent(Vec3 n, Vec3 tangent) {
        const Vec3 s = tangent - n * dot(n, tangent);
        const float l2 = dot(s, s);
        if (!(l2 > 1e-12f * dot(tangent, tangent))) return fromNormal(n);
        const Vec3 su = s / std::sqrt(l2);
        return {su, cross(n, su), n};
    }
    Vec3 toLocal(Vec3 v) const { return {dot(v, s), dot(v, t), dot(v, n)}; }
    Vec3 toWorld(Vec3 v) const { return s * v.x + t * v.y + n * v.z; }
};

// 3x4 affine transform (rows), used by the scene loader.
struct Affine {
    float m[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};
    Vec3 point(Vec3 p) const {
        return {m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3], m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3],
                m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3]};
    }
    Vec3 vector(Vec3 v) const {
        return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z, m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
                m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
    }
};

}  // namespace wmlt
