// Wavefront OBJ reader (scene-format.md, "Geometry" / ObjFile).
//
// A small strict parser of our own rather than tinyobjloader: tinyobjloader neither
// reports line numbers nor rejects bad data (it reads "1.5x" as 1.5 and an index past
// the vertex list as garbage), and the format requires "file:line: problem" messages.
// It maps the file into memory (only the pages it reads become resident, so a huge file
// of garbage fails at its first bad line in bounded memory) and parses numbers with
// std::from_chars (no iostreams, locale-independent); the 871k-triangle Stanford dragon
// loads in well under a second. Tokens quoted in messages are cut to 40 characters, with
// control characters shown as '?'.
//
// Supported: v (x y z, extra components ignored), vt (u [v [w]]), vn, f with v, v/vt,
// v//vn, v/vt/vn and negative (relative) indices, polygons (fan-triangulated).
// Ignored: o, g, s, usemtl, mtllib, l, p, vp, comments. Anything else is an error.
// Indices must refer to elements defined above the face (OBJ's rule).
// Vertices: one per distinct (v, vt, vn) corner; a file with only v and f shares its
// vertices directly. SmoothShading: the file's vn, else area-weighted normals
// accumulated per position (so uv seams do not split them); flat: no normals.
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <unordered_map>
#include <vector>

#include "scene/read_file.h"
#include "wavemmlt/error.h"
#include "wavemmlt/scene_desc.h"

namespace wmlt {
namespace {

struct Corner {
    int64_t v, vt, vn;  // 0-based; -1: absent
    bool operator==(const Corner& o) const { return v == o.v && vt == o.vt && vn == o.vn; }
};
struct CornerHash {
    size_t operator()(const Corner& c) const {
        uint64_t h = uint64_t(c.v) * 0x9E3779B97F4A7C15ull;
        h ^= uint64_t(c.vt + 1) * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
        h ^= uint64_t(c.vn + 1) * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
        return size_t(h);
    }
};

class ObjParser {
public:
    ObjParser(const std::string& path, const char* b, const char* e) : path_(path), p_(b), end_(e) {}

    void run(bool smooth, TriangleMesh& out);

private:
    const std::string& path_;
    const char* p_;
    const char* end_;
    int line_ = 1;
    std::vector<float> pos_, tex_, nrm_;  // 3, 2, 3 floats per element
    std::vector<Corner> corners_;         // 3 per triangle
    bool anyVt_ = false, anyVn_ = false;

    [[noreturn]] void fail(const std::string& msg) const { throw InputError(path_, line_, msg); }
    static bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }
    void skipSpace() {
        while (p_ < end_ && isSpace(*p_)) ++p_;
    }
    bool atEol() {
        skipSpace();
        return p_ == end_ || *p_ == '\n' || *p_ == '#';
    }
    void skipLine() {
        while (p_ < end_ && *p_ != '\n') ++p_;
    }
    // The next token, at most kMaxToken characters (a longer one is no keyword, and only
    // messages quote it).
    static constexpr size_t kMaxToken = 64;
    std::string token() {
        const char* b = p_;
        while (p_ < end_ && !isSpace(*p_) && *p_ != '\n' && size_t(p_ - b) < kMaxToken) ++p_;
        return std::string(b, p_);
    }
    // s for a message: at most 40 characters, control characters as '?'.
    static std::string quoted(const std::string& s) {
        std::string q = "\"";
        for (size_t i = 0; i < s.size() && i < 40; ++i) q += (unsigned char)s[i] < 0x20 || s[i] == 0x7f ? '?' : s[i];
        return q + (s.size() > 40 ? "...\"" : "\"");
    }

    float number() {
        skipSpace();
        const char* b = p_;
        if (p_ < end_ && *p_ == '+' && p_ + 1 < end_ && p_[1] != '-') ++p_;
        double v = 0;  // double: 1e-50 becomes 0, 1e40 is rejected below
        auto r = std::from_chars(p_, end_, v);
        const char* stop = r.ptr;
        if (r.ec == std::errc() && stop < end_ && !isSpace(*stop) && *stop != '\n' && *stop != '#')
            r.ec = std::errc::invalid_argument;  // trailing garbage: "1.5x"
        if (r.ec != std::errc() || !std::isfinite(float(v))) {
            p_ = b;
            std::string t = token();
            fail(t.empty() ? "a number is missing" : quoted(t) + " is not a finite number");
        }
        p_ = stop;
        return float(v);
    }

