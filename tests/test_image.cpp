// Image files: round trips, format details (PFM endianness and row order, sRGB), errors
// (missing, truncated, empty, absurd sizes), the temporary-file protocol, wavemmlt-img.
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <ImfRgbaFile.h>
#include <stb/stb_image.h>
#include <stb/stb_image_write.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "wavemmlt/error.h"
#include "wavemmlt/image.h"

using namespace wmlt;
namespace fs = std::filesystem;

namespace {

// A fresh directory under the system's temporary folder, removed afterwards.
struct TempDir {
    fs::path path;
    TempDir() {
        static int counter = 0;
        path = fs::temp_directory_path() / ("wavemmlt-test-image-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
    std::string file(const std::string& name) const { return (path / name).string(); }
};

Image makeImage(int w, int h, bool unitRange) {
    Image img(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            if (unitRange) img.set(x, y, Vec3(float(x) / float(w), float(y) / float(h), float((x * 7 + y * 3) % 11) / 10.0f));
            else img.set(x, y, Vec3(std::sin(float(x * 13 + y)) * 1e3f, 1e-30f * float(x + 1) - float(y), 3.0e20f / float(1 + x * y)));
        }
    return img;
}

std::string readBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}
void writeBytes(const std::string& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(bytes.data(), std::streamsize(bytes.size()));
}

// The message of the InputError readImage(path) throws ("" when it does not throw).
std::string readError(const std::string& path) {
    try {
        readImage(path);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

void appendBE32(std::string& s, uint32_t v) {
    for (int i = 3; i >= 0; --i) s += char((v >> (8 * i)) & 0xff);
}
void appendFloat(std::string& s, float f, bool bigEndian) {
    unsigned char b[4];
    std::memcpy(b, &f, 4);  // host (x86-64) is little-endian
    if (bigEndian) {
        std::swap(b[0], b[3]);
        std::swap(b[1], b[2]);
    }
    s.append(reinterpret_cast<char*>(b), 4);
}

struct Run {
    int status = -1;
    std::string out;
};
Run run(const std::string& args) {
    Run r;
    std::string cmd = std::string(WAVEMMLT_IMG_BIN) + " " + args + " 2>&1";
    FILE* p = popen(cmd.c_str(), "r");
    REQUIRE(p != nullptr);
    char buf[4096];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, p)) > 0) r.out.append(buf, n);
    int st = pclose(p);
    r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
    return r;
}
double valueAfter(const std::string& text, const std::string& key) {
    size_t i = text.find(key);
    REQUIRE(i != std::string::npos);
    return std::strtod(text.c_str() + i + key.size(), nullptr);
}

}  // namespace

TEST_CASE("sRGB transfer functions follow IEC 61966-2-1", "[image]") {
    CHECK(srgbToLinear(0.0f) == 0.0f);
    CHECK(srgbToLinear(1.0f) == Approx(1.0f).epsilon(1e-7));
    CHECK(srgbToLinear(0.5f) == Approx(0.21404114048223255).epsilon(1e-6));
    CHECK(srgbToLinear(128.0f / 255.0f) == Approx(0.21586050011389926).epsilon(1e-6));
    CHECK(srgbToLinear(0.2f) == Approx(0.033104766570885055).epsilon(1e-6));
    CHECK(srgbToLinear(0.04f) == Approx(0.04 / 12.92).epsilon(1e-6));  // linear segment
    CHECK(linearToSrgb(0.18f) == Approx(0.46135612950044164).epsilon(1e-6));
    CHECK(linearToSrgb(0.5f) == Approx(0.7353569830524495).epsilon(1e-6));
    CHECK(linearToSrgb(0.001f) == Approx(0.01292).epsilon(1e-6));
    CHECK(linearToSrgb(1.0f) == Approx(1.0f).epsilon(1e-7));
    for (int i = 0; i <= 1000; ++i) {
        float v = float(i) / 1000.0f;
        CHECK(linearToSrgb(srgbToLinear(v)) == Approx(v).margin(2e-6));
        CHECK(srgbToLinear(linearToSrgb(v)) == Approx(v).margin(2e-6));
    }
    // Monotone across the segment boundary.
    float prev = -1;
    for (int i = 0; i <= 2000; ++i) {
        float l = srgbToLinear(0.03f + 0.02f * float(i) / 2000.0f);
        CHECK(l >= prev);
        prev = l;
    }
}

