// Mitsuba's serialized meshes (load_serialized.cpp, the `serialized` shape): files written
// here with zlib's compress2 in the format Mitsuba documents (versions 3 and 4, float and
// double, with and without normals, uv and colours, several shapes), loaded back and
// compared with what was written; the same mesh as ply and as serialized gives the same
// SceneDesc and the same image; each kind of bad file is one InputError naming the problem.
#include <zlib.h>
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "render_stats.h"
#include "wavemmlt/error.h"
#include "wavemmlt/render.h"
#include "wavemmlt/scene_desc.h"

using namespace wmlt;

namespace {

// One shape as written: values per vertex (doubles, written as float or double).
struct Shape {
    std::vector<double> pos, nrm, uv, col;
    std::vector<uint32_t> idx;
    bool dbl = false;
    std::string name = "mesh";
    uint32_t extraFlags = 0;
    uint64_t vertices = ~0ull, triangles = ~0ull;  // counts written (~0: the data's)
};

template <class T>
void put(std::string& s, T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    s.append(b, sizeof(T));
}

// The uncompressed stream of one shape.
std::string stream(const Shape& m, int version) {
    std::string s;
    put(s, uint32_t((m.nrm.empty() ? 0 : 0x0001) | (m.uv.empty() ? 0 : 0x0002) | (m.col.empty() ? 0 : 0x0008) | (m.dbl ? 0x2000 : 0x1000) |
                    m.extraFlags));
    if (version == 4) s += m.name + '\0';
    put(s, uint64_t(m.vertices != ~0ull ? m.vertices : m.pos.size() / 3));
    put(s, uint64_t(m.triangles != ~0ull ? m.triangles : m.idx.size() / 3));
    for (const auto* a : {&m.pos, &m.nrm, &m.uv, &m.col})
        for (double v : *a) m.dbl ? put(s, v) : put(s, float(v));
    for (uint32_t i : m.idx) put(s, i);
    return s;
}

std::string compressed(const std::string& raw) {
    uLongf n = compressBound(uLong(raw.size()));
    std::string out(n, '\0');
    REQUIRE(compress2(reinterpret_cast<Bytef*>(&out[0]), &n, reinterpret_cast<const Bytef*>(raw.data()), uLong(raw.size()), 9) == Z_OK);
    out.resize(n);
    return out;
}

// A file of the given (already compressed, or raw if !compress) shape streams, with the
// end-of-file dictionary (uint64 offsets in version 4, uint32 in 3) and the count.
std::string file(const std::vector<std::string>& streams, int version) {
    std::string s;
    std::vector<uint64_t> offsets;
    for (const std::string& z : streams) {
        offsets.push_back(s.size());
        put(s, uint16_t(0x041C));
        put(s, uint16_t(version));
        s += z;
    }
    for (uint64_t o : offsets) version == 4 ? put(s, o) : put(s, uint32_t(o));
    put(s, uint32_t(streams.size()));
    return s;
}

std::string file(const std::vector<Shape>& shapes, int version) {
    std::vector<std::string> z;
    for (const Shape& m : shapes) z.push_back(compressed(stream(m, version)));
    return file(z, version);
}

void writeFile(const std::string& path, const std::string& bytes) {
    std::ofstream f(path, std::ios::binary);
    f << bytes;
}

// A unit quad at z = 0 with normals (one tilted), uv and colours; a triangle with nothing else.
Shape quad() {
    Shape m;
    m.pos = {0, 0, 0, 1, 0, 0, 1, 1, 0.1, 0, 1, 0};
    m.nrm = {0, 0, 1, 0, 0, 1, 0, 0.6, 0.8, 0, 0, 2};  // the last is not unit length: normalised
    m.uv = {0, 0, 1, 0, 1, 1, 0, 1};
    m.col = {1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1};
    m.idx = {0, 1, 2, 0, 2, 3};
    m.name = "quad \xC3\xA9";  // UTF-8
    return m;
}
Shape triangle() {
    Shape m;
    m.pos = {0, 0, 5, 2, 0, 5, 0, 2, 5};
    m.idx = {0, 1, 2};
    return m;
}

}  // namespace

