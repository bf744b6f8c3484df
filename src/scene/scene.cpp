// Scene::build: the renderable scene from its description (materials as kernel data:
// scene_materials.cpp; the Embree BVH; lights; media; the camera).
#include "scene/scene.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <string>
#include <unordered_map>

#include "kernels/rng.h"
#include "kernels/texture.h"
#include "scene/transform.h"
#include "stages/core/trace.h"  // (the scene's own queries once it is built: the media around a point)
#include "wavemmlt/error.h"

namespace wmlt {

namespace {

// Embree reports errors through a C callback: remember the first message (throwing
// across Embree's C frames would be undefined), and check after building.
void embreeError(void* user, RTCError, const char* str) {
    auto* first = static_cast<std::string*>(user);
    if (first->empty()) *first = str ? str : "unknown error";
}

// The mesh's own vertex and index arrays are shared with Embree: no second copy.
RTCGeometry buildMesh(RTCDevice device, TriangleMesh& m) {
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    m.positions.reserve(m.positions.size() + 2);  // Embree reads vertices with 16-byte loads
    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, m.positions.data(), 0, sizeof(Vec3), m.positions.size());
    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, m.indices.data(), 0, 3 * sizeof(uint32_t), m.indices.size() / 3);
    return g;
}

RTCGeometry buildSphere(RTCDevice device, Vec3 c, float r) {
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), 1));
    v[0] = c.x;
    v[1] = c.y;
    v[2] = c.z;
    v[3] = r;
    return g;
}

// Mitsuba's mask: the surface is hit with probability alpha (its opacity, or its texture's
// luminance at the hit), decided by a hash of the ray, the primitive and the geometry so
// that one ray decides alike in the closest-hit and occlusion queries, two surfaces along
// it decide independently, and every render is repeatable (pbrt-v4's alpha test). Set on
// masked geometries only: other scenes call no filter.
float maskAlpha(const MaskRecord& m, RTCRayN* ray, RTCHitN* hit, unsigned N, unsigned i) {
    if (m.texture < 0) return m.opacity;
    float u = 0, v = 0;
    const Vec3 p(RTCRayN_org_x(ray, N, i) + RTCRayN_tfar(ray, N, i) * RTCRayN_dir_x(ray, N, i),
                 RTCRayN_org_y(ray, N, i) + RTCRayN_tfar(ray, N, i) * RTCRayN_dir_y(ray, N, i),
                 RTCRayN_org_z(ray, N, i) + RTCRayN_tfar(ray, N, i) * RTCRayN_dir_z(ray, N, i));
    if (m.mesh) {
        if (!m.mesh->uvs.empty()) {
            const uint32_t* tri = &m.mesh->indices[size_t(RTCHitN_primID(hit, N, i)) * 3];
            const float b1 = RTCHitN_u(hit, N, i), b2 = RTCHitN_v(hit, N, i), b0 = 1 - b1 - b2;
            const float* uv = m.mesh->uvs.data();
            u = uv[2 * tri[0]] * b0 + uv[2 * tri[1]] * b1 + uv[2 * tri[2]] * b2;
            v = uv[2 * tri[0] + 1] * b0 + uv[2 * tri[1] + 1] * b1 + uv[2 * tri[2] + 1] * b2;
        }
    } else {  // a sphere: Mitsuba's (u, v) of the hit point's local direction
        const Vec3 l = normalize(m.toLocal.vector(p - m.center));
        u = std::atan2(l.y, l.x) * kInv2Pi;
        if (u < 0) u += 1;
        v = std::acos(std::clamp(l.z, -1.0f, 1.0f)) * kInvPi;
    }
    const Vec3 ng(RTCHitN_Ng_x(hit, N, i), RTCHitN_Ng_y(hit, N, i), RTCHitN_Ng_z(hit, N, i));
    return luminance(evalTextureOf(*m.textures, size_t(m.texture), u, v, p, ng));
}

void maskFilter(const RTCFilterFunctionNArguments* args) {
    const MaskRecord& m = *static_cast<const MaskRecord*>(args->geometryUserPtr);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        const float alpha = maskAlpha(m, args->ray, args->hit, args->N, i);
        if (alpha >= 1) continue;
        uint64_t h = mix64(0x6d61736bull ^ (uint64_t(m.geomID) << 32 | RTCHitN_primID(args->hit, args->N, i)));
        for (float f : {RTCRayN_org_x(args->ray, args->N, i), RTCRayN_org_y(args->ray, args->N, i), RTCRayN_org_z(args->ray, args->N, i),
                        RTCRayN_dir_x(args->ray, args->N, i), RTCRayN_dir_y(args->ray, args->N, i), RTCRayN_dir_z(args->ray, args->N, i)}) {
            uint32_t bits;
            std::memcpy(&bits, &f, 4);
            h = mix64(h ^ bits);
        }
        const float xi = float(h >> 40) * 0x1p-24f;
        if (!(xi < alpha)) args->valid[i] = 0;  // the ray passes through
    }
}

