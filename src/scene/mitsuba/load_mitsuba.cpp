// The Mitsuba 3 importer: a <scene version="3.x"> file (also 2.x, and 0.6.x/0.5.x with
// camelCase names) into a SceneDesc. What is supported and the conventions chosen:
// docs/mitsuba.md. Anything else is one InputError naming the file, line and plugin.
#include <algorithm>
#include <cmath>
#include <filesystem>

#include "kernels/envmap.h"
#include "scene/filter_desc.h"
#include "scene/mitsuba/mitsuba_importer.h"
#include "scene/mitsuba/mitsuba_shapes.h"
#include "scene/number.h"
#include "scene/read_file.h"
#include "wavemmlt/error.h"
#include "wavemmlt/image.h"
#include "wavemmlt/render.h"

namespace wmlt::mitsuba {

namespace {

// Mitsuba 3's envmap: local direction d -> (u, v) = (atan2(d.x, -d.z) / 2 pi, acos(d.y) / pi),
// bilinear with texel centres at u = (i + 1/2) / W (wrapping) and v = j / (H - 1) (row 0
// at the +y pole, row H - 1 at -y), times scale. Its (u, v) orientation is wavemmlt's own
// (envmap.h), but wavemmlt looks up the nearest pixel of rows covering [j, j + 1) pi / H:
// the map is resampled onto wavemmlt's grid at f = 4, 3, 2 or 1 times the resolution (the
// largest that keeps it under 2^23 pixels), each pixel Mitsuba's value at its centre's
// direction, rotated by to_world: within 1 / (2 f) texel of Mitsuba's lookup.
Image resampleEnvMap(const Image& src, const Matrix& toWorld, float scale) {
    const int W = src.width, H = src.height;
    int f = 4;
    while (f > 1 && double(W) * H * f * f > double(1 << 23)) --f;
    Image out(W * f, H * f);
    auto texel = [&](int x, int y) { return src.at(((x % W) + W) % W, std::min(std::max(y, 0), H - 1)); };
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x) {
            const Vec3 dw = envDirection((float(x) + 0.5f) / float(out.width), (float(y) + 0.5f) / float(out.height));
            // World to the map's frame: the inverse (transpose) of the rotation.
            const double lx = toWorld.m[0][0] * dw.x + toWorld.m[1][0] * dw.y + toWorld.m[2][0] * dw.z;
            const double ly = toWorld.m[0][1] * dw.x + toWorld.m[1][1] * dw.y + toWorld.m[2][1] * dw.z;
            const double lz = toWorld.m[0][2] * dw.x + toWorld.m[1][2] * dw.y + toWorld.m[2][2] * dw.z;
            double u = std::atan2(lx, -lz) / (2 * M_PI) - 0.5 / W;
            u -= std::floor(u);
            const double v = std::acos(std::clamp(ly / std::sqrt(lx * lx + ly * ly + lz * lz), -1.0, 1.0)) / M_PI;
            const double px = u * W, py = v * (H - 1);
            const int x0 = std::min(int(px), W - 1), y0 = std::min(int(py), H - 2);
            const float tx = float(px - x0), ty = float(py - y0);
            const Vec3 c = texel(x0, y0) * ((1 - tx) * (1 - ty)) + texel(x0 + 1, y0) * (tx * (1 - ty)) + texel(x0, y0 + 1) * ((1 - tx) * ty) +
                           texel(x0 + 1, y0 + 1) * (tx * ty);
            out.set(x, y, c * scale);
        }
    return out;
}

}  // namespace

// <default> values and <include> files first (defaults may be used before they appear),
// then every id (references may point forward).
void Importer::collect(Node scene, int depth) {
    if (depth > 16) files_.fail(scene, "includes nested too deeply (a cycle?)");
    for (Node c : scene.children()) {
        if (c.type() != pugi::node_element) continue;
        const std::string tag = c.name();
        if (tag == "default") {
            const std::string name = c.attribute("name").value();
            if (name.empty() || !c.attribute("value")) files_.fail(c, "needs name and value");
            if (!overridden_.count(name)) params_[name] = c.attribute("value").value();
        } else if (tag == "include") {
            if (!c.attribute("filename")) files_.fail(c, "missing attribute \"filename\"");
            Node inc = files_.addFile(resolve(c.attribute("filename").value()), c);
            collect(inc, depth + 1);
            for (Node k = inc.first_child(); k; k = k.next_sibling())  // included in place
                scene.insert_copy_before(k, c);
        }
    }
}

