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
        if (!::mkdtemp(&tmpl[0])) { std::perror("mkdtemp"); std::abort(); }
        static std::string keep = tmpl;
        std::atexit([] { std::error_code ec; std::filesystem::remove_all(keep, ec); });
        return tmpl;
    }();
    return dir;
}

// Writes `size` bytes to tempDir()/name and returns the path.
inline std::string writeFile(const std::string& name, const uint8_t* data, size_t size) {
    const std::string path = tempDir() + "/" + name;
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) { std::perror(path.c_str()); std::abort(); }
    if (size && std::fwrite(data, 1, size, f) != size) { std::perror(path.c_str()); std::abort(); }
    std::fclose(f);
    return path;
}

inline std::string writeFile(const std::string& name, const std::string& text) {
    return writeFile(name, reinterpret_cast<const uint8_t*>(text.data()), text.size());
}

}  // namespace fuzz
