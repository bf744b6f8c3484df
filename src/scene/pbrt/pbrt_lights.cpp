// pbrt-v4 lights (docs/pbrt.md): diffuse area lights on shapes, point, spot, distant and an
// infinite light (constant, or an equal-area octahedral image), with pbrt-v4's scale and power / illuminance normalisations.
// Spectra of emitters are pbrt's: an rgb value as it is, any other spectrum scaled to a
// luminance of 1 (Importer::spectrum, SpectrumUse::Illuminant).
#include <algorithm>
#include <cmath>

#include "kernels/envmap.h"
#include "scene/number.h"
#include "scene/pbrt/equal_area.h"
#include "scene/pbrt/pbrt_importer.h"
#include "scene/read_file.h"
#include "wavemmlt/error.h"
#include "wavemmlt/image.h"

namespace wmlt::pbrt {

namespace {

// A light's value times its scale (and its power or illuminance normalisation), each product
// in double and checked: finite numbers whose product is not (rgb L 1e38 with scale 1e38,
// power 1e38 on a sphere of radius 1e-10) would light nothing or poison the image with NaN.
Vec3 scaled(const Loc& at, Vec3 L, double scale, const std::string& what) {
    Vec3 out;
    for (int i = 0; i < 3; ++i) {
        const double v = double(L[i]) * scale;
        if (!fitsFloat(v))
            fail(at, what + " times scale (" + numberText(L[i]) + " x " + numberText(scale) + ") is " +
                         (std::isnan(v) ? "not a number" : "beyond a float's range"));
        if (!(v >= 0)) fail(at, what + " times scale must be >= 0");
        out[i] = float(v);
    }
    return out;
}
void scaleImage(const Loc& at, Image& im, double scale, const std::string& what) {
    for (float& v : im.rgb) {
        const double x = double(v) * scale;
        if (!fitsFloat(x)) fail(at, what + ": a pixel (" + numberText(v) + ") times scale (" + numberText(scale) + ") is beyond a float's range");
        v = float(x);
    }
}

// The area of a shape's triangles (world space), or its sphere's.
double areaOf(const ShapeDesc& sh) {
    if (sh.kind == ShapeKind::Sphere) return 4 * M_PI * double(sh.radius) * sh.radius;
    double a = 0;
    const TriangleMesh& m = sh.mesh;
    for (size_t t = 0; t + 2 < m.indices.size(); t += 3)
        a += 0.5 * double(length(
                       cross(m.positions[m.indices[t + 1]] - m.positions[m.indices[t]], m.positions[m.indices[t + 2]] - m.positions[m.indices[t]])));
    return a;
}

// Two triangles sharing a diagonal whose four corners form a parallelogram, both wound to
// one side: the analytic rectangle light (Scene's rectLight reads this layout), which the
// flat light-sample loops serve, instead of a two-triangle mesh light. The same emission.
bool isParallelogram(const TriangleMesh& m) {
    if (m.indices.size() != 6 || m.positions.size() > 6) return false;
    const Vec3* p = m.positions.data();
    const uint32_t* t = m.indices.data();
    int shared = 0, lone0 = -1;
    for (int i = 0; i < 3; ++i) {
        bool found = false;
        for (int j = 3; j < 6; ++j) found = found || t[i] == t[j];
        if (found) ++shared;
        else lone0 = i;
    }
    if (shared != 2) return false;
    int lone1 = -1;
    for (int j = 3; j < 6; ++j)
        if (t[j] != t[0] && t[j] != t[1] && t[j] != t[2]) lone1 = j;
    if (lone1 < 0) return false;
    const Vec3 c = p[t[lone0]], a = p[t[(lone0 + 1) % 3]], b = p[t[(lone0 + 2) % 3]], d = p[t[lone1]];
    const Vec3 n0 = cross(a - c, b - c), n1 = cross(p[t[4]] - p[t[3]], p[t[5]] - p[t[3]]);
    const float size = std::max(length(a - c), length(b - c));
    return dot(n0, n1) > 0 && length((a + b) - (c + d)) <= 1e-5f * size && length(n0) > 0;
}

// pbrt's equal-area octahedral map src (square, row 0 at v = 0, bilinear with texel centres at
// (i + 1/2) / N, clamped at the edges), whose light frame is M, resampled onto envmap.h's
// latitude-longitude grid of 2N x N pixels at 2 x 2 points each: each pixel the mean of the
// map's bilinear values at those points' directions taken into the light's frame.
Image resampleOctahedral(const Image& src, const Matrix& M) {
    const int N = src.width;
    const int H = std::max(2, std::min(N, 2048)), W = 2 * H;
    const Matrix toLight = M.inverse();
    auto texel = [&](int x, int y) { return src.at(std::clamp(x, 0, N - 1), std::clamp(y, 0, N - 1)); };
    Image out(W, H);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            Vec3 sum(0.0f);
            for (int j = 0; j < 2; ++j)
                for (int i = 0; i < 2; ++i) {
                    const Vec3 dw = envDirection((float(x) + (0.25f + 0.5f * i)) / float(W), (float(y) + (0.25f + 0.5f * j)) / float(H));
                    double u, v;
                    equalAreaSphereToSquare(normalize(toLight.vector(dw)), u, v);
                    const double px = u * N - 0.5, py = v * N - 0.5;
                    const int x0 = int(std::floor(px)), y0 = int(std::floor(py));
                    const float tx = float(px - x0), ty = float(py - y0);
                    sum = sum + texel(x0, y0) * ((1 - tx) * (1 - ty)) + texel(x0 + 1, y0) * (tx * (1 - ty)) + texel(x0, y0 + 1) * ((1 - tx) * ty) +
                          texel(x0 + 1, y0 + 1) * (tx * ty);
                }
            out.set(x, y, sum * 0.25f);
        }
    return out;
}

// The illuminance on a surface facing `up` under the latitude-longitude map: sum of
// luminance L cos over its pixels' solid angles, the upper hemisphere only.
double upperIlluminance(const Image& map, Vec3 up) {
    double e = 0;
    for (int y = 0; y < map.height; ++y) {
        const double v0 = double(y) / map.height, v1 = double(y + 1) / map.height;
        const double dOmega = 2 * M_PI / map.width * (std::cos(M_PI * v0) - std::cos(M_PI * v1));
        for (int x = 0; x < map.width; ++x) {
            const Vec3 d = envDirection((float(x) + 0.5f) / float(map.width), (float(y) + 0.5f) / float(map.height));
            const double c = dot(d, up);
            if (c > 0) e += luminance(map.at(x, y)) * c * dOmega;
        }
    }
    return e;
}

}  // namespace