TEST_CASE("EXR and PFM round trips are bit-exact", "[image]") {
    TempDir dir;
    Image img = makeImage(37, 23, false);
    for (const char* name : {"a.exr", "a.pfm", "b.EXR"}) {
        std::string path = dir.file(name);
        writeImage(path, img);
        Image back = readImage(path);
        REQUIRE(back.width == img.width);
        REQUIRE(back.height == img.height);
        REQUIRE(back.rgb.size() == img.rgb.size());
        CHECK(std::memcmp(back.rgb.data(), img.rgb.data(), img.rgb.size() * sizeof(float)) == 0);
    }
    // No temporary files are left behind.
    for (const auto& e : fs::directory_iterator(dir.path)) CHECK(!contains(e.path().string(), ".tmp-"));
}

TEST_CASE("PNG round trip is within half a code value after sRGB", "[image]") {
    TempDir dir;
    Image img = makeImage(19, 11, true);
    std::string path = dir.file("a.png");
    writeImage(path, img);
    Image back = readImage(path);
    REQUIRE(back.width == 19);
    REQUIRE(back.height == 11);
    for (size_t i = 0; i < img.rgb.size(); ++i) CHECK(linearToSrgb(back.rgb[i]) == Approx(linearToSrgb(img.rgb[i])).margin(0.5 / 255.0 + 1e-6));

    // Exposure +1 doubles before encoding; values above 1 clamp to 255.
    Image small(2, 1);
    small.set(0, 0, Vec3(0.1f, 0.25f, 0.6f));
    small.set(1, 0, Vec3(-1.0f, NAN, 100.0f));
    writeImage(path, small, 1.0f);
    back = readImage(path);
    CHECK(linearToSrgb(back.at(0, 0).x) == Approx(linearToSrgb(0.2f)).margin(0.5 / 255.0 + 1e-6));
    CHECK(linearToSrgb(back.at(0, 0).y) == Approx(linearToSrgb(0.5f)).margin(0.5 / 255.0 + 1e-6));
    CHECK(back.at(0, 0).z == Approx(1.0f).epsilon(1e-6));
    CHECK(back.at(1, 0).x == 0.0f);
    CHECK(back.at(1, 0).y == 0.0f);
    CHECK(back.at(1, 0).z == Approx(1.0f).epsilon(1e-6));
}

TEST_CASE("PNG and JPEG are decoded and linearised, grey becomes RGB", "[image]") {
    TempDir dir;
    // An 8-bit grey+alpha PNG and an RGB one, written directly with stb_image_write.
    unsigned char ga[2 * 2 * 2] = {0, 255, 128, 10, 255, 0, 64, 255};
    REQUIRE(stbi_write_png(dir.file("ga.png").c_str(), 2, 2, 2, ga, 4));
    Image g = readImage(dir.file("ga.png"));
    REQUIRE(g.width == 2);
    CHECK(g.at(0, 0).x == 0.0f);
    CHECK(g.at(1, 0).x == Approx(0.21586050011389926).epsilon(1e-6));
    CHECK(g.at(1, 0).y == g.at(1, 0).x);
    CHECK(g.at(1, 0).z == g.at(1, 0).x);
    CHECK(g.at(0, 1).x == Approx(1.0f).epsilon(1e-6));  // alpha is ignored
    unsigned char rgb[3 * 2] = {255, 0, 51, 0, 10, 255};
    REQUIRE(stbi_write_png(dir.file("c.png").c_str(), 2, 1, 3, rgb, 6));
    Image c = readImage(dir.file("c.png"));
    CHECK(c.at(0, 0).x == Approx(1.0f));
    CHECK(c.at(0, 0).y == 0.0f);
    CHECK(c.at(0, 0).z == Approx(srgbToLinear(0.2f)).epsilon(1e-6));
    CHECK(c.at(1, 0).y == Approx(10.0 / 255.0 / 12.92).epsilon(1e-6));

    // JPEG of a flat colour: decoded close to the colour, linearised.
    std::vector<unsigned char> flat(16 * 16 * 3);
    for (size_t i = 0; i < flat.size(); i += 3) {
        flat[i] = 200;
        flat[i + 1] = 100;
        flat[i + 2] = 50;
    }
    REQUIRE(stbi_write_jpg(dir.file("f.jpg").c_str(), 16, 16, 3, flat.data(), 95));
    Image j = readImage(dir.file("f.jpg"));
    REQUIRE(j.width == 16);
    CHECK(linearToSrgb(j.at(5, 5).x) * 255 == Approx(200).margin(3));
    CHECK(linearToSrgb(j.at(5, 5).y) * 255 == Approx(100).margin(3));
    CHECK(linearToSrgb(j.at(5, 5).z) * 255 == Approx(50).margin(3));
}

