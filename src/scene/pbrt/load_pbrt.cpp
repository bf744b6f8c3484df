// pbrt-v4 scene files (docs/pbrt.md): the directives, the graphics state and transforms,
// objects and instances, and the camera, film, sampler, integrator and filter.
#include <algorithm>
#include <cmath>
#include <filesystem>

#include "scene/number.h"
#include "scene/pbrt/pbrt_importer.h"
#include "wavemmlt/error.h"

namespace wmlt {

SceneDesc loadPbrt(const std::string& path, const LoadOptions& options) { return pbrt::Importer(path, options).run(); }

namespace pbrt {

Importer::Importer(const std::string& path, const LoadOptions& options)
    : parser_(path), options_(options), path_(path), base_(std::filesystem::path(path).parent_path().string()) {}

std::string Importer::resolve(const std::string& f) const {
    std::filesystem::path p(f);
    if (p.is_relative() && !base_.empty()) p = std::filesystem::path(base_) / p;
    return p.lexically_normal().string();
}

void Importer::warn(const Loc& at, const std::string& msg) {
    s_.warnings.push_back((at.file ? *at.file : path_) + ":" + std::to_string(at.line) + ": " + msg);
}

SceneDesc Importer::run() {
    s_.path = path_;
    namedCoords_["world"] = Matrix();
    Directive d;
    while (parser_.next(d)) directive(d);
    finish();
    return std::move(s_);
}

void Importer::transform(const Directive& d) {
    const std::vector<double>& v = d.numbers;
    Matrix T;
    if (d.name == "Translate") {
        T = Matrix::translate(v[0], v[1], v[2]);
    } else if (d.name == "Scale") {
        T = Matrix::scale(v[0], v[1], v[2]);
    } else if (d.name == "Rotate") {
        if (!(v[1] * v[1] + v[2] * v[2] + v[3] * v[3] > 0)) fail(d.at, "Rotate: the axis is zero");
        T = Matrix::rotate(v[0], v[1], v[2], v[3]);
    } else if (d.name == "LookAt") {  // camera from world: the inverse of the camera's frame
        Matrix W;
        if (!Matrix::lookAt(&v[0], &v[3], &v[6], W)) fail(d.at, "LookAt: eye equals look, or up is zero or along the view");
        T = W.inverse();
    } else {  // Transform, ConcatTransform: 16 numbers, column by column (pbrt's layout)
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j) T.m[j][i] = v[size_t(4 * i + j)];
        if (T.m[3][0] != 0 || T.m[3][1] != 0 || T.m[3][2] != 0 || T.m[3][3] != 1)
            fail(d.at, d.name + ": a projective matrix (not 0 0 0 1 in the last row) is not supported");
    }
    if (endTimeOnly_) return;  // motion: the end transform is read and not used
    if (d.name == "Transform") g_.ctm = T;
    else g_.ctm = g_.ctm * T;
    // Finite numbers whose product is not (Scale 1e30 1e30 1e30 twice): every entry must stay
    // a finite float, or the shapes it places would be NaN and infinities.
    for (const auto& row : g_.ctm.m)
        for (double x : row)
            if (!fitsFloat(x)) fail(d.at, d.name + ": the transform so far has an entry of " + numberText(x) + ", beyond a float's range");
    if (std::fabs(g_.ctm.det3()) < 1e-30) fail(d.at, d.name + ": the transform is singular");
}

Importer::State Importer::closeBlock(const Directive& d, const std::string& begin) {
    if (stack_.empty()) fail(d.at, d.name + " without a matching begin");
    const Block& b = stack_.back();
    if (b.begin != begin) fail(d.at, d.name + " closes the " + b.begin + " of line " + std::to_string(b.at.line) + " (mismatched nesting)");
    const State saved = b.state;
    stack_.pop_back();
    return saved;
}

void Importer::withAttributes(Directive& d, const std::string& target) const {
    auto it = g_.attributes.find(target);
    if (it == g_.attributes.end()) return;
    for (const Param& p : it->second)
        if (!d.params.has(p.name)) d.params.list.push_back(p);
}

void Importer::directive(Directive& d) {
    const std::string& n = d.name;
    if (n == "Translate" || n == "Scale" || n == "Rotate" || n == "LookAt" || n == "Transform" || n == "ConcatTransform") {
        transform(d);
    } else if (n == "Identity") {
        if (!endTimeOnly_) g_.ctm = Matrix();
    } else if (n == "CoordinateSystem") {
        namedCoords_[d.strings[0]] = g_.ctm;
    } else if (n == "CoordSysTransform") {
        auto it = namedCoords_.find(d.strings[0]);
        if (it == namedCoords_.end()) fail(d.at, "CoordSysTransform: no coordinate system \"" + d.strings[0] + "\"");
        g_.ctm = it->second;
    } else if (n == "ActiveTransform") {
        const std::string& w = d.strings[0];
        if (w != "StartTime" && w != "EndTime" && w != "All") fail(d.at, "ActiveTransform: \"" + w + "\" is not StartTime, EndTime or All");
        endTimeOnly_ = w == "EndTime";
        if (!warnedMotion_) warn(d.at, "motion (ActiveTransform): wavemmlt renders the start transform");
        warnedMotion_ = true;
    } else if (n == "TransformTimes") {
        if (!warnedMotion_) warn(d.at, "motion (TransformTimes): wavemmlt renders the start transform");
        warnedMotion_ = true;
    } else if (n == "ReverseOrientation") {
        g_.reverse = !g_.reverse;
    } else if (n == "AttributeBegin" || n == "TransformBegin") {
        stack_.push_back({g_, n, d.at});
        if (stack_.size() > 10000) fail(d.at, n + " nested too deep");
    } else if (n == "AttributeEnd" || n == "TransformEnd") {
        const State saved = closeBlock(d, n == "AttributeEnd" ? "AttributeBegin" : "TransformBegin");
        if (n == "TransformEnd") {
            g_.ctm = saved.ctm;
        } else {
            g_ = saved;
        }
    } else if (n == "WorldBegin") {
        if (inWorld_) fail(d.at, "a second WorldBegin");
        inWorld_ = true;
        g_.ctm = Matrix();
        namedCoords_["world"] = g_.ctm;
    } else if (n == "WorldEnd") {
        // pbrt-v3's end of the file: nothing to do
    } else if (n == "Camera" || n == "Film" || n == "Sampler" || n == "Integrator" || n == "PixelFilter" || n == "Accelerator") {
        if (inWorld_) fail(d.at, n + " inside the world block (it belongs before WorldBegin)");
        if (n == "Camera") {
            camera_ = d;
            cameraMedium_ = g_.outsideMedium;  // pbrt-v4: the camera is in the outside medium
            cameraAt_ = d.at;
            cameraFromWorld_ = g_.ctm;
            namedCoords_["camera"] = g_.ctm.inverse();
            haveCamera_ = true;
        } else if (n == "Film") {
            film_ = d;
        } else if (n == "Sampler") {
            sampler_ = d;
        } else if (n == "Integrator") {
            integrator_ = d;
        } else if (n == "PixelFilter") {
            filter_ = d;
        }
    } else if (n == "ColorSpace") {
        if (d.strings[0] != "srgb") fail(d.at, "ColorSpace \"" + d.strings[0] + "\": wavemmlt renders in linear sRGB only");
    } else if (n == "Option") {
        for (const Param& p : d.params.list) warn(p.at, "Option \"" + p.name + "\" is ignored");
    } else if (n == "Attribute") {
        const std::string& target = d.strings[0];
        if (target != "shape" && target != "light" && target != "material" && target != "medium" && target != "texture")
            fail(d.at, "Attribute \"" + target + "\" is not shape, light, material, medium or texture");
        std::vector<Param>& defaults = g_.attributes[target];
        for (Param& p : d.params.list) {
            p.used = true;  // a default no directive reads is no mistake
            auto same = std::find_if(defaults.begin(), defaults.end(), [&](const Param& q) { return q.name == p.name; });
            if (same != defaults.end()) *same = p;
            else defaults.push_back(p);
        }
    } else if (n == "MakeNamedMedium") {
        withAttributes(d, "medium");
        medium(d);
        done(d);
    } else if (n == "MediumInterface") {  // "inside" "outside", or one name for both
        g_.insideMedium = d.strings[0];
        g_.outsideMedium = d.strings.size() > 1 ? d.strings[1] : d.strings[0];
    } else if (n == "ObjectBegin") {
        if (!inWorld_) fail(d.at, "ObjectBegin before WorldBegin");
        if (currentObject_ >= 0) fail(d.at, "ObjectBegin inside an object (nested objects are not supported; pbrt-v4 refuses them too)");
        if (objects_.count(d.strings[0])) fail(d.at, "object \"" + d.strings[0] + "\" defined twice");
        stack_.push_back({g_, n, d.at});
        currentObject_ = s_.groups++;
        objects_[d.strings[0]] = currentObject_;
    } else if (n == "ObjectEnd") {
        if (currentObject_ < 0) fail(d.at, "ObjectEnd without ObjectBegin");
        g_ = closeBlock(d, "ObjectBegin");
        currentObject_ = -1;
    } else if (n == "ObjectInstance") {
        if (currentObject_ >= 0) fail(d.at, "ObjectInstance inside an object (nested instancing is not supported; pbrt-v4 refuses it too)");
        auto it = objects_.find(d.strings[0]);
        if (it == objects_.end()) fail(d.at, "ObjectInstance of an unknown object \"" + d.strings[0] + "\"");
        InstanceDesc in;
        in.group = it->second;
        in.toWorld = g_.ctm.affine();
        in.toLocal = g_.ctm.inverse().affine();
        in.line = d.at.line;
        s_.instances.push_back(in);
    } else if (n == "Material" || n == "MakeNamedMaterial" || n == "NamedMaterial") {
        withAttributes(d, "material");
        if (n == "NamedMaterial") {
            auto it = namedMaterials_.find(d.strings[0]);
            if (it == namedMaterials_.end()) fail(d.at, "NamedMaterial: no material named \"" + d.strings[0] + "\"");
            g_.material = it->second;
        } else if (n == "Material") {
            g_.material = material(d.strings[0], d);
            done(d);
        } else {
            if (namedMaterials_.count(d.strings[0])) fail(d.at, "MakeNamedMaterial: \"" + d.strings[0] + "\" defined twice");
            const std::string type = d.params.getString("type", "");
            if (type.empty()) fail(d.at, "MakeNamedMaterial \"" + d.strings[0] + "\" needs a \"string type\"");
            namedMaterials_[d.strings[0]] = material(type, d);
            done(d);
        }
    } else if (n == "Texture") {
        withAttributes(d, "texture");
        texture(d);
        done(d);
    } else if (n == "LightSource") {
        if (!inWorld_) fail(d.at, "LightSource before WorldBegin");
        withAttributes(d, "light");
        lightSource(d);
        done(d);
    } else if (n == "AreaLightSource") {
        if (d.strings[0] != "diffuse") fail(d.at, "AreaLightSource \"" + d.strings[0] + "\" is not supported (diffuse is)");
        withAttributes(d, "light");
        g_.areaLight = true;
        g_.areaLightDirective = d;
    } else if (n == "Shape") {
        if (!inWorld_) fail(d.at, "Shape before WorldBegin");
        withAttributes(d, "shape");
        shape(d);
        done(d);
    }
}

// ---- Camera, film, sampler, integrator, filter -----------------------------------------

void Importer::film() {
    Directive& f = film_;
    if (!f.name.empty() && f.strings[0] != "rgb") fail(f.at, "Film \"" + f.strings[0] + "\" is not supported (rgb is)");
    Params& p = f.params;
    s_.settings.width = p.getInt("xresolution", 1280);
    s_.settings.height = p.getInt("yresolution", 720);
    if (s_.settings.width < 1 || s_.settings.height < 1 || s_.settings.width > 16384 || s_.settings.height > 16384)
        fail(f.at, "the film's resolution must be 1 to 16384 pixels on each side");
    const std::string out = p.getString("filename", "pbrt.exr");
    s_.settings.output = out;
    // pbrt-v4's pixel bounds [x0, x1) x [y0, y1) (y down): `pixelbounds`, or `cropwindow`'s
    // fractions (clamped to [0, 1], each pair in either order) rounded up to pixels. The image
    // is that part of the film (CameraDesc::window).
    const int W = s_.settings.width, H = s_.settings.height;
    int b[4] = {0, W, 0, H};
    if (p.has("pixelbounds")) {
        if (p.has("cropwindow")) fail(p.find("cropwindow")->at, "give cropwindow or pixelbounds, not both");
        const Param& q = *p.find("pixelbounds");
        const std::vector<int> pb = p.getInts("pixelbounds");
        if (pb.size() != 4) fail(q.at, "pixelbounds: expected four integers");
        std::copy(pb.begin(), pb.end(), b);
        if (b[0] < 0 || b[2] < 0 || b[1] > W || b[3] > H || b[0] >= b[1] || b[2] >= b[3])
            fail(q.at, "pixelbounds must be a nonempty part of the film (x0 < x1 <= xresolution, y0 < y1 <= yresolution)");
    } else if (p.has("cropwindow")) {
        const Param& q = *p.find("cropwindow");
        const std::vector<double> c = p.getNumbers("cropwindow");
        if (c.size() != 4) fail(q.at, "cropwindow: expected four numbers");
        for (double v : c)
            if (!std::isfinite(v)) fail(q.at, "cropwindow: the numbers must be finite");
        auto clamp01 = [](double v) { return std::clamp(v, 0.0, 1.0); };
        b[0] = int(std::ceil(W * clamp01(std::min(c[0], c[1]))));
        b[1] = int(std::ceil(W * clamp01(std::max(c[0], c[1]))));
        b[2] = int(std::ceil(H * clamp01(std::min(c[2], c[3]))));
        b[3] = int(std::ceil(H * clamp01(std::max(c[2], c[3]))));
        if (b[0] >= b[1] || b[2] >= b[3]) fail(q.at, "cropwindow: no pixel inside it");
    }
    if (b[0] != 0 || b[1] != W || b[2] != 0 || b[3] != H) {
        s_.settings.width = b[1] - b[0];
        s_.settings.height = b[3] - b[2];
        float* win = s_.camera.window;
        win[0] = float(b[0]) / float(W), win[1] = float(b[1]) / float(W);
        win[2] = float(b[2]) / float(H), win[3] = float(b[3]) / float(H);
    }
    const std::string sensor = p.getString("sensor", "cie1931");
    if (sensor != "cie1931") fail(p.find("sensor")->at, "sensor \"" + sensor + "\": only cie1931 (the default) is supported");
    if (p.getFloat("whitebalance", 0) != 0) fail(p.find("whitebalance")->at, "whitebalance is not supported with the cie1931 sensor");
    // pbrt-v4's PixelSensor: the imaging ratio exposure time * ISO / 100 scales the image
    // (the exposure time is the camera's shutter interval: camera())
    imagingRatio_ = float(p.getFloat("iso", 100) / 100);
    if (!(imagingRatio_ > 0)) fail(f.at, "iso must be > 0");
    p.getFloat("diagonal", 35);
    p.getFloat("maxcomponentvalue", INFINITY);
    p.getBool("savefp16", true);
    if (!f.name.empty()) done(f);
}

void Importer::camera() {
    if (!haveCamera_) {  // pbrt's default: perspective, fov 90, at the origin looking along +z
        camera_.name = "Camera";
        camera_.strings = {"perspective"};
    }
    Params& p = camera_.params;
    const std::string type = camera_.strings[0];
    if (type != "perspective" && type != "orthographic")
        fail(camera_.at, "Camera \"" + type + "\" is not supported (perspective and orthographic are)");
    const Matrix W = cameraFromWorld_.inverse();  // world from camera
    CameraDesc& c = s_.camera;
    const Vec3 o = W.point(Vec3(0.0f)), fwd = normalize(W.vector(Vec3(0, 0, 1))), up = normalize(W.vector(Vec3(0, 1, 0)));
    const Vec3 right = W.vector(Vec3(1, 0, 0));
    c.position = o;
    c.lookAt = o + fwd;
    c.up = up;
    c.flipX = dot(right, cross(fwd, up)) < 0;  // pbrt: image right is camera +x
    const float* win = c.window;               // the whole film's aspect, not a crop window's
    const float aspect = (float(s_.settings.width) / (win[1] - win[0])) / (float(s_.settings.height) / (win[3] - win[2]));
    if (p.has("screenwindow")) fail(p.find("screenwindow")->at, "screenwindow is not supported");
    const double frame = p.getFloat("frameaspectratio", aspect);
    if (std::fabs(frame - aspect) > 1e-4 * aspect) fail(p.find("frameaspectratio")->at, "frameaspectratio differs from the film's");
    const double open = p.getFloat("shutteropen", 0), close = p.getFloat("shutterclose", 1);
    if (!(close > open)) fail(camera_.at, "shutterclose must be after shutteropen");
    imagingRatio_ *= float(close - open);  // pbrt-v4's exposure time
    if (type == "perspective") {
        c.fovDegrees = float(p.getFloat("fov", 90));
        if (!(c.fovDegrees > 0 && c.fovDegrees < 180)) fail(camera_.at, "fov must be in (0, 180) degrees");
    } else {  // the screen window [-1, 1] on the shorter side, in camera units
        c.orthographic = true;
        const float sx = length(right), sy = length(W.vector(Vec3(0, 1, 0)));
        c.orthoHalfWidth = (aspect >= 1 ? aspect : 1.0f) * sx;
        c.orthoHalfHeight = (aspect >= 1 ? 1.0f : 1.0f / aspect) * sy;
    }
    const double lens = p.getFloat("lensradius", 0), focus = p.getFloat("focaldistance", 1e6);
    if (lens < 0 || !(focus > 0)) fail(camera_.at, "lensradius must be >= 0 and focaldistance > 0");
    if (lens > 0) {
        if (c.orthographic) fail(camera_.at, "a lens on the orthographic camera is not supported");
        c.dof = true;
        c.focalLength = float(focus);
        c.fStop = float(focus / (2 * lens));
    }
    if (haveCamera_) done(camera_);
}

void Importer::options() {
    // Sampler: pixelsamples, rounded up to a square n x n
    Params& sp = sampler_.params;
    constexpr int64_t kMaxSpp = int64_t(1) << 24;  // --spp's limit: 4096 x 4096
    const int64_t spp = sp.getInt("pixelsamples", 16, 1, kMaxSpp, "wavemmlt's limit, as --spp's");
    const int64_t n = int64_t(std::ceil(std::sqrt(double(spp)) - 1e-9));
    if (n * n != spp)
        warn(sampler_.at, "pixelsamples " + std::to_string(spp) + " rounded up to " + std::to_string(n * n) + " (" + std::to_string(n) + " x " +
                              std::to_string(n) + ")");
    for (const char* k : {"seed", "randomization", "jitter", "xsamples", "ysamples"})
        if (sp.has(k)) sp.find(k);
    s_.settings.samples = int(n);
    if (!sampler_.name.empty()) done(sampler_);
    // Integrator: the tracer and pbrt's maxdepth (bounces) as path segments
    Params& ip = integrator_.params;
    const std::string type = integrator_.name.empty() ? "volpath" : integrator_.strings[0];
    s_.settings.spectral = true;  // pbrt-v4 renders spectrally (docs/spectral.md)
    if (type == "path" || type == "volpath") s_.settings.tracer = TracerKind::PT;
    else if (type == "bdpt") s_.settings.tracer = TracerKind::BPT;
    else if (type == "lightpath") s_.settings.tracer = TracerKind::LT;
    else if (type == "mlt") s_.settings.tracer = TracerKind::MMLT;
    else if (options_.tracerGiven) {  // the command line's tracer renders the scene; the integrator's parameters mean nothing to it
        warn(integrator_.at,
             "Integrator \"" + type + "\" is not one of wavemmlt's: replaced by the tracer the command line gives (its parameters are ignored)");
        for (Param& q : ip.list) q.used = true;
    } else
        fail(integrator_.at, "Integrator \"" + type + "\" is not supported (path, volpath, bdpt, lightpath, mlt are; or choose one with --tracer)");
    const int64_t maxDepth = ip.getInt("maxdepth", 5, 0, INT32_MAX);
    s_.settings.maxPathLength = int(std::min<int64_t>(maxDepth + 1, 64));
    if (maxDepth + 1 > 64) warn(ip.has("maxdepth") ? ip.find("maxdepth")->at : integrator_.at, "maxdepth above 63 becomes 63");
    // pbrt's path regularisation (roughened BSDFs after a path's first non-specular bounce,
    // scene/regularize.h): the PT and BPT renders apply it, as pbrt-v4's path, volpath and
    // bdpt do; judged by the tracer that renders (the command line's, else the integrator's),
    // the others render without it, with a warning
    if (ip.getBool("regularize", false)) {
        const Loc& at = ip.find("regularize")->at;
        s_.regularize = true;
        s_.regularizeAt = (at.file ? *at.file : path_) + ":" + std::to_string(at.line);
        const TracerKind tracer = options_.tracerGiven ? options_.tracer : s_.settings.tracer;
        if (tracer == TracerKind::MMLT || tracer == TracerKind::PSSMLT)
            warn(at, "regularize is not applied: it would bias the Markov chains' target (rendered without it)");
        else if (tracer == TracerKind::LT)
            warn(at, "regularize is not applied by the light tracer (nor by pbrt-v4's lightpath): rendered without it");
    }
    if (type == "mlt") {
        s_.settings.probLarge = float(ip.getFloat("largestepprobability", 0.3));
        const int64_t mpp = ip.getInt("mutationsperpixel", 100, 1, kMaxSpp, "wavemmlt's limit, as --spp's");
        s_.settings.samples = int(std::ceil(std::sqrt(double(mpp)) - 1e-9));
        for (const char* k : {"sigma", "bootstrapsamples", "chains"})
            if (ip.has(k)) warn(ip.find(k)->at, std::string(k) + " is read and not used (wavemmlt's MMLT chooses its own)");
    }
    for (const char* k : {"lightsampler", "visualizestrategies", "visualizeweights"})
        if (ip.has(k)) warn(ip.find(k)->at, std::string(k) + " is read and not used");
    if (!integrator_.name.empty()) done(integrator_);
    // pbrt-v4's path and lightpath integrators do not scatter in media: it renders such a
    // scene as if they were not there (pass-through boundaries still pass), and so does
    // wavemmlt, to render what pbrt renders (docs/media.md)
    if ((type == "path" || type == "lightpath") && (!s_.media.empty() || s_.cameraMedium >= 0)) {
        warn(integrator_.at, "the \"" + type +
                                 "\" integrator does not render participating media (pbrt-v4 ignores them "
                                 "too): rendered without them; use \"volpath\" (or bdpt, mlt) to render them");
        s_.media.clear();
        s_.cameraMedium = -1;
        for (ShapeDesc& sh : s_.shapes) {
            sh.mediumBoundary = false;
            sh.mediumInside = sh.mediumOutside = -1;
        }
        for (LightDesc& l : s_.lights) l.mediumFront = l.mediumBack = -1;
    }
    // PixelFilter (pbrt's default: gaussian, radius 1.5, sigma 0.5)
    FilterDesc& f = s_.filter;
    const std::string ft = filter_.name.empty() ? "gaussian" : filter_.strings[0];
    Params& fp = filter_.params;
    double r = 0;
    if (ft == "box") {
        f.kind = FilterKind::Box;
        r = 0.5;
    } else if (ft == "gaussian") {
        f.kind = FilterKind::Gaussian;
        r = 1.5;
        f.stddev = float(fp.getFloat("sigma", 0.5));
    } else if (ft == "triangle") {
        f.kind = FilterKind::Tent;
        r = 2;
    } else if (ft == "mitchell") {
        f.kind = FilterKind::Mitchell;
        r = 2;
        f.B = float(fp.getFloat("B", 1 / 3.0));
        f.C = float(fp.getFloat("C", 1 / 3.0));
    } else if (ft == "sinc") {
        f.kind = FilterKind::Lanczos;
        r = 4;
        f.tau = float(fp.getFloat("tau", 3));
    } else fail(filter_.at, "PixelFilter \"" + ft + "\" is not supported (box, gaussian, triangle, mitchell, sinc are)");
    const double rx = fp.getFloat("xradius", r), ry = fp.getFloat("yradius", r);
    if (rx != ry) fail(filter_.at, "xradius and yradius differ: wavemmlt's filters have one radius");
    if (!(rx > 0)) fail(filter_.at, "the filter radius must be > 0");
    if (f.kind == FilterKind::Gaussian && !(f.stddev > 0)) fail(filter_.at, "sigma must be > 0");
    f.radius = float(rx);
    if (!filter_.name.empty()) done(filter_);
}

void Importer::finish() {
    // pbrt-v4 refuses a file that ends inside a block, and so does wavemmlt: the block's line.
    if (!stack_.empty()) {
        const Block& b = stack_.back();
        const std::string end = b.begin == "ObjectBegin" ? "ObjectEnd" : b.begin == "TransformBegin" ? "TransformEnd" : "AttributeEnd";
        fail(b.at, b.begin + " without " + end + " (the file ends inside it)");
    }
    film();
    camera();
    resolveMedia();
    options();
    if (imagingRatio_ != 1) {  // each product checked: iso 1e30 on a light of 1e30 overflows a float
        const Loc at = film_.name.empty() ? camera_.at : film_.at;
        auto times = [&](float& v) {
            const double x = double(v) * imagingRatio_;
            if (!fitsFloat(x))
                fail(at, "the film's imaging ratio (iso / 100 times the shutter time, " + numberText(imagingRatio_) + ") times an emitter's value (" +
                             numberText(v) + ") is beyond a float's range");
            v = float(x);
        };
        for (LightDesc& l : s_.lights) times(l.radiance.x), times(l.radiance.y), times(l.radiance.z);
        for (float& v : s_.envMap.rgb) times(v);
    }
    if (s_.lights.empty() && s_.envMap.width == 0) fail(Loc{&path_, 0}, "the scene has no light");
    if (s_.shapes.empty()) fail(Loc{&path_, 0}, "the scene has no shape");
}

}  // namespace pbrt
}  // namespace wmlt