void Importer::areaLight(const Directive& directive, ShapeDesc& sh) {
    Directive d = directive;  // each shape reads the area light's parameters afresh
    Params& p = d.params;
    // An image instead of L (pbrt-v4): radiance scale image(u, 1 - v), bilinear, clamped at
    // the edges: a textured mesh light (LightDesc::texture), L 1.
    int image = -1;
    if (const Param* f = p.find("filename")) {
        if (p.has("L")) fail(f->at, "an area light takes L or filename, not both");
        if (sh.kind == ShapeKind::Sphere) fail(f->at, "an area light with an image on a sphere is not supported (give it as a mesh)");
        if (sh.mesh.uvs.empty())
            fail(f->at, "an area light with an image needs the shape's (u, v) (pbrt's default per-triangle (u, v) is not reproduced)");
        TextureDesc t;
        t.kind = TextureKind::Bitmap;
        try {
            t.image = readSceneImage(resolve(p.getString("filename", "")));
        } catch (const InputError& e) {
            fail(f->at, e.what());
        }
        for (float& v : t.image.rgb) v = std::max(0.0f, v);  // pbrt: ClampZero
        t.wrap = TextureWrap::Clamp;
        const float flip[6] = {1, 0, 0, 0, -1, 1};
        std::copy(flip, flip + 6, t.uvTransform);
        t.id = image = int(s_.textures.size());
        s_.textures.push_back(std::move(t));
    }
    const Vec3 L = image >= 0 ? Vec3(1.0f) : spectrum(p, "L", Vec3(1.0f), SpectrumUse::Illuminant);
    const int spectral = image >= 0 ? -1 : lastSpectrum_;
    double scale = p.getFloat("scale", 1);
    const bool twoSided = p.getBool("twosided", false);
    const double power = p.getFloat("power", -1);
    if (power > 0) {  // pbrt-v4: scale so that the light emits `power` watts (k_e = pi A L, twice from two faces;
                      // an image's: its pixels' mean luminance for L)
        double lum = luminance(L);
        if (image >= 0) {
            const Image& im = s_.textures[size_t(image)].image;
            lum = 0;
            for (int y = 0; y < im.height; ++y)
                for (int x = 0; x < im.width; ++x) lum += luminance(im.at(x, y));
            lum /= std::max(1, im.width * im.height);
        }
        const double ke = (twoSided ? 2 : 1) * M_PI * areaOf(sh) * lum;
        if (!(ke > 0)) fail(d.at, "power: the light has no area or no luminance");
        scale *= power / ke;
    }
    LightDesc l;
    l.kind = sh.kind == ShapeKind::Sphere                         ? LightKind::Sphere
             : isParallelogram(sh.mesh) && !twoSided && image < 0 ? LightKind::Rect
                                                                  : LightKind::Mesh;
    l.twoSided = twoSided;
    l.texture = image;
    l.radiance = scaled(d.at, L, scale, power > 0 ? "L (normalised to its power)" : "L");
    l.spectrum = spectral;
    l.shape = int(&sh - s_.shapes.data());
    sh.light = int(s_.lights.size());
    pendingLightMedia_.push_back({sh.light, g_.insideMedium, g_.outsideMedium, d.at});  // the shape's MediumInterface
    s_.lights.push_back(l);
    d.params.warnUnused(s_.warnings);
}