TEST_CASE("Mitsuba serialized: versions 3 and 4, float and double, two shapes, as written", "[serialized][mitsuba]") {
    const std::string dir = rstats::tempDir("serialized");
    for (int version : {3, 4})
        for (bool dbl : {false, true}) {
            INFO("version " << version << (dbl ? ", double" : ", float"));
            Shape q = quad(), t = triangle();
            q.dbl = t.dbl = dbl;
            q.pos[1] = 0.1;         // not a float: rounded once, from the double when dbl
            q.extraFlags = 0x0010;  // face normals: ignored, as Mitsuba ignores it
            const std::string path = dir + "/two-" + std::to_string(version) + (dbl ? "d" : "f") + ".serialized";
            writeFile(path, file({q, t}, version));

            const TriangleMesh m = loadSerialized(path, 0, true);
            REQUIRE(m.positions.size() == 4);
            for (size_t i = 0; i < 4; ++i)
                for (int k = 0; k < 3; ++k) CHECK(m.positions[i][k] == float(q.pos[3 * i + size_t(k)]));
            CHECK(m.indices == q.idx);
            REQUIRE(m.uvs.size() == 8);
            for (size_t i = 0; i < 8; ++i) CHECK(m.uvs[i] == float(q.uv[i]));
            REQUIRE(m.normals.size() == 4);
            CHECK(m.normals[0].z == 1.0f);
            CHECK(m.normals[2].y == Approx(0.6f));
            CHECK(m.normals[2].z == Approx(0.8f));
            CHECK(m.normals[3].z == 1.0f);  // (0, 0, 2) normalised
            const TriangleMesh flat = loadSerialized(path, 0, false);
            CHECK(flat.normals.empty());
            CHECK(flat.positions.size() == 4);
            CHECK(flat.uvs.size() == 8);

            // The second shape, found through the dictionary: no normals (smooth: computed
            // from the faces, as PLY's are), no uv.
            const TriangleMesh t1 = loadSerialized(path, 1, true);
            REQUIRE(t1.positions.size() == 3);
            CHECK(t1.positions[1].x == 2.0f);
            CHECK(t1.positions[2].z == 5.0f);
            CHECK(t1.indices == t.idx);
            CHECK(t1.uvs.empty());
            REQUIRE(t1.normals.size() == 3);
            for (const Vec3& n : t1.normals) CHECK(n.z == 1.0f);
        }
    std::filesystem::remove_all(dir);
}

namespace {

// The same mesh as an ASCII PLY (%.9g: floats exactly) with normals and uv when given.
std::string asPly(const Shape& m) {
    const size_t n = m.pos.size() / 3;
    std::string s = "ply\nformat ascii 1.0\nelement vertex " + std::to_string(n) + "\nproperty float x\nproperty float y\nproperty float z\n";
    if (!m.nrm.empty()) s += "property float nx\nproperty float ny\nproperty float nz\n";
    if (!m.uv.empty()) s += "property float u\nproperty float v\n";
    s += "element face " + std::to_string(m.idx.size() / 3) + "\nproperty list uchar int vertex_indices\nend_header\n";
    char b[64];
    for (size_t i = 0; i < n; ++i) {
        for (int k = 0; k < 3; ++k) {
            std::snprintf(b, sizeof b, "%.9g ", double(float(m.pos[3 * i + size_t(k)])));
            s += b;
        }
        for (int k = 0; k < 3 && !m.nrm.empty(); ++k) {
            std::snprintf(b, sizeof b, "%.9g ", double(float(m.nrm[3 * i + size_t(k)])));
            s += b;
        }
        for (int k = 0; k < 2 && !m.uv.empty(); ++k) {
            std::snprintf(b, sizeof b, "%.9g ", double(float(m.uv[2 * i + size_t(k)])));
            s += b;
        }
        s += "\n";
    }
    for (size_t t = 0; t < m.idx.size(); t += 3)
        s += "3 " + std::to_string(m.idx[t]) + " " + std::to_string(m.idx[t + 1]) + " " + std::to_string(m.idx[t + 2]) + "\n";
    return s;
}

// A bumpy 6 x 6 grid of quads over [-1, 1]^2 (z up to 0.2), with normals and uv.
Shape grid() {
    Shape m;
    const int n = 7;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const double x = -1 + 2.0 * i / (n - 1), y = -1 + 2.0 * j / (n - 1), z = 0.2 * std::sin(3 * x) * std::cos(2 * y);
            m.pos.insert(m.pos.end(), {x, y, z});
            const double nx = -0.6 * std::cos(3 * x) * std::cos(2 * y), ny = 0.4 * std::sin(3 * x) * std::sin(2 * y);
            const double l = std::sqrt(nx * nx + ny * ny + 1);
            m.nrm.insert(m.nrm.end(), {nx / l, ny / l, 1 / l});
            m.uv.insert(m.uv.end(), {double(i) / (n - 1), double(j) / (n - 1)});
        }
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i) {
            const uint32_t a = uint32_t(j * n + i), b = a + 1, c = a + uint32_t(n), d = c + 1;
            m.idx.insert(m.idx.end(), {a, b, d, a, d, c});
        }
    return m;
}

