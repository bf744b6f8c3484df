// pbrt-v4's scene description, read into directives (its file-format reference): tokens
// (quoted strings, numbers, bare words, brackets; '#' comments), each directive with its
// positional arguments and its parameter list ("type name" value | [values]). Include and
// Import are followed here (relative to the scene file's folder, as pbrt-v4 resolves every
// file name), so the importer sees one stream. Files are read in chunks, a .gz inflated as it
// is read, and each value converted as it is read: memory is what the parsed scene holds,
// and a binary file or a gzip bomb fails at its first bad byte. pbrt-v4's strictness:
// unknown escapes are errors. Every error is an InputError naming the file (the included
// one where it is) and the line, quoting at most 60 characters of a token.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "wavemmlt/math.h"

namespace wmlt::pbrt {

struct Loc {
    const std::string* file = nullptr;
    int line = 0;
};
[[noreturn]] void fail(const Loc& at, const std::string& msg);

// One parameter: "type name" and its values (numbers, strings or bools by type).
struct Param {
    std::string type, name;
    std::vector<double> numbers;
    std::vector<std::string> strings;
    std::vector<bool> bools;
    Loc at;
    bool used = false;
};

// A directive's parameter list, read by type with pbrt's defaults; each read marks the
// parameter used, and the importer warns about the ones nobody read.
class Params {
public:
    std::vector<Param> list;
    const Param* find(const std::string& name);  // marks it used; null when absent
    bool has(const std::string& name) const;
    double getFloat(const std::string& name, double def);
    int getInt(const std::string& name, int def);
    // An integer in [lo, hi]: else an InputError at the parameter's line that names the range
    // (`why` says where the bound comes from).
    int getInt(const std::string& name, int def, int64_t lo, int64_t hi, const std::string& why = "");
    bool getBool(const std::string& name, bool def);
    std::string getString(const std::string& name, const std::string& def);
    // All of a parameter's numbers, `count` per item when count > 0 (checked).
    std::vector<double> getNumbers(const std::string& name, int count = 0);
    std::vector<int> getInts(const std::string& name);
    Vec3 getPoint3(const std::string& name, Vec3 def);
    // Parameters of a type nobody read: "unused parameter" warnings, "file:line: ...".
    void warnUnused(std::vector<std::string>& warnings) const;
};

struct Directive {
    std::string name;                  // "Shape", "Translate", ...
    std::vector<std::string> strings;  // quoted positional arguments ("trianglemesh") or a bare word (ActiveTransform)
    std::vector<double> numbers;       // numeric positional arguments (Translate 1 2 3, Transform [16])
    Params params;
    Loc at;
};

class Parser {
public:
    explicit Parser(const std::string& path);  // throws when the file cannot be read
    ~Parser();
    bool next(Directive& d);  // false at the end of the top-level file

private:
    struct File;
    struct Token {
        std::string text;
        bool quoted = false;
        Loc at;
    };
    std::vector<std::unique_ptr<File>> stack_;
    std::vector<std::unique_ptr<std::string>> names_;  // file names that Locs point to
    bool peeked_ = false;
    Token peek_;
    bool read(Token& t);  // next token across includes; false at the very end
    bool peek(Token& t);
    void push(const std::string& path, const Loc& from);
    void param(Directive& d, const Token& decl);
};

}  // namespace wmlt::pbrt