void Importer::topLevel(Node scene) {
    std::function<void(Node)> ids = [&](Node n) {
        for (Node c : n.children()) {
            if (c.type() != pugi::node_element) continue;
            if (const char* id = c.attribute("id").value(); *id && std::string(c.name()) != "ref") {
                if (ids_.count(id)) files_.fail(c, std::string("id \"") + id + "\" is already used on " + files_.where(ids_[id]));
                ids_[id] = c;
            }
            ids(c);
        }
    };
    ids(scene);
    for (Node c : scene.children()) {
        if (c.type() != pugi::node_element) continue;
        const std::string tag = c.name();
        if (tag == "default" || tag == "include" || tag == "bsdf" || tag == "texture" || tag == "medium") continue;  // when used
        if (tag == "shape") shape(c);
        else if (tag == "sensor") sensor(c);
        else if (tag == "integrator") integrator(c);
        else if (tag == "emitter") emitter(c, -1);
        else files_.fail(c, "not supported by wavemmlt's Mitsuba importer (docs/mitsuba.md lists what is)");
    }
    if (!haveSensor_) files_.fail(scene, "no <sensor>");
}

// <shape type="shapegroup" id="...">: its shapes (triangle meshes, without emitters or
// masks) in the group's own coordinates, stored once (ShapeDesc::group); read when first
// met, at its place or at an instance that refers to it before it.
int Importer::shapeGroup(Node n) {
    if (auto it = groupOf_.find(n.internal_object()); it != groupOf_.end()) return it->second;
    if (currentGroup_ >= 0) files_.fail(n, "a shapegroup inside a shapegroup is not supported (nor is Mitsuba's)");
    const int g = s_.groups++;
    groupOf_[n.internal_object()] = g;
    currentGroup_ = g;
    int shapes = 0;
    for (Node c : n.children()) {
        if (c.type() != pugi::node_element) continue;
        if (std::string(c.name()) != "shape") files_.fail(c, "a shapegroup holds shapes only");
        shape(c);
        ++shapes;
    }
    currentGroup_ = -1;
    if (shapes == 0) files_.fail(n, "an empty shapegroup");
    return g;
}

// <shape type="instance"><ref id="group"/> with to_world: one placement of a shapegroup.
void Importer::instance(Node n) {
    if (currentGroup_ >= 0) files_.fail(n, "an instance inside a shapegroup is not supported (nested instancing)");
    Props p = props(n);
    const Matrix M = p.getTransform("to_world");
    if (M.det3() == 0) p.fail(n, "to_world is singular");
    const std::vector<Node> groups = p.nested("shape");  // the <ref id=...> resolved
    if (groups.size() != 1) p.fail(n, "an instance needs one <ref id=...> to a shapegroup");
    Node gn = groups[0];
    if (std::string(gn.attribute("type").value()) != "shapegroup")
        p.fail(n,
               "an instance's <ref> must name a shapegroup (" + files_.where(gn) + " is a shape of type \"" + gn.attribute("type").value() + "\")");
    InstanceDesc in;
    in.group = shapeGroup(gn);
    in.toWorld = M.affine();
    in.toLocal = M.inverse().affine();
    in.line = files_.line(n);
    p.finish();
    s_.instances.push_back(in);
}

