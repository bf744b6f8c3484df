// Spectra in scene files (scene/spectrum.h): the CIE projection onto linear sRGB against
// closed forms and against Mitsuba 3's own projection of gold, and the Mitsuba importer's
// <spectrum> (pairs, .spd files, constants) with the weighting Mitsuba 3's RGB variants use
// for each parameter, and its bad input.
#include <catch2/catch.hpp>

#include <fstream>
#include <string>

#include "scene/spectrum.h"
#include "wavemmlt/error.h"
#include "wavemmlt/scene_desc.h"

using namespace wmlt;

namespace {

const std::string kSpds = std::string(WAVEMMLT_TEST_DATA) + "/scenes/pbrt-v4/cornell-box/spds/";

SampledSpectrum spd(const std::string& name) {
    SampledSpectrum s;
    const std::string why = readSpectrumFile(kSpds + name, s);
    REQUIRE(why.empty());
    return s;
}

SceneDesc load(const std::string& body) {
    return loadMitsubaFromString(R"(<scene version="3.0.0">
  <sensor type="perspective"><film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film></sensor>
  <emitter type="point"><point name="position" x="0" y="5" z="0"/></emitter>
  )" + body + "\n</scene>\n",
                                 "t.xml", kSpds);
}
std::string errorOf(const std::string& body) {
    try {
        load(body);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}
void checkRgb(Vec3 got, Vec3 want, float rel) {
    CHECK(got.x == Approx(want.x).epsilon(rel));
    CHECK(got.y == Approx(want.y).epsilon(rel));
    CHECK(got.z == Approx(want.z).epsilon(rel));
}

}  // namespace

TEST_CASE("spectrum: projection onto sRGB", "[spectrum]") {
    const SampledSpectrum one{{360, 830}, {1, 1}};
    // A perfect reflector under D65 is sRGB white: D65 is sRGB's white point (to the 4
    // digits of the matrix and the 5 nm tables).
    checkRgb(spectrumToRgb(one, true), Vec3(1.0f), 2e-4);
    // Against E (an emitter, an index): XYZ = (int x-bar, int y-bar, int z-bar) / int y-bar,
    // the three integrals equal by the CIE's definition, so sRGB of XYZ (1, 1, 1).
    checkRgb(spectrumToRgb(one, false), xyzToLinearSrgb(Vec3(1.0f)), 2e-3);
    checkRgb(xyzToLinearSrgb(Vec3(1.0f)), Vec3(1.2049f, 0.9483f, 0.9086f), 1e-3);
    // Linear in the values; a constant c under D65 is c white.
    const SampledSpectrum c{{300, 900}, {0.37, 0.37}};
    checkRgb(spectrumToRgb(c, true), Vec3(0.37f), 2e-4);
    // A narrow triangle at 600 nm (width 2 nm): XYZ proportional to the matching functions there.
    const SampledSpectrum line{{599, 600, 601}, {0, 1, 0}};
    const Vec3 rgb = spectrumToRgb(line, false);
    const Vec3 xyz = cieXyz(600);
    const Vec3 want = xyzToLinearSrgb(xyz);
    const float s = rgb.y / want.y;
    CHECK(rgb.x == Approx(want.x * s).epsilon(0.02));
    CHECK(rgb.z == Approx(std::max(want.z * s, 0.0f)).margin(1e-6));  // clamped where negative
    // Zero outside the pairs: a spectrum that ends at 400 nm has nothing at 550 nm.
    const SampledSpectrum blue{{360, 400}, {1, 1}};
    CHECK(spectrumToRgb(blue, false).y < 0.01f);
    // The tables: y-bar peaks at 555 nm (1.0), D65 is 100 at 560 in CIE's scale (1 here).
    CHECK(cieXyz(555).y == Approx(1.0f));
    CHECK(cieD65(560) == Approx(1.0));
    CHECK(cieXyz(200).y == 0.0f);
}

TEST_CASE("spectrum: gold projected as Mitsuba 3 projects its named conductors", "[spectrum]") {
    // Mitsuba 3's RGB variants turn material="Au" into eta and k by the projection against E
    // (ior_from_file: no D65). wavemmlt's table holds Mitsuba's results; the same projection
    // of pbrt's gold data (the same measurements, sampled a little differently) agrees to a
    // few parts in a thousand -- and differs from the D65 projection by 40% in red.
    const Vec3 eta = spectrumToRgb(spd("Au.eta.spd"), false), k = spectrumToRgb(spd("Au.k.spd"), false);
    checkRgb(eta, Vec3(0.1431189557f, 0.3749570432f, 1.4424785571f), 3e-3);
    checkRgb(k, Vec3(3.9831604247f, 2.3857207478f, 1.6032152899f), 3e-4);
    CHECK(spectrumToRgb(spd("Au.eta.spd"), true).x < 0.6f * eta.x);
}