// A rectangle light from the loader's two triangles: the corner opposite the shared
// diagonal and the two edges leaving it span the rectangle.
Light rectLight(const TriangleMesh& m, Vec3 L) {
    const Vec3* p = m.positions.data();
    uint32_t a = m.indices[0], b = m.indices[1], c = m.indices[2];
    auto inSecond = [&](uint32_t i) {
        for (int k = 3; k < 6; ++k) {
            Vec3 q = p[m.indices[k]];
            if (q.x == p[i].x && q.y == p[i].y && q.z == p[i].z) return true;
        }
        return false;
    };
    uint32_t corner = a, o1 = b, o2 = c;
    if (!inSecond(b) && inSecond(a)) {
        corner = b;
        o1 = c;
        o2 = a;
    } else if (!inSecond(c) && inSecond(a)) {
        corner = c;
        o1 = a;
        o2 = b;
    }
    Light l;
    l.type = LightType::Rect;
    l.L = L;
    l.corner = p[corner];
    l.e1 = p[o1] - p[corner];
    l.e2 = p[o2] - p[corner];
    Vec3 ng = cross(p[b] - p[a], p[c] - p[a]);  // the loader's winding: the emitting side
    Vec3 n = cross(l.e1, l.e2);
    l.area = length(n);
    l.n = n / l.area;
    if (dot(l.n, ng) < 0) l.n = -l.n;
    return l;
}

}  // namespace

