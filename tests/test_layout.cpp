// Issue 10's rule for the wavefront's code: files small enough to read in one sitting (no
// file in src/stages/ over 400 lines), checked on the sources this binary was built from.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>

TEST_CASE("no file in src/stages is over 400 lines", "[layout]") {
    const std::filesystem::path dir = std::filesystem::path(WAVEMMLT_TEST_DATA) / ".." / ".." / "src" / "stages";
    REQUIRE(std::filesystem::is_directory(dir));
    int files = 0;
    for (const auto& e : std::filesystem::directory_iterator(dir)) {
        std::ifstream in(e.path());
        std::string line;
        int lines = 0;
        while (std::getline(in, line)) ++lines;
        INFO(e.path().filename().string() << ": " << lines << " lines");
        CHECK(lines <= 400);
        ++files;
    }
    CHECK(files > 20);
}
