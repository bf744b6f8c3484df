// Issue 10's rule for the wavefront's code: files small enough to read in one sitting (no
// file in src/stages/ over 400 lines), and the brief's: a folder of about 30 files at most
// (src/stages/ is one folder per part of the wavefront: core/, pt/, lt/, bpt/, mmlt/);
// checked on the sources this binary was built from.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <map>
#include <string>

TEST_CASE("no file in src/stages is over 400 lines, no folder there over 30 files", "[layout]") {
    const std::filesystem::path dir = std::filesystem::path(WAVEMMLT_TEST_DATA) / ".." / ".." / "src" / "stages";
    REQUIRE(std::filesystem::is_directory(dir));
    int files = 0;
    std::map<std::string, int> perFolder;
    for (const auto& e : std::filesystem::recursive_directory_iterator(dir)) {
        if (!e.is_regular_file()) continue;
        std::ifstream in(e.path());
        std::string line;
        int lines = 0;
        while (std::getline(in, line)) ++lines;
        INFO(e.path().lexically_relative(dir).string() << ": " << lines << " lines");
        CHECK(lines <= 400);
        ++files;
        ++perFolder[e.path().parent_path().lexically_relative(dir).string()];
    }
    CHECK(files > 20);
    for (const auto& [folder, n] : perFolder) {
        INFO("src/stages/" << folder << ": " << n << " files");
        CHECK(n <= 30);
    }
}