void Importer::shape(Node n) {
    const std::string type = n.attribute("type").value();
    if (type == "shapegroup") {
        shapeGroup(n);
        return;
    }
    if (type == "instance") {
        instance(n);
        return;
    }
    Props p = props(n);
    const std::string t = p.type();
    ShapeDesc sh;
    sh.id = n.attribute("id").value();
    sh.line = files_.line(n);
    const Matrix M = p.getTransform("to_world");
    if (M.det3() == 0) p.fail(n, "to_world is singular");
    const bool flip = p.getBool("flip_normals", false);
    if (t == "obj") {
        const std::string path = resolve(p.getString("filename", ""));
        const bool faceNormals = p.getBool("face_normals", false);
        const bool flipUv = p.getBool("flip_tex_coords", true);
        try {
            sh.mesh = loadObj(path, !faceNormals);
        } catch (const InputError& e) {
            p.fail(n, e.what());
        }
        if (flipUv)  // Mitsuba's v = 1 - the file's
            for (size_t i = 1; i < sh.mesh.uvs.size(); i += 2) sh.mesh.uvs[i] = 1 - sh.mesh.uvs[i];
        transformMesh(sh.mesh, M, flip);
    } else if (t == "ply" || t == "serialized") {  // uv as stored (Mitsuba flips only OBJ's)
        const std::string path = resolve(p.getString("filename", ""));
        const bool faceNormals = p.getBool("face_normals", false);
        const int index = t == "serialized" ? p.getInt("shape_index", 0) : 0;
        if (index < 0) p.fail(n, "shape_index must be >= 0");
        try {
            sh.mesh = t == "ply" ? loadPly(path, !faceNormals) : loadSerialized(path, index, !faceNormals);
        } catch (const InputError& e) {
            p.fail(n, e.what());
        }
        transformMesh(sh.mesh, M, flip);
    } else if (t == "rectangle" || t == "cube" || t == "disk") {
        sh.mesh = t == "rectangle" ? rectangleMesh() : t == "cube" ? cubeMesh() : diskMesh(kDiskSegments);
        if (t == "disk") warn(n, "disk: approximated by a polygon of " + std::to_string(kDiskSegments) + " sides");
        // A rectangle's or disk's normal is M^-T z (Mitsuba); the winding turns with det < 0.
        transformMesh(sh.mesh, M, flip != (t != "cube" && M.det3() < 0));
    } else if (t == "sphere") {
        const Vec3 c = p.getPoint("center", Vec3(0.0f));
        const float r = p.getFloat("radius", 1.0f);
        if (!(r > 0)) p.fail(n, "radius must be > 0");
        if (flip) p.fail(n, "flip_normals on a sphere is not supported (its normal points outwards)");
        // to_world must keep spheres spheres: a uniform scale times a rotation.
        double col[3];
        for (int j = 0; j < 3; ++j) col[j] = std::sqrt(M.m[0][j] * M.m[0][j] + M.m[1][j] * M.m[1][j] + M.m[2][j] * M.m[2][j]);
        for (int i = 0; i < 3; ++i)
            for (int j = i + 1; j < 3; ++j) {
                const double d = M.m[0][i] * M.m[0][j] + M.m[1][i] * M.m[1][j] + M.m[2][i] * M.m[2][j];
                if (std::fabs(d) > 1e-5 * col[i] * col[j] || std::fabs(col[i] - col[j]) > 1e-5 * col[i])
                    p.fail(n, "a sphere's to_world must be a uniform scale, rotation and translation");
            }
        sh.kind = ShapeKind::Sphere;
        sh.uv = UvKind::SphereMitsuba;
        sh.center = M.point(c);
        sh.radius = float(r * col[0]);
        // The unit sphere to world, rotation included (Mitsuba's (u, v) turn with to_world).
        Matrix T;
        for (int i = 0; i < 3; ++i) {
            T.m[i][i] = r;
            T.m[i][3] = c[i];
        }
        const Matrix W = M * T;
        sh.toWorld = W.affine();
        sh.toLocal = W.inverse().affine();
    } else {
        p.fail(n, "shape not supported by wavemmlt's Mitsuba importer (docs/mitsuba.md lists what is)");
    }
    if (sh.kind == ShapeKind::Mesh) sh.uv = sh.mesh.uvs.empty() ? UvKind::None : UvKind::Mesh;
    sh.group = currentGroup_;
    if (sh.group >= 0 && sh.kind != ShapeKind::Mesh) p.fail(n, "a sphere inside a shapegroup is not supported (triangle meshes are)");
    std::vector<Node> bsdfs = p.nested("bsdf");
    if (bsdfs.size() > 1) p.fail(bsdfs[1], "a shape has one BSDF");
    std::vector<Node> emitters = p.nested("emitter");
    if (emitters.size() > 1) p.fail(emitters[1], "a shape has one emitter");
    shapeMedia(p, sh);
    const bool null = !bsdfs.empty() && std::string(bsdfs[0].attribute("type").value()) == "null";
    if (null) {  // Mitsuba's null BSDF: an index-matched boundary, rays pass
        if (!emitters.empty()) p.fail(emitters[0], "an emitter on a shape with the null BSDF (it has no surface)");
        if (sh.group >= 0) p.fail(bsdfs[0], "a null BSDF inside a shapegroup is not supported");
        props(bsdfs[0]).finish();
        sh.passThrough = true;
        sh.material = -1;
        p.finish();
        s_.shapes.push_back(std::move(sh));
        return;
    }
    if (bsdfs.empty()) {  // Mitsuba's default, emitters included: a diffuse 0.5 (one-sided)
        MaterialDesc m;
        m.id = int(s_.materials.size());
        m.twoSided = false;
        s_.materials.push_back(m);
        sh.material = m.id;
    } else {
        sh.material = material(bsdfs[0]);
        if (s_.materials[sh.material].normalMap >= 0 && sh.uv == UvKind::None)
            p.fail(bsdfs[0], "a normalmap needs the mesh's (u, v), and this mesh has none");
    }
    if (sh.group >= 0 && (s_.materials[sh.material].opacity < 1 || s_.materials[sh.material].opacityTexture >= 0))
        p.fail(bsdfs[0], "a mask inside a shapegroup is not supported");
    if (!emitters.empty()) {
        if (sh.group >= 0) p.fail(emitters[0], "an emitter inside a shapegroup is not supported (nor is Mitsuba's)");
        // Emitters scatter by their BSDF as Mitsuba's do; a black diffuse one only absorbs,
        // which wavemmlt's emitters without a material (-1) do at no cost.
        const MaterialDesc& m = s_.materials[sh.material];
        if (m.opacity < 1 || m.opacityTexture >= 0)
            p.fail(bsdfs[0], "a mask on an emitting shape is not supported (its light would be partly there)");
        if (m.kind == MaterialKind::Matte && isBlack(m.diffuse) && m.texture[MaterialParam::Diffuse] < 0) sh.material = -1;
        s_.shapes.push_back(std::move(sh));
        emitter(emitters[0], int(s_.shapes.size()) - 1);
        p.finish();
        return;
    }
    p.finish();
    s_.shapes.push_back(std::move(sh));
}