TEST_CASE("TGA: plain and run-length, written by stb_image_write, decoded top row first and linearised", "[image]") {
    TempDir dir;
    // stbi_write_tga writes run-length TGA by default; the 2 x 2 image's top row first.
    unsigned char rgb[3 * 4] = {255, 0, 51, 0, 10, 255, 128, 128, 128, 0, 0, 0};
    for (int rle : {1, 0}) {
        stbi_write_tga_with_rle = rle;
        const std::string f = dir.file("c" + std::to_string(rle) + ".tga");
        REQUIRE(stbi_write_tga(f.c_str(), 2, 2, 3, rgb));
        const Image c = readImage(f);
        REQUIRE((c.width == 2 && c.height == 2));
        CHECK(c.at(0, 0).x == Approx(1.0f));
        CHECK(c.at(0, 0).y == 0.0f);
        CHECK(c.at(0, 0).z == Approx(srgbToLinear(0.2f)).epsilon(1e-6));
        CHECK(c.at(1, 0).y == Approx(10.0 / 255.0 / 12.92).epsilon(1e-6));
        CHECK(c.at(0, 1).x == Approx(srgbToLinear(128 / 255.0f)).epsilon(1e-6));
        CHECK(c.at(1, 1).z == 0.0f);
    }
    stbi_write_tga_with_rle = 1;
    // A PNG named .tga is refused (no decoder but the named format's is reached).
    REQUIRE(stbi_write_png(dir.file("p.png").c_str(), 2, 2, 3, rgb, 6));
    fs::copy_file(dir.file("p.png"), dir.file("p.tga"));
    std::string what;
    try {
        readImage(dir.file("p.tga"));
    } catch (const InputError& e) {
        what = e.what();
    }
    CHECK(what.find("not a TGA file") != std::string::npos);
    // A header of 1000 x 1000 pixels over 4 bytes of data: refused before decoding.
    {
        std::ofstream f(dir.file("t.tga"), std::ios::binary);
        const unsigned char h[18] = {0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0xE8, 3, 0xE8, 3, 24, 0};
        f.write(reinterpret_cast<const char*>(h), 18);
        f.write("abcd", 4);
    }
    what.clear();
    try {
        readImage(dir.file("t.tga"));
    } catch (const InputError& e) {
        what = e.what();
    }
    CHECK(what.find("the file holds 22 bytes, fewer than its 1000 x 1000 pixels need (3000018)") != std::string::npos);
}