namespace {

// Whether every edge of the mesh is shared by exactly two of its triangles (it has an
// inside, as a medium boundary needs). Vertices at the same position are one vertex: a
// mesh with split vertices for flat normals or uv seams (Mitsuba's cube has 24) is closed.
bool closedMesh(const TriangleMesh& m) {
    std::unordered_map<uint64_t, uint32_t> firstAt;  // position bits -> first vertex there
    std::vector<uint32_t> weld(m.positions.size());
    firstAt.reserve(m.positions.size());
    auto bits = [](float f) {
        uint32_t b;
        std::memcpy(&b, &f, 4);
        return f == 0 ? 0u : b;
    };  // -0 == +0
    for (size_t i = 0; i < m.positions.size(); ++i) {
        const Vec3 p = m.positions[i];
        const uint64_t h = (uint64_t(bits(p.x)) * 0x9E3779B97F4A7C15ull) ^ (uint64_t(bits(p.y)) * 0xC2B2AE3D27D4EB4Full) ^ bits(p.z);
        auto [it, fresh] = firstAt.try_emplace(h, uint32_t(i));
        // a hash collision between different positions: keep the vertex apart (never a false weld)
        const Vec3 q = m.positions[it->second];
        weld[i] = fresh || !(q.x == p.x && q.y == p.y && q.z == p.z) ? uint32_t(i) : it->second;
    }
    std::unordered_map<uint64_t, int> edges;
    edges.reserve(m.indices.size());
    for (size_t t = 0; t + 2 < m.indices.size(); t += 3)
        for (int e = 0; e < 3; ++e) {
            const uint64_t a = weld[m.indices[t + size_t(e)]], b = weld[m.indices[t + size_t((e + 1) % 3)]];
            if (a == b) continue;  // a degenerate edge bounds nothing
            ++edges[a < b ? a << 32 | b : b << 32 | a];
        }
    for (const auto& kv : edges)
        if (kv.second != 2) return false;
    return !edges.empty();
}

// The majorant grid of a density grid (m.density, nx, ny, nz set) or of RGB coefficient
// grids: buildMajorants sets m.mx, my, mz (at most 16 cells per axis) and fills cells by
// majorantCells with each voxel's largest density times the largest sigma_t, or its
// largest component of sigma_t (m.majorants is the caller's to point at cells).
void buildMajorants(Medium& m, std::vector<float>& cells) {
    m.mx = std::min(m.nx, 16), m.my = std::min(m.ny, 16), m.mz = std::min(m.nz, 16);
    const float sMax = std::max(m.sigmaT.x, std::max(m.sigmaT.y, m.sigmaT.z));
    majorantCells(
        m, [&](size_t i) { return m.density ? m.density[i] * sMax : maxComponent(m.gridSigmaA[i] + m.gridSigmaS[i]); }, cells);
}

// The media as the stages read them, and the checks the importers leave to the model.
void buildMedia(const SceneDesc& d, Scene& s) {
    for (const MediumDesc& m : d.media) {
        auto bad = [&](Vec3 v) { return !isFinite(v) || v.x < 0 || v.y < 0 || v.z < 0; };
        if (bad(m.sigmaA) || bad(m.sigmaS))
            throw InputError(d.path, m.line, "medium \"" + m.name + "\": sigma_a and sigma_s must be finite and >= 0");
        if (!(m.g > -1 && m.g < 1)) throw InputError(d.path, m.line, "medium \"" + m.name + "\": g must be in (-1, 1)");
        Medium r;
        r.sigmaT = m.sigmaA + m.sigmaS;
        r.sigmaS = m.sigmaS;
        r.g = m.g;
        const bool rgb = !m.sigmaAGrid.empty() || !m.sigmaSGrid.empty();
        if (!m.density.empty() || rgb) {
            const size_t n = size_t(std::max(m.nx, 0)) * size_t(std::max(m.ny, 0)) * size_t(std::max(m.nz, 0));
            if (m.nx < 1 || m.ny < 1 || m.nz < 1 || (rgb ? m.sigmaAGrid.size() != n || m.sigmaSGrid.size() != n : m.density.size() != n))
                throw InputError(d.path, m.line, "medium \"" + m.name + "\": the grid's size disagrees with its values");
            float maxValue = 0;  // of the density, or of sigma_t
            for (size_t i = 0; i < n; ++i) {
                const bool ok = rgb ? !bad(m.sigmaAGrid[i]) && !bad(m.sigmaSGrid[i]) : m.density[i] >= 0 && std::isfinite(m.density[i]);
                if (!ok) throw InputError(d.path, m.line, "medium \"" + m.name + "\": grid values must be finite and >= 0");
                maxValue = std::max(maxValue, rgb ? maxComponent(m.sigmaAGrid[i] + m.sigmaSGrid[i]) : m.density[i]);
            }
            if (rgb) {
                r.gridSigmaA = m.sigmaAGrid.data();
                r.gridSigmaS = m.sigmaSGrid.data();
            } else {
                r.density = m.density.data();
            }
            r.nx = m.nx, r.ny = m.ny, r.nz = m.nz;
            r.worldToGrid = m.worldToGrid;
            r.clampEdges = m.clampEdges;
            r.majorant = rgb ? maxValue : maxValue * std::max(r.sigmaT.x, std::max(r.sigmaT.y, r.sigmaT.z));
            s.majorantGrids.emplace_back();
            buildMajorants(r, s.majorantGrids.back());
        }
        if (bad(m.Le)) throw InputError(d.path, m.line, "medium \"" + m.name + "\": its emission Le must be finite and >= 0");
        if (!m.LeGrid.empty()) {
            if (r.nx == 0 || m.LeGrid.size() != size_t(r.nx) * size_t(r.ny) * size_t(r.nz))
                throw InputError(d.path, m.line, "medium \"" + m.name + "\": its emission grid's size disagrees with its grid");
            for (const Vec3& v : m.LeGrid)
                if (bad(v)) throw InputError(d.path, m.line, "medium \"" + m.name + "\": emission values must be finite and >= 0");
            r.gridLe = m.LeGrid.data();
        }
        r.Le = m.Le;
        r.emissive = !m.LeGrid.empty() || !isBlack(m.Le);
        if (!m.albedoGrid.empty()) {
            if (!r.density || m.albedoGrid.size() != m.density.size())
                throw InputError(d.path, m.line, "medium \"" + m.name + "\": its albedo grid's size disagrees with its density grid");
            for (const Vec3& a : m.albedoGrid)
                if (bad(a) || a.x > 1 || a.y > 1 || a.z > 1)
                    throw InputError(d.path, m.line, "medium \"" + m.name + "\": albedo values must be in [0, 1]");
            r.gridAlbedo = m.albedoGrid.data();
        }
        s.media.push_back(r);
    }
    // the majorant grids have stopped moving: point the media at them
    size_t g = 0;
    for (Medium& r : s.media)
        if (r.nx > 0) r.majorants = s.majorantGrids[g++].data();
    auto valid = [&](int i) { return i >= -1 && i < int(d.media.size()); };
    if (!valid(d.cameraMedium)) throw InputError(d.path, 0, "the camera's medium is not one of the scene's");
    s.cameraMedium = d.cameraMedium;
    for (const ShapeDesc& sh : d.shapes) {
        if (!valid(sh.mediumInside) || !valid(sh.mediumOutside)) throw InputError(d.path, sh.line, "a shape names an unknown medium");
        if (sh.passThrough && (sh.material >= 0 || sh.light >= 0))
            throw InputError(d.path, sh.line, "a pass-through (index-matched) boundary takes no material and emits no light");
        // A surface that scatters decides a ray's medium by the side the ray leaves on, open or
        // not (pbrt-v4's walls between "" and fog); a ray crossing an open pass-through
        // boundary could end up "inside" something with no inside.
        if (!d.mediaAsDeclared && sh.passThrough && sh.mediumBoundary && sh.mediumInside != sh.mediumOutside && sh.kind == ShapeKind::Mesh &&
            !closedMesh(sh.mesh))
            throw InputError(d.path, sh.line, "a pass-through medium boundary on an open mesh (it has no inside): close it");
    }
}

// The closed medium boundary (a sphere or a closed mesh, not instanced) around p: the
// shape whose surface every axis ray from p meets first, from inside (crossing the
// surfaces that are no boundary); -1 when there is none or the rays disagree. closed:
// per shape, whether it is closed (-1: not known yet; filled as met).
int enclosingBoundary(const Scene& s, const SceneDesc& d, Vec3 p, std::vector<int8_t>& closed) {
    static const Vec3 dirs[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    int found = -1;
    for (const Vec3& dir : dirs) {
        RTCRayHit rh;
        setRayHit(rh, p, dir);
        int shape = -1;
        for (int k = 0; k < 64; ++k) {
            traceClosest(s.rtc, &rh, 1, false);
            if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) break;
            const GeomRecord& g = s.geoms[rh.hit.geomID];
            const Vec3 n = s.hitNormal(rh);
            if (g.mediumBoundary) {
                const ShapeDesc& sh = d.shapes[rh.hit.geomID];
                int8_t& isClosed = closed[rh.hit.geomID];
                if (isClosed < 0) isClosed = sh.kind == ShapeKind::Sphere || closedMesh(sh.mesh) ? 1 : 0;
                if (rh.hit.instID[0] == RTC_INVALID_GEOMETRY_ID && isClosed && dot(dir, n) > 0) shape = int(rh.hit.geomID);
                break;
            }
            const Vec3 q = Vec3(rh.ray.org_x, rh.ray.org_y, rh.ray.org_z) + dir * rh.ray.tfar;
            setRayHit(rh, s.offsetRayOrigin(q, normalize(n), dir), dir);
        }
        if (shape < 0 || (found >= 0 && found != shape)) return -1;
        found = shape;
    }
    return found;
}

std::string mediumName(const SceneDesc& d, int m) { return m < 0 ? "vacuum" : "medium \"" + d.media[size_t(m)].name + "\""; }

// A camera at `position` inside a closed boundary whose inside is not the camera's medium:
// refused, naming the boundary.
void checkCameraMedium(const SceneDesc& d, Scene& s, Vec3 position) {
    if (!s.features.media || d.mediaAsDeclared) return;
    if (const int e = enclosingBoundary(s, d, position, s.closedShapes); e >= 0 && d.shapes[size_t(e)].mediumInside != s.cameraMedium)
        throw InputError(d.path, d.shapes[size_t(e)].line,
                         "the camera is inside this closed boundary, whose inside is " + mediumName(d, d.shapes[size_t(e)].mediumInside) +
                             ", but the camera's medium is " + mediumName(d, s.cameraMedium));
}

// Once the scene is built: the camera's medium checked against a closed boundary around it;
// each light's media (Scene::lightMediumFront, lightMediumBack).
void placeLightsInMedia(const SceneDesc& d, Scene& s) {
    if (!s.features.media) {
        s.lightMediumFront.assign(d.lights.size(), -1);
        s.lightMediumBack.assign(d.lights.size(), -1);
        return;
    }
    std::vector<int8_t>& closed = s.closedShapes;
    checkCameraMedium(d, s, d.camera.position);
    for (const LightDesc& ld : d.lights) {
        const ShapeDesc* sh = ld.shape >= 0 ? &d.shapes[size_t(ld.shape)] : nullptr;
        int front = s.cameraMedium, back = s.cameraMedium;
        if (ld.mediumFront != LightDesc::kMediumUndeclared) {  // as the file declares (pbrt-v4)
            if (ld.mediumFront < -1 || ld.mediumFront >= int(d.media.size()) || ld.mediumBack < -1 || ld.mediumBack >= int(d.media.size()))
                throw InputError(d.path, 0, "a light names an unknown medium");
            front = ld.mediumFront;
            back = ld.mediumBack;
        } else if (sh && sh->mediumBoundary) {  // an emitter on a boundary: its sides' media
            front = sh->mediumOutside;
            back = sh->mediumInside;
        } else if (ld.kind != LightKind::Directional) {  // inside a closed boundary: its inside medium
            Vec3 p = ld.position;
            if (sh && sh->kind == ShapeKind::Sphere) p = sh->center;
            if (sh && sh->kind == ShapeKind::Mesh && sh->mesh.indices.size() >= 3) {  // just off its first triangle
                const Vec3 a = sh->mesh.positions[sh->mesh.indices[0]], b = sh->mesh.positions[sh->mesh.indices[1]],
                           c = sh->mesh.positions[sh->mesh.indices[2]];
                const Vec3 n = normalize(cross(b - a, c - a));
                p = s.offsetRayOrigin((a + b + c) * (1.0f / 3.0f), n, n);
            }
            if (const int e = enclosingBoundary(s, d, p, closed); e >= 0) front = back = d.shapes[size_t(e)].mediumInside;
        }
        s.lightMediumFront.push_back(front);
        s.lightMediumBack.push_back(back);
    }
}

}  // namespace