void Importer::emitter(Node n, int shape) {
    Props p = props(n);
    const std::string t = p.type();
    // A light without a shape (point, spot, directional) of kind k: its colour `name`
    // (Mitsuba's default 1) must be >= 0.
    auto shapeless = [&](LightKind k, const char* name) {
        if (shape >= 0) p.fail(n, "a " + t + " emitter cannot be attached to a shape");
        LightDesc l;
        l.kind = k;
        l.radiance = p.getColor(name, Vec3(1.0f), Props::ColorUse::Emission);
        l.spectrum = p.lastSpectrum();
        if (!(l.radiance.x >= 0 && l.radiance.y >= 0 && l.radiance.z >= 0)) p.fail(n, std::string(name) + " must be >= 0");
        return l;
    };
    if (t == "area") {
        if (shape < 0) p.fail(n, "an area emitter belongs inside a <shape>");
        ShapeDesc& sh = s_.shapes[shape];
        LightDesc l;
        // A textured radiance: L = 1 times the texture at the point (a mesh light sampled by its
        // luminance, scene/mesh_light.h).
        if (Node tx = textureParam(p, "radiance")) {
            if (sh.kind == ShapeKind::Sphere) p.fail(tx, "a textured radiance on a sphere is not supported (on meshes and rectangles it is)");
            if (sh.mesh.uvs.empty()) p.fail(tx, "a textured radiance needs a mesh with (u, v) coordinates");
            l.texture = texture(tx);
        } else {
            l.radiance = p.getColor("radiance", Vec3(1.0f), Props::ColorUse::Emission);
            l.spectrum = p.lastSpectrum();
            if (!(l.radiance.x >= 0 && l.radiance.y >= 0 && l.radiance.z >= 0)) p.fail(n, "radiance must be >= 0");
        }
        // A rectangle: the analytic rect light; any other mesh (obj, ply, serialized, cube, disk),
        // or one with a textured radiance: a triangle mesh light emitting on its winding's side.
        if (sh.kind == ShapeKind::Sphere) l.kind = LightKind::Sphere;
        else if (std::string(n.parent().attribute("type").value()) == "rectangle" && l.texture < 0) l.kind = LightKind::Rect;
        else l.kind = LightKind::Mesh;
        l.shape = shape;
        sh.light = int(s_.lights.size());
        s_.lights.push_back(l);
    } else if (t == "point") {  // a delta in position: intensity I (W / sr), never seen
        LightDesc l = shapeless(LightKind::Point, "intensity");
        const bool hasPosition = p.has("position"), hasTransform = p.has("to_world");
        if (hasPosition && hasTransform) p.fail(n, "give position or to_world, not both");
        l.position = hasPosition ? p.getPoint("position", Vec3(0.0f)) : p.getTransform("to_world").point(Vec3(0.0f));
        s_.lights.push_back(l);
    } else if (t == "directional") {  // a delta in direction: irradiance E, from infinity
        LightDesc l = shapeless(LightKind::Directional, "irradiance");
        const bool hasDirection = p.has("direction"), hasTransform = p.has("to_world");
        if (hasDirection && hasTransform) p.fail(n, "give direction or to_world, not both");
        const Vec3 d = hasDirection ? p.getPoint("direction", Vec3(0, 0, 1)) : p.getTransform("to_world").vector(Vec3(0, 0, 1));
        if (!(length(d) > 0) || !isFinite(d)) p.fail(n, "the direction must be a nonzero vector");
        l.direction = normalize(d);
        s_.lights.push_back(l);
    } else if (t == "spot") {  // a point light shining along +z of to_world within a cone
        LightDesc l = shapeless(LightKind::Point, "intensity");
        if (p.has("texture")) p.fail(n, "a spot's texture (a projected image) is not supported");
        const float cutoff = p.getFloat("cutoff_angle", 20.0f), beam = p.getFloat("beam_width", cutoff * 0.75f);
        if (!(cutoff > 0 && cutoff <= 180)) p.fail(n, "cutoff_angle must be in (0, 180] degrees");
        if (!(beam >= 0 && beam <= cutoff)) p.fail(n, "beam_width must be in [0, cutoff_angle]");
        const Matrix M = p.getTransform("to_world");
        l.position = M.point(Vec3(0.0f));
        const Vec3 axis = M.vector(Vec3(0, 0, 1));
        if (!(length(axis) > 0)) p.fail(n, "to_world has no usable direction");
        l.spotAxis = normalize(axis);
        l.spotCutoff = float(cutoff * M_PI / 180);
        l.spotBeam = float(beam * M_PI / 180);
        s_.lights.push_back(l);
    } else if (t == "envmap") {
        if (shape >= 0) p.fail(n, "an envmap cannot be attached to a shape");
        if (s_.envMap.width > 0) p.fail(n, "a second environment emitter");
        if (!p.has("filename")) p.fail(n, "an envmap needs a filename");
        const std::string path = resolve(p.getString("filename", ""));
        Image src;
        try {
            src = readSceneImage(path);
        } catch (const InputError& e) {
            p.fail(n, e.what());
        }
        if (src.width < 2 || src.height < 3) p.fail(n, "the environment map must be at least 2 x 3 pixels (Mitsuba's rule)");
        const float scale = p.getFloat("scale", 1.0f);
        if (!(scale >= 0)) p.fail(n, "scale must be >= 0");
        const Matrix M = p.getTransform("to_world");
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) {
                double d = 0;
                for (int k = 0; k < 3; ++k) d += M.m[k][i] * M.m[k][j];
                if (std::fabs(d - (i == j ? 1.0 : 0.0)) > 1e-4) p.fail(n, "an envmap's to_world must be a rotation (no scale or shear)");
            }
        p.getBool("mis_compensation", false);  // sampling only
        s_.envMap = resampleEnvMap(src, M, scale);
        for (float v : s_.envMap.rgb)  // finite pixels times a finite scale can overflow a float
            if (!std::isfinite(v)) p.fail(n, path + ": its pixels times scale (" + numberText(scale) + ") are beyond a float's range");
        s_.settings.envMap = path;
    } else if (t == "constant") {  // a uniform sky: a 2 x 2 map of one colour
        const Vec3 L = p.getColor("radiance", Vec3(1.0f), Props::ColorUse::Emission);
        if (s_.envMap.width > 0) p.fail(n, "a second environment emitter");
        s_.envMap = Image(2, 2);
        for (int y = 0; y < 2; ++y)
            for (int x = 0; x < 2; ++x) s_.envMap.set(x, y, L);
        s_.settings.envMap = "(constant)";
    } else {
        p.fail(n, "emitter not supported by wavemmlt's Mitsuba importer (docs/mitsuba.md lists what is)");
    }
    p.finish();
}