TEST_CASE("Radiance HDR matches stb_image's float loader", "[image]") {
    TempDir dir;
    for (int w : {5, 40}) {  // < 8 wide: flat scanlines; otherwise run-length encoded
        const int h = 7;
        std::vector<float> px(size_t(w) * h * 3);
        for (size_t i = 0; i < px.size(); ++i) px[i] = (i % 5 == 0) ? 0.0f : std::exp(std::sin(float(i)) * 6.0f);
        for (int x = 0; x < w; ++x) px[3 * x] = px[3 * x + 1] = px[3 * x + 2] = 2.5f;  // runs
        std::string path = dir.file("a" + std::to_string(w) + ".hdr");
        REQUIRE(stbi_write_hdr(path.c_str(), w, h, 3, px.data()));
        Image img = readImage(path);
        int sw, sh, sc;
        float* ref = stbi_loadf(path.c_str(), &sw, &sh, &sc, 3);
        REQUIRE(ref != nullptr);
        REQUIRE(img.width == sw);
        REQUIRE(img.height == sh);
        CHECK(std::memcmp(ref, img.rgb.data(), size_t(sw) * sh * 3 * sizeof(float)) == 0);
        stbi_image_free(ref);
        // RGBE shares one exponent per pixel: the error is below 1/128 of the largest component.
        for (size_t i = 0; i < px.size(); i += 3) {
            const float m = std::max({px[i], px[i + 1], px[i + 2]});
            for (int c = 0; c < 3; ++c) CHECK(std::fabs(img.rgb[i + c] - px[i + c]) <= m / 128.0f);
        }
    }
}

TEST_CASE("EXR: half RGBA and luminance-only files read as float RGB", "[image]") {
    TempDir dir;
    {
        Imf::RgbaOutputFile out(dir.file("half.exr").c_str(), 3, 2, Imf::WRITE_RGBA);
        std::vector<Imf::Rgba> px(6);
        for (int i = 0; i < 6; ++i) px[i] = Imf::Rgba(0.5f * i, 1.0f, -2.0f, 0.5f);
        out.setFrameBuffer(px.data(), 1, 3);
        out.writePixels(2);
    }
    Image h = readImage(dir.file("half.exr"));
    REQUIRE(h.width == 3);
    REQUIRE(h.height == 2);
    CHECK(h.at(2, 1).x == 2.5f);
    CHECK(h.at(2, 1).y == 1.0f);
    CHECK(h.at(2, 1).z == -2.0f);
    {
        Imf::Header hdr(2, 2);
        hdr.channels().insert("Y", Imf::Channel(Imf::FLOAT));
        Imf::OutputFile out(dir.file("y.exr").c_str(), hdr);
        float y[4] = {0.25f, 1.0f, 3.0f, 7.5f};
        Imf::FrameBuffer fb;
        fb.insert("Y", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(y), sizeof(float), 2 * sizeof(float)));
        out.setFrameBuffer(fb);
        out.writePixels(2);
    }
    Image y = readImage(dir.file("y.exr"));
    CHECK(y.at(0, 1).x == 3.0f);
    CHECK(y.at(0, 1).y == 3.0f);
    CHECK(y.at(1, 1).z == 7.5f);
}

TEST_CASE("PFM: either endianness, bottom row first, grey and scale", "[image]") {
    TempDir dir;
    // 2 x 2, big-endian (positive scale); stored rows: bottom (10, 11), then top (20, 21).
    std::string be = "PF\n2 2\n1.0\n";
    for (float v : {10.f, 11.f, 12.f, 13.f, 14.f, 15.f, 20.f, 21.f, 22.f, 23.f, 24.f, 25.f}) appendFloat(be, v, true);
    writeBytes(dir.file("be.pfm"), be);
    Image a = readImage(dir.file("be.pfm"));
    REQUIRE(a.width == 2);
    REQUIRE(a.height == 2);
    CHECK(a.at(0, 0).x == 20.f);  // top-left: the last row stored
    CHECK(a.at(1, 0).z == 25.f);
    CHECK(a.at(0, 1).x == 10.f);
    CHECK(a.at(1, 1).y == 14.f);
    // The same little-endian, scale -1: identical image.
    std::string le = "PF\n2 2\n-1.0\n";
    for (float v : {10.f, 11.f, 12.f, 13.f, 14.f, 15.f, 20.f, 21.f, 22.f, 23.f, 24.f, 25.f}) appendFloat(le, v, false);
    writeBytes(dir.file("le.pfm"), le);
    Image b = readImage(dir.file("le.pfm"));
    CHECK(b.rgb == a.rgb);
    // Grey, 3 x 1, little-endian with |scale| = 2 (multiplies the data, as pbrt reads it).
    std::string g = "Pf 3 1 -2.0\n";
    for (float v : {1.f, 2.f, 3.f}) appendFloat(g, v, false);
    writeBytes(dir.file("g.pfm"), g);
    Image c = readImage(dir.file("g.pfm"));
    REQUIRE(c.width == 3);
    CHECK(c.at(2, 0).x == 6.f);
    CHECK(c.at(2, 0).y == 6.f);
    CHECK(c.at(1, 0).z == 4.f);
    // What writeImage produces: "PF", little-endian, bottom row first.
    Image d(1, 2);
    d.set(0, 0, Vec3(1, 2, 3));
    d.set(0, 1, Vec3(4, 5, 6));
    writeImage(dir.file("d.pfm"), d);
    std::string expect = "PF\n1 2\n-1.0\n";
    for (float v : {4.f, 5.f, 6.f, 1.f, 2.f, 3.f}) appendFloat(expect, v, false);
    CHECK(readBytes(dir.file("d.pfm")) == expect);
}