TEST_CASE("spectrum: .spd files and pairs, bad input", "[spectrum][bad-input]") {
    SampledSpectrum s;
    CHECK(parseSpectrumPairs("400:0.5, 500:0.25 600:1", s).empty());
    CHECK(s.lambda.size() == 3);
    CHECK(s.value[1] == 0.25);
    CHECK(parseSpectrumPairs("500:0.5, 400:0.25", s) == "the wavelengths must increase");
    CHECK(parseSpectrumPairs("400:0.5", s) == "a spectrum needs at least two wavelength-value pairs");
    CHECK(parseSpectrumPairs("400:0.5, 500", s) == "\"500\" is not a wavelength:value pair");
    CHECK(parseSpectrumPairs("400:x, 500:1", s) == "\"400:x\" is not a wavelength:value pair");
    const std::string bad = "/tmp/wmlt-test-bad.spd";
    std::ofstream(bad) << "# gold\n400 1\n\n450 2 3\n";
    CHECK(readSpectrumFile(bad, s) == "line 4: expected a wavelength and a value");
    std::ofstream(bad) << "400 1\n450 two\n";
    CHECK(readSpectrumFile(bad, s) == "line 2: expected a wavelength and a value");
    CHECK(readSpectrumFile("/nonexistent.spd", s) == "cannot open the spectrum file");
}

