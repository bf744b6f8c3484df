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

namespace fuzz {

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