const char* kSceneHead = R"(<scene version="3.0.0">
  <integrator type="path"><integer name="max_depth" value="3"/></integrator>
  <sensor type="perspective"><float name="fov" value="50"/>
    <transform name="to_world"><lookat origin="0, -2, 3" target="0, 0, 0" up="0, 0, 1"/></transform>
    <film type="hdrfilm"><integer name="width" value="12"/><integer name="height" value="10"/></film></sensor>
)";

}  // namespace

TEST_CASE("Mitsuba serialized: the same meshes as ply and as serialized give the same scene and image", "[serialized][mitsuba][render]") {
    const std::string dir = rstats::tempDir("serialized-ply");
    Shape g = grid(), light = triangle();
    g.dbl = true;
    light.pos = {-0.5, -0.5, 2, 0.5, -0.5, 2, 0, 0.5, 2};
    light.idx = {0, 1, 2};  // facing up: flip_normals turns it down
    writeFile(dir + "/grid.ply", asPly(g));
    writeFile(dir + "/light.ply", asPly(light));
    writeFile(dir + "/both.serialized", file({g, light}, 4));
    // Smooth (the file's normals), computed normals, and flat, with to_world, flip_normals,
    // a BSDF and an area emitter on a mesh.
    for (const char* normals : {"false", "true"}) {
        INFO("face_normals " << normals);
        auto sceneWith = [&](const std::string& grid, const std::string& lamp) {
            return std::string(kSceneHead) + "<shape type=\"" + grid + "<boolean name=\"face_normals\" value=\"" + normals +
                   "\"/>\n<transform name=\"to_world\"><rotate z=\"1\" angle=\"20\"/><scale x=\"1.5\"/></transform>"
                   "<bsdf type=\"roughplastic\"><float name=\"alpha\" value=\"0.3\"/></bsdf></shape>\n"
                   "<shape type=\"" +
                   lamp +
                   "<boolean name=\"flip_normals\" value=\"true\"/><transform name=\"to_world\"><translate x=\"0.2\"/></transform>"
                   "<emitter type=\"area\"><rgb name=\"radiance\" value=\"5, 4, 3\"/></emitter></shape>\n</scene>\n";
        };
        const SceneDesc a = loadMitsubaFromString(
            sceneWith("ply\"><string name=\"filename\" value=\"grid.ply\"/>", "ply\"><string name=\"filename\" value=\"light.ply\"/>"), "a.xml", dir);
        const SceneDesc b = loadMitsubaFromString(
            sceneWith("serialized\"><string name=\"filename\" value=\"both.serialized\"/>",
                      "serialized\"><string name=\"filename\" value=\"both.serialized\"/><integer name=\"shape_index\" value=\"1\"/>"),
            "b.xml", dir);
        REQUIRE(a.shapes.size() == 2);
        REQUIRE(b.shapes.size() == 2);
        for (size_t s = 0; s < 2; ++s) {
            INFO("shape " << s);
            const TriangleMesh &ma = a.shapes[s].mesh, &mb = b.shapes[s].mesh;
            REQUIRE(ma.positions.size() == mb.positions.size());
            for (size_t i = 0; i < ma.positions.size(); ++i)
                for (int k = 0; k < 3; ++k) REQUIRE(ma.positions[i][k] == mb.positions[i][k]);
            REQUIRE(ma.normals.size() == mb.normals.size());
            for (size_t i = 0; i < ma.normals.size(); ++i)
                for (int k = 0; k < 3; ++k) REQUIRE(ma.normals[i][k] == mb.normals[i][k]);
            CHECK(ma.uvs == mb.uvs);
            CHECK(ma.indices == mb.indices);
            CHECK(a.shapes[s].material == b.shapes[s].material);
            CHECK(a.shapes[s].light == b.shapes[s].light);
        }
        CHECK(a.shapes[0].mesh.normals.empty() == (std::string(normals) == "true"));
        REQUIRE(b.lights.size() == 1);
        CHECK(b.lights[0].kind == LightKind::Mesh);
        const RenderResult ra = render(a, rstats::renderOptions(TracerKind::PT, 4, 11, 1, 3));
        const RenderResult rb = render(b, rstats::renderOptions(TracerKind::PT, 4, 11, 1, 3));
        double sum = 0;
        for (float v : ra.image.rgb) sum += v;
        CHECK(sum > 0);                       // the light reaches the camera
        CHECK(ra.image.rgb == rb.image.rgb);  // bit for bit
    }
    std::filesystem::remove_all(dir);
}

