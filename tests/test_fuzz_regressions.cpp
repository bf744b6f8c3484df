// Every fuzz seed (tests/fuzz/corpus/<target>/) and every input a fuzzer found a bug with
// (tests/fuzz/regressions/<target>/) through the normal loaders: each must load or be
// refused with an InputError; nothing else (a crash, another exception) is acceptable.
// The seeds are valid files and must load (scenes: their meshes are not copied, so a scene
// may also stop at a missing file). scripts/fuzz.sh runs the fuzzers themselves.
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "../fuzz/gzip_members.h"
#include "wavemmlt/error.h"
#include "wavemmlt/image.h"
#include "wavemmlt/scene_desc.h"

using namespace wmlt;
namespace fs = std::filesystem;

namespace {

const fs::path kFuzz = fs::path(WAVEMMLT_TEST_DATA) / ".." / "fuzz";

std::vector<fs::path> inputs(const std::string& kind, const std::string& target) {
    std::vector<fs::path> files;
    const fs::path dir = kFuzz / kind / target;
    if (fs::is_directory(dir))
        for (const auto& e : fs::directory_iterator(dir))
            if (e.is_regular_file() && e.path().filename().string().rfind("README", 0) != 0) files.push_back(e.path());
    std::sort(files.begin(), files.end());
    return files;
}

// The file under a name with the reader's extension (the fuzzers' inputs have none).
struct Renamed {
    fs::path path;
    Renamed(const fs::path& src, const std::string& ext) {
        static int counter = 0;
        path = fs::temp_directory_path() / ("wavemmlt-fuzz-regression-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + ext);
        fs::copy_file(src, path, fs::copy_options::overwrite_existing);
    }
    ~Renamed() {
        std::error_code ec;
        fs::remove(path, ec);
    }
};

enum class Outcome { Loaded, Refused };

template <class F>
Outcome run(const fs::path& file, F&& load) {
    try {
        load();
        return Outcome::Loaded;
    } catch (const InputError& e) {
        const std::string what = e.what();
        CHECK_FALSE(what.empty());
        return Outcome::Refused;
    }  // any other exception fails the test case
}

void images(const std::string& target, const std::string& ext) {
    const auto seeds = inputs("corpus", target);
    REQUIRE(seeds.size() >= 2);
    for (const fs::path& f : seeds) {
        INFO(f.string());
        Renamed r(f, ext);
        CHECK(run(f, [&] {
                  Image img = readImage(r.path.string());
                  REQUIRE(img.width > 0);
                  REQUIRE(img.rgb.size() == size_t(img.width) * size_t(img.height) * 3);
              }) == Outcome::Loaded);
    }
    for (const fs::path& f : inputs("regressions", target)) {
        INFO(f.string());
        Renamed r(f, ext);
        run(f, [&] {
            Image img = readImage(r.path.string());
            REQUIRE(img.rgb.size() == size_t(img.width) * size_t(img.height) * 3);
        });
    }
}

}  // namespace

TEST_CASE("fuzz corpus and regressions: scene loader", "[fuzz]") {
    const auto seeds = inputs("corpus", "scene");
    REQUIRE(seeds.size() >= 5);
    for (const auto& kind : {"corpus", "regressions"}) {
        for (const fs::path& f : inputs(kind, "scene")) {
            INFO(f.string());
            run(f, [&] { loadScene(f.string()); });
            // As the fuzzer calls it: from memory, files resolved in an empty folder.
            run(f, [&] {
                std::string xml;
                {
                    std::FILE* in = std::fopen(f.string().c_str(), "rb");
                    REQUIRE(in);
                    char buf[4096];
                    size_t n;
                    while ((n = std::fread(buf, 1, sizeof buf, in)) > 0) xml.append(buf, n);
                    std::fclose(in);
                }
                loadSceneFromString(xml, f.filename().string(), fs::temp_directory_path().string() + "/wavemmlt-none");
            });
        }
    }
}

TEST_CASE("fuzz corpus and regressions: pbrt-v4 importer", "[fuzz][pbrt]") {
    // The seeds are real scenes (some refused: media, coated materials, files not copied) and
    // one that names the fuzz target's fixtures; each loads or is refused, never crashes.
    const auto seeds = inputs("corpus", "pbrt");
    REQUIRE(seeds.size() >= 5);
    int loaded = 0;
    for (const auto& kind : {"corpus", "regressions"})
        for (const fs::path& f : inputs(kind, "pbrt")) {
            INFO(f.string());
            if (run(f, [&] { loadPbrt(f.string()); }) == Outcome::Loaded) ++loaded;
        }
    CHECK(loaded >= 3);  // the Cornell boxes
}

TEST_CASE("fuzz corpus and regressions: pbrt-v4 .pbrt.gz files", "[fuzz][pbrt]") {
    // As fuzz_pbrt_gz feeds them: text gzipped in two members, gzip files as they are (two
    // members, truncated, NULs); in a temporary folder (the files they name are absent).
    const auto seeds = inputs("corpus", "pbrtgz");
    REQUIRE(seeds.size() >= 5);
    int loaded = 0;
    for (const auto& kind : {"corpus", "regressions"})
        for (const fs::path& f : inputs(kind, "pbrtgz")) {
            INFO(f.string());
            std::FILE* in = std::fopen(f.c_str(), "rb");
            REQUIRE(in);
            std::string bytes;
            char buf[4096];
            for (size_t n; (n = std::fread(buf, 1, sizeof buf, in)) > 0;) bytes.append(buf, n);
            std::fclose(in);
            const std::string gz = fuzz::asGzip(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
            const fs::path path = fs::temp_directory_path() / ("wavemmlt-fuzz-regression-" + std::to_string(::getpid()) + ".pbrt.gz");
            std::FILE* out = std::fopen(path.c_str(), "wb");
            REQUIRE(out);
            std::fwrite(gz.data(), 1, gz.size(), out);
            std::fclose(out);
            const Outcome o = run(f, [&] { loadPbrt(path.string()); });
            fs::remove(path);
            if (o == Outcome::Loaded) ++loaded;
        }
    CHECK(loaded >= 2);  // the Cornell box (its meshes are inline) and smallpt in two members
}

TEST_CASE("fuzz corpus and regressions: OBJ loader", "[fuzz]") {
    const auto seeds = inputs("corpus", "obj");
    REQUIRE(seeds.size() >= 3);
    for (const fs::path& f : seeds) {
        INFO(f.string());
        for (bool smooth : {false, true}) {
            TriangleMesh m;
            CHECK(run(f, [&] { m = loadObj(f.string(), smooth); }) == Outcome::Loaded);
            for (uint32_t i : m.indices) REQUIRE(i < m.positions.size());
        }
    }
    for (const fs::path& f : inputs("regressions", "obj")) {
        INFO(f.string());
        for (bool smooth : {false, true}) run(f, [&] { loadObj(f.string(), smooth); });
    }
}

TEST_CASE("fuzz corpus and regressions: serialized loader", "[fuzz]") {
    const auto seeds = inputs("corpus", "serialized");
    REQUIRE(seeds.size() >= 3);
    for (const fs::path& f : seeds) {
        INFO(f.string());
        for (bool smooth : {false, true}) {
            TriangleMesh m;
            CHECK(run(f, [&] { m = loadSerialized(f.string(), 0, smooth); }) == Outcome::Loaded);
            for (uint32_t i : m.indices) REQUIRE(i < m.positions.size());
        }
    }
    for (const fs::path& f : inputs("regressions", "serialized")) {
        INFO(f.string());
        for (int shape : {0, 1})
            for (bool smooth : {false, true}) run(f, [&] { loadSerialized(f.string(), shape, smooth); });
    }
}

TEST_CASE("fuzz corpus and regressions: PNG reader", "[fuzz]") { images("png", ".png"); }
TEST_CASE("fuzz corpus and regressions: JPEG reader", "[fuzz]") { images("jpeg", ".jpg"); }
TEST_CASE("fuzz corpus and regressions: TGA reader", "[fuzz]") { images("tga", ".tga"); }
TEST_CASE("fuzz corpus and regressions: EXR reader", "[fuzz]") { images("exr", ".exr"); }
TEST_CASE("fuzz corpus and regressions: HDR reader", "[fuzz]") { images("hdr", ".hdr"); }
TEST_CASE("fuzz corpus and regressions: PFM reader", "[fuzz]") { images("pfm", ".pfm"); }

TEST_CASE("fuzz regressions: each found bug's input is refused cleanly", "[fuzz]") {
    // The JPEG Huffman tables stb_image 2.27 would overflow on.
    for (const fs::path& f : inputs("regressions", "jpeg")) {
        INFO(f.string());
        Renamed r(f, ".jpg");
        CHECK(run(f, [&] { readImage(r.path.string()); }) == Outcome::Refused);
    }
}
