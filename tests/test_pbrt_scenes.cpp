// pbrt-v4 scenes against pbrt-v4's own renders of the same files (tests/data/scenes/pbrt-v4,
// README): wavemmlt's PT at the reference's size, K runs, 16 x 16 block means of each channel.
// Per block the difference must be within 5 standard deviations of the two estimates' noise
// (ours from the spread of K = 8 runs -- fewer underestimate the heavy-tailed noise of the
// glass sphere's caustic; pbrt's 1024 spp from ours scaled by spp / 1024, the same estimator) plus a stated spectral allowance: pbrt-v4 renders spectrally, wavemmlt in RGB, so
// an allowance of 1% of the image mean per block: RGB reflectances under white light, and
// metals given as spectra (eta, k projected onto RGB with the albedo made the spectral one,
// conductorAlbedoScale: without it gold's highlights miss by 4% in red). Also the image means
// to that allowance, and the same scene with pbrt's maxdepth counted one off fails.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>

#include "render_stats.h"
#include "wavemmlt/image.h"
#include "wavemmlt/render.h"
#include "wavemmlt/scene_desc.h"

using namespace wmlt;

namespace {

const std::string kDir = std::string(WAVEMMLT_TEST_DATA) + "/scenes/pbrt-v4/";

struct Match {
    double worstExcess = 0;  // max over blocks of (|d| - allowance) / sigma
    double meanRatio[3] = {0, 0, 0};
    double meanSigma[3] = {0, 0, 0};  // of meanRatio: the blocks' sigmas combined
    std::string worst;
};

// PT of `d` (its own size and maxdepth) at spp x K runs against the reference image.
Match compare(const SceneDesc& d, const std::string& reference, int spp, int K, double allowance, bool spectral = false) {
    const Image ref = readImage(kDir + reference);
    REQUIRE(ref.width == d.settings.width);
    REQUIRE(ref.height == d.settings.height);
    const int B = 16;
    rstats::RunStats runs[3];
    for (int k = 0; k < K; ++k) {
        RenderOptions opt = rstats::renderOptions(TracerKind::PT, spp, 11 + uint64_t(k), 1, d.settings.maxPathLength);
        opt.spectral = spectral;
        const RenderResult r = render(d, opt);
        REQUIRE(r.stats.spectral == spectral);
        const Image& im = r.image;
        for (int c = 0; c < 3; ++c) runs[c].add(rstats::blockMeans(im, B, c));
    }
    Match m;
    double refMean[3] = {0, 0, 0}, ourMean[3] = {0, 0, 0};
    for (int c = 0; c < 3; ++c) {
        const std::vector<double> r = rstats::blockMeans(ref, B, c);
        for (size_t i = 0; i < r.size(); ++i) {
            refMean[c] += r[i] / double(r.size());
            ourMean[c] += runs[c].mean(i) / double(r.size());
        }
    }
    const double mean = (refMean[0] + refMean[1] + refMean[2]) / 3;
    for (int c = 0; c < 3; ++c) {
        m.meanRatio[c] = ourMean[c] / refMean[c];
        const std::vector<double> r = rstats::blockMeans(ref, B, c);
        for (size_t i = 0; i < r.size(); ++i) {
            const double varOurs = runs[c].variance(i);  // one run of spp
            const double sigma = std::sqrt(varOurs / K + varOurs * spp / 1024.0);
            m.meanSigma[c] += sigma * sigma / (double(r.size()) * double(r.size()) * refMean[c] * refMean[c]);
            const double excess = (std::fabs(runs[c].mean(i) - r[i]) - allowance * mean) / std::max(sigma, 1e-12);
            if (excess > m.worstExcess) {
                m.worstExcess = excess;
                m.worst = "block " + std::to_string(i) + " channel " + std::to_string(c) + ": ours " + std::to_string(runs[c].mean(i)) + " pbrt " +
                          std::to_string(r[i]) + " sigma " + std::to_string(sigma);
            }
        }
    }
    return m;
}

// The file at the reference's size (as the references were made: the film's resolution set).
SceneDesc atSize(const std::string& file, int w, int h) {
    SceneDesc d = loadScene(kDir + file);
    d.settings.width = w;
    d.settings.height = h;
    return d;
}

void check(const std::string& file, const std::string& reference, double allowance, int w = 256, int h = 256, int spp = 32, int K = 8,
           bool spectral = false) {
    const SceneDesc d = atSize(file, w, h);
    const Match m = compare(d, reference, spp, K, allowance, spectral);
    INFO(file << ": worst " << m.worst << ", mean ratios " << m.meanRatio[0] << " " << m.meanRatio[1] << " " << m.meanRatio[2]);
    CHECK(m.worstExcess <= 5.0);
    // the means: within the allowance, or with none (spectral) within 5 sigma of their noise
    for (int c = 0; c < 3; ++c) CHECK(std::fabs(m.meanRatio[c] - 1) <= (allowance > 0 ? allowance : 5 * std::sqrt(m.meanSigma[c])));
}

}  // namespace

TEST_CASE("pbrt-v4 scenes: the Cornell boxes render what pbrt-v4 renders", "[pbrt][reference][render][stat]") {
    check("cornell-box/cornell-box.pbrt", "cornell-box/reference/pbrt-cornell-box-256x256-1024spp.exr", 0.01);
    check("cornell-box/smallpt.pbrt", "cornell-box/reference/pbrt-smallpt-256x256-1024spp.exr", 0.01);
    check("cornell-box/cornell-box-specular.pbrt", "cornell-box/reference/pbrt-cornell-box-specular-256x256-1024spp.exr", 0.01);
    check("cornell-box/cornell-box-silver.pbrt", "cornell-box/reference/pbrt-cornell-box-silver-256x256-1024spp.exr", 0.01);
}