TEST_CASE("Missing, truncated and corrupt files throw InputError naming the path", "[image]") {
    TempDir dir;
    for (const char* name : {"none.exr", "none.pfm", "none.png", "none.jpg", "none.hdr"}) {
        std::string p = dir.file(name);
        std::string msg = readError(p);
        CHECK(contains(msg, p));
        CHECK(contains(msg, "No such file or directory"));
    }
    CHECK(contains(readError(dir.path.string() + "/x.bmp"), "unknown image extension"));
    fs::create_directories(dir.path / "d.exr");
    CHECK(contains(readError(dir.file("d.exr")), "is a directory"));

    Image img = makeImage(64, 48, true);
    std::vector<float> hdrPx(img.rgb.begin(), img.rgb.end());
    REQUIRE(stbi_write_hdr(dir.file("full.hdr").c_str(), 64, 48, 3, hdrPx.data()));
    for (const char* ext : {".png", ".exr", ".pfm", ".hdr", ".jpg"}) {
        std::string full = dir.file(std::string("full") + ext);
        if (std::string(ext) == ".jpg") {
            std::vector<unsigned char> b(64 * 48 * 3);
            for (size_t i = 0; i < b.size(); ++i) b[i] = (unsigned char)(i * 7);
            REQUIRE(stbi_write_jpg(full.c_str(), 64, 48, 3, b.data(), 90));
        } else if (std::string(ext) != ".hdr") {
            writeImage(full, img);
        }
        std::string bytes = readBytes(full);
        REQUIRE(bytes.size() > 100);
        for (double frac : {0.0, 0.02, 0.3, 0.6, 0.9, 0.98}) {
            std::string p = dir.file(std::string("cut") + ext);
            writeBytes(p, bytes.substr(0, size_t(double(bytes.size()) * frac)));
            INFO(ext << " cut at " << frac);
            std::string msg = readError(p);
            CHECK(contains(msg, p));
        }
        std::string garbage = dir.file(std::string("garbage") + ext);
        writeBytes(garbage, std::string(300, 'x'));
        CHECK(contains(readError(garbage), garbage));
    }
}

