#include "scene/mitsuba/mitsuba_xml.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "scene/number.h"
#include "scene/read_file.h"
#include "scene/spectrum.h"
#include "scene/xml_nesting.h"
#include "wavemmlt/error.h"

namespace wmlt::mitsuba {

// ---- Files -------------------------------------------------------------------------

Node Files::add(const std::string& xml, const std::string& name) {
    auto d = std::make_unique<Doc>();
    d->name = name;
    d->xml = xml;
    d->lineStarts.push_back(0);
    for (size_t i = 0; i < xml.size(); ++i)
        if (xml[i] == '\n') d->lineStarts.push_back(i + 1);
    pugi::xml_parse_result r = d->doc.load_buffer(d->xml.data(), d->xml.size(), pugi::parse_default, pugi::encoding_utf8);
    Doc& doc = *d;
    docs_.push_back(std::move(d));
    auto lineOf = [&](ptrdiff_t off) {
        return int(std::upper_bound(doc.lineStarts.begin(), doc.lineStarts.end(), size_t(std::max<ptrdiff_t>(off, 0))) - doc.lineStarts.begin());
    };
    if (!r) throw InputError(name, lineOf(r.offset), std::string("not well-formed XML: ") + r.description());
    // Before anything walks the tree recursively (substitute, the ids, nested plugins).
    if (Node deep = firstNestedDeeperThan(doc.doc))
        throw InputError(name, lineOf(deep.offset_debug()), "elements nested deeper than " + std::to_string(kMaxXmlNesting));
    Node root;
    for (Node c : doc.doc.children()) {
        if (c.type() != pugi::node_element) continue;
        if (root || std::string(c.name()) != "scene") fail(c, "expected one <scene> element");
        root = c;
    }
    if (!root) throw InputError(name, 0, "no <scene> element");
    return root;
}

Node Files::addFile(const std::string& path, Node from) {
    std::string xml;
    try {
        xml = readWholeFile(path, "the included file");  // a regular file only
    } catch (const InputError& e) {
        fail(from, e.what());
    }
    return add(xml, path);
}

const Files::Doc& Files::docOf(Node n) const {
    const Node root = n.root();
    for (const auto& d : docs_)
        if (d->doc == root) return *d;
    return *docs_.front();
}
int Files::line(Node n) const {
    const Doc& d = docOf(n);
    const ptrdiff_t off = n.offset_debug();
    if (off < 0) return 0;
    return int(std::upper_bound(d.lineStarts.begin(), d.lineStarts.end(), size_t(off)) - d.lineStarts.begin());
}
const std::string& Files::file(Node n) const { return docOf(n).name; }
std::string Files::where(Node n) const { return file(n) + ":" + std::to_string(line(n)); }

void Files::fail(Node n, const std::string& msg) const {
    std::string what = "<" + std::string(n.name());
    for (const char* a : {"type", "name", "id"})
        if (n.attribute(a)) what += std::string(" ") + a + "=\"" + n.attribute(a).value() + "\"";
    throw InputError(file(n), line(n), what + ">: " + msg);
}

void substitute(const Files& f, Node n, const std::map<std::string, std::string>& params) {
    for (pugi::xml_attribute a : n.attributes()) {
        std::string v = a.value();
        if (v.find('$') == std::string::npos) continue;
        std::string out;
        for (size_t i = 0; i < v.size();) {
            if (v[i] != '$') {
                out += v[i++];
                continue;
            }
            size_t j = i + 1;
            while (j < v.size() && (std::isalnum((unsigned char)v[j]) || v[j] == '_')) ++j;
            const std::string key = v.substr(i + 1, j - i - 1);
            auto it = params.find(key);
            if (key.empty() || it == params.end())
                f.fail(n, "\"$" + key + "\" is not defined (no <default name=\"" + key + "\"> and no -D " + key + "=...)");
            out += it->second;
            i = j;
        }
        a.set_value(out.c_str());
    }
    for (Node c : n.children())
        if (c.type() == pugi::node_element) substitute(f, c, params);
}

double number(const Files& f, Node n, const std::string& text, bool integer) {
    double v = 0;
    if (!parseNumber(text, integer, v)) f.fail(n, "\"" + text.substr(0, 40) + "\" is not " + (integer ? "an integer" : "a finite number"));
    return v;
}

// ---- Props -------------------------------------------------------------------------

namespace {
// Mitsuba 0.6 spells properties in camelCase (intIOR, toWorld): to snake_case.
std::string snake(const std::string& s) {
    std::string o;
    for (size_t i = 0; i < s.size(); ++i) {
        const bool up = std::isupper((unsigned char)s[i]);
        if (up && i > 0 && std::islower((unsigned char)s[i - 1])) o += '_';
        o += char(std::tolower((unsigned char)s[i]));
    }
    return o;
}
std::vector<double> numbers(const Files& f, Node n, const std::string& text) {
    std::vector<double> v;
    std::string tok;
    for (size_t i = 0; i <= text.size(); ++i) {
        const char c = i < text.size() ? text[i] : ' ';
        if (c == ',' || std::isspace((unsigned char)c)) {
            if (!tok.empty()) v.push_back(number(f, n, tok));
            tok.clear();
        } else {
            tok += c;
        }
    }
    return v;
}
}  // namespace

Props::Props(const Files& f, Node plugin, bool camelCase) : files_(f), node_(plugin), camel_(camelCase) {
    type_ = plugin.attribute("type").value();
    for (Node c : plugin.children()) {
        if (c.type() == pugi::node_pcdata) files_.fail(plugin, "unexpected text");
        if (c.type() != pugi::node_element) continue;
        std::string name = c.attribute("name").value();
        if (camel_) name = snake(name);
        items_.push_back({c, name});
    }
}

Props::Item* Props::find(const std::string& name) {
    Item* hit = nullptr;
    for (Item& it : items_) {
        if (it.name != name) continue;
        if (hit) files_.fail(it.n, "\"" + name + "\" given twice (first on line " + std::to_string(files_.line(hit->n)) + ")");
        hit = &it;
    }
    if (hit) hit->used = true;
    return hit;
}
bool Props::has(const std::string& name) const {
    return std::any_of(items_.begin(), items_.end(), [&](const Item& i) { return i.name == name; });
}

namespace {
std::string value(const Files& f, Node n) {
    if (!n.attribute("value")) f.fail(n, "missing attribute \"value\"");
    return n.attribute("value").value();
}
void expectTag(const Files& f, Node n, std::initializer_list<const char*> tags) {
    for (const char* t : tags)
        if (std::string(n.name()) == t) return;
    std::string s;
    for (const char* t : tags) s += (s.empty() ? "<" : ", <") + std::string(t) + ">";
    f.fail(n, "wrong element for this parameter (expected " + s + ")");
}
}  // namespace

float Props::getFloat(const std::string& name, float def) {
    Item* it = find(name);
    if (!it) return def;
    expectTag(files_, it->n, {"float", "integer"});
    return float(number(files_, it->n, value(files_, it->n)));
}
int Props::getInt(const std::string& name, int def) {
    Item* it = find(name);
    if (!it) return def;
    expectTag(files_, it->n, {"integer"});
    const double v = number(files_, it->n, value(files_, it->n), true);
    if (std::fabs(v) > 2147483647.0) files_.fail(it->n, "out of range");
    return int(v);
}
bool Props::getBool(const std::string& name, bool def) {
    Item* it = find(name);
    if (!it) return def;
    expectTag(files_, it->n, {"boolean"});
    const std::string v = value(files_, it->n);
    if (v == "true" || v == "1") return true;
    if (v == "false" || v == "0") return false;
    files_.fail(it->n, "\"" + v + "\" is not true or false");
}
std::string Props::getString(const std::string& name, const std::string& def) {
    Item* it = find(name);
    if (!it) return def;
    expectTag(files_, it->n, {"string"});
    return value(files_, it->n);
}
Vec3 Props::getColor(const std::string& name, Vec3 def, ColorUse use) {
    last_ = -1;
    Item* it = find(name);
    if (!it) return def;
    expectTag(files_, it->n, {"rgb", "spectrum", "float"});
    const std::string tag = it->n.name();
    if (tag == "spectrum") return spectrum(it->n, use);
    const std::vector<double> v = numbers(files_, it->n, value(files_, it->n));
    if (v.size() == 1) return Vec3(float(v[0]));
    if (v.size() == 3 && tag == "rgb") return Vec3(float(v[0]), float(v[1]), float(v[2]));
    files_.fail(it->n, "expected one value or three (r, g, b)");
}
Vec3 Props::spectrum(Node n, ColorUse use) {
    SampledSpectrum s;
    std::string why, source;
    float kelvin = 0, peak = 1;  // a blackbody: its temperature, its radiance at its peak
    const std::string type = n.attribute("type").value();
    if (type == "blackbody") {  // Planck's law in W m^-2 sr^-1 nm^-1, as Mitsuba 3's
        double T = -1;
        for (Node c : n.children()) {
            if (std::string(c.name()) != "float" || std::string(c.attribute("name").value()) != "temperature")
                files_.fail(c, "a blackbody spectrum takes one <float name=\"temperature\"> (kelvin)");
            T = number(files_, c, c.attribute("value").value());
        }
        if (!(T > 0 && T < 1e6)) files_.fail(n, "a blackbody spectrum needs a temperature in kelvin, > 0");
        kelvin = float(T);
        peak = float(blackbodyPeakPerNm(T));
        for (int l = int(kLambdaMin); l <= int(kLambdaMax); ++l) {
            s.lambda.push_back(l);
            s.value.push_back(blackbodyNormalized(l, T) * double(peak));
        }
        source = "blackbody " + std::to_string(int(std::lround(T))) + " K";
    } else if (!type.empty()) {
        files_.fail(n, "spectrum type \"" + type + "\" is not supported (values, a file or blackbody are)");
    }
    const bool hasFile = bool(n.attribute("filename")), hasValue = bool(n.attribute("value"));
    if (kelvin > 0) {
        if (hasFile || hasValue) files_.fail(n, "a blackbody spectrum has no value or filename");
    } else if (hasFile == hasValue) {
        files_.fail(n, "a spectrum needs either value or filename");
    } else if (hasFile) {
        std::filesystem::path f(n.attribute("filename").value());
        if (f.is_relative() && base_ && !base_->empty()) f = std::filesystem::path(*base_) / f;
        why = readSpectrumFile(f.lexically_normal().string(), s);
        if (!why.empty()) files_.fail(n, f.lexically_normal().string() + ": " + why);
        source = n.attribute("filename").value();
    } else {
        const std::string text = n.attribute("value").value();
        source = files_.where(n);
        if (text.find(':') == std::string::npos) {  // one value: a constant spectrum
            const std::vector<double> v = numbers(files_, n, text);
            if (v.size() != 1) files_.fail(n, "a spectrum's value is one number or wavelength:value pairs");
            if (use != ColorUse::Emission) return Vec3(float(v[0]));  // (its RGB's spectrum is the constant)
            // Mitsuba 3 RGB: an emitter's constant spectrum is E white, purple-ish in sRGB; kept
            // as the constant for spectral renders.
            const Vec3 c = float(v[0]) * xyzToLinearSrgb(Vec3(1.0f));
            if (keep_ && luminance(c) > 0)
                last_ = keepSpectrum(*keep_, SampledSpectrum{{double(kLambdaMin), double(kLambdaMax)}, {v[0], v[0]}}, 1.0f / luminance(c), source);
            return c;
        }
        why = parseSpectrumPairs(text, s);
        if (!why.empty()) files_.fail(n, why);
    }
    bool negative = false;
    Vec3 c = spectrumToRgb(s, use != ColorUse::Emission, &negative);
    const bool high = use == ColorUse::Reflectance && (c.x > 1 || c.y > 1 || c.z > 1);
    if ((negative || high) && warnings_) {
        char rgb[96];
        std::snprintf(rgb, sizeof rgb, "(%g, %g, %g)", c.x, c.y, c.z);
        warnings_->push_back(files_.where(n) + ": the spectrum is outside sRGB's gamut, " + rgb +
                             (high ? " clamped to [0, 1]" : " after negative components were clamped to 0"));
    }
    if (high) c = Vec3(std::min(c.x, 1.0f), std::min(c.y, 1.0f), std::min(c.z, 1.0f));
    // kept for spectral renders: as given (a blackbody: normalised, times its peak), an
    // emitter's with luminance 1 (its RGB, returned, carries the luminance)
    const float y = use == ColorUse::Emission ? luminance(c) : 1.0f;
    if (keep_ && y > 0) last_ = keepSpectrum(*keep_, s, peak / y, source, kelvin);
    return c;
}
Vec3 Props::getPoint(const std::string& name, Vec3 def) {
    Item* it = find(name);
    if (!it) return def;
    expectTag(files_, it->n, {"point", "vector"});
    if (it->n.attribute("value")) {
        const std::vector<double> v = numbers(files_, it->n, value(files_, it->n));
        if (v.size() != 3) files_.fail(it->n, "expected three values");
        return Vec3(float(v[0]), float(v[1]), float(v[2]));
    }
    Vec3 p;
    const char* xyz[3] = {"x", "y", "z"};
    for (int i = 0; i < 3; ++i)
        if (it->n.attribute(xyz[i])) p[i] = float(number(files_, it->n, it->n.attribute(xyz[i]).value()));
    return p;
}

// <transform>: its operations applied in file order, each after the previous ones.
Matrix Props::getTransform(const std::string& name) {
    Item* it = find(name);
    Matrix M;
    if (!it) return M;
    expectTag(files_, it->n, {"transform"});
    auto vec3 = [&](Node n, const char* attr) {
        const std::vector<double> v = numbers(files_, n, n.attribute(attr).value());
        if (v.size() != 3) files_.fail(n, std::string("\"") + attr + "\" needs three numbers");
        return v;
    };
    auto xyz = [&](Node n, double def) {  // x, y, z attributes or value="x y z" (or one value)
        std::vector<double> v = {def, def, def};
        if (n.attribute("value")) {
            v = numbers(files_, n, n.attribute("value").value());
            if (v.size() == 1) v = {v[0], v[0], v[0]};
            if (v.size() != 3) files_.fail(n, "expected one or three numbers");
            return v;
        }
        const char* a[3] = {"x", "y", "z"};
        for (int i = 0; i < 3; ++i)
            if (n.attribute(a[i])) v[i] = number(files_, n, n.attribute(a[i]).value());
        return v;
    };
    for (Node op : it->n.children()) {
        if (op.type() != pugi::node_element) continue;
        const std::string t = op.name();
        Matrix T;
        if (t == "translate") {
            const std::vector<double> v = xyz(op, 0);
            T = Matrix::translate(v[0], v[1], v[2]);
        } else if (t == "scale") {
            const std::vector<double> v = xyz(op, 1);
            T = Matrix::scale(v[0], v[1], v[2]);
        } else if (t == "rotate") {  // Rodrigues: right-handed about the unit axis
            std::vector<double> a = xyz(op, 0);
            if (!(a[0] * a[0] + a[1] * a[1] + a[2] * a[2] > 0)) files_.fail(op, "the rotation axis is zero");
            if (!op.attribute("angle")) files_.fail(op, "missing attribute \"angle\"");
            T = Matrix::rotate(number(files_, op, op.attribute("angle").value()), a[0], a[1], a[2]);
        } else if (t == "matrix") {
            const std::vector<double> v = numbers(files_, op, value(files_, op));
            if (v.size() == 16) {
                for (int i = 0; i < 16; ++i) T.m[i / 4][i % 4] = v[i];
                if (v[12] != 0 || v[13] != 0 || v[14] != 0 || v[15] != 1)
                    files_.fail(op, "a projective matrix (last row not 0 0 0 1) is not supported");
            } else if (v.size() == 9) {
                for (int i = 0; i < 9; ++i) T.m[i / 3][i % 3] = v[i];
            } else {
                files_.fail(op, "expected 16 or 9 numbers, found " + std::to_string(v.size()));
            }
        } else if (t == "lookat") {  // columns: left = up x dir, up' = dir x left, dir, origin
            const std::vector<double> o = vec3(op, "origin"), tg = vec3(op, "target");
            std::vector<double> up = op.attribute("up") ? vec3(op, "up") : std::vector<double>{0, 1, 0};
            if (o == tg) files_.fail(op, "origin equals target");
            if (!Matrix::lookAt(o.data(), tg.data(), up.data(), T)) files_.fail(op, "up is zero or parallel to the view direction");
        } else {
            files_.fail(op, "unknown transform operation (expected translate, rotate, scale, matrix, lookat)");
        }
        M = T * M;
    }
    return M;
}

Node Props::resolve(Node n) const {
    if (std::string(n.name()) != "ref") return n;
    const std::string id = n.attribute("id").value();
    if (!ids_ || !ids_->count(id)) files_.fail(n, "no element has id \"" + id + "\" (defined before this reference)");
    return ids_->at(id);
}
Node Props::getNested(const std::string& tag, const std::string& name) {
    Item* it = find(name);
    if (!it) return Node();
    Node n = resolve(it->n);
    if (std::string(n.name()) != tag) files_.fail(it->n, "expected a <" + tag + ">");
    return n;
}
bool Props::isNested(const std::string& tag, const std::string& name) const {
    for (const Item& it : items_)
        if (it.name == name) return std::string(resolve(it.n).name()) == tag;
    return false;
}
std::vector<Node> Props::nested(const std::string& tag) {
    std::vector<Node> out;
    for (Item& it : items_) {
        if (!it.name.empty()) continue;
        Node n = resolve(it.n);
        if (std::string(n.name()) != tag) continue;
        it.used = true;
        out.push_back(n);
    }
    return out;
}
void Props::finish() const {
    for (const Item& it : items_)
        if (!it.used)
            files_.fail(it.n, "not supported by wavemmlt's Mitsuba importer for <" + std::string(node_.name()) + " type=\"" + type_ +
                                  "\"> (docs/mitsuba.md lists what is)");
}

}  // namespace wmlt::mitsuba
