// Shared by the libFuzzer targets: a per-process temporary folder (removed at exit) and
// writing the fuzz input to a file in it, for the loaders that read only files.
// A target passes when the loader returns or throws wmlt::InputError; any other
// exception escapes LLVMFuzzerTestOneInput and libFuzzer reports it (abort: a finding).
#pragma once
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "wavemmlt/scene_desc.h"

namespace fuzz {

// A loaded mesh must be consistent: every index names a vertex, and normals and (u, v)
// (when present) go with every vertex. Traps (a finding) otherwise.
inline void checkMesh(const wmlt::TriangleMesh& m) {
    if (m.indices.size() % 3) __builtin_trap();
    for (uint32_t i : m.indices)
        if (i >= m.positions.size()) __builtin_trap();  // an index past the vertices
    if (!m.normals.empty() && m.normals.size() != m.positions.size()) __builtin_trap();
    if (!m.uvs.empty() && m.uvs.size() != 2 * m.positions.size()) __builtin_trap();
}

inline const std::string& tempDir() {
    static const std::string dir = [] {
        const char* base = std::getenv("TMPDIR");
        std::string tmpl = std::string(base && *base ? base : "/tmp") + "/wavemmlt-fuzz-XXXXXX";
        if (!::mkdtemp(&tmpl[0])) {
            std::perror("mkdtemp");
            std::abort();
        }
        static std::string keep = tmpl;
        std::atexit([] {
            std::error_code ec;
            std::filesystem::remove_all(keep, ec);
        });
        return tmpl;
    }();
    return dir;
}

// Writes `size` bytes to tempDir()/name and returns the path.
inline std::string writeFile(const std::string& name, const uint8_t* data, size_t size) {
    const std::string path = tempDir() + "/" + name;
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) {
        std::perror(path.c_str());
        std::abort();
    }
    if (size && std::fwrite(data, 1, size, f) != size) {
        std::perror(path.c_str());
        std::abort();
    }
    std::fclose(f);
    return path;
}

inline std::string writeFile(const std::string& name, const std::string& text) {
    return writeFile(name, reinterpret_cast<const uint8_t*>(text.data()), text.size());
}

// The files a pbrt scene of the fuzzers may name beside it (fuzz_pbrt, fuzz_pbrt_gz): a
// PLY ("m.ply"), a tiny image ("t.pfm"), one with a NaN and an infinite pixel ("nan.pfm",
// refused), a square one for an infinite light ("sq.pfm"), a spectrum ("s.spd") and a
// gzipped PLY whose first line is not "ply" ("bad.ply.gz").
inline void writePbrtFixtures() {
    static const bool done = [] {
        writeFile("m.ply", std::string("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                       "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                       "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"));
        writeFile("t.pfm", std::string("PF\n2 1\n-1.0\n") + std::string(24, '\0'));
        const float bad[6] = {__builtin_nanf(""), 1, 1, __builtin_inff(), 1, 1};
        writeFile("nan.pfm", std::string("PF\n2 1\n-1.0\n") + std::string(reinterpret_cast<const char*>(bad), sizeof bad));
        writeFile("sq.pfm", std::string("PF\n2 2\n-1.0\n") + std::string(48, '\0'));
        writeFile("s.spd", std::string("400 1.5\n500 1.2\n600 0.9\n700 0.5\n"));
        writeFile("bad.ply.gz",
                  std::string("\x1f\x8b\x08\x00\x00\x00\x00\x00\x00\x03\x2b\xc8\x49\xad\xe0\x02\x00\x42\x4c\x2f\x07\x05\x00\x00\x00", 25));
        return true;
    }();
    (void)done;
}

}  // namespace fuzz