    void readFloats(std::vector<float>& dst, int minCount, int keep, float fill) {
        int n = 0;
        while (!atEol()) {
            float v = number();
            if (n < keep) dst.push_back(v);
            ++n;
        }
        if (n < minCount) fail("expected at least " + std::to_string(minCount) + " numbers");
        for (; n < keep; ++n) dst.push_back(fill);
    }

    // An OBJ index (1-based, or negative relative to the end) into `count` elements.
    int64_t index(const char*& q, const char* e, size_t count, const char* what, const char* whats) {
        long long i = 0;
        auto r = std::from_chars(q, e, i);
        if (r.ec != std::errc() || r.ptr == q) fail("face corner " + quoted(std::string(q, e)) + " is malformed");
        q = r.ptr;
        long long k = i > 0 ? i - 1 : (long long)count + i;
        if (i == 0) fail("face index 0 is invalid (OBJ indices start at 1)");
        if (k < 0 || k >= (long long)count)
            fail(std::string("face ") + what + "index " + std::to_string(i) + " is past the " + std::to_string(count) + " " + whats +
                 " defined above");
        return k;
    }

    Corner corner() {
        const char* b = p_;
        while (p_ < end_ && !isSpace(*p_) && *p_ != '\n') ++p_;
        const char* e = p_;
        const char* q = b;
        Corner c{index(q, e, pos_.size() / 3, "", "vertices"), -1, -1};
        if (q < e && *q == '/') {
            ++q;
            if (q < e && *q != '/') {
                c.vt = index(q, e, tex_.size() / 2, "texture ", "texture coordinates");
                anyVt_ = true;
            }
            if (q < e && *q == '/') {
                ++q;
                c.vn = index(q, e, nrm_.size() / 3, "normal ", "normals");
                anyVn_ = true;
            }
        }
        if (q != e) fail("face corner " + quoted(std::string(b, e)) + " is malformed");
        return c;
    }

    void face() {
        Corner first{}, prev{};
        int n = 0;
        while (!atEol()) {
            Corner c = corner();
            if (n == 0) first = c;
            else if (n >= 2) {
                corners_.push_back(first);
                corners_.push_back(prev);
                corners_.push_back(c);
            }
            prev = c;
            ++n;
        }
        if (n < 3) fail("a face needs at least 3 vertices, this one has " + std::to_string(n));
    }

