// pbrt-v4 shapes (docs/pbrt.md): trianglemesh, plymesh, bilinearmesh (two triangles per
// patch), sphere (wavemmlt's sphere when whole and uniformly scaled, else a mesh), disk and
// cylinder (meshes), each with its area light and alpha; inside ObjectBegin, a group's
// triangle meshes.
#include <algorithm>
#include <cmath>

#include "scene/features.h"
#include "scene/meshes/loop_subdivision.h"
#include "scene/pbrt/pbrt_importer.h"
#include "wavemmlt/error.h"

namespace wmlt::pbrt {

namespace {

constexpr int kSegments = 256;  // around a disk, cylinder or partial sphere
constexpr int kRings = 128;     // along a partial sphere or a cylinder

// A surface of revolution about z as a grid of (u, v) in [0, 1]^2: point(u, v) and its
// outward normal, (kSegments + 1) x (rings + 1) vertices, uv as pbrt defines them.
template <typename P>
TriangleMesh gridMesh(int rings, P point) {
    TriangleMesh m;
    for (int j = 0; j <= rings; ++j)
        for (int i = 0; i <= kSegments; ++i) {
            const float u = float(i) / kSegments, v = float(j) / rings;
            Vec3 n;
            m.positions.push_back(point(u, v, n));
            m.normals.push_back(n);
            m.uvs.insert(m.uvs.end(), {u, v});
        }
    const uint32_t w = kSegments + 1;
    for (int j = 0; j < rings; ++j)
        for (int i = 0; i < kSegments; ++i) {
            const uint32_t a = uint32_t(j) * w + uint32_t(i), b = a + 1, c = a + w, d = c + 1;
            m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
        }
    return m;
}

// Turns every triangle over (its winding) when `flip`, or, with vertex normals, where its
// winding's normal points away from their mean.
void orient(TriangleMesh& m, bool flip) {
    for (size_t t = 0; t + 2 < m.indices.size(); t += 3) {
        uint32_t* ix = &m.indices[t];
        const Vec3 ng = cross(m.positions[ix[1]] - m.positions[ix[0]], m.positions[ix[2]] - m.positions[ix[0]]);
        bool turn = flip;
        if (!m.normals.empty()) turn = dot(ng, m.normals[ix[0]] + m.normals[ix[1]] + m.normals[ix[2]]) < 0;
        if (turn) std::swap(ix[1], ix[2]);
    }
}

}  // namespace

void Importer::shape(Directive& d) {
    Params& p = d.params;
    const std::string type = d.strings[0];
    ShapeDesc sh;
    sh.line = d.at.line;
    sh.kind = ShapeKind::Mesh;
    sh.uv = UvKind::Mesh;
    sh.material = currentMaterial();
    if (sh.material == kInterfaceMaterial) {  // pbrt's interface: an index-matched boundary
        sh.material = -1;
        sh.passThrough = true;
        if (g_.areaLight) fail(d.at, "an area light on a shape with the interface material (it has no surface)");
    }
    if (auto ss = subsurfaceMedium_.find(sh.material); ss != subsurfaceMedium_.end())  // its interior, in the medium around it
        pendingMedia_.push_back({int(s_.shapes.size()), ss->second, g_.outsideMedium, d.at});
    else if (g_.insideMedium != g_.outsideMedium) pendingMedia_.push_back({int(s_.shapes.size()), g_.insideMedium, g_.outsideMedium, d.at});
    sh.toWorld = g_.ctm.affine();
    sh.toLocal = g_.ctm.inverse().affine();
    TriangleMesh& m = sh.mesh;
    // pbrt's surface normal: the winding's (or the vertex normals' side), turned over by
    // ReverseOrientation; a handedness-swapping transform keeps it (pbrt compensates).
    bool reverse = g_.reverse;
    bool analyticSphere = false;
    if (type == "trianglemesh" || type == "bilinearmesh") {
        const std::vector<double> P = p.getNumbers("P", 3), N = p.getNumbers("N", 3), uv = p.getNumbers("uv", 2);
        std::vector<int> idx = p.getInts("indices");
        const size_t nv = P.size() / 3;
        if (nv == 0) fail(d.at, type + " needs \"point3 P\"");
        const int per = type == "trianglemesh" ? 3 : 4;
        if (idx.empty()) {
            if (int(nv) != per) fail(d.at, type + " without \"integer indices\" needs exactly " + std::to_string(per) + " points");
            for (int i = 0; i < per; ++i) idx.push_back(i);
        }
        if (idx.size() % size_t(per) != 0) fail(p.find("indices")->at, "\"indices\": not a multiple of " + std::to_string(per));
        for (int i : idx)
            if (i < 0 || size_t(i) >= nv)
                fail(p.find("indices")->at, "\"indices\": index " + std::to_string(i) + " out of range (" + std::to_string(nv) + " points)");
        if (!N.empty() && N.size() != P.size()) fail(p.find("N")->at, "\"N\": one normal per point is needed");
        if (!uv.empty() && uv.size() / 2 != nv) fail(p.find("uv")->at, "\"uv\": one (u, v) per point is needed");
        for (size_t i = 0; i < nv; ++i) m.positions.push_back(Vec3(float(P[3 * i]), float(P[3 * i + 1]), float(P[3 * i + 2])));
        for (size_t i = 0; i < N.size() / 3; ++i) m.normals.push_back(Vec3(float(N[3 * i]), float(N[3 * i + 1]), float(N[3 * i + 2])));
        for (double x : uv) m.uvs.push_back(float(x));
        if (per == 3) {
            m.indices.assign(idx.begin(), idx.end());
        } else {  // a bilinear patch (v00, v10, v01, v11) as two triangles
            for (size_t q = 0; q < idx.size(); q += 4) {
                const uint32_t a = uint32_t(idx[q]), b = uint32_t(idx[q + 1]), c = uint32_t(idx[q + 2]), e = uint32_t(idx[q + 3]);
                m.indices.insert(m.indices.end(), {a, b, e, a, e, c});
            }
        }
        for (const char* k : {"S", "faceIndices"}) p.find(k);
    } else if (type == "plymesh") {
        const std::string f = p.getString("filename", "");
        if (f.empty()) fail(d.at, "plymesh needs \"string filename\"");
        try {
            m = loadPly(resolve(f), true, false);  // the file's normals, else flat (pbrt)
        } catch (const InputError& e) {
            fail(d.at, e.what());
        }
        if (p.has("displacement")) fail(p.find("displacement")->at, "plymesh displacement is not supported");
        p.getFloat("edgelength", 1);
    } else if (type == "sphere" || type == "disk" || type == "cylinder") {
        const double r = p.getFloat("radius", 1);
        const double phiMax = std::clamp(p.getFloat("phimax", 360), 0.0, 360.0) * M_PI / 180;
        if (!(r > 0) || !(phiMax > 0)) fail(d.at, type + ": radius and phimax must be > 0");
        if (type == "sphere") {
            const double zmin = std::clamp(std::min(p.getFloat("zmin", -r), p.getFloat("zmax", r)), -r, r);
            const double zmax = std::clamp(std::max(p.getFloat("zmin", -r), p.getFloat("zmax", r)), -r, r);
            // Whole and uniformly scaled without shear: wavemmlt's analytic sphere.
            const Vec3 ax = g_.ctm.vector(Vec3(1, 0, 0)), ay = g_.ctm.vector(Vec3(0, 1, 0)), az = g_.ctm.vector(Vec3(0, 0, 1));
            const float s = length(ax);
            const bool similar = std::fabs(length(ay) - s) < 1e-5f * s && std::fabs(length(az) - s) < 1e-5f * s &&
                                 std::fabs(dot(ax, ay)) < 1e-5f * s * s && std::fabs(dot(ax, az)) < 1e-5f * s * s &&
                                 std::fabs(dot(ay, az)) < 1e-5f * s * s;
            const bool whole = zmin <= -r && zmax >= r && phiMax >= 2 * M_PI;
            const double thMin = std::acos(zmin / r), thMax = std::acos(zmax / r);
            // A two-sided light is a mesh (wavemmlt's analytic sphere light emits outwards only):
            // seen from inside too, as in a furnace around the camera.
            Params light = g_.areaLightDirective.params;
            const bool twoSidedLight = g_.areaLight && light.getBool("twosided", false);
            if (whole && similar && currentObject_ < 0 && !(g_.areaLight && reverse) && !twoSidedLight &&
                (sh.material < 0 || !readsTexture(s_, s_.materials[size_t(sh.material)]))) {
                analyticSphere = true;
                sh.kind = ShapeKind::Sphere;
                sh.uv = UvKind::SphereMitsuba;
                sh.center = g_.ctm.point(Vec3(0.0f));
                sh.radius = float(r) * s;
            } else {  // pbrt's (u, v): u = phi / phiMax, v from zmin (theta_min) to zmax
                m = gridMesh(kRings, [&](float u, float v, Vec3& n) {
                    const double phi = u * phiMax, th = thMin + v * (thMax - thMin);
                    n = Vec3(float(std::sin(th) * std::cos(phi)), float(std::sin(th) * std::sin(phi)), float(std::cos(th)));
                    return n * float(r);
                });
            }
        } else if (type == "disk") {
            const double h = p.getFloat("height", 0), ri = p.getFloat("innerradius", 0);
            if (ri < 0 || ri >= r) fail(d.at, "disk: innerradius must be in [0, radius)");
            m = gridMesh(1, [&](float u, float v, Vec3& n) {  // v = (r - rho) / (r - ri)
                const double phi = u * phiMax, rho = r - v * (r - ri);
                n = Vec3(0, 0, 1);
                return Vec3(float(rho * std::cos(phi)), float(rho * std::sin(phi)), float(h));
            });
        } else {
            const double z0 = p.getFloat("zmin", -1), z1 = p.getFloat("zmax", 1);
            if (!(z1 > z0)) fail(d.at, "cylinder: zmax must be above zmin");
            m = gridMesh(1, [&](float u, float v, Vec3& n) {
                const double phi = u * phiMax;
                n = Vec3(float(std::cos(phi)), float(std::sin(phi)), 0);
                return Vec3(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z0 + v * (z1 - z0)));
            });
        }
        if (!analyticSphere) orient(m, false);  // the parameterisation's normals: the side, and smooth shading
    } else if (type == "loopsubdiv") {
        const std::vector<double> P = p.getNumbers("P", 3);
        const std::vector<int> idx = p.getInts("indices");
        const int levels = p.getInt("levels", 3);
        if (P.empty() || idx.empty() || idx.size() % 3) fail(d.at, "loopsubdiv needs \"point3 P\" and \"integer indices\" (3 per triangle)");
        if (levels < 0 || levels > 8) fail(d.at, "loopsubdiv: levels must be 0 to 8");
        if (double(idx.size() / 3) * std::pow(4.0, levels) > double(1 << 24))
            fail(d.at, "loopsubdiv: " + std::to_string(idx.size() / 3) + " triangles at " + std::to_string(levels) +
                           " levels would make more than 2^24 triangles");
        for (size_t i = 0; i < P.size(); i += 3) m.positions.push_back(Vec3(float(P[i]), float(P[i + 1]), float(P[i + 2])));
        for (int i : idx) {
            if (i < 0 || size_t(i) >= m.positions.size())
                fail(p.find("indices")->at,
                     "\"indices\": index " + std::to_string(i) + " out of range (" + std::to_string(m.positions.size()) + " points)");
            m.indices.push_back(uint32_t(i));
        }
        const std::string why = loopSubdivide(m.positions, m.indices, levels, m.normals);
        if (!why.empty()) fail(d.at, "loopsubdiv: " + why);
        sh.uv = UvKind::None;
    } else if (type == "curve") {
        fail(d.at, "Shape \"" + type + "\" is not supported yet (docs/pbrt.md)");
    } else {
        fail(d.at, "unknown Shape \"" + type + "\"");
    }
    if (!analyticSphere) {
        // pbrt's side of a triangle: its winding's normal taken through the transform as a
        // normal (so a mirroring transform keeps it), turned over by ReverseOrientation; or
        // the vertex normals' (turned over too). The winding here must give that side in
        // world space: it is what an area light emits to.
        const bool hadNormals = !m.normals.empty();
        transformMesh(m, g_.ctm, false);
        if (hadNormals) {
            if (reverse)
                for (Vec3& n : m.normals) n = -n;
            orient(m, false);
        } else {
            orient(m, reverse != (g_.ctm.det3() < 0));
        }
    }
    // Finite numbers whose product is not: coordinates times the transform past a float's range.
    auto finite = [](Vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
    if (analyticSphere ? !(finite(sh.center) && std::isfinite(sh.radius) && sh.radius > 0)
                       : !std::all_of(m.positions.begin(), m.positions.end(), finite))
        fail(d.at, "Shape \"" + type + "\": its coordinates times the transform are beyond a float's range (or a radius underflows to 0)");
    // alpha: pbrt's cut-out, as the material's opacity on a copy for this shape
    int alphaTex = -1;
    const float alpha = floatParam(p, "alpha", 1, alphaTex);
    if (alphaTex >= 0 || alpha < 1) {
        if (!(alpha >= 0 && alpha <= 1)) fail(p.find("alpha")->at, "alpha must be in [0, 1]");
        if (sh.material < 0) fail(p.find("alpha")->at, "alpha on a shape with the interface material");
        MaterialDesc mat = s_.materials[size_t(sh.material)];
        mat.opacity = alphaTex >= 0 ? 1 : alpha;
        mat.opacityTexture = alphaTex;
        mat.id = int(s_.materials.size());
        sh.material = mat.id;
        s_.materials.push_back(mat);
    }
    if (currentObject_ >= 0) {
        if (g_.areaLight) fail(d.at, "an area light inside an object (ObjectBegin) is not supported (pbrt-v4 refuses it too)");
        if (alphaTex >= 0 || alpha < 1) fail(d.at, "alpha inside an object (ObjectBegin) is not supported");
        sh.group = currentObject_;
    }
    const int index = int(s_.shapes.size());
    s_.shapes.push_back(std::move(sh));
    if (g_.areaLight) areaLight(g_.areaLightDirective, s_.shapes[size_t(index)]);
    (void)index;
}

}  // namespace wmlt::pbrt