TEST_CASE("pbrt-v4 scenes: spectral PT renders what pbrt-v4 renders, with no allowance for RGB against spectral",
          "[pbrt][reference][render][stat][spectral]") {
    // --spectral (docs/spectral.md): the RGB colours uplifted as pbrt-v4 does, the film in XYZ;
    // per block and for the means within 5 sigma of both renders' noise and nothing more.
    // (smallpt's silver is pbrt's named metal, which wavemmlt has as RGB only: a block of it
    // misses by 8.5 sigma.)
    check("cornell-box/cornell-box.pbrt", "cornell-box/reference/pbrt-cornell-box-256x256-1024spp.exr", 0.0, 256, 256, 32, 8, true);
    // The gold killeroo (gold's .spd files, an image texture, a distant light): with K = 8 its
    // worst block was 6 sigma, the sigma of 8 runs too small for the gold's highlights.
    check("killeroos/killeroo-gold.pbrt", "killeroos/reference/pbrt-killeroo-gold-256x192-1024spp.exr", 0.0, 256, 192, 32, 16, true);
    check("veach-mis/veach-mis.pbrt", "veach-mis/reference/pbrt-veach-mis-288x216-1024spp.exr", 0.0, 288, 216, 32, 16, true);
}

TEST_CASE("pbrt-v4 scenes: fog under pbrt's path integrator renders as pbrt renders it (without the fog)", "[pbrt][reference][render][stat][media]") {
    // pbrt-v4's "path" integrator ignores media, and so does the importer (with fog the image
    // would be 2.4 times darker). The light is a saturated orange (rgb L 108 76 24): in RGB
    // its products with the coloured walls miss pbrt's spectral ones (the red wall's red 24%
    // below pbrt's); spectral (the file's default), block by block with no allowance.
    const SceneDesc d = atSize("cornell-box/cornell-box-volume.pbrt", 256, 256);
    REQUIRE(d.media.empty());
    REQUIRE(d.settings.spectral);
    check("cornell-box/cornell-box-volume.pbrt", "cornell-box/reference/pbrt-cornell-box-volume-256x256-1024spp.exr", 0.0, 256, 256, 32, 8, true);
}

TEST_CASE("pbrt-v4 scenes: the gold killeroo (loopsubdiv, .spd metal, imagemap, distant light) renders what pbrt-v4 renders",
          "[pbrt][reference][render][stat]") {
    check("killeroos/killeroo-gold.pbrt", "killeroos/reference/pbrt-killeroo-gold-256x192-1024spp.exr", 0.01, 256, 192);
}

TEST_CASE("pbrt-v4 scenes: the coated gold killeroo differs from pbrt-v4's render by pbrt's coat weighting alone",
          "[pbrt][reference][render][stat]") {
    // pbrt-v4's LayeredBxDF weighs a direction sampled inside the slab against next-event
    // estimation through the exit with the wrong density (kernels/bsdf_coated.cpp), which
    // makes its f integrate above its own walk's albedo (test_bsdf_coated.cpp). With that
    // weighting planted back, this coated conductor (gold's .spd files under the coat)
    // renders spectrally what pbrt-v4 renders (blocks and means within 5 sigma, no allowance);
    // with wavemmlt's, the highlights are 4-8% darker than pbrt's: the difference docs/pbrt.md
    // once put down to RGB against spectral.
    SceneDesc d = atSize("killeroos/killeroo-coated-gold.pbrt", 256, 192);
    int coated = 0;
    for (MaterialDesc& m : d.materials)
        if (m.kind == MaterialKind::Coated) {
            m.coating.pbrtExitWeight = true;
            ++coated;
        }
    REQUIRE(coated == 1);
    const Match pbrtWeights = compare(d, "killeroos/reference/pbrt-killeroo-coated-gold-256x192-1024spp.exr", 16, 16, 0.0, true);
    INFO("pbrt's weighting: worst " << pbrtWeights.worst << ", mean ratios " << pbrtWeights.meanRatio[0] << " " << pbrtWeights.meanRatio[1] << " "
                                    << pbrtWeights.meanRatio[2]);
    CHECK(pbrtWeights.worstExcess <= 5.0);
    for (int c = 0; c < 3; ++c) CHECK(std::fabs(pbrtWeights.meanRatio[c] - 1) <= 5 * std::sqrt(pbrtWeights.meanSigma[c]));
    for (MaterialDesc& m : d.materials) m.coating.pbrtExitWeight = false;
    const Match ours = compare(d, "killeroos/reference/pbrt-killeroo-coated-gold-256x192-1024spp.exr", 16, 16, 0.0, true);
    INFO("wavemmlt's weighting: worst " << ours.worst);
    CHECK(ours.worstExcess > 5.0);
}

TEST_CASE("pbrt-v4 scenes: maxdepth counts bounces as pbrt-v4 does", "[pbrt][reference][render][stat]") {
    // The Cornell box's maxdepth 5 is 6 segments, camera to light; counted one off either
    // way (5 or 7), the comparison above fails.
    SceneDesc d = atSize("cornell-box/cornell-box.pbrt", 256, 256);
    CHECK(d.settings.maxPathLength == 6);
    for (int off : {-1, 1}) {
        d.settings.maxPathLength = 6 + off;
        const Match m = compare(d, "cornell-box/reference/pbrt-cornell-box-256x256-1024spp.exr", 32, 8, 0.01);
        INFO("maxPathLength " << d.settings.maxPathLength << ": worst " << m.worst << ", mean ratio " << m.meanRatio[1]);
        CHECK(m.worstExcess > 5.0);
    }
}