TEST_CASE("Mitsuba serialized: bad files are one InputError naming the file and the problem", "[serialized][mitsuba][bad-input]") {
    const std::string dir = rstats::tempDir("serialized-bad");
    const std::string p = dir + "/x.serialized";
    auto errorIn = [&](const std::string& bytes, int index = 0) {
        writeFile(p, bytes);
        try {
            loadSerialized(p, index, true);
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    const Shape q = quad();
    const std::string good = file({q, triangle()}, 4);
    CHECK(errorIn(good).empty());
    CHECK(errorIn(good, 1).empty());
    auto with = [&](auto change, int version = 4) {
        Shape m = quad();
        change(m);
        return file({m}, version);
    };
    std::string badId = good, badVersion = good;
    badId[0] = 'P';
    badVersion[2] = 5;
    const std::string z = compressed(stream(q, 4));
    const std::string cutStream = file({z.substr(0, z.size() / 2)}, 4);  // the dictionary is intact
    std::string tableOff = good;
    tableOff[tableOff.size() - 4 - 8 + 3] = 1;  // shape 1's offset, 16 MiB past the data
    std::string countHuge = good;
    countHuge[countHuge.size() - 1] = 0x10;
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"", p + ": too short for a serialized file (0 bytes)"},
        {good.substr(0, 3), p + ": too short for a serialized file (3 bytes)"},
        {good.substr(0, 6), p + ": the file ends before its shape count"},
        {badId, p + ": byte 0: not a Mitsuba serialized file (identifier 0x0450, expected 0x041C)"},
        {std::string("\x04\x1C\x04\x00", 4) + good.substr(4), p + ": byte 0: a serialized file of an old Mitsuba"},
        {badVersion, p + ": byte 2: serialized format version 5 (wavemmlt reads 3 and 4)"},
        {cutStream, p + ": byte " + std::to_string(4 + z.size() / 2) + ": the file ends inside shape 0's compressed data"},
        {with([](Shape& m) { m.vertices = 1000; }), p + ": shape 0: the compressed data ends early"},
        {with([](Shape& m) { m.vertices = 1000000; }), p + ": shape 0: 1000000 vertices and 2 triangles need 44000024 bytes, more than its"},
        {with([](Shape& m) { m.triangles = 1ull << 40; }), p + ": shape 0: 4 vertices and 1099511627776 triangles need more than 8 GiB"},
        {with([](Shape& m) { m.vertices = 1ull << 33; }), p + ": shape 0: too many vertices (8589934592"},
        {with([](Shape& m) { m.idx[4] = 7; }), p + ": shape 0: triangle 1: vertex index 7 is out of range (4 vertices)"},
        {with([](Shape& m) { m.pos[7] = std::nan(""); }), p + ": shape 0: the position of vertex 2 is not finite"},
        {with([](Shape& m) { m.pos[3] = INFINITY; }, 3), p + ": shape 0: the position of vertex 1 is not finite"},
        {with([](Shape& m) {
             m.dbl = true;
             m.uv[3] = 1e300;
         }),
         p + ": shape 0: the uv of vertex 1 does not fit a float"},
        {with([](Shape& m) {
             m.triangles = 0;
             m.idx.clear();
         }),
         p + ": shape 0: no triangles"},
        {with([](Shape& m) { m.extraFlags = 0x2000; }), p + ": shape 0: the flags say both single and double precision"},
        {with([](Shape& m) { m.name = std::string(70000, 'n'); }), p + ": shape 0: the shape's name has no terminating 0"},
        {countHuge, p + ": byte " + std::to_string(good.size() - 4) + ": the shape count 268435458 is more than the file holds"},
        {file(std::vector<std::string>{}, 4).insert(0, std::string("\x1C\x04\x04\x00", 4)), p + ": byte 4: the shape count is 0"},
    };
    for (const auto& [bytes, want] : cases) {
        const std::string e = errorIn(bytes);
        INFO(e);
        CHECK(e.find(want) == 0);
    }
    std::string e = errorIn(file({std::string("this is not zlib data")}, 4));
    CHECK(e.find(p + ": byte ") == 0);
    CHECK(e.find(": shape 0: not zlib data (zlib: incorrect header check)") != std::string::npos);
    e = errorIn(tableOff, 1);
    CHECK(e.find(p + ": byte " + std::to_string(good.size() - 4 - 8) + ": shape 1's offset 16777") == 0);
    CHECK(e.find("is past the shapes' data") != std::string::npos);
    CHECK(errorIn(good, 2) == p + ": shape_index 2 is out of range (the file holds 2 shapes)");
    CHECK(errorIn(file({q}, 3), 1) == p + ": shape_index 1 is out of range (the file holds 1 shape)");
    CHECK(errorIn(good, -1).find("shape_index -1 is out of range") != std::string::npos);
    // A version 3 file reads 32-bit offsets: its second shape is found.
    writeFile(p, file({triangle(), q}, 3));
    CHECK(loadSerialized(p, 1, false).positions.size() == 4);
    CHECK_THROWS_WITH(loadSerialized(dir + "/missing.serialized", 0, true), dir + "/missing.serialized: cannot open the serialized file");
    std::filesystem::remove_all(dir);
}