void Importer::sensor(Node n) {
    if (haveSensor_) files_.fail(n, "a second <sensor>");
    haveSensor_ = true;
    Props p = props(n);
    const std::string t = p.type();
    if (t != "perspective" && t != "thinlens" && t != "orthographic") p.fail(n, "sensor not supported (perspective, thinlens and orthographic are)");
    const bool ortho = t == "orthographic";
    // The medium the sensor is in (docs/media.md): <ref name="medium" id=...> or a nested one
    if (Node med = p.getNested("medium", "medium")) {
        s_.cameraMedium = medium(med);
    } else {
        const std::vector<Node> ms = p.nested("medium");
        if (ms.size() > 1) p.fail(ms[1], "a sensor is in one medium");
        if (!ms.empty()) s_.cameraMedium = medium(ms[0]);
    }
    // fov (about fov_axis), or focal_length (Mitsuba 3: "<x>mm" of a 36 x 24 mm film, the
    // diagonal's field of view; the default, 50mm, when neither is given).
    if (!ortho && p.has("fov") && p.has("focal_length")) p.fail(n, "give either fov or focal_length, not both");
    float fov = 90.0f;
    std::string axis = "x";
    if (!ortho && p.has("fov")) {
        fov = p.getFloat("fov", 0);
        if (!(fov > 0 && fov < 180)) p.fail(n, "fov must be in (0, 180)");
        axis = p.getString("fov_axis", "x");
    } else if (!ortho) {
        Node fn = p.node().find_child_by_attribute("name", "focal_length");
        std::string f =
            fn && std::string(fn.name()) == "float" ? std::to_string(p.getFloat("focal_length", 50)) : p.getString("focal_length", "50mm");
        if (f.size() > 2 && f.compare(f.size() - 2, 2, "mm") == 0) f.resize(f.size() - 2);
        char* end = nullptr;
        const double mm = std::strtod(f.c_str(), &end);
        if (f.empty() || *end != '\0' || !(mm > 0) || !std::isfinite(mm)) p.fail(fn ? fn : n, "focal_length must be <x>mm with x > 0");
        fov = float(2.0 * std::atan(std::sqrt(36.0 * 36.0 + 24.0 * 24.0) / (2.0 * mm)) * 180.0 / M_PI);
        axis = "diagonal";
        if (p.has("fov_axis")) {  // not read by Mitsuba 3 with a focal length
            warn(p.node().find_child_by_attribute("name", "fov_axis"), "fov_axis is ignored with focal_length (the diagonal's, as Mitsuba 3)");
            p.getString("fov_axis", "x");
        }
    }
    const Matrix M = p.getTransform("to_world");
    // near_clip: accepted on the projective sensors (nothing in these scenes is that close);
    // an orthographic sensor's rays start there.
    const float nearClip = p.getFloat("near_clip", 0.01f);
    if (ortho && !(nearClip >= 0)) p.fail(n, "near_clip must be >= 0");
    p.getFloat("far_clip", 1e4f);
    CameraDesc& c = s_.camera;
    // Mitsuba reads focus_distance on every projective sensor; a pinhole has no focus.
    if (t == "perspective" && p.has("focus_distance") && !(p.getFloat("focus_distance", 1) > 0)) p.fail(n, "focus_distance must be > 0");
    if (t == "thinlens") {
        c.dof = true;
        const float r = p.getFloat("aperture_radius", 0.03f), f = p.getFloat("focus_distance", 0);
        if (!(r > 0) || !(f > 0)) p.fail(n, "thinlens needs aperture_radius > 0 and focus_distance > 0");
        c.focalLength = f;
        c.fStop = f / (2 * r);
    }
    int w = 768, h = 576;
    int crop[4] = {0, 0, 0, 0};          // crop_offset_x, _y, crop_width, _height (0 x 0: none)
    namedFilter("gaussian", s_.filter);  // Mitsuba's default rfilter
    for (Node film : p.nested("film")) {
        Props fp = props(film);
        if (fp.type() != "hdrfilm") fp.fail(film, "film not supported (hdrfilm is)");
        w = fp.getInt("width", 768);
        h = fp.getInt("height", 576);
        if (w < 1 || h < 1 || w > 16384 || h > 16384) fp.fail(film, "width and height must be 1 to 16384");
        crop[0] = fp.getInt("crop_offset_x", 0), crop[1] = fp.getInt("crop_offset_y", 0);
        crop[2] = fp.getInt("crop_width", w - crop[0]), crop[3] = fp.getInt("crop_height", h - crop[1]);
        if (crop[0] < 0 || crop[1] < 0 || crop[2] < 1 || crop[3] < 1 || crop[0] + crop[2] > w || crop[1] + crop[3] > h)
            fp.fail(film, "the crop window (crop_offset_x, crop_offset_y, crop_width, crop_height) must be a nonempty part of the film");
        for (const char* ignored : {"file_format", "pixel_format", "component_format", "banner"}) fp.getString(ignored, "");
        for (Node rf : fp.nested("rfilter")) s_.filter = reconstructionFilter(rf);
        fp.finish();
    }
    for (Node smp : p.nested("sampler")) {
        Props sp = props(smp);
        const int64_t count = sp.getInt("sample_count", 4);
        if (count < 1 || count > (int64_t(1) << 24))
            sp.fail(smp, "sample_count " + std::to_string(count) + " is out of range [1, 16777216] (wavemmlt's limit, as --spp's)");
        const int64_t k = int64_t(std::ceil(std::sqrt(double(count)) - 1e-9));
        s_.settings.samples = int(k);
        if (k * k != count) warn(smp, "sample_count " + std::to_string(count) + " is rendered as " + std::to_string(k * k) + " (a square)");
        sp.getInt("seed", 0);
        sp.finish();
    }
    s_.settings.width = w;
    s_.settings.height = h;
    if (crop[2] > 0 && (crop[2] != w || crop[3] != h)) {  // the image is that window of the film
        s_.settings.width = crop[2];
        s_.settings.height = crop[3];
        float* win = c.window;
        win[0] = float(crop[0]) / float(w), win[1] = float(crop[0] + crop[2]) / float(w);
        win[2] = float(crop[1]) / float(h), win[3] = float(crop[1] + crop[3]) / float(h);
    }
    // FOV: wavemmlt's is across the shorter side.
    const double tx = std::tan(0.5 * fov * M_PI / 180), shorter = std::min(w, h), diag = std::sqrt(double(w) * w + double(h) * h);
    double ts;
    if (axis == "x") ts = tx * shorter / w;
    else if (axis == "y") ts = tx * shorter / h;
    else if (axis == "diagonal") ts = tx * shorter / diag;
    else if (axis == "smaller") ts = tx;
    else if (axis == "larger") ts = tx * shorter / std::max(w, h);
    else p.fail(n, "fov_axis \"" + axis + "\" is not x, y, diagonal, smaller or larger");
    c.fovDegrees = float(2 * std::atan(ts) * 180 / M_PI);
    // Mitsuba looks along +z of to_world with +y up and +x to the image's LEFT: wavemmlt's
    // right = forward x up is -x for a rotation; a mirroring to_world flips it.
    c.position = M.point(Vec3(0.0f));
    c.lookAt = c.position + normalize(M.vector(Vec3(0, 0, 1)));
    c.up = normalize(M.vector(Vec3(0, 1, 0)));
    c.flipX = M.det3() < 0;
    if (length(cross(normalize(c.lookAt - c.position), c.up)) < 1e-6f) p.fail(n, "to_world has no usable view direction");
    if (ortho) {  // Mitsuba's [-1, 1] x [-1 / aspect, 1 / aspect] of to_world's x-y plane
        c.orthographic = true;
        c.nearClip = nearClip;
        c.orthoHalfWidth = length(M.vector(Vec3(1, 0, 0)));
        c.orthoHalfHeight = length(M.vector(Vec3(0, 1, 0))) * float(h) / float(w);
        if (!(c.orthoHalfWidth > 0 && c.orthoHalfHeight > 0) || !std::isfinite(c.orthoHalfWidth * c.orthoHalfHeight))
            p.fail(n, "to_world gives the orthographic film no area");
    }
    p.finish();
}

