#include "scene/pbrt/pbrt_parser.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>

#include "scene/number.h"
#include "scene/read_file.h"
#include "wavemmlt/error.h"

namespace wmlt::pbrt {

void fail(const Loc& at, const std::string& msg) { throw InputError(at.file ? *at.file : std::string(), at.line, msg); }

// ---- Params ---------------------------------------------------------------------------

const Param* Params::find(const std::string& name) {
    for (Param& p : list)
        if (p.name == name) {
            p.used = true;
            return &p;
        }
    return nullptr;
}
bool Params::has(const std::string& name) const {
    return std::any_of(list.begin(), list.end(), [&](const Param& p) { return p.name == name; });
}

namespace {
bool isNumeric(const std::string& t) {
    return t == "float" || t == "integer" || t == "point2" || t == "vector2" || t == "point3" || t == "vector3" ||
           t == "point" || t == "vector" || t == "normal" || t == "normal3" || t == "rgb" || t == "color" ||
           t == "blackbody";
}
bool isStringy(const std::string& t) { return t == "string" || t == "texture"; }
const std::vector<std::string> kTypes = {"integer", "float",  "point2", "vector2", "point3",  "vector3",  "point",
                                         "vector",  "normal", "normal3", "bool",   "string",  "texture",  "rgb",
                                         "color",   "spectrum", "blackbody"};

void expectType(const Param& p, std::initializer_list<const char*> types) {
    for (const char* t : types)
        if (p.type == t) return;
    std::string want;
    for (const char* t : types) want += std::string(want.empty() ? "" : " or ") + t;
    fail(p.at, "\"" + p.type + " " + p.name + "\": expected a " + want + " parameter");
}
void expectOne(const Param& p, size_t n) {
    if (n != 1) fail(p.at, "\"" + p.type + " " + p.name + "\": expected one value, found " + std::to_string(n));
}
}  // namespace

double Params::getFloat(const std::string& name, double def) {
    const Param* p = find(name);
    if (!p) return def;
    expectType(*p, {"float"});
    expectOne(*p, p->numbers.size());
    return p->numbers[0];
}
int Params::getInt(const std::string& name, int def) {
    const Param* p = find(name);
    if (!p) return def;
    expectType(*p, {"integer"});
    expectOne(*p, p->numbers.size());
    return int(p->numbers[0]);
}
bool Params::getBool(const std::string& name, bool def) {
    const Param* p = find(name);
    if (!p) return def;
    expectType(*p, {"bool"});
    expectOne(*p, p->bools.size());
    return p->bools[0];
}
std::string Params::getString(const std::string& name, const std::string& def) {
    const Param* p = find(name);
    if (!p) return def;
    expectType(*p, {"string"});
    expectOne(*p, p->strings.size());
    return p->strings[0];
}
std::vector<double> Params::getNumbers(const std::string& name, int count) {
    const Param* p = find(name);
    if (!p) return {};
    if (!isNumeric(p->type)) fail(p->at, "\"" + p->type + " " + p->name + "\": expected numbers");
    if (count > 0 && p->numbers.size() % size_t(count) != 0)
        fail(p->at, "\"" + p->type + " " + p->name + "\": " + std::to_string(p->numbers.size()) +
                        " values, not a multiple of " + std::to_string(count));
    return p->numbers;
}
std::vector<int> Params::getInts(const std::string& name) {
    const Param* p = find(name);
    if (!p) return {};
    expectType(*p, {"integer"});
    return std::vector<int>(p->numbers.begin(), p->numbers.end());
}
Vec3 Params::getPoint3(const std::string& name, Vec3 def) {
    const Param* p = find(name);
    if (!p) return def;
    expectType(*p, {"point3", "point", "vector3", "vector", "normal", "normal3"});
    if (p->numbers.size() != 3) fail(p->at, "\"" + p->type + " " + p->name + "\": expected three values");
    return Vec3(float(p->numbers[0]), float(p->numbers[1]), float(p->numbers[2]));
}
void Params::warnUnused(std::vector<std::string>& warnings) const {
    for (const Param& p : list)
        if (!p.used)
            warnings.push_back(*p.at.file + ":" + std::to_string(p.at.line) + ": \"" + p.type + " " + p.name +
                               "\": parameter not used by wavemmlt (ignored)");
}

// ---- Tokens ---------------------------------------------------------------------------

struct Parser::File {
    std::string text, dir;
    const std::string* name = nullptr;
    size_t pos = 0;
    int line = 1;
};

Parser::Parser(const std::string& path) { push(path, Loc{}); }
Parser::~Parser() = default;

void Parser::push(const std::string& path, const Loc& from) {
    if (stack_.size() > 32) fail(from, "Include nested more than 32 deep (a recursive Include?)");
    const std::string norm = std::filesystem::path(path).lexically_normal().string();
    for (const auto& f : stack_)
        if (*f->name == norm) fail(from, "\"" + path + "\" includes itself (a recursive Include)");
    auto f = std::make_unique<File>();
    names_.push_back(std::make_unique<std::string>(norm));
    f->name = names_.back().get();
    try {
        f->text = readWholeFile(norm, from.file ? "the included file" : "the scene file");
    } catch (const InputError& e) {
        if (!from.file) throw;
        fail(from, e.what());
    }
    f->dir = std::filesystem::path(norm).parent_path().string();
    stack_.push_back(std::move(f));
}

bool Parser::read(Token& t) {
    if (peeked_) {
        peeked_ = false;
        t = std::move(peek_);
        return true;
    }
    while (!stack_.empty()) {
        File& f = *stack_.back();
        const std::string& s = f.text;
        while (f.pos < s.size()) {  // white space and comments
            const char c = s[f.pos];
            if (c == '\n') {
                ++f.line;
                ++f.pos;
            } else if (std::isspace((unsigned char)c)) {
                ++f.pos;
            } else if (c == '#') {
                while (f.pos < s.size() && s[f.pos] != '\n') ++f.pos;
            } else {
                break;
            }
        }
        if (f.pos >= s.size()) {
            if (stack_.size() == 1) return false;
            stack_.pop_back();
            continue;
        }
        t = Token{};
        t.at = Loc{f.name, f.line};
        const char c = s[f.pos];
        if (c == '[' || c == ']') {
            t.text = std::string(1, c);
            ++f.pos;
        } else if (c == '"') {
            t.quoted = true;
            ++f.pos;
            for (;;) {
                if (f.pos >= s.size() || s[f.pos] == '\n') fail(t.at, "unterminated string");
                char d = s[f.pos++];
                if (d == '"') break;
                if (d == '\\') {
                    if (f.pos >= s.size()) fail(t.at, "unterminated string");
                    d = s[f.pos++];
                    d = d == 'n' ? '\n' : d == 't' ? '\t' : d;
                }
                t.text += d;
            }
        } else {
            while (f.pos < s.size() && !std::isspace((unsigned char)s[f.pos]) && s[f.pos] != '"' && s[f.pos] != '[' &&
                   s[f.pos] != ']' && s[f.pos] != '#')
                t.text += s[f.pos++];
        }
        return true;
    }
    return false;
}

bool Parser::peek(Token& t) {
    if (!peeked_) {
        if (!read(peek_)) return false;
        peeked_ = true;
    }
    t = peek_;
    return true;
}

// ---- Directives -----------------------------------------------------------------------

namespace {

// Each directive's positional arguments: how many quoted strings, numbers, a bare word.
struct Shape {
    const char* name;
    int strings;      // quoted strings (-1: one or two, MediumInterface)
    int numbers;      // numbers (bracketed or not)
    bool params;      // a parameter list follows
    bool bareWord;    // ActiveTransform's StartTime / EndTime / All
};
const Shape kDirectives[] = {
    {"AttributeBegin", 0, 0, false, false}, {"AttributeEnd", 0, 0, false, false},
    {"TransformBegin", 0, 0, false, false}, {"TransformEnd", 0, 0, false, false},
    {"WorldBegin", 0, 0, false, false},     {"WorldEnd", 0, 0, false, false},
    {"Identity", 0, 0, false, false},       {"ReverseOrientation", 0, 0, false, false},
    {"ObjectEnd", 0, 0, false, false},      {"Translate", 0, 3, false, false},
    {"Scale", 0, 3, false, false},          {"Rotate", 0, 4, false, false},
    {"LookAt", 0, 9, false, false},         {"Transform", 0, 16, false, false},
    {"ConcatTransform", 0, 16, false, false}, {"TransformTimes", 0, 2, false, false},
    {"CoordinateSystem", 1, 0, false, false}, {"CoordSysTransform", 1, 0, false, false},
    {"ActiveTransform", 0, 0, false, true}, {"ObjectBegin", 1, 0, false, false},
    {"ObjectInstance", 1, 0, false, false}, {"NamedMaterial", 1, 0, false, false},
    {"MediumInterface", -1, 0, false, false}, {"ColorSpace", 1, 0, false, false},
    {"Option", 0, 0, true, false},          {"Attribute", 1, 0, true, false},
    {"Camera", 1, 0, true, false},          {"Film", 1, 0, true, false},
    {"Sampler", 1, 0, true, false},         {"PixelFilter", 1, 0, true, false},
    {"Integrator", 1, 0, true, false},      {"Accelerator", 1, 0, true, false},
    {"Material", 1, 0, true, false},        {"MakeNamedMaterial", 1, 0, true, false},
    {"LightSource", 1, 0, true, false},     {"AreaLightSource", 1, 0, true, false},
    {"Shape", 1, 0, true, false},           {"MakeNamedMedium", 1, 0, true, false},
    {"Texture", 3, 0, true, false},         {"Include", 1, 0, false, false},
    {"Import", 1, 0, false, false}};

double toNumber(const std::string& text, const Loc& at, const std::string& what) {
    double v = 0;
    if (!parseNumber(text, false, v)) fail(at, "\"" + text + "\" is not a number (" + what + ")");
    return v;
}

}  // namespace

void Parser::param(Directive& d, const Token& decl) {
    Param p;
    p.at = decl.at;
    // "type name": two words
    const std::string& s = decl.text;
    const size_t b = s.find_first_not_of(" \t"), m = s.find_first_of(" \t", b == std::string::npos ? 0 : b);
    const size_t c = m == std::string::npos ? m : s.find_first_not_of(" \t", m);
    if (b == std::string::npos || c == std::string::npos)
        fail(decl.at, "\"" + s + "\" is not a parameter declaration (\"type name\")");
    p.type = s.substr(b, m - b);
    p.name = s.substr(c, s.find_last_not_of(" \t") + 1 - c);
    if (p.name.find_first_of(" \t") != std::string::npos) fail(decl.at, "\"" + s + "\" is not a parameter declaration (\"type name\")");
    if (std::find(kTypes.begin(), kTypes.end(), p.type) == kTypes.end()) fail(decl.at, "unknown parameter type \"" + p.type + "\"");
    if (d.params.has(p.name)) fail(decl.at, "parameter \"" + p.name + "\" given twice");
    // Values: one bare value or a bracketed list.
    std::vector<Token> values;
    Token t;
    if (!read(t)) fail(decl.at, "\"" + s + "\": missing value");
    if (t.text == "[" && !t.quoted) {
        for (;;) {
            if (!read(t)) fail(decl.at, "\"" + s + "\": unterminated [");
            if (t.text == "]" && !t.quoted) break;
            if (t.text == "[" && !t.quoted) fail(t.at, "\"" + s + "\": [ inside [");
            values.push_back(t);
        }
    } else {
        values.push_back(t);
    }
    const bool spectrumNames = p.type == "spectrum" && !values.empty() && values[0].quoted;
    for (const Token& v : values) {
        if (p.type == "bool") {
            if (v.text != "true" && v.text != "false") fail(v.at, "\"" + s + "\": \"" + v.text + "\" is not true or false");
            p.bools.push_back(v.text == "true");
        } else if (isStringy(p.type) || spectrumNames) {
            if (!v.quoted) fail(v.at, "\"" + s + "\": expected a quoted string, found " + v.text);
            p.strings.push_back(v.text);
        } else {
            if (v.quoted) fail(v.at, "\"" + s + "\": expected a number, found \"" + v.text + "\"");
            const double x = toNumber(v.text, v.at, s);
            if (p.type == "integer" && (x != std::floor(x) || std::fabs(x) > 2147483647.0))
                fail(v.at, "\"" + s + "\": " + v.text + " is not an integer (of 32 bits)");
            p.numbers.push_back(x);
        }
    }
    d.params.list.push_back(std::move(p));
}

bool Parser::next(Directive& d) {
    Token t;
    for (;;) {
        d = Directive{};
        if (!read(t)) return false;
        double number = 0;
        if (t.quoted || t.text == "[" || t.text == "]" || parseNumber(t.text, false, number))
            fail(t.at, "expected a directive, found " + (t.quoted ? "\"" + t.text + "\"" : t.text) +
                           (t.text == "[" || t.quoted ? "" : " (a value outside a parameter's brackets?)"));
        const Shape* shape = nullptr;
        for (const Shape& k : kDirectives)
            if (t.text == k.name) shape = &k;
        if (!shape) fail(t.at, "unknown directive \"" + t.text + "\"");
        d.name = t.text;
        d.at = t.at;
        const int strings = shape->strings < 0 ? 1 : shape->strings;
        for (int i = 0; i < strings; ++i) {
            Token a;
            if (!read(a) || !a.quoted) fail(d.at, d.name + ": expected " + std::to_string(strings) + " quoted string(s)");
            d.strings.push_back(a.text);
        }
        if (shape->strings < 0) {  // MediumInterface: a second name is optional
            Token a;
            if (peek(a) && a.quoted) {
                read(a);
                d.strings.push_back(a.text);
            }
        }
        if (shape->bareWord) {
            Token a;
            if (!read(a) || a.quoted) fail(d.at, d.name + ": expected StartTime, EndTime or All");
            d.strings.push_back(a.text);
        }
        if (shape->numbers > 0) {
            Token a;
            bool bracket = peek(a) && a.text == "[" && !a.quoted;
            if (bracket) read(a);
            while ((int)d.numbers.size() < shape->numbers) {
                if (!read(a)) fail(d.at, d.name + ": expected " + std::to_string(shape->numbers) + " numbers");
                if (a.quoted || a.text == "[" || a.text == "]")
                    fail(a.at, d.name + ": expected " + std::to_string(shape->numbers) + " numbers, found " +
                                   std::to_string(d.numbers.size()));
                d.numbers.push_back(toNumber(a.text, a.at, d.name));
            }
            if (bracket && (!read(a) || a.text != "]" || a.quoted))
                fail(d.at, d.name + ": expected ] after " + std::to_string(shape->numbers) + " numbers");
        }
        if (shape->params) {
            Token a;
            while (peek(a) && a.quoted) {
                read(a);
                param(d, a);
            }
        }
        if (d.name == "Include" || d.name == "Import") {  // followed here
            std::filesystem::path p(d.strings[0]);
            if (p.is_relative()) p = std::filesystem::path(stack_.front()->dir) / p;  // pbrt-v4: the scene file's folder
            push(p.string(), d.at);
            continue;
        }
        return true;
    }
}

}  // namespace wmlt::pbrt