TEST_CASE("Mitsuba: <spectrum> parameters", "[spectrum][mitsuba][import]") {
    {  // a reflectance's pairs under D65; a constant as itself
        const SceneDesc d = load(R"(<shape type="cube"><bsdf type="diffuse"><spectrum name="reflectance" value="360:0.5, 830:0.5"/></bsdf></shape>
  <shape type="sphere"><bsdf type="diffuse"><spectrum name="reflectance" value="0.25"/></bsdf></shape>)");
        checkRgb(d.materials[size_t(d.shapes[0].material)].diffuse, Vec3(0.5f), 2e-4);
        CHECK(d.materials[size_t(d.shapes[1].material)].diffuse.y == 0.25f);
        CHECK(d.warnings.empty());
    }
    {  // eta and k from .spd files: under D65 (Mitsuba's texture path), not like material="Au"
        const SceneDesc d = load(
            R"(<shape type="cube"><bsdf type="conductor"><spectrum name="eta" filename="Au.eta.spd"/><spectrum name="k" filename="Au.k.spd"/></bsdf></shape>
  <shape type="sphere"><bsdf type="conductor"><string name="material" value="Au"/></bsdf></shape>)");
        const MaterialDesc& m = d.materials[size_t(d.shapes[0].material)];
        checkRgb(m.conductorEta, spectrumToRgb(spd("Au.eta.spd"), true), 1e-6);
        checkRgb(m.conductorK, spectrumToRgb(spd("Au.k.spd"), true), 1e-6);
        CHECK(d.materials[size_t(d.shapes[1].material)].conductorEta.x == 0.1431189557f);
        CHECK(d.warnings.empty());  // unbounded: k > 1 is no gamut problem
    }
    {  // an emitter: pairs against E, a constant as E white (purple-ish in sRGB)
        const SceneDesc d = load(R"(<emitter type="point"><spectrum name="intensity" value="3"/></emitter>
  <emitter type="directional"><spectrum name="irradiance" value="360:2, 830:2"/></emitter>)");
        checkRgb(d.lights[1].radiance, 3.0f * xyzToLinearSrgb(Vec3(1.0f)), 1e-6);
        checkRgb(d.lights[2].radiance, 2.0f * xyzToLinearSrgb(Vec3(1.0f)), 2e-3);
    }
    {   // kept for spectral renders, which the file's spectra choose (Mitsuba's scalar_spectral):
        // a reflectance's pairs as given; an emitter's with luminance 1, its RGB carrying it;
        // a constant reflectance not (its RGB's spectrum is the constant); a blackbody as Planck's
        // law per nm (its normalised curve times its peak)
        const SceneDesc d = load(R"(<shape type="cube"><bsdf type="diffuse"><spectrum name="reflectance" value="400:0.2, 700:0.6"/></bsdf></shape>
  <shape type="sphere"><bsdf type="diffuse"><spectrum name="reflectance" value="0.25"/></bsdf></shape>
  <emitter type="directional"><spectrum name="irradiance" value="400:2, 700:2"/></emitter>
  <emitter type="point"><spectrum name="intensity" type="blackbody"><float name="temperature" value="3000"/></spectrum></emitter>)");
        CHECK(d.settings.spectral);
        const MaterialDesc& m = d.materials[size_t(d.shapes[0].material)];
        REQUIRE(m.spectra[MaterialParam::Diffuse] >= 0);
        const SpectrumDesc& r = d.spectra[size_t(m.spectra[MaterialParam::Diffuse])];
        CHECK(r.lambda == std::vector<float>{400, 700});
        CHECK(r.value == std::vector<float>{0.2f, 0.6f});
        CHECK(r.scale == 1.0f);
        CHECK(d.materials[size_t(d.shapes[1].material)].spectra[MaterialParam::Diffuse] == -1);
        REQUIRE(d.lights[1].spectrum >= 0);
        const SpectrumDesc& e = d.spectra[size_t(d.lights[1].spectrum)];
        CHECK(e.scale * luminance(d.lights[1].radiance) == Approx(1.0f).epsilon(1e-6));
        REQUIRE(d.lights[2].spectrum >= 0);
        const SpectrumDesc& bb = d.spectra[size_t(d.lights[2].spectrum)];
        CHECK(bb.kind == SpectrumDesc::Kind::Blackbody);
        CHECK(bb.kelvin == 3000.0f);
        // its peak radiance (Wien: 966 nm, beyond the visible): 2 h c^2 / l^5 / (exp(h c / (l k T)) - 1), per nm
        const double l = 2.8977721e-3 / 3000, peak = 1e-9 * 2 * 6.62606957e-34 * 299792458.0 * 299792458.0 / std::pow(l, 5) /
                                                     (std::exp(6.62606957e-34 * 299792458.0 / (l * 1.3806488e-23 * 3000)) - 1);
        CHECK(double(bb.scale) * double(luminance(d.lights[2].radiance)) == Approx(peak).epsilon(1e-5));
        // RGB colours alone: an RGB render
        CHECK_FALSE(
            load(R"(<shape type="cube"><bsdf type="diffuse"><rgb name="reflectance" value="0.2, 0.4, 0.6"/></bsdf></shape>)").settings.spectral);
        CHECK(errorOf(
                  R"(<emitter type="point"><spectrum name="intensity" type="blackbody"><float name="kelvin" value="3000"/></spectrum></emitter>)") ==
              "t.xml:4: <float name=\"kelvin\">: a blackbody spectrum takes one <float name=\"temperature\"> (kelvin)");
    }
    {  // a reflectance out of gamut: clamped to [0, 1], with a warning naming the line
        const SceneDesc d = load(R"(<shape type="cube"><bsdf type="diffuse"><spectrum name="reflectance" value="600:2, 700:2"/></bsdf></shape>)");
        const Vec3 r = d.materials[size_t(d.shapes[0].material)].diffuse;
        CHECK(r.x == 1.0f);
        CHECK(r.z == 0.0f);
        REQUIRE(d.warnings.size() == 1);
        CHECK(d.warnings[0].find("t.xml:4") != std::string::npos);
        CHECK(d.warnings[0].find("outside sRGB's gamut") != std::string::npos);
    }
    CHECK(errorOf(R"(<shape type="cube"><bsdf type="diffuse"><spectrum name="reflectance" value="500:1, 400:1"/></bsdf></shape>)") ==
          "t.xml:4: <spectrum name=\"reflectance\">: the wavelengths must increase");
    CHECK(errorOf(R"(<shape type="cube"><bsdf type="diffuse"><spectrum name="reflectance" filename="none.spd"/></bsdf></shape>)")
              .find("none.spd: cannot open the spectrum file") != std::string::npos);
    CHECK(errorOf(R"(<shape type="cube"><bsdf type="diffuse"><spectrum name="reflectance" value="1" filename="Au.k.spd"/></bsdf></shape>)") ==
          "t.xml:4: <spectrum name=\"reflectance\">: a spectrum needs either value or filename");
    CHECK(errorOf(R"(<shape type="cube"><bsdf type="diffuse"><spectrum name="reflectance" value="1 2"/></bsdf></shape>)") ==
          "t.xml:4: <spectrum name=\"reflectance\">: a spectrum's value is one number or wavelength:value pairs");
}