// <rfilter type="..."> with Mitsuba 3's parameters (docs/filters.md): box, tent (radius),
// gaussian (stddev; radius 4 stddev), mitchell (B, C), catmullrom, lanczos (lobes).
FilterDesc Importer::reconstructionFilter(Node rf) {
    Props p = props(rf);
    FilterDesc f;
    if (!namedFilter(p.type(), f)) p.fail(rf, std::string("not one of ") + kFilterNames);
    auto set = [&](const char* name, double v) {
        const std::string problem = setFilterParameter(f, name, v);
        if (!problem.empty()) p.fail(rf, problem);
    };
    if (p.has("stddev")) set("stddev", p.getFloat("stddev", f.stddev));
    if (p.has("radius")) set("radius", p.getFloat("radius", f.radius));
    if (p.has("B")) set("B", p.getFloat("B", f.B));
    if (p.has("C")) set("C", p.getFloat("C", f.C));
    if (p.has("lobes")) set("lobes", p.getInt("lobes", 3));
    p.finish();
    return f;
}

void Importer::integrator(Node n) {
    if (haveIntegrator_) files_.fail(n, "a second <integrator>");
    haveIntegrator_ = true;
    Props p = props(n);
    const std::string t = p.type();
    Settings& st = s_.settings;
    if (t == "path" || t == "volpath") st.tracer = TracerKind::PT;
    else if (t == "bdpt") st.tracer = TracerKind::BPT;
    else if (t == "ptracer") st.tracer = TracerKind::LT;
    else if (t == "pssmlt") st.tracer = TracerKind::PSSMLT;
    else if (t == "mlt") st.tracer = TracerKind::MMLT;
    else if (options_.tracerGiven) {  // the command line's tracer renders the scene; the plugin's parameters mean nothing to it
        warn(n, "integrator \"" + t + "\" is not one of wavemmlt's: replaced by the tracer the command line gives (its parameters are ignored)");
        return;
    } else p.fail(n, "integrator not supported (path, volpath, bdpt, ptracer, pssmlt, mlt are; or choose one with --tracer)");
    const int depth = p.getInt("max_depth", -1);
    if (depth == 0 || depth < -1) p.fail(n, "max_depth must be -1 (unlimited) or >= 1");
    st.maxPathLength = depth;  // Mitsuba counts segments, as wavemmlt does
    if (depth == -1 || depth > kMaxPathLength) {
        st.maxPathLength = kMaxPathLength;
        warn(n, "max_depth " + std::to_string(depth) + " is rendered as " + std::to_string(kMaxPathLength) + " (wavemmlt's longest paths)");
    }
    p.getInt("rr_depth", 5);  // Russian roulette: noise only
    if (p.getBool("hide_emitters", false)) p.fail(n, "hide_emitters is not supported");
    p.finish();
}

