// Stanford PLY reader for Mitsuba's `ply` shape (docs/mitsuba.md).
//
// Formats: ascii 1.0, binary_little_endian 1.0, binary_big_endian 1.0. The header's
// elements are read in order; of `vertex`: x y z (required), nx ny nz (all three or none),
// u v, s t, texture_u texture_v or texture_s texture_t; of `face`: the list vertex_indices
// (or vertex_index), polygons fan-triangulated. Every other element and property (colours,
// edges, material indices...) is read past. Scalar types: char/int8, uchar/uint8,
// short/int16, ushort/uint16, int/int32, uint/uint32, float/float32, double/float64.
// Problems are InputErrors naming the file and, for the header and ASCII data, the line
// ("file:line: ..."), for binary data the byte offset ("file: byte N: ..."). Counts are
// checked against the bytes left before anything is allocated, so a lying header fails
// fast in bounded memory; the header is read and checked before the rest of the file (a
// .ply.gz is inflated as it is read). Numbers in ASCII data are parsed by scene/number.h.
// Normals: the file's when smoothShading and the file has them, else area-weighted
// per-vertex normals when smoothShading (Mitsuba computes vertex normals for a mesh
// without them unless face_normals), none when flat.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "scene/meshes/vertex_normals.h"
#include "scene/number.h"
#include "scene/read_file.h"
#include "wavemmlt/error.h"
#include "wavemmlt/scene_desc.h"

namespace wmlt {
namespace {

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "binary PLY reading assumes a little-endian host");

enum class Type : uint8_t { I8, U8, I16, U16, I32, U32, F32, F64 };

int sizeOf(Type t) {
    switch (t) {
        case Type::I8:
        case Type::U8: return 1;
        case Type::I16:
        case Type::U16: return 2;
        case Type::I32:
        case Type::U32:
        case Type::F32: return 4;
        case Type::F64: return 8;
    }
    return 1;
}

bool typeOf(const std::string& s, Type& t) {
    static const std::pair<const char*, Type> names[] = {{"char", Type::I8},   {"int8", Type::I8},     {"uchar", Type::U8},   {"uint8", Type::U8},
                                                         {"short", Type::I16}, {"int16", Type::I16},   {"ushort", Type::U16}, {"uint16", Type::U16},
                                                         {"int", Type::I32},   {"int32", Type::I32},   {"uint", Type::U32},   {"uint32", Type::U32},
                                                         {"float", Type::F32}, {"float32", Type::F32}, {"double", Type::F64}, {"float64", Type::F64}};
    for (const auto& [n, ty] : names)
        if (s == n) {
            t = ty;
            return true;
        }
    return false;
}

struct Property {
    std::string name;
    Type type = Type::F32;
    bool list = false;
    Type countType = Type::U8;
};

struct Element {
    std::string name;
    uint64_t count = 0;
    std::vector<Property> props;
    int line = 0;
};

enum class Format : uint8_t { Ascii, Little, Big };

class PlyReader {
public:
    PlyReader(const std::string& path, const std::string& data) : path_(path), d_(data) {}
    void run(bool smooth, bool computeMissing, TriangleMesh& out);
    void checkHeader() { header(); }

private:
    const std::string& path_;
    const std::string& d_;
    size_t pos_ = 0;
    int line_ = 1;
    Format format_ = Format::Ascii;
    std::vector<Element> elements_;

    [[noreturn]] void failLine(int line, const std::string& msg) const { throw InputError(path_, line, msg); }
    [[noreturn]] void failHere(const std::string& msg) const {
        if (format_ == Format::Ascii) failLine(line_, msg);
        throw InputError(path_, 0, "byte " + std::to_string(pos_) + ": " + msg);
    }
    static std::string shown(const std::string& s) {
        std::string o;
        for (char c : s.substr(0, 40)) o += (unsigned char)c < 32 || (unsigned char)c > 126 ? '?' : c;
        return o;
    }