// Each cell of m's majorant grid (m.mx, my, mz) the largest voxelMax(i) among the voxels i
// whose trilinear support reaches into it (and 0, the value outside, where the cube's
// faces are).
void majorantCells(const Medium& m, const std::function<float(size_t)>& voxelMax, std::vector<float>& cells) {
    cells.assign(size_t(m.mx) * size_t(m.my) * size_t(m.mz), 0.0f);
    // voxel i's centre is (i + 0.5) / n: it reaches [(i - 0.5) / n, (i + 1.5) / n]
    auto range = [](int c, int cells, int n, int& lo, int& hi) {
        lo = std::max(0, int(std::floor(float(c) / float(cells) * float(n) - 1.5f)));
        hi = std::min(n - 1, int(std::ceil(float(c + 1) / float(cells) * float(n) + 0.5f)));
    };
    for (int cz = 0; cz < m.mz; ++cz)
        for (int cy = 0; cy < m.my; ++cy)
            for (int cx = 0; cx < m.mx; ++cx) {
                int x0, x1, y0, y1, z0, z1;
                range(cx, m.mx, m.nx, x0, x1);
                range(cy, m.my, m.ny, y0, y1);
                range(cz, m.mz, m.nz, z0, z1);
                float d = 0;
                for (int z = z0; z <= z1; ++z)
                    for (int y = y0; y <= y1; ++y)
                        for (int x = x0; x <= x1; ++x) d = std::max(d, voxelMax((size_t(z) * size_t(m.ny) + size_t(y)) * size_t(m.nx) + size_t(x)));
                cells[(size_t(cz) * size_t(m.my) + size_t(cy)) * size_t(m.mx) + size_t(cx)] = d;
            }
}