TEST_CASE("Mitsuba serialized: the importer (shape_index, face_normals) and its errors name the scene line", "[serialized][mitsuba][import]") {
    const std::string dir = rstats::tempDir("serialized-import");
    writeFile(dir + "/m.serialized", file({triangle(), quad()}, 4));
    writeFile(dir + "/bad.serialized", "not a mesh");
    auto sceneWith = [](const std::string& shape) { return std::string(kSceneHead) + shape + "\n<emitter type=\"constant\"/></scene>\n"; };
    SceneDesc d = loadMitsubaFromString(sceneWith(R"(<shape type="serialized"><string name="filename" value="m.serialized"/>
  <integer name="shape_index" value="1"/><transform name="to_world"><translate z="2"/></transform>
  <emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>)"),
                                        "t.xml", dir);
    REQUIRE(d.shapes.size() == 1);
    CHECK(d.shapes[0].mesh.positions.size() == 4);
    CHECK(d.shapes[0].mesh.positions[2].z == Approx(2.1f));
    CHECK(d.shapes[0].mesh.normals.size() == 4);  // the file's
    CHECK(d.shapes[0].uv == UvKind::Mesh);
    CHECK(d.lights.size() == 1);
    d = loadMitsubaFromString(sceneWith(R"(<shape type="serialized"><string name="filename" value="m.serialized"/>
  <boolean name="face_normals" value="true"/></shape>)"),
                              "t.xml", dir);
    CHECK(d.shapes[0].mesh.positions.size() == 3);  // shape 0 by default
    CHECK(d.shapes[0].mesh.normals.empty());
    CHECK(d.shapes[0].uv == UvKind::None);
    // Mitsuba 0.6's camelCase spelling.
    d = loadMitsubaFromString(R"(<scene version="0.6.0"><sensor type="perspective"><float name="fov" value="40"/></sensor>
<shape type="serialized"><string name="filename" value="m.serialized"/><integer name="shapeIndex" value="1"/></shape><emitter type="constant"/></scene>)",
                              "t.xml", dir);
    CHECK(d.shapes[0].mesh.positions.size() == 4);
    auto errorOf = [&](const std::string& shape) {
        try {
            loadMitsubaFromString(sceneWith(shape), "t.xml", dir);
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    const std::string kAt = "t.xml:6: <shape type=\"serialized\">: ";
    const std::vector<std::pair<std::string, std::string>> cases = {
        {R"(<shape type="serialized"><string name="filename" value="bad.serialized"/></shape>)",
         kAt + dir + "/bad.serialized: byte 0: not a Mitsuba serialized file"},
        {R"(<shape type="serialized"><string name="filename" value="m.serialized"/><integer name="shape_index" value="2"/></shape>)",
         kAt + dir + "/m.serialized: shape_index 2 is out of range (the file holds 2 shapes)"},
        {R"(<shape type="serialized"><string name="filename" value="m.serialized"/><integer name="shape_index" value="-1"/></shape>)",
         kAt + "shape_index must be >= 0"},
        {R"(<shape type="serialized"><string name="filename" value="none.serialized"/></shape>)",
         kAt + dir + "/none.serialized: cannot open the serialized file"},
        {R"(<shape type="serialized"><string name="filename" value="m.serialized"/><float name="max_smooth_angle" value="30"/></shape>)",
         "t.xml:6: <float name=\"max_smooth_angle\">: "},
    };
    for (const auto& [shape, want] : cases) {
        const std::string e = errorOf(shape);
        INFO(e);
        CHECK(e.find(want) == 0);
    }
    std::filesystem::remove_all(dir);
}