    // ---- header ----
    bool headerLine(std::string& line) {
        if (pos_ >= d_.size()) return false;
        size_t e = d_.find('\n', pos_);
        if (e == std::string::npos) e = d_.size();
        line = d_.substr(pos_, e - pos_);
        if (!line.empty() && line.back() == '\r') line.pop_back();
        pos_ = e < d_.size() ? e + 1 : e;
        return true;
    }
    static std::vector<std::string> words(const std::string& s) {
        std::vector<std::string> w;
        size_t i = 0;
        while (i < s.size()) {
            while (i < s.size() && (s[i] == ' ' || s[i] == '\t')) ++i;
            size_t j = i;
            while (j < s.size() && s[j] != ' ' && s[j] != '\t') ++j;
            if (j > i) w.push_back(s.substr(i, j - i));
            i = j;
        }
        return w;
    }
    void header();

    // ---- data ----
    // ASCII: the next white-space separated token (lines counted).
    std::string token() {
        while (pos_ < d_.size() && (d_[pos_] == ' ' || d_[pos_] == '\t' || d_[pos_] == '\r' || d_[pos_] == '\n')) {
            if (d_[pos_] == '\n') ++line_;
            ++pos_;
        }
        if (pos_ >= d_.size())  // (the last line, not the empty one after its newline)
            failLine(line_ - (d_.back() == '\n' ? 1 : 0), "the data ends early (more elements are declared than the file holds)");
        const size_t b = pos_;
        while (pos_ < d_.size() && !std::isspace((unsigned char)d_[pos_])) ++pos_;
        return d_.substr(b, pos_ - b);
    }
    double value(Type t) {
        if (format_ == Format::Ascii) {
            const std::string s = token();
            const bool integer = t != Type::F32 && t != Type::F64;
            double v = 0;
            if (!parseNumber(s, integer, v)) failHere("\"" + shown(s) + "\" is not " + (integer ? "an integer" : "a finite number"));
            return v;
        }
        const int n = sizeOf(t);
        if (d_.size() - pos_ < size_t(n)) failHere("the data ends early (more elements are declared than the file holds)");
        unsigned char b[8];
        std::memcpy(b, d_.data() + pos_, size_t(n));
        if (format_ == Format::Big) std::reverse(b, b + n);  // the host is little-endian (x86-64, arm64)
        const size_t at = pos_;
        pos_ += size_t(n);
        switch (t) {
            case Type::I8: {
                int8_t x;
                std::memcpy(&x, b, 1);
                return x;
            }
            case Type::U8: return b[0];
            case Type::I16: {
                int16_t x;
                std::memcpy(&x, b, 2);
                return x;
            }
            case Type::U16: {
                uint16_t x;
                std::memcpy(&x, b, 2);
                return x;
            }
            case Type::I32: {
                int32_t x;
                std::memcpy(&x, b, 4);
                return x;
            }
            case Type::U32: {
                uint32_t x;
                std::memcpy(&x, b, 4);
                return x;
            }
            case Type::F32: {
                float x;
                std::memcpy(&x, b, 4);
                if (!std::isfinite(x)) {
                    pos_ = at;
                    failHere("a number is not finite");
                }
                return x;
            }
            case Type::F64: {
                double x;
                std::memcpy(&x, b, 8);
                if (!std::isfinite(x) || std::fabs(x) > 3.4e38) {
                    pos_ = at;
                    failHere("a number is not finite or does not fit a float");
                }
                return x;
            }
        }
        return 0;
    }
    // The smallest number of bytes (binary) or characters (ASCII) one element can take.
    static size_t minBytes(const Element& e, Format f) {
        size_t n = 0;
        for (const Property& p : e.props) n += f == Format::Ascii ? 2 : size_t(sizeOf(p.list ? p.countType : p.type));
        return std::max<size_t>(n, 1);
    }
};

void PlyReader::header() {
    std::string line;
    if (!headerLine(line) || line != "ply") failLine(1, "not a PLY file (the first line must be \"ply\")");
    bool haveFormat = false;
    for (;;) {
        ++line_;
        if (!headerLine(line)) failLine(line_, "the header has no end_header");
        const std::vector<std::string> w = words(line);
        if (w.empty() || w[0] == "comment" || w[0] == "obj_info") continue;
        if (w[0] == "end_header") break;
        if (w[0] == "format") {
            if (w.size() != 3) failLine(line_, "expected \"format <ascii|binary_little_endian|binary_big_endian> 1.0\"");
            if (w[1] == "ascii") format_ = Format::Ascii;
            else if (w[1] == "binary_little_endian") format_ = Format::Little;
            else if (w[1] == "binary_big_endian") format_ = Format::Big;
            else failLine(line_, "unknown format \"" + shown(w[1]) + "\"");
            if (w[2] != "1.0") failLine(line_, "PLY version \"" + shown(w[2]) + "\" is not 1.0");
            haveFormat = true;
        } else if (w[0] == "element") {
            double n = 0;
            if (w.size() != 3 || !parseNumber(w[2], true, n) || n < 0) failLine(line_, "expected \"element <name> <count>\" with a count >= 0");
            elements_.push_back({w[1], uint64_t(n), {}, line_});
        } else if (w[0] == "property") {
            if (elements_.empty()) failLine(line_, "a property before any element");
            Property p;
            if (w.size() == 5 && w[1] == "list") {
                p.list = true;
                if (!typeOf(w[2], p.countType) || !typeOf(w[3], p.type)) failLine(line_, "unknown type in \"" + shown(line) + "\"");
                if (p.countType == Type::F32 || p.countType == Type::F64) failLine(line_, "a list's count must be an integer type");
                p.name = w[4];
            } else if (w.size() == 3) {
                if (!typeOf(w[1], p.type)) failLine(line_, "unknown type \"" + shown(w[1]) + "\"");
                p.name = w[2];
            } else {
                failLine(line_, "expected \"property <type> <name>\" or \"property list <count type> <type> <name>\"");
            }
            elements_.back().props.push_back(p);
        } else {
            failLine(line_, "unknown header line \"" + shown(line) + "\"");
        }
    }
    if (!haveFormat) failLine(line_, "the header has no format line");
    ++line_;  // ASCII data starts on the next line
}

void PlyReader::run(bool smooth, bool computeMissing, TriangleMesh& out) {
    header();
    std::vector<float> pos, nrm, uv;
    std::vector<uint32_t> idx;
    uint64_t nVertices = 0;
    bool haveVertices = false, haveNormals = false, haveUv = false, haveFaces = false;
    for (const Element& e : elements_) {
        // Enough data left for `count` elements? (before allocating anything for them)
        const size_t left = d_.size() - pos_;
        if (e.count > 0 && e.count > left / minBytes(e, format_))
            failLine(e.line, "element " + shown(e.name) + " declares " + std::to_string(e.count) + " items, more than the file holds");
        if (e.name == "vertex") {
            if (haveVertices) failLine(e.line, "a second vertex element");
            haveVertices = true;
            int ix = -1, iy = -1, iz = -1, inx = -1, iny = -1, inz = -1, iu = -1, iv = -1;
            for (int i = 0; i < int(e.props.size()); ++i) {
                const std::string& n = e.props[size_t(i)].name;
                if (e.props[size_t(i)].list) continue;
                if (n == "x") ix = i;
                else if (n == "y") iy = i;
                else if (n == "z") iz = i;
                else if (n == "nx") inx = i;
                else if (n == "ny") iny = i;
                else if (n == "nz") inz = i;
                else if (n == "u" || n == "s" || n == "texture_u" || n == "texture_s") iu = i;
                else if (n == "v" || n == "t" || n == "texture_v" || n == "texture_t") iv = i;
            }
            if (ix < 0 || iy < 0 || iz < 0) failLine(e.line, "the vertex element needs properties x, y and z");
            if ((inx >= 0) != (iny >= 0) || (inx >= 0) != (inz >= 0)) failLine(e.line, "normals need all of nx, ny and nz");
            if ((iu >= 0) != (iv >= 0)) failLine(e.line, "texture coordinates need both u and v (or s and t)");
            if (e.count > 0xFFFFFFFFull) failLine(e.line, "too many vertices");
            haveNormals = inx >= 0;
            haveUv = iu >= 0;
            nVertices = e.count;
            pos.resize(3 * e.count);
            if (haveNormals) nrm.resize(3 * e.count);
            if (haveUv) uv.resize(2 * e.count);
            for (uint64_t k = 0; k < e.count; ++k)
                for (int i = 0; i < int(e.props.size()); ++i) {
                    const Property& p = e.props[size_t(i)];
                    if (p.list) {
                        const double n = value(p.countType);
                        if (n < 0) failHere("a negative list length");
                        for (double j = 0; j < n; ++j) value(p.type);
                        continue;
                    }
                    const float v = float(value(p.type));
                    if (i == ix) pos[3 * k] = v;
                    else if (i == iy) pos[3 * k + 1] = v;
                    else if (i == iz) pos[3 * k + 2] = v;
                    else if (i == inx) nrm[3 * k] = v;
                    else if (i == iny) nrm[3 * k + 1] = v;
                    else if (i == inz) nrm[3 * k + 2] = v;
                    else if (i == iu) uv[2 * k] = v;
                    else if (i == iv) uv[2 * k + 1] = v;
                }
        } else if (e.name == "face") {
            if (haveFaces) failLine(e.line, "a second face element");
            haveFaces = true;
            int iList = -1;
            for (int i = 0; i < int(e.props.size()); ++i)
                if (e.props[size_t(i)].list && (e.props[size_t(i)].name == "vertex_indices" || e.props[size_t(i)].name == "vertex_index")) iList = i;
            if (iList < 0) failLine(e.line, "the face element needs a list property vertex_indices");
            if (e.props[size_t(iList)].type == Type::F32 || e.props[size_t(iList)].type == Type::F64)
                failLine(e.line, "vertex_indices must be integers");
            std::vector<uint32_t> poly;
            for (uint64_t k = 0; k < e.count; ++k)
                for (int i = 0; i < int(e.props.size()); ++i) {
                    const Property& p = e.props[size_t(i)];
                    if (!p.list) {
                        value(p.type);
                        continue;
                    }
                    const double n = value(p.countType);
                    if (n < 0) failHere("a negative list length");
                    if (i != iList) {
                        for (double j = 0; j < n; ++j) value(p.type);
                        continue;
                    }
                    if (n < 3) failHere("a face with " + std::to_string(int64_t(n)) + " vertices (at least 3)");
                    poly.clear();
                    for (double j = 0; j < n; ++j) {
                        const double v = value(p.type);
                        if (!haveVertices || v < 0 || v >= double(nVertices))
                            failHere("vertex index " + std::to_string(int64_t(v)) + " is out of range (" + std::to_string(nVertices) + " vertices" +
                                     (haveVertices ? "" : ", none declared before the faces") + ")");
                        poly.push_back(uint32_t(v));
                    }
                    for (size_t j = 1; j + 1 < poly.size(); ++j) idx.insert(idx.end(), {poly[0], poly[j], poly[j + 1]});
                }
        } else {  // read past it
            for (uint64_t k = 0; k < e.count; ++k)
                for (const Property& p : e.props) {
                    if (!p.list) {
                        value(p.type);
                        continue;
                    }
                    const double n = value(p.countType);
                    if (n < 0) failHere("a negative list length");
                    for (double j = 0; j < n; ++j) value(p.type);
                }
        }
    }
    if (!haveVertices || !haveFaces || idx.empty()) failLine(0, "no faces (a PLY mesh needs vertex and face elements)");
    out.positions.resize(nVertices);
    for (size_t i = 0; i < nVertices; ++i) out.positions[i] = {pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]};
    out.indices = std::move(idx);
    if (haveUv) out.uvs = std::move(uv);
    if (smooth && (!nrm.empty() || computeMissing)) smoothVertexNormals(out, nrm);  // (nrm is empty without the file's normals)
}

}  // namespace

TriangleMesh loadPly(const std::string& path, bool smoothShading, bool computeMissingNormals) {
    // The header first: a file that is no PLY (a .ply.gz bomb, /dev/zero is refused by
    // FileStream) fails before the rest is read or inflated.
    FileStream in(path, "the PLY file");
    std::string data = readUntil(in, "end_header", size_t(1) << 20);
    PlyReader(path, data).checkHeader();
    readRest(in, data);
    TriangleMesh mesh;
    PlyReader(path, data).run(smoothShading, computeMissingNormals, mesh);
    return mesh;
}

}  // namespace wmlt
