// The XML scene loader: reads and validates a scene file (../shared/spec/scene-format.md)
// into a SceneDesc. Every problem is one InputError "file:line: <element>: problem";
// unknown elements and attributes are errors; warnings go to SceneDesc::warnings.
// Choices where the spec is silent are marked "(choice)".
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <pugixml.hpp>
#include <string>
#include <vector>

#include "scene/filter_desc.h"
#include "scene/number.h"
#include "scene/read_file.h"
#include "scene/thesis/load_thesis.h"
#include "scene/transform.h"
#include "scene/xml_nesting.h"
#include "wavemmlt/error.h"
#include "wavemmlt/scene_desc.h"

namespace wmlt {
namespace {

// The shader index a Shader of Type Interface stands for (ShapeDesc::passThrough).
constexpr int kPassThroughShader = -2;

using Node = pugi::xml_node;
using Names = std::vector<const char*>;

bool in(const Names& names, const char* s) {
    return std::any_of(names.begin(), names.end(), [&](const char* n) { return std::string(n) == s; });
}
std::string join(const Names& names) {
    std::string s;
    for (const char* n : names) s += (s.empty() ? "" : ", ") + std::string(n);
    return s;
}

// A value quoted in a message: at most 40 characters, control characters as '?'.
std::string excerpt(const std::string& v) {
    std::string s = v.substr(0, 40);
    for (char& c : s)
        if ((unsigned char)c < 0x20 || c == 0x7f) c = '?';
    return v.size() > 40 ? s + "..." : s;
}

// The children of a container element, by name: each at most once (choice: a repeated
// element is an error, as a repeated property is in Mitsuba).
struct Kids {
    std::vector<Node> nodes;
    Node operator[](const char* name) const {
        for (Node n : nodes)
            if (std::string(n.name()) == name) return n;
        return Node();
    }
};

class Loader {
public:
    Loader(const std::string& xml, const std::string& file, const std::string& baseDir) : xml_(xml), file_(file), base_(baseDir) {
        lineStarts_.push_back(0);
        for (size_t i = 0; i < xml.size(); ++i)
            if (xml[i] == '\n') lineStarts_.push_back(i + 1);
    }
    SceneDesc run();

private:
    const std::string& xml_;
    std::string file_, base_;
    std::vector<size_t> lineStarts_;
    Node root_;
    SceneDesc s_;
    std::map<int, int> shaderIndex_, textureIndex_, shaderLine_, textureLine_, mediumIndex_, mediumLine_;
    int interfaceShader_ = -1;  // a Shader of Type Interface: its ID (kPassThrough as its index)
    std::map<std::string, int> geometryLine_, lightLine_;

    int lineOfOffset(ptrdiff_t off) const {
        if (off < 0) return 0;
        return int(std::upper_bound(lineStarts_.begin(), lineStarts_.end(), size_t(off)) - lineStarts_.begin());
    }
    int line(Node n) const { return lineOfOffset(n.offset_debug()); }
    // "Geometry ID="3": Radius": the element and the top-level element holding it.
    std::string what(Node n) const {
        Node p = n.parent();
        std::string s = (p && p != root_ && p.type() == pugi::node_element) ? what(p) + ": " : "";
        s += n.name();
        if (p == root_ && n.attribute("ID")) s += std::string(" ID=\"") + n.attribute("ID").value() + "\"";
        return s;
    }
    [[noreturn]] void fail(Node n, const std::string& msg) const { throw InputError(file_, line(n), what(n) + ": " + msg); }
    void warn(Node n, const std::string& msg) { s_.warnings.push_back(InputError(file_, line(n), what(n) + ": " + msg).what()); }
    std::string resolve(const std::string& name) const {
        std::filesystem::path p(name);
        if (p.is_relative() && !base_.empty()) p = std::filesystem::path(base_) / p;
        return p.lexically_normal().string();
    }

    // "--" may not occur inside a comment (XML 1.0, 2.5); pugixml does not check it. A
    // comment ended by "->" that runs on to the next "-->" would hide elements.
    void checkComments(Node n) const {
        for (Node c : n.children()) {
            if (c.type() == pugi::node_comment && std::string(c.value()).find("--") != std::string::npos)
                throw InputError(file_, line(c), "not well-formed XML: \"--\" inside a comment (a comment ended by \"->\"?)");
            checkComments(c);
        }
    }

