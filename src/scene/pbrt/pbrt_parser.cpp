#include "scene/pbrt/pbrt_parser.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>

#include "scene/number.h"
#include "scene/read_file.h"
#include "wavemmlt/error.h"
#include "wavemmlt/quote.h"

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
    return t == "float" || t == "integer" || t == "point2" || t == "vector2" || t == "point3" || t == "vector3" || t == "point" || t == "vector" ||
           t == "normal" || t == "normal3" || t == "rgb" || t == "color" || t == "blackbody";
}
bool isStringy(const std::string& t) { return t == "string" || t == "texture"; }
const std::vector<std::string> kTypes = {"integer", "float", "point2", "vector2", "point3", "vector3", "point",    "vector",   "normal",
                                         "normal3", "bool",  "string", "texture", "rgb",    "color",   "spectrum", "blackbody"};

void expectType(const Param& p, std::initializer_list<const char*> types) {
    for (const char* t : types)
        if (p.type == t) return;
    std::string want;
    for (const char* t : types) want += std::string(want.empty() ? "" : " or ") + t;
    fail(p.at, quoteToken(p.type + " " + p.name) + ": expected a " + want + " parameter");
}
void expectOne(const Param& p, size_t n) {
    if (n != 1) fail(p.at, quoteToken(p.type + " " + p.name) + ": expected one value, found " + std::to_string(n));
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
int Params::getInt(const std::string& name, int def, int64_t lo, int64_t hi, const std::string& why) {
    const int v = getInt(name, def);
    if (const Param* p = find(name); p && (v < lo || v > hi))
        fail(p->at, quoteToken(p->type + " " + p->name) + ": " + std::to_string(v) + " is out of range [" + std::to_string(lo) + ", " +
                        std::to_string(hi) + "]" + (why.empty() ? "" : " (" + why + ")"));
    return v;
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
    if (!isNumeric(p->type)) fail(p->at, quoteToken(p->type + " " + p->name) + ": expected numbers");
    if (count > 0 && p->numbers.size() % size_t(count) != 0)
        fail(p->at,
             quoteToken(p->type + " " + p->name) + ": " + std::to_string(p->numbers.size()) + " values, not a multiple of " + std::to_string(count));
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
    if (p->numbers.size() != 3) fail(p->at, quoteToken(p->type + " " + p->name) + ": expected three values");
    return Vec3(float(p->numbers[0]), float(p->numbers[1]), float(p->numbers[2]));
}
void Params::warnUnused(std::vector<std::string>& warnings) const {
    for (const Param& p : list)
        if (!p.used)
            warnings.push_back(*p.at.file + ":" + std::to_string(p.at.line) + ": " + quoteToken(p.type + " " + p.name) +
                               ": parameter not used by wavemmlt (ignored)");
}

// ---- Tokens ---------------------------------------------------------------------------

// The file is read in chunks (scene/read_file.h: a .gz inflated as it is read), so a binary
// file or a gzip bomb fails at its first bad byte, and a token longer than kMaxToken (no
// name, number or file name is) stops the reading where it starts.
constexpr size_t kMaxToken = 4096;

struct Parser::File {
    std::unique_ptr<FileStream> in;
    std::string buf, dir;
    const std::string* name = nullptr;
    size_t pos = 0;
    int line = 1;
    bool atEnd = false;
    // The next byte (-1 at the end of the file), read on when the chunk is used up.
    int peek() {
        if (pos < buf.size()) return (unsigned char)buf[pos];
        if (atEnd) return -1;
        buf.resize(1 << 16);
        buf.resize(in->read(buf.data(), buf.size()));
        pos = 0;
        if (buf.empty()) atEnd = true;
        return atEnd ? -1 : (unsigned char)buf[0];
    }
};

Parser::Parser(const std::string& path) { push(path, Loc{}); }
Parser::~Parser() = default;

void Parser::push(const std::string& path, const Loc& from) {
    if (stack_.size() > 32) fail(from, "Include nested more than 32 deep (a recursive Include?)");
    const std::string norm = std::filesystem::path(path).lexically_normal().string();
    for (const auto& f : stack_)
        if (*f->name == norm) fail(from, quoteToken(path) + " includes itself (a recursive Include)");
    auto f = std::make_unique<File>();
    names_.push_back(std::make_unique<std::string>(norm));
    f->name = names_.back().get();
    try {
        f->in = std::make_unique<FileStream>(norm, from.file ? "the included file" : "the scene file");
    } catch (const InputError& e) {
        if (!from.file) throw;
        fail(from, e.what());
    }
    f->dir = std::filesystem::path(norm).parent_path().string();
    stack_.push_back(std::move(f));
}

namespace {
// A byte no pbrt text holds outside a quoted string: NUL and the control characters other
// than white space.
bool binaryByte(int c) { return c == 0 || (c < 32 && c != '\t' && c != '\n' && c != '\r' && c != '\f' && c != '\v') || c == 127; }
std::string byteName(int c) {
    if (c == 0) return "a NUL byte (a binary file?)";
    char hex[8];
    std::snprintf(hex, sizeof hex, "0x%02X", c);
    return std::string("a control byte ") + hex + " (a binary file?)";
}
}  // namespace

bool Parser::read(Token& t) {
    if (peeked_) {
        peeked_ = false;
        t = std::move(peek_);
        return true;
    }
    while (!stack_.empty()) {
        File& f = *stack_.back();
        int c;
        while ((c = f.peek()) >= 0) {  // white space and comments
            if (c == '\n') {
                ++f.line;
                ++f.pos;
            } else if (std::isspace(c)) {
                ++f.pos;
            } else if (c == '#') {
                while ((c = f.peek()) >= 0 && c != '\n') {
                    if (c == 0) fail(Loc{f.name, f.line}, byteName(c));
                    ++f.pos;
                }
            } else {
                break;
            }
        }
        if (c < 0) {
            if (stack_.size() == 1) return false;
            stack_.pop_back();
            continue;
        }
        t.text.clear();
        t.quoted = false;
        t.at = Loc{f.name, f.line};
        auto add = [&](char d) {
            if (t.text.size() >= kMaxToken)
                fail(t.at, std::string(t.quoted ? "a string" : "a token") + " longer than " + std::to_string(kMaxToken) + " bytes, starting " +
                               quoteToken(t.text));
            t.text += d;
        };
        if (binaryByte(c)) fail(t.at, byteName(c));
        if (c == '[' || c == ']') {
            t.text = std::string(1, char(c));
            ++f.pos;
        } else if (c == '"') {
            // pbrt-v4's escapes: \b \f \n \r \t \\ \' \"; any other is an error, as in pbrt.
            t.quoted = true;
            ++f.pos;
            for (;;) {
                int d = f.peek();
                if (d < 0 || d == '\n') fail(t.at, "unterminated string");
                if (d == 0) fail(t.at, byteName(d));
                ++f.pos;
                if (d == '"') break;
                if (d == '\\') {
                    const int e = f.peek();
                    if (e < 0 || e == '\n') fail(t.at, "unterminated string");
                    ++f.pos;
                    switch (e) {
                        case 'b': d = '\b'; break;
                        case 'f': d = '\f'; break;
                        case 'n': d = '\n'; break;
                        case 'r': d = '\r'; break;
                        case 't': d = '\t'; break;
                        case '\\':
                        case '\'':
                        case '"': d = e; break;
                        default:
                            fail(t.at, "unexpected escaped character " + quoteToken(std::string("\\") + char(e)) + " in the string " +
                                           quoteToken(t.text) + " (pbrt-v4 takes \\b \\f \\n \\r \\t \\\\ \\' \\\")");
                    }
                }
                add(char(d));
            }
        } else {
            for (int d; (d = f.peek()) >= 0 && !std::isspace(d) && d != '"' && d != '[' && d != ']' && d != '#'; ++f.pos) {
                if (binaryByte(d)) fail(t.at, byteName(d) + " after " + quoteToken(t.text));
                add(char(d));
            }
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
    int strings;    // quoted strings (-1: one or two, MediumInterface)
    int numbers;    // numbers (bracketed or not)
    bool params;    // a parameter list follows
    bool bareWord;  // ActiveTransform's StartTime / EndTime / All
};
const Shape kDirectives[] = {{"AttributeBegin", 0, 0, false, false},
                             {"AttributeEnd", 0, 0, false, false},
                             {"TransformBegin", 0, 0, false, false},
                             {"TransformEnd", 0, 0, false, false},
                             {"WorldBegin", 0, 0, false, false},
                             {"WorldEnd", 0, 0, false, false},
                             {"Identity", 0, 0, false, false},
                             {"ReverseOrientation", 0, 0, false, false},
                             {"ObjectEnd", 0, 0, false, false},
                             {"Translate", 0, 3, false, false},
                             {"Scale", 0, 3, false, false},
                             {"Rotate", 0, 4, false, false},
                             {"LookAt", 0, 9, false, false},
                             {"Transform", 0, 16, false, false},
                             {"ConcatTransform", 0, 16, false, false},
                             {"TransformTimes", 0, 2, false, false},
                             {"CoordinateSystem", 1, 0, false, false},
                             {"CoordSysTransform", 1, 0, false, false},
                             {"ActiveTransform", 0, 0, false, true},
                             {"ObjectBegin", 1, 0, false, false},
                             {"ObjectInstance", 1, 0, false, false},
                             {"NamedMaterial", 1, 0, false, false},
                             {"MediumInterface", -1, 0, false, false},
                             {"ColorSpace", 1, 0, false, false},
                             {"Option", 0, 0, true, false},
                             {"Attribute", 1, 0, true, false},
                             {"Camera", 1, 0, true, false},
                             {"Film", 1, 0, true, false},
                             {"Sampler", 1, 0, true, false},
                             {"PixelFilter", 1, 0, true, false},
                             {"Integrator", 1, 0, true, false},
                             {"Accelerator", 1, 0, true, false},
                             {"Material", 1, 0, true, false},
                             {"MakeNamedMaterial", 1, 0, true, false},
                             {"LightSource", 1, 0, true, false},
                             {"AreaLightSource", 1, 0, true, false},
                             {"Shape", 1, 0, true, false},
                             {"MakeNamedMedium", 1, 0, true, false},
                             {"Texture", 3, 0, true, false},
                             {"Include", 1, 0, false, false},
                             {"Import", 1, 0, false, false}};

// A bare token as the file has it (cut and escaped as quoteToken() does, without the quotes).
std::string shownBare(const std::string& text) {
    const std::string q = quoteToken(text);
    return q.substr(1, q.rfind('"') - 1) + q.substr(q.rfind('"') + 1);
}

double toNumber(const std::string& text, const Loc& at, const std::string& what) {
    double v = 0;
    if (!parseNumber(text, false, v)) fail(at, quoteToken(text) + " is not a number (" + quoteToken(what) + ")");
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
    if (b == std::string::npos || c == std::string::npos) fail(decl.at, quoteToken(s) + " is not a parameter declaration (\"type name\")");
    p.type = s.substr(b, m - b);
    p.name = s.substr(c, s.find_last_not_of(" \t") + 1 - c);
    if (p.name.find_first_of(" \t") != std::string::npos) fail(decl.at, quoteToken(s) + " is not a parameter declaration (\"type name\")");
    if (std::find(kTypes.begin(), kTypes.end(), p.type) == kTypes.end()) fail(decl.at, "unknown parameter type " + quoteToken(p.type));
    if (d.params.has(p.name)) fail(decl.at, "parameter " + quoteToken(p.name) + " given twice");
    // Values: one bare value or a bracketed list, each converted as it is read (a token is
    // not kept: a mesh's million numbers take 8 bytes each).
    const std::string what = quoteToken(s);
    bool first = true, spectrumNames = false;
    auto value = [&](const Token& v) {
        if (first) spectrumNames = p.type == "spectrum" && v.quoted, first = false;
        if (p.type == "bool") {
            if (v.text != "true" && v.text != "false") fail(v.at, what + ": " + quoteToken(v.text) + " is not true or false");
            p.bools.push_back(v.text == "true");
        } else if (isStringy(p.type) || spectrumNames) {
            if (!v.quoted) fail(v.at, what + ": expected a quoted string, found " + quoteToken(v.text));
            p.strings.push_back(v.text);
        } else {
            if (v.quoted) fail(v.at, what + ": expected a number, found " + quoteToken(v.text));
            const double x = toNumber(v.text, v.at, s);
            if (p.type == "integer" && (x != std::floor(x) || std::fabs(x) > 2147483647.0))
                fail(v.at, what + ": " + quoteToken(v.text) + " is not an integer (of 32 bits)");
            p.numbers.push_back(x);
        }
    };
    Token t;
    if (!read(t)) fail(decl.at, what + ": missing value");
    if (t.text == "[" && !t.quoted) {
        for (;;) {
            if (!read(t)) fail(decl.at, what + ": unterminated [");
            if (t.text == "]" && !t.quoted) break;
            if (t.text == "[" && !t.quoted) fail(t.at, what + ": [ inside [");
            value(t);
        }
    } else {
        value(t);
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
            fail(t.at, "expected a directive, found " + (t.quoted ? quoteToken(t.text) : shownBare(t.text)) +
                           (t.text == "[" || t.quoted ? "" : " (a value outside a parameter's brackets?)"));
        const Shape* shape = nullptr;
        for (const Shape& k : kDirectives)
            if (t.text == k.name) shape = &k;
        if (!shape) fail(t.at, "unknown directive " + quoteToken(t.text));
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
                    fail(a.at, d.name + ": expected " + std::to_string(shape->numbers) + " numbers, found " + std::to_string(d.numbers.size()));
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