TEST_CASE("Empty and absurdly large headers are refused before allocating", "[image]") {
    TempDir dir;
    writeBytes(dir.file("zero.pfm"), "PF\n0 0\n-1.0\n");
    CHECK(contains(readError(dir.file("zero.pfm")), "empty image"));
    writeBytes(dir.file("neg.pfm"), "PF\n-3 2\n-1.0\n");
    CHECK(contains(readError(dir.file("neg.pfm")), "empty image"));
    writeBytes(dir.file("huge.pfm"), "PF\n1000000 1000000\n-1.0\n" + std::string(64, '\0'));
    CHECK(contains(readError(dir.file("huge.pfm")), "too large"));
    writeBytes(dir.file("big.pfm"), "PF\n4000 4000\n-1.0\n" + std::string(64, '\0'));  // plausible size, no data
    CHECK(contains(readError(dir.file("big.pfm")), "truncated"));
    writeBytes(dir.file("huge.hdr"), "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1000000 +X 1000000\n");
    CHECK(contains(readError(dir.file("huge.hdr")), "too large"));
    writeBytes(dir.file("zero.hdr"), "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 0 +X 0\n");
    CHECK(contains(readError(dir.file("zero.hdr")), "empty image"));

    // A PNG whose header claims 1e6 x 1e6 pixels (stb_image itself allows up to 2^24).
    std::string png = "\x89PNG\r\n\x1a\n";
    appendBE32(png, 13);
    png += "IHDR";
    appendBE32(png, 1000000);
    appendBE32(png, 1000000);
    png += std::string("\x08\x02\x00\x00\x00", 5);
    appendBE32(png, 0);  // CRC (not checked)
    writeBytes(dir.file("huge.png"), png);
    std::string msg = readError(dir.file("huge.png"));
    INFO(msg);
    CHECK(contains(msg, dir.file("huge.png")));
    CHECK(contains(msg, "too large"));

    // An EXR whose data window claims 1e6 x 1e6 pixels: a valid 4 x 3 file whose header's
    // dataWindow (box2i: xMin, yMin, xMax, yMax, little-endian int32) is patched.
    {
        const std::string small = dir.file("small.exr"), p = dir.file("huge.exr");
        writeImage(small, makeImage(4, 3, true));
        std::string exr = readBytes(small);
        const std::string attr = std::string("dataWindow") + '\0' + "box2i" + '\0';
        const size_t at = exr.find(attr);
        REQUIRE(at != std::string::npos);
        const size_t box = at + attr.size() + 4;  // after the attribute's size (16)
        REQUIRE(box + 16 <= exr.size());
        for (int i = 0; i < 2; ++i) {  // xMax and yMax = 999999
            const uint32_t v = 999999;
            for (int b = 0; b < 4; ++b) exr[box + 8 + size_t(4 * i + b)] = char((v >> (8 * b)) & 0xff);
        }
        writeBytes(p, exr);
        std::string m = readError(p);
        INFO(m);
        CHECK(contains(m, p));
        CHECK(contains(m, "too large"));
    }
}

TEST_CASE("writeImage: temporary file and rename, errors name the path", "[image]") {
    TempDir dir;
    Image img = makeImage(4, 3, true);
    std::string missing = dir.file("no/such/folder/out.exr");
    for (const char* ext : {".exr", ".pfm", ".png"}) {
        std::string p = dir.file(std::string("no/out") + ext);
        try {
            writeImage(p, img);
            FAIL("writeImage into a missing folder did not throw");
        } catch (const InputError& e) {
            std::string m = e.what();
            CHECK(contains(m, "cannot write " + p));
            CHECK(contains(m, "No such file or directory"));
        }
        CHECK(!fs::exists(dir.path / "no"));
    }
    // The destination is a directory: the rename fails, and the temporary is removed.
    fs::create_directories(dir.path / "taken.exr");
    fs::create_directories(dir.path / "taken.png");
    CHECK_THROWS_AS(writeImage(dir.file("taken.exr"), img), InputError);
    CHECK_THROWS_AS(writeImage(dir.file("taken.png"), img), InputError);
    int files = 0;
    for (const auto& e : fs::directory_iterator(dir.path)) {
        ++files;
        CHECK(!contains(e.path().string(), ".tmp-"));
    }
    CHECK(files == 2);
    // Unknown extension, empty image.
    CHECK_THROWS_WITH(writeImage(dir.file("x.jpg"), img), Catch::Contains("unknown image extension"));
    CHECK_THROWS_AS(writeImage(dir.file("x.exr"), Image()), InputError);
    CHECK(isWritableImageExtension("a/b.PNG"));
    CHECK(isWritableImageExtension("x.exr"));
    CHECK(isWritableImageExtension("x.pfm"));
    CHECK(!isWritableImageExtension("x.hdr"));
    CHECK(!isWritableImageExtension("x.png/y"));
    // Overwriting an existing file replaces it whole.
    writeImage(dir.file("o.pfm"), makeImage(40, 40, false));
    writeImage(dir.file("o.pfm"), img);
    CHECK(readImage(dir.file("o.pfm")).rgb == img.rgb);
}