    void build(bool smooth, TriangleMesh& out);
};

void ObjParser::run(bool smooth, TriangleMesh& out) {
    for (; p_ < end_; ++line_) {
        skipSpace();
        if (p_ < end_ && *p_ != '\n' && *p_ != '#') {
            std::string kw = token();
            if (kw == "v") readFloats(pos_, 3, 3, 0);
            else if (kw == "vt") readFloats(tex_, 1, 2, 0);
            else if (kw == "vn") readFloats(nrm_, 3, 3, 0);
            else if (kw == "f") face();
            else if (kw == "o" || kw == "g" || kw == "s" || kw == "usemtl" || kw == "mtllib" || kw == "l" || kw == "p" || kw == "vp") skipLine();
            else if (kw.find('\0') != std::string::npos) fail("not a text file (a NUL byte)");
            else fail("unknown statement " + quoted(kw));
            if (!atEol()) fail("unexpected " + quoted(token()));
        }
        skipLine();
        if (p_ < end_) ++p_;  // the '\n'
    }
    if (corners_.empty()) throw InputError(path_, 0, "the file has no faces");
    build(smooth, out);
}

void ObjParser::build(bool smooth, TriangleMesh& out) {
    const bool useVn = smooth && anyVn_;
    const size_t nPos = pos_.size() / 3;
    out = TriangleMesh();
    out.indices.resize(corners_.size());
    std::vector<int64_t> posOf;  // output vertex -> position index
    if (nPos >= 0xFFFFFFFFull) throw InputError(path_, 0, "too many vertices");
    if (!anyVt_ && !useVn) {
        // Only positions matter: share the file's vertices as they are.
        for (size_t i = 0; i < corners_.size(); ++i) out.indices[i] = uint32_t(corners_[i].v);
        out.positions.resize(nPos);
        for (size_t i = 0; i < nPos; ++i) out.positions[i] = {pos_[3 * i], pos_[3 * i + 1], pos_[3 * i + 2]};
        posOf.resize(nPos);
        for (size_t i = 0; i < nPos; ++i) posOf[i] = int64_t(i);
    } else {
        std::unordered_map<Corner, uint32_t, CornerHash> ids;
        ids.reserve(corners_.size() / 2 + 16);
        for (size_t i = 0; i < corners_.size(); ++i) {
            Corner c = corners_[i];
            if (!useVn) c.vn = -1;
            auto [it, fresh] = ids.emplace(c, uint32_t(posOf.size()));
            if (fresh) {
                if (posOf.size() >= 0xFFFFFFFFull) throw InputError(path_, 0, "too many vertices");
                posOf.push_back(c.v);
                out.positions.push_back({pos_[3 * c.v], pos_[3 * c.v + 1], pos_[3 * c.v + 2]});
                if (anyVt_) {
                    out.uvs.push_back(c.vt >= 0 ? tex_[2 * c.vt] : 0.0f);
                    out.uvs.push_back(c.vt >= 0 ? tex_[2 * c.vt + 1] : 0.0f);
                }
                if (useVn) {
                    out.normals.push_back(c.vn >= 0 ? Vec3{nrm_[3 * c.vn], nrm_[3 * c.vn + 1], nrm_[3 * c.vn + 2]} : Vec3{0, 0, 0});
                }
            }
            out.indices[i] = it->second;
        }
    }
    if (!smooth) return;
    // Area-weighted normals per position, for vertices without a usable vn.
    if (out.normals.empty()) out.normals.assign(out.positions.size(), Vec3{0, 0, 0});
    bool needed = false;
    for (Vec3& n : out.normals) {
        float l = length(n);
        if (l > 0 && std::isfinite(l)) n = n / l;
        else {
            n = Vec3{0, 0, 0};
            needed = true;
        }
    }
    if (!needed) return;
    std::vector<Vec3> acc(nPos, Vec3{0, 0, 0});
    for (size_t t = 0; t < corners_.size(); t += 3) {
        Vec3 p[3];
        for (int k = 0; k < 3; ++k) {
            int64_t v = corners_[t + k].v;
            p[k] = {pos_[3 * v], pos_[3 * v + 1], pos_[3 * v + 2]};
        }
        Vec3 n = cross(p[1] - p[0], p[2] - p[0]);  // length = 2 * area
        for (int k = 0; k < 3; ++k) acc[corners_[t + k].v] += n;
    }
    for (size_t i = 0; i < out.normals.size(); ++i) {
        if (!isBlack(out.normals[i])) continue;
        Vec3 n = acc[posOf[i]];
        float l = length(n);
        // A vertex only on zero-area triangles is never hit: any unit vector will do.
        out.normals[i] = (l > 0 && std::isfinite(l)) ? n / l : Vec3{0, 1, 0};
    }
}

}  // namespace

TriangleMesh loadObj(const std::string& path, bool smoothShading) {
    requireRegularFile(path, "the OBJ file");  // before open(): a FIFO's open waits for a writer
    const int fd = ::open(path.c_str(), O_RDONLY);
    if (fd < 0) throw InputError(path, 0, "cannot open the OBJ file");
    struct stat st;
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        ::close(fd);
        throw InputError(path, 0, "cannot read the OBJ file (not a regular file)");
    }
    const size_t size = size_t(st.st_size);
    void* data = size ? ::mmap(nullptr, size, PROT_READ, MAP_PRIVATE, fd, 0) : nullptr;
    ::close(fd);
    if (size && data == MAP_FAILED) throw InputError(path, 0, "cannot read the OBJ file");
    struct Unmap {
        void* p;
        size_t n;
        ~Unmap() {
            if (p) ::munmap(p, n);
        }
    } unmap{data, size};
    if (size) ::madvise(data, size, MADV_SEQUENTIAL);
    const char* b = static_cast<const char*>(data);
    TriangleMesh mesh;
    ObjParser(path, b, b + size).run(smoothShading, mesh);
    return mesh;
}

}  // namespace wmlt