    // Text outside <Scene> (trailing garbage) and NUL bytes: pugixml silently drops
    // PCDATA at the document level unless it parses a fragment, so the file is parsed a
    // second time as one to find it.
    void checkOutsideText() const {
        const size_t nul = xml_.find('\0');
        if (nul != std::string::npos) throw InputError(file_, lineOfOffset(ptrdiff_t(nul)), "not well-formed XML: a NUL byte (a binary file?)");
        pugi::xml_document frag;
        if (!frag.load_buffer(xml_.data(), xml_.size(), pugi::parse_default | pugi::parse_fragment, pugi::encoding_utf8)) return;
        for (Node c : frag.children()) {
            if (c.type() != pugi::node_pcdata && c.type() != pugi::node_cdata) continue;
            const std::string v = c.value();
            const size_t lead = std::min(v.find_first_not_of(" \t\r\n"), v.size());
            const std::string text = v.substr(lead, v.find_last_not_of(" \t\r\n") + 1 - lead);
            throw InputError(file_, lineOfOffset(c.offset_debug() + ptrdiff_t(lead)),
                             "not well-formed XML: text outside the <Scene> element (\"" + excerpt(text) + "\")");
        }
    }

    // ---- structure checks ----
    void attrs(Node n, const Names& allowed) const {
        for (pugi::xml_attribute a : n.attributes())
            if (!in(allowed, a.name()))
                fail(n, std::string("unknown attribute \"") + a.name() + "\"" + (allowed.empty() ? "" : " (expected " + join(allowed) + ")"));
    }
    void noText(Node n) const {
        for (Node c : n.children())
            if (c.type() == pugi::node_pcdata || c.type() == pugi::node_cdata) fail(n, "unexpected text \"" + excerpt(c.value()) + "\"");
    }
    // A leaf element with exactly the attributes `allowed`.
    void leaf(Node n, const Names& allowed) const {
        attrs(n, allowed);
        noText(n);
        for (Node c : n.children())
            if (c.type() == pugi::node_element) fail(c, std::string("unknown element inside <") + n.name() + ">");
    }
    Kids kids(Node parent, const Names& allowed) const {
        noText(parent);
        Kids k;
        for (Node c : parent.children()) {
            if (c.type() != pugi::node_element) continue;
            if (!in(allowed, c.name())) fail(c, "unknown element (expected one of " + join(allowed) + ")");
            if (Node prev = k[c.name()]) fail(c, "given twice (first on line " + std::to_string(line(prev)) + ")");
            k.nodes.push_back(c);
        }
        return k;
    }
    Node need(const Kids& k, Node parent, const char* name) const {
        Node n = k[name];
        if (!n) fail(parent, std::string("missing required element <") + name + ">");
        return n;
    }
    std::string attr(Node n, const char* a) const {
        pugi::xml_attribute at = n.attribute(a);
        if (!at) fail(n, std::string("missing attribute \"") + a + "\"");
        return at.value();
    }

    // ---- values ----
    // A number (scene/number.h: finite, fits a float, the whole attribute).
    double number(Node n, const char* a, bool integer = false) const {
        double v = 0;
        if (!parseNumber(attr(n, a), integer, v))
            fail(n, std::string(a) + "=\"" + n.attribute(a).value() + "\" is not " + (integer ? "an integer" : "a finite number"));
        return v;
    }
    double ranged(Node n, const char* a, double v, bool ok, const std::string& rule) const {
        if (!ok) fail(n, std::string(a) + "=\"" + n.attribute(a).value() + "\" is out of range (" + rule + ")");
        return v;
    }
    double value(Node n) const {
        leaf(n, {"value"});
        return number(n, "value");
    }
    double positive(Node n) const {
        double v = value(n);
        return ranged(n, "value", v, v > 0, "must be > 0");
    }
    int integer(Node n, long long lo, long long hi) const {
        leaf(n, {"value"});
        double v = number(n, "value", true);
        return int(ranged(n, "value", v, v >= lo && v <= hi, std::to_string(lo) + " to " + std::to_string(hi)));
    }
    Vec3 xyz(Node n) const {
        leaf(n, {"x", "y", "z"});
        return Vec3(float(number(n, "x")), float(number(n, "y")), float(number(n, "z")));
    }
    // Colours: linear RGB in [0, 1]; `t` is ignored (spec, "Shaders").
    Vec3 colour(Node n) const {
        leaf(n, {"r", "g", "b", "t"});
        Vec3 c;
        const char* names[3] = {"r", "g", "b"};
        for (int i = 0; i < 3; ++i) {
            double v = number(n, names[i]);
            c[i] = float(ranged(n, names[i], v, v >= 0 && v <= 1, "0 to 1"));
        }
        return c;
    }
    std::string name(Node n) const {
        leaf(n, {"name"});
        std::string s = attr(n, "name");
        if (s.empty()) fail(n, "name is empty");
        return s;
    }
    std::string type(Node n, const Names& types) const {
        std::string t = attr(n, "Type");
        if (!in(types, t.c_str())) fail(n, "Type=\"" + t + "\" is not one of " + join(types));
        return t;
    }
    Image image(Node n, const std::string& path) {
        Image img;
        try {
            img = readSceneImage(path);
        } catch (const InputError& e) {
            fail(n, e.what());
        }
        if (img.width <= 0 || img.height <= 0) fail(n, path + ": the image is empty (0 x 0)");
        // (choice) NaN or infinite pixels are an error (readSceneImage); negative ones
        // (filtering ringing in EXR files) are set to 0.
        size_t negative = 0;
        for (float& v : img.rgb)
            if (v < 0) {
                v = 0;
                ++negative;
            }
        if (negative) warn(n, path + ": " + std::to_string(negative) + " negative pixel values set to 0");
        return img;
    }