TEST_CASE("wavemmlt-img diff, convert and info", "[image][tool]") {
    TempDir dir;
    // A = 0; B = 1 in one value and 2 in another: 12 values, squared errors 1 and 4.
    Image a(2, 2), b(2, 2);
    b.set(0, 0, Vec3(1, 0, 0));
    b.set(1, 1, Vec3(0, 0, 2));
    writeImage(dir.file("a.pfm"), a);
    writeImage(dir.file("b.exr"), b);
    Run r = run("diff " + dir.file("a.pfm") + " " + dir.file("b.exr"));
    INFO(r.out);
    CHECK(r.status == 0);
    CHECK(valueAfter(r.out, "rmse") == Approx(std::sqrt(5.0 / 12.0)).epsilon(1e-7));
    CHECK(valueAfter(r.out, "relmse") == Approx((1.0 / 1.01 + 4.0 / 4.01) / 12.0).epsilon(1e-7));
    CHECK(valueAfter(r.out, "mae") == Approx(3.0 / 12.0).epsilon(1e-7));
    CHECK(valueAfter(r.out, "max_abs") == Approx(2.0).epsilon(1e-7));

    r = run("diff " + dir.file("a.pfm") + " " + dir.file("b.exr") + " --json --mask " + dir.file("m.png"));
    CHECK(r.status == 0);
    CHECK(valueAfter(r.out, "\"rmse\":") == Approx(std::sqrt(5.0 / 12.0)).epsilon(1e-7));
    Image m = readImage(dir.file("m.png"));
    REQUIRE(m.width == 2);
    CHECK(m.at(1, 1).x == Approx(1.0f));  // the largest error: white
    CHECK(m.at(0, 1).x == 0.0f);          // equal: black
    CHECK(m.at(0, 0).x > 0.0f);           // smaller error: grey
    CHECK(m.at(0, 0).x < 1.0f);

    // Identical images.
    r = run("diff " + dir.file("b.exr") + " " + dir.file("b.exr"));
    CHECK(r.status == 0);
    CHECK(valueAfter(r.out, "rmse") == 0.0);

    // Size mismatch, missing file, unknown command: exit 2 with a message.
    writeImage(dir.file("c.pfm"), Image(3, 2));
    r = run("diff " + dir.file("a.pfm") + " " + dir.file("c.pfm"));
    CHECK(r.status == 2);
    CHECK(contains(r.out, "size mismatch"));
    r = run("diff " + dir.file("a.pfm") + " " + dir.file("nope.exr"));
    CHECK(r.status == 2);
    CHECK(contains(r.out, dir.file("nope.exr")));
    CHECK(run("frobnicate").status == 2);
    CHECK(run("diff " + dir.file("a.pfm")).status == 2);
    r = run("--help");
    CHECK(r.status == 0);
    CHECK(contains(r.out, "1e-2"));

    // convert with exposure, then info.
    r = run("convert " + dir.file("b.exr") + " " + dir.file("b2.pfm") + " --exposure 1");
    CHECK(r.status == 0);
    Image b2 = readImage(dir.file("b2.pfm"));
    CHECK(b2.at(1, 1).z == 4.0f);
    CHECK(run("convert " + dir.file("b.exr") + " " + dir.file("b.png")).status == 0);
    CHECK(readImage(dir.file("b.png")).at(0, 0).x == Approx(1.0f));
    CHECK(run("convert " + dir.file("b.exr") + " " + dir.file("b.tga")).status == 2);

    Image n(2, 1);
    n.set(0, 0, Vec3(NAN, 1, INFINITY));
    n.set(1, 0, Vec3(3, -1, 2));
    writeImage(dir.file("n.exr"), n);
    r = run("info " + dir.file("n.exr"));
    INFO(r.out);
    CHECK(r.status == 0);
    CHECK(contains(r.out, "2 x 1"));
    CHECK(valueAfter(r.out, "nan") == 1);
    CHECK(valueAfter(r.out, "inf") == 1);
    r = run("info " + dir.file("n.exr") + " --json");
    CHECK(contains(r.out, "\"G\": {\"min\": -1, \"max\": 1, \"mean\": 0}"));
}