void Scene::setImage(const CameraDesc& c, int width, int height) {
    camera = makeCamera(c, width, height);
    filterNormX.clear();
    filterNormY.clear();
    for (int x = 0; x < width; ++x) filterNormX.push_back(float(filterNorm(filter, x, width)));
    for (int y = 0; y < height; ++y) filterNormY.push_back(float(filterNorm(filter, y, height)));
    features.depthOfField = c.dof;
}

void Scene::setView(const CameraDesc& c, int width, int height) {
    if (!(width >= 1 && height >= 1)) throw InputError("an image needs at least one pixel");
    if (c.position.x != desc.camera.position.x || c.position.y != desc.camera.position.y || c.position.z != desc.camera.position.z)
        checkCameraMedium(desc, *this, c.position);
    setImage(c, width, height);
    desc.camera = c;
    desc.settings.width = width;
    desc.settings.height = height;
}

void Scene::checkCameraAt(Vec3 position) { checkCameraMedium(desc, *this, position); }

Vec3 Scene::hitNormal(const RTCRayHit& rh) const {
    const GeomRecord& g = geoms[rh.hit.geomID];
    if (g.kind == ShapeKind::Sphere) {
        const Vec3 p(rh.ray.org_x + rh.ray.dir_x * rh.ray.tfar, rh.ray.org_y + rh.ray.dir_y * rh.ray.tfar, rh.ray.org_z + rh.ray.dir_z * rh.ray.tfar);
        return p - g.center;
    }
    const Vec3 n(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
    if (rh.hit.instID[0] == RTC_INVALID_GEOMETRY_ID) return n;
    return normalToWorld(instances[rh.hit.instID[0] - firstInstanceID].toLocal, n);
}

std::unique_ptr<Scene> Scene::build(SceneDesc desc, int threads) {
    std::unique_ptr<Scene> s(new Scene());
    s->desc = std::move(desc);
    const SceneDesc& d = s->desc;
    s->features = deriveFeatures(d);
    buildMedia(d, *s);
    s->filter = makePixelFilter(d.filter);
    s->setImage(d.camera, d.settings.width, d.settings.height);
    s->closedShapes.assign(d.shapes.size(), -1);

    std::string config = threads > 0 ? "threads=" + std::to_string(threads) : "";
    s->device = rtcNewDevice(config.c_str());
    if (!s->device) throw std::runtime_error("cannot create the Embree device");
    rtcSetDeviceErrorFunction(s->device, embreeError, &s->embreeErrorMessage);
    rtcSetDeviceMemoryMonitorFunction(
        s->device,
        [](void* p, ssize_t bytes, bool) {
            static_cast<std::atomic<int64_t>*>(p)->fetch_add(int64_t(bytes), std::memory_order_relaxed);
            return true;
        },
        &s->embreeBytes);
    s->rtc = rtcNewScene(s->device);
    // Medium (binned SAH): on the bunny and the dragon both the build and the traversal
    // measured faster than high (spatial splits), and Embree's multi-threaded high-quality
    // builds are not promised to be deterministic (embree issue #20), medium's are.
    rtcSetSceneBuildQuality(s->rtc, RTC_BUILD_QUALITY_MEDIUM);

    // Scale and Mix: their operands below them (no cycles), and only on material parameters
    // (the texture stage combines them; bump, normal maps, masks and emission read one texture).
    auto composite = [&](int t) { return t >= 0 && combinesTextures(d.textures[size_t(t)]); };
    for (size_t i = 0; i < d.textures.size(); ++i)
        for (int o : d.textures[i].operand)
            if (composite(int(i)) && (o < -1 || o >= int(i)))
                throw InputError(d.path, 0, "texture " + std::to_string(i) + ": an operand must be an earlier texture");
    for (const MaterialDesc& m : d.materials)
        if (m.bumpMitsuba && composite(m.bump))
            throw InputError(d.path, 0, "a scale, mix or textured dots texture as a Mitsuba bump map (the gradient of a bitmap) is not supported");
    for (const LightDesc& l : d.lights)
        if (composite(l.texture)) throw InputError(d.path, 0, "a scale, mix or textured dots texture as an emitter's radiance is not supported");
    // The net under every importer's own checks: an emission that is not finite (a product of
    // finite parameters past a float's range) would light nothing or poison the image.
    for (size_t i = 0; i < d.lights.size(); ++i) {
        const Vec3 L = d.lights[i].radiance;
        if (!(std::isfinite(L.x) && std::isfinite(L.y) && std::isfinite(L.z)))
            throw InputError(d.path, 0,
                             "light " + std::to_string(i + 1) + " of " + std::to_string(d.lights.size()) +
                                 ": its emission is not finite (a product of its parameters overflows a float)");
    }
    for (float v : d.envMap.rgb)
        if (!std::isfinite(v))
            throw InputError(d.path, 0, "the environment map's emission is not finite (a product of its parameters overflows a float)");

    buildMaterials(d, *s);

    Vec3 lo(INFINITY), hi(-INFINITY);
    std::vector<Vec3> groupLo(size_t(d.groups), Vec3(INFINITY)), groupHi(size_t(d.groups), Vec3(-INFINITY));
    for (int g = 0; g < d.groups; ++g) {
        s->groupScenes.push_back(rtcNewScene(s->device));
        rtcSetSceneBuildQuality(s->groupScenes.back(), RTC_BUILD_QUALITY_MEDIUM);
    }
    s->geoms.resize(d.shapes.size());
    s->masks.reserve(d.shapes.size());  // not reallocated: the filters point into it
    for (size_t i = 0; i < d.shapes.size(); ++i) {
        const ShapeDesc& sh = d.shapes[i];
        GeomRecord& r = s->geoms[i];
        r.kind = sh.kind;
        r.uv = sh.uv;
        r.material = sh.material;
        r.light = sh.light;
        r.toLocal = sh.toLocal;
        r.toWorld = sh.toWorld;
        r.mediumBoundary = sh.mediumBoundary;
        r.passThrough = sh.passThrough;
        r.mediumInside = sh.mediumInside;
        r.mediumOutside = sh.mediumOutside;
        RTCGeometry g;
        if (sh.kind == ShapeKind::Mesh) {
            r.mesh = &sh.mesh;
            if (!sh.mesh.normals.empty()) {
                r.cornerNormals.resize(sh.mesh.indices.size());
                for (size_t c = 0; c < sh.mesh.indices.size(); ++c) r.cornerNormals[c] = sh.mesh.normals[sh.mesh.indices[c]];
            }
            Vec3& l = sh.group >= 0 ? groupLo[size_t(sh.group)] : lo;
            Vec3& h = sh.group >= 0 ? groupHi[size_t(sh.group)] : hi;
            for (Vec3 p : sh.mesh.positions) {
                l = vmin(l, p);
                h = vmax(h, p);
            }
            s->meshBytes += sh.mesh.positions.size() * sizeof(Vec3) + sh.mesh.normals.size() * sizeof(Vec3) + sh.mesh.uvs.size() * sizeof(float) +
                            sh.mesh.indices.size() * sizeof(uint32_t) + s->geoms[i].cornerNormals.size() * sizeof(Vec3);
            g = buildMesh(s->device, s->desc.shapes[i].mesh);
        } else {
            r.center = sh.center;
            r.radius = sh.radius;
            lo = vmin(lo, sh.center - Vec3(sh.radius));
            hi = vmax(hi, sh.center + Vec3(sh.radius));
            g = buildSphere(s->device, sh.center, sh.radius);
        }
        if (sh.material >= 0) {
            const MaterialDesc& m = d.materials[sh.material];
            if (m.opacity < 1 || m.opacityTexture >= 0) {
                MaskRecord mr;
                mr.mesh = sh.kind == ShapeKind::Mesh ? &sh.mesh : nullptr;
                mr.uv = sh.uv;
                mr.toLocal = sh.toLocal;
                mr.center = sh.center;
                mr.opacity = m.opacity;
                mr.textures = &d.textures;
                mr.texture = m.opacityTexture;
                mr.geomID = unsigned(i);
                s->masks.push_back(mr);
                rtcSetGeometryUserData(g, &s->masks.back());
                rtcSetGeometryIntersectFilterFunction(g, maskFilter);
                rtcSetGeometryOccludedFilterFunction(g, maskFilter);
            }
        }
        rtcCommitGeometry(g);
        rtcAttachGeometryByID(sh.group >= 0 ? s->groupScenes[size_t(sh.group)] : s->rtc, g, unsigned(i));
        rtcReleaseGeometry(g);
    }
    // The instances: each group's scene committed first, then an instance geometry per
    // placement (Embree's order), its bounds the group's box carried to the world.
    for (RTCScene gs : s->groupScenes) rtcCommitScene(gs);
    s->instances = d.instances;
    s->firstInstanceID = unsigned(d.shapes.size());
    for (size_t k = 0; k < d.instances.size(); ++k) {
        const InstanceDesc& in = d.instances[k];
        RTCGeometry g = rtcNewGeometry(s->device, RTC_GEOMETRY_TYPE_INSTANCE);
        rtcSetGeometryInstancedScene(g, s->groupScenes[size_t(in.group)]);
        float m[12];  // column-major 3 x 4
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 3; ++r) m[3 * c + r] = in.toWorld.m[r][c];
        rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, m);
        rtcCommitGeometry(g);
        rtcAttachGeometryByID(s->rtc, g, s->firstInstanceID + unsigned(k));
        rtcReleaseGeometry(g);
        const Vec3 gl = groupLo[size_t(in.group)], gh = groupHi[size_t(in.group)];
        for (int corner = 0; corner < 8; ++corner) {
            const Vec3 p = in.toWorld.point(Vec3(corner & 1 ? gh.x : gl.x, corner & 2 ? gh.y : gl.y, corner & 4 ? gh.z : gl.z));
            lo = vmin(lo, p);
            hi = vmax(hi, p);
        }
    }
    rtcCommitScene(s->rtc);
    if (rtcGetDeviceError(s->device) != RTC_ERROR_NONE || !s->embreeErrorMessage.empty())
        throw std::runtime_error("Embree could not build the scene: " + s->embreeErrorMessage);
    if (!(lo.x <= hi.x)) lo = hi = Vec3(0.0f);
    s->boundsMin = lo;
    s->boundsMax = hi;
    s->center = (lo + hi) * 0.5f;
    s->radius = std::max(0.5f * length(hi - lo), 1e-6f);
    s->epsilonScale = 1e-6f * s->radius;

    for (const LightDesc& ld : d.lights) {
        Light l;
        if (ld.kind == LightKind::Directional) {
            l.type = LightType::Directional;
            l.L = ld.radiance;
            l.axis = normalize(ld.direction);
            l.area = kPi * s->radius * s->radius;  // its emission disc
            s->lights.push_back(l);
            continue;
        }
        if (ld.kind == LightKind::Point) {
            l.type = LightType::Point;
            l.L = ld.radiance;
            l.center = ld.position;
            if (ld.spotCutoff > 0) {
                l.axis = normalize(ld.spotAxis);
                l.axisFrame = Frame::fromNormal(l.axis);
                l.cutoff = ld.spotCutoff;
                l.cosCutoff = std::cos(ld.spotCutoff);
                l.cosBeam = std::cos(ld.spotBeam);
                l.invTransition = ld.spotCutoff > ld.spotBeam ? 1.0f / (ld.spotCutoff - ld.spotBeam) : 0.0f;
                l.smoothstep = ld.spotSmoothstep;
            }
            s->lights.push_back(l);
            continue;
        }
        const ShapeDesc& sh = d.shapes[ld.shape];
        if (ld.twoSided && ld.kind != LightKind::Mesh) throw InputError(d.path, sh.line, "only a mesh emitter can be two-sided");
        if (ld.kind == LightKind::Rect) {
            l = rectLight(sh.mesh, ld.radiance);
        } else if (ld.kind == LightKind::Mesh) {
            if (ld.texture >= 0 && sh.mesh.uvs.empty()) throw InputError(d.path, sh.line, "a textured emitter on a mesh without (u, v)");
            MeshLight ml = buildMeshLight(sh.mesh, ld.texture >= 0 ? &d.textures[size_t(ld.texture)] : nullptr);
            if (!(ml.area > 0)) throw InputError(d.path, sh.line, "an emitting mesh of zero area");
            l.type = LightType::Mesh;
            l.L = ld.radiance;
            l.twoSided = ld.twoSided;
            l.area = float(ml.area);
            l.mesh = int(s->meshLights.size());
            s->meshLights.push_back(std::move(ml));
        } else {
            l.type = LightType::Sphere;
            l.L = ld.radiance;
            l.center = sh.center;
            l.radius = sh.radius;
            l.area = 4.0f * kPi * sh.radius * sh.radius;
        }
        s->lights.push_back(l);
    }
    placeLightsInMedia(d, *s);  // (the environment, appended below, too)
    std::vector<float> power;
    for (const Light& l : s->lights)  // a textured emitter's: times its texture's mean luminance
        power.push_back(lightPower(l) * (l.type == LightType::Mesh ? s->meshLights[size_t(l.mesh)].meanLuminance : 1.0f));
    if (s->features.envMap) {
        s->env.build(d.envMap);
        Light l;
        l.type = LightType::Env;
        s->envLight = int(s->lights.size());
        s->lights.push_back(l);
        s->lightMediumFront.push_back(s->cameraMedium);
        s->lightMediumBack.push_back(s->cameraMedium);
        // Flux through the scene's bounding sphere: pi * L_avg * 4 pi R^2.
        power.push_back(kPi * s->env.meanLuminance * 4.0f * kPi * s->radius * s->radius);
    }
    if (s->lights.empty()) throw InputError(d.path, 0, "the scene has no light and no environment map");
    float total = 0;
    for (float p : power) total += p;
    if (!(total > 0))
        for (float& p : power) p = 1.0f;  // all black: choose uniformly
    s->lightDistribution = Distribution1D(power);
    // The very probabilities sampleDiscrete uses, so MIS sees what sampling did.
    for (size_t i = 0; i < power.size(); ++i) s->lightPmf.push_back(s->lightDistribution.discretePmf(int(i)));
    for (const Light& l : s->lights) {
        const bool rect = l.type == LightType::Rect && !isBlack(l.L);
        s->lightRects.push_back(rect ? rectFloats(l) : RectFloats{});
        s->anyRectLight = s->anyRectLight || rect;
    }
    return s;
}

Scene::~Scene() {
    if (rtc) rtcReleaseScene(rtc);
    for (RTCScene g : groupScenes) rtcReleaseScene(g);
    if (device) rtcReleaseDevice(device);
}

}  // namespace wmlt
