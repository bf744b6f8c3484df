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

// ctest runs each test by its name (catch_discover_tests), and CMake splits a name at ';': the
// first half matches nothing, Catch exits 0, and ctest counts a test that never ran as passed.
// '[' would start a tag and a leading '~' or '-' a negation; none of these may be in a name.
TEST_CASE("every test's name is one ctest can run: no semicolon, bracket or leading negation", "[layout]") {
    const auto& tests = Catch::getRegistryHub().getTestCaseRegistry().getAllTests();
    CHECK(tests.size() > 300);
    for (const auto& t : tests) {
        INFO(t.name);
        CHECK(t.name.find(';') == std::string::npos);
        CHECK(t.name.find('[') == std::string::npos);
        CHECK(!t.name.empty());
        if (!t.name.empty()) CHECK((t.name[0] != '~' && t.name[0] != '-'));
    }
}