    // An integer ID, unique among `lines` (ID -> line of its element).
    int uniqueId(Node n, std::map<int, int>& lines, int lo, const char* kind) const {
        const double id = number(n, "ID", true);
        ranged(n, "ID", id, id >= lo && id <= INT32_MAX, std::string(kind) + " IDs are >= " + std::to_string(lo));
        if (lines.count(int(id)))
            fail(n, "ID " + std::to_string(int(id)) + " is already used by the " + kind + " on line " + std::to_string(lines[int(id)]));
        lines[int(id)] = line(n);
        return int(id);
    }
    // Plane and rectangle light: Width x Depth, both > 0.
    void rect(const Kids& k, Node n, ShapeDesc& sh) const;
    // Sphere and sphere light: Radius > 0 times the (uniform) scale.
    void sphere(Node radius, float scale, ShapeDesc& sh) const {
        sh.kind = ShapeKind::Sphere;
        sh.uv = UvKind::Sphere;
        sh.center = sh.toWorld.point(Vec3(0.0f));
        sh.radius = float(positive(radius)) * scale;
    }

    void settings(Node n);
    void filter(Node c);
    void camera(Node n);
    void texture(Node n);
    void shader(Node n);
    void medium(Node n);
    int mediumRef(Node n, const char* attribute);
    void textureRef(Node n, int& slot) const;
    void transform(const Kids& k, ShapeDesc& sh, Vec3& scale) const;
    void geometry(Node n);
    void light(Node n);
};

// A Width x Depth rectangle in the local xz-plane, normal +y, in world space. The corners
// are wound counter-clockwise seen from +y, so the geometric normal cross(p1 - p0, p2 - p0)
// points along the transformed +y (a positive scale keeps it so): the renderer relies on
// this for the side a rectangle light emits on. uv = (x / Width + 0.5, z / Depth + 0.5).
TriangleMesh rectangle(float w, float d, const Affine& toWorld) {
    TriangleMesh m;
    const float hx = 0.5f * w, hz = 0.5f * d;
    const Vec3 local[4] = {{-hx, 0, -hz}, {-hx, 0, hz}, {hx, 0, hz}, {hx, 0, -hz}};
    for (const Vec3& p : local) {
        m.positions.push_back(toWorld.point(p));
        m.uvs.push_back(p.x / w + 0.5f);
        m.uvs.push_back(p.z / d + 0.5f);
    }
    m.indices = {0, 1, 2, 0, 2, 3};
    return m;
}

void Loader::rect(const Kids& k, Node n, ShapeDesc& sh) const {
    const float w = float(positive(need(k, n, "Width"))), d = float(positive(need(k, n, "Depth")));
    sh.mesh = rectangle(w, d, sh.toWorld);
    sh.uv = UvKind::Plane;
}

void Loader::settings(Node n) {
    attrs(n, {});
    Kids k = kids(
        n, {"Width", "Height", "Sample", "Thread", "Tracer", "MaxPathLength", "MinPathLength", "ProbLarge", "Output", "EnvMap", "Filter", "Medium"});
    Settings& st = s_.settings;
    if (Node c = k["Width"]) st.width = integer(c, 1, 16384);
    if (Node c = k["Height"]) st.height = integer(c, 1, 16384);
    if (Node c = k["Sample"]) st.samples = integer(c, 1, 4096);  // (choice) N <= 4096
    if (Node c = k["Thread"]) st.threads = integer(c, 0, 4096);  // (choice) 0 = all
    if (Node c = k["Tracer"]) {
        std::string t = name(c);
        std::transform(t.begin(), t.end(), t.begin(), [](unsigned char ch) { return char(std::toupper(ch)); });
        if (t == "MMLT") st.tracer = TracerKind::MMLT;
        else if (t == "BPT") st.tracer = TracerKind::BPT;
        else if (t == "LT") st.tracer = TracerKind::LT;
        else if (t == "PT") st.tracer = TracerKind::PT;
        else if (t == "PSSMLT") st.tracer = TracerKind::PSSMLT;  // (extension: docs/scene-format.md)
        else fail(c, "name=\"" + std::string(c.attribute("name").value()) + "\" is not one of MMLT, BPT, LT, PT, PSSMLT");
    }
    if (Node c = k["MaxPathLength"]) st.maxPathLength = integer(c, 1, 64);
    if (Node c = k["MinPathLength"]) st.minPathLength = integer(c, 1, 64);
    if (st.minPathLength > st.maxPathLength)
        fail(k["MinPathLength"] ? k["MinPathLength"] : k["MaxPathLength"],
             "MinPathLength " + std::to_string(st.minPathLength) + " is greater than MaxPathLength " + std::to_string(st.maxPathLength));
    if (Node c = k["ProbLarge"]) {
        double p = value(c);
        st.probLarge = float(ranged(c, "value", p, p > 0 && p <= 1, "0 < p <= 1"));
    }
    if (Node c = k["Output"]) {
        // Surrounding quotes (the appendix's "'render.png'") are stripped.
        std::string o = name(c);
        if (o.size() >= 2 && (o[0] == '"' || o[0] == '\'') && o.back() == o[0]) o = o.substr(1, o.size() - 2);
        if (o.empty()) fail(c, "name is empty");
        if (!isWritableImageExtension(o)) fail(c, "\"" + o + "\": the extension must be .exr, .pfm or .png");
        st.output = o;
    }
    if (Node c = k["Filter"]) filter(c);
    if (Node c = k["Medium"]) {  // (choice, docs/media.md) the medium around everything: the camera's
        leaf(c, {"value"});
        s_.cameraMedium = mediumRef(c, "value");
    }
    if (Node c = k["EnvMap"]) {
        // (choice) any format readImage reads; the spec names .exr and .hdr.
        st.envMap = resolve(name(c));
        s_.envMap = image(c, st.envMap);
        // (choice) a latitude-longitude map needs at least 2 x 2 pixels; a constant sky is
        // written as a 2 x 2 map of one colour.
        if (s_.envMap.width < 2 || s_.envMap.height < 2)
            fail(c, st.envMap + ": an environment map of " + std::to_string(s_.envMap.width) + " x " + std::to_string(s_.envMap.height) +
                        " pixels is too small (at least 2 x 2)");
    }
}

// (choice, docs/filters.md) <Filter name="gaussian" radius="2" stddev="0.5" B=".." C=".."
// lobes="3"/>: a name of kFilterNames and that filter's parameters; absent, the box.
void Loader::filter(Node c) {
    leaf(c, {"name", "radius", "stddev", "B", "C", "lobes", "tau"});
    const std::string nm = attr(c, "name");
    if (!namedFilter(nm, s_.filter)) fail(c, "name=\"" + nm + "\" is not one of " + kFilterNames);
    for (const char* a : {"stddev", "radius", "B", "C", "lobes", "tau"}) {
        if (!c.attribute(a)) continue;
        const std::string problem = setFilterParameter(s_.filter, a, number(c, a));
        if (!problem.empty()) fail(c, std::string(a) + "=\"" + c.attribute(a).value() + "\": " + problem);
    }
}

void Loader::camera(Node n) {
    attrs(n, {"Type", "ID"});
    if (n.attribute("Type")) type(n, {"Camera"});  // (choice) Type may be omitted
    Kids k = kids(n, {"Position", "LookAt", "Up", "FOV", "DOF", "F-Length", "F-Stop"});
    CameraDesc& c = s_.camera;
    c.position = xyz(need(k, n, "Position"));
    Node look = need(k, n, "LookAt");
    c.lookAt = xyz(look);
    if (Node u = k["Up"]) c.up = xyz(u);
    Node fov = need(k, n, "FOV");
    double f = value(fov);
    c.fovDegrees = float(ranged(fov, "value", f, f > 0 && f < 180, "0 < FOV < 180"));
    if (Node d = k["DOF"]) c.dof = integer(d, 0, 1) == 1;
    // F-Length and F-Stop are read always but need to be > 0 only with DOF on.
    Node fl = c.dof ? need(k, n, "F-Length") : k["F-Length"];
    Node fs = c.dof ? need(k, n, "F-Stop") : k["F-Stop"];
    if (fl) c.focalLength = float(c.dof ? positive(fl) : value(fl));
    if (fs) c.fStop = float(c.dof ? positive(fs) : value(fs));
    // (choice) a camera with no direction or an Up along it is an error.
    Vec3 fwd = c.lookAt - c.position;
    if (lengthSquared(fwd) == 0) fail(look, "LookAt equals Position");
    if (lengthSquared(c.up) == 0 || length(cross(normalize(fwd), normalize(c.up))) < 1e-6f)
        fail(k["Up"] ? k["Up"] : n, "Up is zero or parallel to the viewing direction");
}

void Loader::texture(Node n) {
    attrs(n, {"Type", "ID"});
    std::string t = type(n, {"Checker", "ImageFile", "Marble"});
    TextureDesc tx;
    tx.id = uniqueId(n, textureLine_, 1, "Texture");
    Kids k;
    if (t == "Checker") {
        tx.kind = TextureKind::Checker;
        k = kids(n, {"Colour1", "Colour2", "Repeat"});
        tx.colour1 = colour(need(k, n, "Colour1"));
        tx.colour2 = colour(need(k, n, "Colour2"));
    } else if (t == "ImageFile") {
        tx.kind = TextureKind::ImageFile;
        k = kids(n, {"File", "Repeat"});
        Node f = need(k, n, "File");
        tx.image = image(f, resolve(name(f)));
    } else {
        tx.kind = TextureKind::Marble;
        k = kids(n, {"Colour1", "Colour2", "Colour3"});
        tx.colour1 = colour(need(k, n, "Colour1"));
        tx.colour2 = colour(need(k, n, "Colour2"));
        tx.colour3 = colour(need(k, n, "Colour3"));
    }
    if (Node r = k["Repeat"]) {  // (choice) optional, default 1 1; > 0
        leaf(r, {"u", "v"});
        double u = number(r, "u"), v = number(r, "v");
        tx.repeatU = float(ranged(r, "u", u, u > 0, "must be > 0"));
        tx.repeatV = float(ranged(r, "v", v, v > 0, "must be > 0"));
    }
    textureIndex_[tx.id] = int(s_.textures.size());
    s_.textures.push_back(std::move(tx));
}

// `Texture value=ID` / `Bump value=ID`: 0 is none; otherwise the texture must exist.
void Loader::textureRef(Node n, int& slot) const {
    int id = integer(n, 0, INT32_MAX);
    if (id == 0) {
        slot = -1;
        return;
    }
    auto it = textureIndex_.find(id);
    if (it == textureIndex_.end()) fail(n, "texture " + std::to_string(id) + " is not defined");
    slot = it->second;
}

// (choice, docs/media.md) <Medium Type="Homogeneous" ID="n"> with <SigmaA r g b/> and
// <SigmaS r g b/> (per unit length, >= 0, default 0) and <G value/> (Henyey-Greenstein, in
// (-1, 1), default 0).
void Loader::medium(Node n) {
    attrs(n, {"Type", "ID"});
    type(n, {"Homogeneous"});
    MediumDesc m;
    const int id = uniqueId(n, mediumLine_, 0, "Medium");
    m.name = std::to_string(id);
    m.line = line(n);
    Kids k = kids(n, {"SigmaA", "SigmaS", "G"});
    auto coefficients = [&](Node c) {
        leaf(c, {"r", "g", "b"});
        Vec3 v;
        const char* names[3] = {"r", "g", "b"};
        for (int i = 0; i < 3; ++i) {
            const double x = number(c, names[i]);
            v[i] = float(ranged(c, names[i], x, x >= 0 && x < 1e30, ">= 0 (per unit length)"));
        }
        return v;
    };
    if (Node c = k["SigmaA"]) m.sigmaA = coefficients(c);
    if (Node c = k["SigmaS"]) m.sigmaS = coefficients(c);
    if (Node c = k["G"]) {
        const double g = value(c);
        m.g = float(ranged(c, "value", g, g > -1 && g < 1, "-1 < g < 1"));
    }
    mediumIndex_[id] = int(s_.media.size());
    s_.media.push_back(m);
}

int Loader::mediumRef(Node n, const char* attribute) {
    const double id = number(n, attribute);
    auto it = mediumIndex_.find(int(id));
    if (id != std::floor(id) || it == mediumIndex_.end())
        fail(n, std::string(attribute) + "=\"" + n.attribute(attribute).value() + "\": no Medium with that ID");
    return it->second;
}

void Loader::shader(Node n) {
    attrs(n, {"Type", "ID"});
    std::string t = type(n, {"Matte", "Glossy", "Reflective", "Dielectric", "Interface"});
    MaterialDesc m;
    m.id = uniqueId(n, shaderLine_, 0, "Shader");  // (choice) integers >= 0
    Kids k;
    if (t == "Interface") {  // (choice, docs/media.md) an index-matched boundary: no surface
        kids(n, {});
        shaderIndex_[m.id] = kPassThroughShader;
        return;
    }
    if (t == "Matte") {
        m.kind = MaterialKind::Matte;
        k = kids(n, {"Diffuse", "Ambient", "Texture", "Bump"});
        m.diffuse = colour(need(k, n, "Diffuse"));
    } else if (t == "Glossy") {
        m.kind = MaterialKind::Glossy;
        k = kids(n, {"Diffuse", "Specular", "Shininess", "Ambient", "Texture", "Bump"});
        m.diffuse = colour(need(k, n, "Diffuse"));
        Node sp = need(k, n, "Specular");
        m.specular = colour(sp);
        Node sh = need(k, n, "Shininess");
        double e = value(sh);
        m.shininess = float(ranged(sh, "value", e, e >= 0, "must be >= 0"));
        for (int i = 0; i < 3; ++i)  // energy conservation (tolerance for decimal rounding)
            if (m.diffuse[i] + m.specular[i] > 1.0f + 1e-6f)
                fail(sp, "Diffuse + Specular exceeds 1 in the " +
                             std::string(i == 0   ? "red"
                                         : i == 1 ? "green"
                                                  : "blue") +
                             " channel (it would create energy)");
    } else if (t == "Reflective") {
        m.kind = MaterialKind::Reflective;
        k = kids(n, {"Reflect", "Ambient", "Bump"});
        m.reflect = colour(need(k, n, "Reflect"));
    } else {
        m.kind = MaterialKind::Dielectric;
        k = kids(n, {"Reflect", "Refract", "iIOR", "oIOR", "Ambient", "Bump"});
        if (Node r = k["Reflect"]) m.reflect = colour(r);  // (choice) optional, default 1
        if (Node r = k["Refract"]) m.refract = colour(r);
        Node ii = need(k, n, "iIOR"), oi = need(k, n, "oIOR");
        m.iorInside = float(positive(ii));
        m.iorOutside = float(positive(oi));
        if (m.iorInside == m.iorOutside) {
            warn(oi, "iIOR equals oIOR (" + std::string(oi.attribute("value").value()) + "): oIOR is taken as 1");
            m.iorOutside = 1.0f;
        }
    }
    if (Node a = k["Ambient"])
        if (!isBlack(colour(a))) warn(a, "Ambient is not black: ignored (it is not physical)");
    if (Node tx = k["Texture"]) textureRef(tx, m.texture[MaterialParam::Diffuse]);
    if (Node b = k["Bump"]) textureRef(b, m.bump);
    shaderIndex_[m.id] = int(s_.materials.size());
    s_.materials.push_back(m);
}

// Position, Rotation (optional, default 0: choice) and Scale (Geometry only, > 0: choice,
// so that no transform mirrors a surface and flips its winding).
void Loader::transform(const Kids& k, ShapeDesc& sh, Vec3& scale) const {
    Vec3 pos, rot;
    scale = Vec3(1.0f);
    if (Node p = k["Position"]) pos = xyz(p);
    if (Node r = k["Rotation"]) rot = xyz(r);
    if (Node s = k["Scale"]) {
        leaf(s, {"x", "y", "z", "value"});
        const bool uniform = bool(s.attribute("value"));
        if (uniform && (s.attribute("x") || s.attribute("y") || s.attribute("z"))) fail(s, "give either value or x, y and z, not both");
        const char* names[4] = {"x", "y", "z", "value"};
        for (int i = 0; i < 3; ++i) {
            const char* a = uniform ? names[3] : names[i];
            double v = number(s, a);
            scale[i] = float(ranged(s, a, v, v > 0, "must be > 0"));
        }
    }
    objectTransform(pos, rot, scale, sh.toWorld, sh.toLocal);
}

void Loader::geometry(Node n) {
    attrs(n, {"Type", "ID", "Medium", "Outside"});
    std::string t = type(n, {"Plane", "Sphere", "ObjFile"});
    ShapeDesc sh;
    sh.id = attr(n, "ID");
    sh.line = line(n);
    if (sh.id.empty()) fail(n, "ID is empty");
    if (geometryLine_.count(sh.id)) fail(n, "ID \"" + sh.id + "\" is already used by the Geometry on line " + std::to_string(geometryLine_[sh.id]));
    Names allowed = {"Position", "Rotation", "Scale", "Shader"};
    if (t == "Plane") allowed.insert(allowed.end(), {"Width", "Depth"});
    else if (t == "Sphere") allowed.push_back("Radius");
    else allowed.insert(allowed.end(), {"File", "SmoothShading"});
    Kids k = kids(n, allowed);
    Vec3 scale;
    transform(k, sh, scale);
    Node sref = need(k, n, "Shader");
    int sid = integer(sref, 0, INT32_MAX);
    auto it = shaderIndex_.find(sid);
    if (it == shaderIndex_.end()) fail(sref, "Shader " + std::to_string(sid) + " is not defined");
    sh.material = it->second;
    if (sh.material == kPassThroughShader) {
        sh.material = -1;
        sh.passThrough = true;
    }
    // (choice, docs/media.md) Medium="n": the medium inside the shape; Outside="n" the one
    // outside (default: the Settings' Medium, else vacuum)
    if (n.attribute("Medium") || n.attribute("Outside")) {
        sh.mediumBoundary = true;
        sh.mediumInside = n.attribute("Medium") ? mediumRef(n, "Medium") : s_.cameraMedium;
        sh.mediumOutside = n.attribute("Outside") ? mediumRef(n, "Outside") : s_.cameraMedium;
    }
    if (t == "Plane") {
        rect(k, n, sh);
    } else if (t == "Sphere") {
        Node r = need(k, n, "Radius");
        if (scale.x != scale.y || scale.y != scale.z) fail(k["Scale"], "a sphere's Scale must be uniform");
        sphere(r, scale.x, sh);
    } else {
        Node f = need(k, n, "File");
        const std::string path = resolve(name(f));
        const bool smooth = k["SmoothShading"] ? integer(k["SmoothShading"], 0, 1) == 1 : false;  // (choice) default 0
        try {
            sh.mesh = loadObj(path, smooth);
        } catch (const InputError& e) {
            fail(f, e.what());
        }
        meshToWorld(sh.mesh, sh.toWorld, sh.toLocal);
        sh.uv = sh.mesh.uvs.empty() ? UvKind::None : UvKind::Mesh;
    }
    geometryLine_[sh.id] = sh.line;
    s_.shapes.push_back(std::move(sh));
}

void Loader::light(Node n) {
    attrs(n, {"Type", "ID"});
    std::string t = type(n, {"Area", "Sphere"});
    ShapeDesc sh;
    sh.line = line(n);
    if (n.attribute("ID")) {  // (choice) a light's ID is optional
        sh.id = n.attribute("ID").value();
        if (lightLine_.count(sh.id))
            warn(n, "ID \"" + sh.id + "\" is also used by the Light on line " + std::to_string(lightLine_[sh.id]) +
                        " (accepted: nothing refers to light IDs)");
        else lightLine_[sh.id] = sh.line;
    }
    Names allowed = {"Position", "Rotation", "Radius", "Intensity", "Colour"};
    if (t == "Area") allowed.insert(allowed.end(), {"Width", "Depth"});
    Kids k = kids(n, allowed);
    Vec3 scale;
    transform(k, sh, scale);
    LightDesc l;
    const bool isRect = k["Width"] || k["Depth"];
    if (isRect && k["Radius"]) fail(n, "give either Width and Depth (a rectangle) or Radius (a sphere), not both");
    if (!isRect && !k["Radius"]) fail(n, "missing required element <Width> and <Depth> (a rectangle) or <Radius> (a sphere)");
    if (isRect) rect(k, n, sh);  // emits on the side of its normal
    else sphere(k["Radius"], 1.0f, sh);
    l.kind = isRect ? LightKind::Rect : LightKind::Sphere;
    Node inten = need(k, n, "Intensity");
    double i = value(inten);
    ranged(inten, "value", i, i >= 0, "must be >= 0");
    Vec3 c = k["Colour"] ? colour(k["Colour"]) : Vec3(1.0f);  // (choice) default white
    l.radiance = c * float(i);
    if (!isFinite(l.radiance)) fail(inten, "Intensity * Colour is not finite");
    if (isBlack(l.radiance)) warn(n, "emits nothing (Intensity * Colour is black)");
    sh.light = int(s_.lights.size());
    l.shape = int(s_.shapes.size());
    s_.lights.push_back(l);
    s_.shapes.push_back(std::move(sh));
}

SceneDesc Loader::run() {
    pugi::xml_document doc;
    pugi::xml_parse_result r = doc.load_buffer(xml_.data(), xml_.size(), pugi::parse_default | pugi::parse_comments, pugi::encoding_utf8);
    if (r.status == pugi::status_bad_comment) {
        // pugixml stops at the end of the file: name the comment that never ends (the
        // appendix's damaged "->" endings), the first "<!--" with no "-->" after it.
        for (size_t b = xml_.find("<!--"), e = 0; b != std::string::npos; b = xml_.find("<!--", e + 3)) {
            if ((e = xml_.find("-->", b + 4)) == std::string::npos)
                throw InputError(file_, lineOfOffset(ptrdiff_t(b)), "not well-formed XML: comment not closed by \"-->\"");
        }
    }
    if (!r) throw InputError(file_, lineOfOffset(r.offset), std::string("not well-formed XML: ") + r.description());
    // Before anything walks the tree recursively (checkComments, what()).
    if (Node deep = firstNestedDeeperThan(doc)) throw InputError(file_, line(deep), "elements nested deeper than " + std::to_string(kMaxXmlNesting));
    checkComments(doc);
    checkOutsideText();
    for (Node c : doc.children()) {
        if (c.type() == pugi::node_element && !root_ && std::string(c.name()) == "Scene") root_ = c;
        else if (c.type() == pugi::node_element) fail(c, "unexpected element: the file holds one <Scene>");
    }
    if (!root_) throw InputError(file_, 0, "no <Scene> element");
    attrs(root_, {});
    noText(root_);
    const Names top = {"Settings", "Camera", "Geometry", "Light", "Shader", "Texture", "Medium"};
    std::vector<Node> settings, cameras, textures, shaders, objects, media;
    for (Node c : root_.children()) {
        if (c.type() != pugi::node_element) continue;
        const std::string nm = c.name();
        if (!in(top, c.name())) fail(c, "unknown element (expected one of " + join(top) + ")");
        if (nm == "Settings") settings.push_back(c);
        else if (nm == "Camera") cameras.push_back(c);
        else if (nm == "Texture") textures.push_back(c);
        else if (nm == "Shader") shaders.push_back(c);
        else if (nm == "Medium") media.push_back(c);
        else objects.push_back(c);  // Geometry and Light, in file order
    }
    if (settings.size() > 1) fail(settings[1], "given twice (first on line " + std::to_string(line(settings[0])) + ")");
    if (cameras.size() > 1) fail(cameras[1], "a second camera (the first is on line " + std::to_string(line(cameras[0])) + ")");
    if (cameras.empty()) fail(root_, "missing required element <Camera>");
    // Referenced elements first, so references may point forward in the file.
    for (Node m : media) medium(m);
    if (!settings.empty()) this->settings(settings[0]);
    for (Node t : textures) texture(t);
    for (Node s : shaders) shader(s);
    camera(cameras[0]);
    for (Node o : objects) std::string(o.name()) == "Geometry" ? geometry(o) : light(o);
    return std::move(s_);
}

}  // namespace

SceneDesc loadThesisFromString(const std::string& xml, const std::string& name, const std::string& baseDir) {
    return Loader(xml, name, baseDir).run();
}

}  // namespace wmlt