void Importer::lightSource(Directive& d) {
    Params& p = d.params;
    const std::string& type = d.strings[0];
    double scale = p.getFloat("scale", 1);
    LightDesc l;
    if (type == "point" || type == "spot") {
        const Vec3 I = spectrum(p, "I", Vec3(1.0f), SpectrumUse::Illuminant);
        l.spectrum = lastSpectrum_;
        const Vec3 from = p.getPoint3("from", Vec3(0.0f));
        l.kind = LightKind::Point;
        l.position = g_.ctm.point(from);
        double ke = 4 * M_PI;
        if (type == "spot") {  // pbrt-v4: full intensity within coneangle - conedeltaangle, smoothstep to coneangle
            const Vec3 to = p.getPoint3("to", Vec3(0, 0, 1));
            const Vec3 axis = g_.ctm.vector(to - from);
            if (!(length(axis) > 0)) fail(d.at, "spot: from equals to");
            const double cone = p.getFloat("coneangle", 30), delta = p.getFloat("conedeltaangle", 5);
            if (!(cone > 0 && cone <= 180) || delta < 0 || delta > cone)
                fail(d.at, "spot: coneangle must be in (0, 180] and conedeltaangle in [0, coneangle]");
            l.spotAxis = normalize(axis);
            l.spotCutoff = float(cone * M_PI / 180);
            l.spotBeam = float((cone - delta) * M_PI / 180);
            l.spotSmoothstep = true;
            const double cosEnd = std::cos(cone * M_PI / 180), cosStart = std::cos((cone - delta) * M_PI / 180);
            ke = 2 * M_PI * ((1 - cosStart) + (cosStart - cosEnd) / 2);
        }
        const double power = p.getFloat("power", -1);
        if (power > 0) scale *= power / (ke * luminance(I));
        l.radiance = scaled(d.at, I, scale, power > 0 ? "I (normalised to its power)" : "I");
    } else if (type == "distant") {
        const Vec3 L = spectrum(p, "L", Vec3(1.0f), SpectrumUse::Illuminant);
        l.spectrum = lastSpectrum_;
        const Vec3 from = p.getPoint3("from", Vec3(0.0f)), to = p.getPoint3("to", Vec3(0, 0, 1));
        const Vec3 dir = g_.ctm.vector(to - from);  // the light travels from `from` to `to`
        if (!(length(dir) > 0)) fail(d.at, "distant: from equals to");
        const double E = p.getFloat("illuminance", -1);
        if (E > 0) scale *= E / luminance(L);  // pbrt-v4: the illuminance on a facing surface
        l.kind = LightKind::Directional;
        l.direction = normalize(dir);
        l.radiance = scaled(d.at, L, scale, E > 0 ? "L (normalised to its illuminance)" : "L");
    } else if (type == "infinite") {
        if (p.has("portal")) warn(p.find("portal")->at, "portal is read and not used");
        if (s_.envMap.width > 0) fail(d.at, "a second infinite light is not supported");
        const double E = p.getFloat("illuminance", -1);
        if (p.has("filename")) {  // pbrt's equal-area octahedral map, resampled (envmap.h's grid)
            if (p.has("L")) fail(d.at, "give either L or filename, not both");
            const std::string path = resolve(p.getString("filename", ""));
            Image src;
            try {
                src = readSceneImage(path);
            } catch (const InputError& e) {
                fail(d.at, e.what());
            }
            if (src.width != src.height) fail(d.at, path + ": an infinite light's image must be square (pbrt's equal-area octahedral map)");
            s_.envMap = resampleOctahedral(src, g_.ctm);
            s_.settings.envMap = path;
            if (E > 0) {  // pbrt-v4: scaled so that the upper hemisphere gives illuminance E
                const double e = upperIlluminance(s_.envMap, normalize(g_.ctm.vector(Vec3(0, 0, 1))));
                if (!(e > 0)) fail(d.at, "illuminance: the map is black above the horizon");
                scale *= E / e;
            }
            scaleImage(d.at, s_.envMap, scale, path);
            return;
        }
        const Vec3 L = spectrum(p, "L", Vec3(1.0f), SpectrumUse::Illuminant);
        if (E > 0) scale *= E / (M_PI * luminance(L));  // a constant sky: E = pi L on an upward surface
        const Vec3 c = scaled(d.at, L, scale, E > 0 ? "L (normalised to its illuminance)" : "L");
        s_.envMap = Image(2, 2);
        for (int y = 0; y < 2; ++y)
            for (int x = 0; x < 2; ++x) s_.envMap.set(x, y, c);
        s_.settings.envMap = "(constant)";
        return;
    } else if (type == "goniometric" || type == "projection") {
        fail(d.at, "LightSource \"" + type + "\" is not supported");
    } else {
        fail(d.at, "unknown LightSource \"" + type + "\"");
    }
    // pbrt-v4: a light is in the outside medium of the MediumInterface in force at its directive
    pendingLightMedia_.push_back({int(s_.lights.size()), g_.outsideMedium, g_.outsideMedium, d.at});
    s_.lights.push_back(l);
}

}  // namespace wmlt::pbrt
