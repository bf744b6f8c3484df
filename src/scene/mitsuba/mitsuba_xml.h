// Mitsuba 3 XML, the layer below the plugins (load_mitsuba.cpp): the files (with
// <include>), `$name` substitution from <default> and -D, and a plugin's properties
// (<float>, <rgb>, <transform>, ...), each read at most once and every one accounted for.
// Every problem is one InputError "file:line: <element>: problem".
#pragma once
#include <map>
#include <memory>
#include <pugixml.hpp>
#include <string>
#include <utility>
#include <vector>

#include "scene/matrix.h"
#include "wavemmlt/math.h"
#include "wavemmlt/scene_desc.h"

namespace wmlt::mitsuba {

using Node = pugi::xml_node;

// 4x4 affine transforms in double (scene/matrix.h).
using wmlt::Matrix;

// The loaded files: the scene and every included one, kept alive for their nodes.
class Files {
public:
    // Parses `xml` as file `name`; returns its root element (the one <scene>).
    Node add(const std::string& xml, const std::string& name);
    Node addFile(const std::string& path, Node from);  // <include>: errors name `from`
    int line(Node n) const;
    const std::string& file(Node n) const;
    [[noreturn]] void fail(Node n, const std::string& msg) const;
    std::string where(Node n) const;  // "file:line"

private:
    struct Doc {
        std::string name, xml;
        std::vector<size_t> lineStarts;
        pugi::xml_document doc;
    };
    std::vector<std::unique_ptr<Doc>> docs_;
    const Doc& docOf(Node n) const;
};

// Applies `$name` substitution to every attribute under n (Mitsuba: default values, -D
// overrides); an undefined `$name` is an error.
void substitute(const Files& f, Node n, const std::map<std::string, std::string>& params);

// The properties of one plugin element.
class Props {
public:
    Props(const Files& f, Node plugin, bool camelCase);
    const std::string& type() const { return type_; }
    Node node() const { return node_; }

    bool has(const std::string& name) const;
    float getFloat(const std::string& name, float def);
    int getInt(const std::string& name, int def);
    bool getBool(const std::string& name, bool def);
    std::string getString(const std::string& name, const std::string& def);
    // A colour: <rgb value="r, g, b" | "v">, <float>, or <spectrum value="v" |
    // value="lambda:v, ..." | filename="x.spd" | type="blackbody"> projected as Mitsuba 3's RGB
    // variants do (scene/spectrum.h; docs/mitsuba.md "Spectra"): per `use`. A spectrum is
    // also kept for spectral renders (setContext's SceneDesc; lastSpectrum).
    enum class ColorUse {
        Reflectance,  // pairs under D65, clamped to [0, 1] with a warning
        Unbounded,    // pairs under D65, only negatives clamped (a conductor's eta and k)
        Emission      // pairs against E, a constant v as v times E white in sRGB
    };
    Vec3 getColor(const std::string& name, Vec3 def, ColorUse use = ColorUse::Reflectance);
    Vec3 getPoint(const std::string& name, Vec3 def);
    Matrix getTransform(const std::string& name);  // identity when absent
    // A named nested plugin or <ref name=...>: the element (the referenced one for a ref).
    Node getNested(const std::string& tag, const std::string& name);
    // Whether the named property is a nested <tag> (a ref to one included); reads nothing.
    bool isNested(const std::string& tag, const std::string& name) const;
    // Unnamed nested plugins of this tag, in file order (refs resolved).
    std::vector<Node> nested(const std::string& tag);
    // Every property and nested plugin must have been read: else "not supported".
    void finish() const;
    [[noreturn]] void fail(Node n, const std::string& msg) const { files_.fail(n, msg); }
    void setIds(const std::map<std::string, Node>* ids) { ids_ = ids; }
    // Where relative file names (a spectrum's .spd) start, and where warnings go.
    void setContext(const std::string* base, std::vector<std::string>* warnings, SceneDesc* keep = nullptr) {
        base_ = base;
        warnings_ = warnings;
        keep_ = keep;
    }
    // The last getColor's spectrum as kept (SceneDesc::spectra; an emission's with luminance
    // 1, the RGB it returned carrying the luminance), or -1: RGB, a texture, a constant
    // reflectance (whose spectrum is its RGB's).
    int lastSpectrum() const { return last_; }

private:
    const Files& files_;
    Node node_;
    std::string type_;
    bool camel_;
    struct Item {
        Node n;
        std::string name;
        bool used = false;
    };
    std::vector<Item> items_;
    const std::map<std::string, Node>* ids_ = nullptr;
    const std::string* base_ = nullptr;
    std::vector<std::string>* warnings_ = nullptr;
    SceneDesc* keep_ = nullptr;
    int last_ = -1;
    Vec3 spectrum(Node n, ColorUse use);
    Item* find(const std::string& name);
    Node resolve(Node n) const;  // <ref id> -> the element with that id
};

// A number parsed whole (scene/number.h); the node names the error.
double number(const Files& f, Node n, const std::string& text, bool integer = false);

}  // namespace wmlt::mitsuba