SceneDesc Importer::run(const std::string& xml, const std::string& name) {
    Node root = files_.add(xml, name);
    const std::string v = root.attribute("version").value();
    if (v.rfind("3.", 0) == 0 || v.rfind("2.", 0) == 0) camel_ = false;
    else if (v.rfind("0.6.", 0) == 0 || v.rfind("0.5.", 0) == 0) camel_ = true;
    else files_.fail(root, "version \"" + v + "\" is not supported (3.x, 2.x, 0.6.x, 0.5.x)");
    s_.settings.tracer = TracerKind::PT;  // Mitsuba's default integrator is `path`
    s_.settings.maxPathLength = kMaxPathLength;
    s_.settings.output = std::filesystem::path(name).stem().string() + ".exr";
    s_.mediaAsDeclared = true;  // interior and exterior as pbrt-v4's MediumInterface: open boundaries are legal
    collect(root, 0);
    substitute(files_, root, params_);
    topLevel(root);
    if (s_.lights.empty() && s_.envMap.width == 0) files_.fail(root, "the scene has no emitter");
    // Mitsuba files name no variant: one that gives spectra (a <spectrum> of pairs or a file,
    // an emitter's constant, a blackbody) renders spectrally, as its scalar_spectral variant
    // would; one of RGB colours alone in RGB (docs/mitsuba.md, docs/spectral.md).
    s_.settings.spectral = !s_.spectra.empty();
    return std::move(s_);
}

}  // namespace wmlt::mitsuba

namespace wmlt {

bool isMitsubaXml(const std::string& xml) {
    pugi::xml_document doc;
    if (!doc.load_buffer(xml.data(), xml.size(), pugi::parse_minimal, pugi::encoding_utf8)) return false;
    return std::string(doc.document_element().name()) == "scene";
}

SceneDesc loadMitsubaFromString(const std::string& xml, const std::string& name, const std::string& baseDir, const Defines& defines,
                                const LoadOptions& options) {
    return mitsuba::Importer(baseDir, defines, options).run(xml, name);
}

}  // namespace wmlt
