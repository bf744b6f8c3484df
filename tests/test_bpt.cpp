// Bidirectional path tracing (--tracer bpt), with tolerances from the measured variance
// over K independent seeds (render_stats.h), never hand-tuned:
//  1. the MIS weights of kernels/mis.h: a partition of unity over the strategies that can
//     sample a path, equal to the weights computed from products of densities, and 0 for
//     strategies that would connect at a delta vertex;
//  2. BPT image = PT image (8 x 8 block means, se of both tracers' runs) on the Cornell box
//     and on a glossy floor with a glass sphere (caustic) and a mirror sphere;
//  3. BPT's mean luminance by path length = PT's, within their standard errors;
//  4. no NaN or Inf with very bright and very dim lights and MaxPathLength 64;
//  5. an environment map (a light at infinity), a thin lens, the balance heuristic,
//     MinPathLength > 1, and bit-identical images for 1 and 2 threads.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "kernels/mis.h"
#include "render_stats.h"
#include "wavemmlt/image.h"
#include "wavemmlt/render.h"
#include "wavemmlt/scene_desc.h"

using namespace wmlt;

namespace {

// BPT against PT: K runs of each; per channel the 8 x 8 block means.
void compareWithPt(const SceneDesc& desc, int spp, int K, int maxLength, uint64_t seed0, float misBeta = 2, int minLength = 1) {
    const int B = 8;
    rstats::RunStats pt[3], bpt[3];
    for (int k = 0; k < K; ++k) {
        RenderResult a = render(desc, rstats::renderOptions(TracerKind::PT, spp, seed0 + k, minLength, maxLength));
        RenderOptions ob = rstats::renderOptions(TracerKind::BPT, spp, seed0 + 500 + k, minLength, maxLength);
        ob.misBeta = misBeta;
        RenderResult b = render(desc, ob);
        REQUIRE(b.stats.tracer == "bpt");
        REQUIRE(b.stats.spp == uint64_t(spp));
        REQUIRE(b.stats.samplesNonfiniteDiscarded == 0);
        for (int c = 0; c < 3; ++c) {
            pt[c].add(rstats::blockMeans(a.image, B, c));
            bpt[c].add(rstats::blockMeans(b.image, B, c));
        }
    }
    for (int c = 0; c < 3; ++c) {
        double ratio = 0;
        rstats::ZTestResult z = rstats::compareRuns(bpt[c], pt[c], 1e-4 / 3, &ratio);
        INFO("channel " << c << ": BPT / PT image mean = " << ratio << "; " << z.describe());
        CHECK(z.pass);
    }
}

}  // namespace

// ---- 1. MIS weights ---------------------------------------------------------------------

TEST_CASE("BPT MIS: weights are a partition of unity, 0 at delta connections", "[bpt][mis]") {
    std::mt19937 rng(12345);
    std::uniform_real_distribution<float> logPdf(-6.0f, 6.0f);
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    int pathsWithDelta = 0, pathsChecked = 0;
    for (int k = 1; k <= 12; ++k)
        for (int trial = 0; trial < 200; ++trial) {
            float pL[16], pE[16];
            uint8_t delta[16] = {};
            for (int i = 0; i <= k; ++i) {
                pL[i] = std::exp(logPdf(rng));
                pE[i] = std::exp(logPdf(rng));
            }
            const float pL0Nee = std::exp(logPdf(rng));
            const bool inf = trial % 3 == 0;  // x_0 on the environment: no s = 1, t = 1
            for (int i = 1; i < k; ++i) delta[i] = u01(rng) < 0.25f;
            // Delta vertices: the densities of sampling through them are 0.
            for (int i = 1; i < k; ++i)
                if (delta[i]) {
                    pL[i + 1] = 0.0f;
                    pE[i - 1] = 0.0f;
                }
            bool anyDelta = false, anyValid = false;
            for (int i = 0; i <= k; ++i) anyDelta |= delta[i] != 0;
            for (int s = 0; s <= k; ++s) anyValid |= bptStrategyValid(k, s, delta, inf);
            pathsWithDelta += anyDelta;
            ++pathsChecked;
            // Reference: p_s from products of the (remapped) densities, in double.
            std::vector<double> p(size_t(k) + 1);
            auto remap = [](float x) { return x > 0 ? double(x) : 1.0; };
            for (int s = 0; s <= k; ++s) {
                double prod = 1;
                for (int i = 0; i < s; ++i) prod *= i == 0 ? remap(s == 1 ? pL0Nee : pL[0]) : remap(pL[i]);
                for (int i = s; i < k; ++i) prod *= remap(pE[i]);
                p[s] = prod;
            }
            for (float beta : {1.0f, 2.0f}) {
                double sum = 0, refSum = 0;
                for (int s = 0; s <= k; ++s)
                    if (bptStrategyValid(k, s, delta, inf)) refSum += std::pow(p[s], beta);
                for (int s = 0; s <= k; ++s) {
                    float w = bptMisWeight(k, s, pL, pE, delta, pL0Nee, beta, inf);
                    INFO("k = " << k << ", s = " << s << ", beta = " << beta);
                    REQUIRE(std::isfinite(w));
                    REQUIRE(w >= 0.0f);
                    const bool connectsAtDelta = s > 0 && (delta[s - 1] || delta[s]);
                    if (connectsAtDelta || (inf && k == 1 && s == 1)) REQUIRE(w == 0.0f);
                    if (bptStrategyValid(k, s, delta, inf)) REQUIRE(w == Approx(std::pow(p[s], beta) / refSum).epsilon(1e-4).margin(1e-6));
                    sum += w;
                }
                INFO("k = " << k << ", beta = " << beta);
                REQUIRE(std::fabs(sum - (anyValid ? 1.0 : 0.0)) < 1e-5);
            }
        }
    CHECK(pathsWithDelta > pathsChecked / 4);
}

TEST_CASE("BPT MIS: the weight from partial sums cached per subpath vertex equals bptMisWeight", "[bpt][mis]") {
    // Random paths as above, plus point lights; each strategy's weight from the sums a
    // subpath walk caches (T_i on the camera side, L(m) on the light side) and the
    // densities around its connection, against the direct walk over all ratios.
    std::mt19937 rng(777);
    std::uniform_real_distribution<float> logPdf(-6.0f, 6.0f);
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    int compared = 0;
    for (int k = 1; k <= 20; ++k)
        for (int trial = 0; trial < 200; ++trial) {
            float pL[24], pE[24];
            uint8_t delta[24] = {};
            for (int i = 0; i <= k; ++i) {
                pL[i] = u01(rng) < 0.05f ? 0.0f : std::exp(logPdf(rng));
                pE[i] = u01(rng) < 0.05f ? 0.0f : std::exp(logPdf(rng));
            }
            const bool inf = trial % 4 == 0, x0Delta = trial % 4 == 1;
            const float pL0Nee = x0Delta ? pL[0] : std::exp(logPdf(rng));
            for (int i = 1; i < k; ++i) delta[i] = u01(rng) < 0.2f;
            for (float beta : {1.0f, 2.0f}) {
                double T[24], L[24];  // T[i]: camera vertex z_i = x_{k-i}; L[m]: light vertex y_m = x_m
                T[0] = 0;
                for (int i = 1; i <= k; ++i) T[i] = bptSubpathMisSum(T[i - 1], pL[k - i], pE[k - i], delta[k - i], delta[k - i + 1], beta);
                L[0] = bptLightMisSum0(pE[0], pL0Nee, x0Delta, beta);
                if (k >= 1) L[1] = bptLightMisSum1(L[0], pL[0], pL0Nee, pL[1], pE[1], delta[1], beta);
                for (int m = 2; m <= k; ++m) L[m] = bptSubpathMisSum(L[m - 1], pE[m], pL[m], delta[m], delta[m - 1], beta);
                for (int s = 0; s <= k; ++s) {
                    const int t = k + 1 - s;
                    // The connection's ends are not deltas (bptStrategyValid checks that).
                    const float ref = bptMisWeight(k, s, pL, pE, delta, pL0Nee, beta, inf, x0Delta);
                    const float w =
                        bptMisWeightCached(k, s, pL, pE, delta, pL0Nee, beta, inf, x0Delta, t >= 3 ? T[t - 3] : 0.0, s >= 3 ? L[s - 3] : 0.0);
                    INFO("k = " << k << ", s = " << s << ", beta = " << beta << ", trial " << trial);
                    REQUIRE(std::isfinite(w));
                    REQUIRE(w == Approx(ref).epsilon(1e-5).margin(1e-7));
                    ++compared;
                }
            }
        }
    CHECK(compared > 40000);
}

TEST_CASE("BPT MIS: a mirror vertex leaves only the strategies that avoid it", "[bpt][mis]") {
    // x_0 light, x_1 diffuse, x_2 mirror, x_3 camera (k = 3): s = 2 (connect x_1-x_2) and
    // s = 3 (connect x_2-x_3) are impossible; s = 0 and s = 1 share the path.
    float pL[4] = {0.5f, 0.2f, 0.0f, 1.0f}, pE[4] = {0.3f, 0.0f, 0.7f, 1.0f};
    uint8_t delta[4] = {0, 0, 1, 0};
    for (float beta : {1.0f, 2.0f}) {
        CHECK(bptMisWeight(3, 2, pL, pE, delta, 0.4f, beta) == 0.0f);
        CHECK(bptMisWeight(3, 3, pL, pE, delta, 0.4f, beta) == 0.0f);
        float w0 = bptMisWeight(3, 0, pL, pE, delta, 0.4f, beta), w1 = bptMisWeight(3, 1, pL, pE, delta, 0.4f, beta);
        CHECK(w0 + w1 == Approx(1.0f).epsilon(1e-6));
        // p_1 / p_0 = pL0Nee / pE[0] = 0.4 / 0.3.
        CHECK(w1 / w0 == Approx(std::pow(0.4 / 0.3, beta)).epsilon(1e-5));
    }
}

TEST_CASE("BPT MIS: a point light (x_0 a delta in position) leaves out s = 0 and, for k = 1, s = 1", "[bpt][mis]") {
    // x_0 point light, x_1, x_2 diffuse, x_3 camera: pL[0] = pL0Nee (the choice pmf);
    // s = 0 is impossible (no camera path hits a point), the others share the path.
    float pL[4] = {0.25f, 0.2f, 0.6f, 1.0f}, pE[4] = {0.3f, 0.5f, 0.7f, 1.0f};
    uint8_t delta[4] = {0, 0, 0, 0};
    for (float beta : {1.0f, 2.0f}) {
        CHECK(bptMisWeight(3, 0, pL, pE, delta, 0.25f, beta, false, true) == 0.0f);
        double sum = 0, p[4];
        for (int s = 1; s <= 3; ++s) {
            double prod = 1;
            for (int i = 0; i < s; ++i) prod *= pL[i];
            for (int i = s; i < 3; ++i) prod *= pE[i];
            p[s] = std::pow(prod, beta);
            sum += p[s];
        }
        double total = 0;
        for (int s = 1; s <= 3; ++s) {
            const float w = bptMisWeight(3, s, pL, pE, delta, 0.25f, beta, false, true);
            CHECK(w == Approx(p[s] / sum).epsilon(1e-5));
            total += w;
        }
        CHECK(total == Approx(1.0).epsilon(1e-6));
        // k = 1: the camera does not see a point light.
        CHECK(bptMisWeight(1, 1, pL, pE, delta, 0.25f, beta, false, true) == 0.0f);
    }
}

// ---- 2. BPT = PT ------------------------------------------------------------------------

TEST_CASE("BPT matches PT on the Cornell box", "[bpt][render][stat]") { compareWithPt(rstats::cornell64(5), 32, 8, 5, 1000); }

TEST_CASE("BPT matches PT with glossy, glass and mirror (caustics)", "[bpt][render]") {
    compareWithPt(loadSceneFromString(rstats::causticXml(64, 6), "caustic.xml", "."), 32, 8, 6, 2000);
}

TEST_CASE("BPT matches PT with the balance heuristic (beta = 1) and MinPathLength 3", "[bpt][render][stat]") {
    compareWithPt(rstats::cornell64(5), 16, 8, 5, 4000, 1.0f, 3);
}

TEST_CASE("BPT matches PT with a thin-lens camera", "[bpt][render]") {
    SceneDesc d = rstats::cornell64(4);
    d.camera.dof = true;
    d.camera.focalLength = 5.0f;
    d.camera.fStop = 4.0f;
    compareWithPt(d, 16, 8, 4, 5000);
}

TEST_CASE("BPT: the image is bit-identical for 1 and 2 threads", "[bpt][render]") {
    const SceneDesc desc = loadSceneFromString(rstats::causticXml(64, 6), "caustic.xml", ".");
    RenderResult a = render(desc, rstats::renderOptions(TracerKind::BPT, 4, 42, 1, 6, 1));
    RenderResult b = render(desc, rstats::renderOptions(TracerKind::BPT, 4, 42, 1, 6, 2));
    CHECK(a.image.rgb == b.image.rgb);
    CHECK(a.stats.lengthMeanLuminance == b.stats.lengthMeanLuminance);
    CHECK(a.stats.raysOccluded == b.stats.raysOccluded);
    RenderResult c = render(desc, rstats::renderOptions(TracerKind::BPT, 4, 43, 1, 6, 2));
    CHECK(a.image.rgb != c.image.rgb);
}

// ---- 3. per-length ----------------------------------------------------------------------

TEST_CASE("BPT mean luminance by path length matches PT's", "[bpt][render]") {
    const int K = 8, spp = 16, maxLength = 5;
    SceneDesc desc = rstats::cornell64(maxLength);
    rstats::RunStats pt, bpt;
    for (int k = 0; k < K; ++k) {
        RenderResult a = render(desc, rstats::renderOptions(TracerKind::PT, spp, 3000 + k, 1, maxLength));
        RenderResult b = render(desc, rstats::renderOptions(TracerKind::BPT, spp, 3500 + k, 1, maxLength));
        REQUIRE(a.stats.lengthMeanLuminance.size() > size_t(maxLength));
        REQUIRE(b.stats.lengthMeanLuminance.size() > size_t(maxLength));
        CHECK(b.stats.lengthMeanLuminance[maxLength + 1] == 0.0);
        pt.add(std::vector<double>(a.stats.lengthMeanLuminance.begin() + 1, a.stats.lengthMeanLuminance.begin() + maxLength + 1));
        bpt.add(std::vector<double>(b.stats.lengthMeanLuminance.begin() + 1, b.stats.lengthMeanLuminance.begin() + maxLength + 1));
    }
    for (int k = 1; k <= maxLength; ++k) {
        size_t i = size_t(k - 1);
        double z = (bpt.mean(i) - pt.mean(i)) / std::sqrt(bpt.se(i) * bpt.se(i) + pt.se(i) * pt.se(i));
        WARN("length " << k << ": BPT " << bpt.mean(i) << " +- " << bpt.se(i) << ", PT " << pt.mean(i) << " +- " << pt.se(i) << ", z = " << z);
        CHECK(pt.mean(i) > 0);
    }
    rstats::ZTestResult z = rstats::compareRuns(bpt, pt, 1e-4);
    INFO(z.describe());
    CHECK(z.pass);
}

// ---- 4. no NaN or Inf -------------------------------------------------------------------

TEST_CASE("BPT stays finite with extreme lights and MaxPathLength 64", "[bpt][render]") {
    for (const char* intensity : {"1e6", "1e-6"}) {
        SceneDesc d = loadSceneFromString(rstats::causticXml(64, 64, intensity), "extreme.xml", ".");
        d.settings.width = 32;
        d.settings.height = 32;
        RenderResult r = render(d, rstats::renderOptions(TracerKind::BPT, 4, 7, 1, 64));
        INFO("intensity " << intensity);
        CHECK(r.stats.samplesNonfiniteDiscarded == 0);
        double sum = 0;
        for (float v : r.image.rgb) {
            REQUIRE(std::isfinite(v));
            sum += v;
        }
        CHECK(sum > 0);
    }
    SceneDesc c = rstats::cornell64(64);
    RenderResult r = render(c, rstats::renderOptions(TracerKind::BPT, 4, 8, 1, 64));
    CHECK(r.stats.samplesNonfiniteDiscarded == 0);
    for (float v : r.image.rgb) REQUIRE(std::isfinite(v));
}

TEST_CASE("BPT matches PT with an environment map (and a glass ball)", "[bpt][render]") {
    std::string dir = rstats::tempDir("bptsky");
    writeImage(dir + "/sky.pfm", rstats::skyWithSun());
    const std::string xml = R"(<Scene>
  <Settings><Width value="64"/><Height value="48"/><MaxPathLength value="4"/><EnvMap name="sky.pfm"/></Settings>
  <Camera Type="Camera"><Position x="0" y="1.2" z="-4"/><LookAt x="0" y="0.5" z="0"/><FOV value="45"/></Camera>
  <Shader Type="Matte" ID="0"><Diffuse r="0.7" g="0.6" b="0.5"/></Shader>
  <Shader Type="Matte" ID="1"><Diffuse r="0.3" g="0.5" b="0.7"/></Shader>
  <Shader Type="Dielectric" ID="2"><Reflect r="1" g="1" b="1"/><Refract r="1" g="1" b="1"/>
    <iIOR value="1.5"/><oIOR value="1"/></Shader>
  <Geometry Type="Plane" ID="floor"><Position x="0" y="0" z="0"/><Width value="4"/><Depth value="4"/><Shader value="0"/></Geometry>
  <Geometry Type="Sphere" ID="ball"><Position x="-0.5" y="0.6" z="0"/><Radius value="0.6"/><Shader value="1"/></Geometry>
  <Geometry Type="Sphere" ID="glass"><Position x="0.8" y="0.4" z="-0.5"/><Radius value="0.4"/><Shader value="2"/></Geometry>
  <Light Type="Area" ID="lamp"><Position x="1.5" y="2" z="-1"/><Radius value="0.2"/>
    <Intensity value="5"/><Colour r="1" g="1" b="1"/></Light>
</Scene>
)";
    SceneDesc desc = loadSceneFromString(xml, "sky.xml", dir);
    compareWithPt(desc, 16, 8, 4, 6000);
    std::filesystem::remove_all(dir);
}

// ---- 6. strategy images -------------------------------------------------------------------

namespace {

// The strategy images of a BPT render of `desc` with MinPathLength = MaxPathLength = k.
RenderResult renderStrategies(const SceneDesc& desc, int spp, uint64_t seed, int k) {
    RenderOptions o = rstats::renderOptions(TracerKind::BPT, spp, seed, k, k);
    o.strategyImages = "unused";  // render() keeps the images; only the CLI writes them
    return render(desc, o);
}

}  // namespace

TEST_CASE("BPT strategy images: the weighted ones add up to the image", "[bpt][strategies]") {
    SceneDesc desc = rstats::cornell64(3);
    RenderOptions o = rstats::renderOptions(TracerKind::BPT, 4, 11, 1, 3);
    o.strategyImages = "unused";
    RenderResult r = render(desc, o);
    REQUIRE(r.strategyImages.size() == 2 + 3 + 4);  // (s, t) for k = 1, 2, 3
    std::vector<double> sum(r.image.rgb.size(), 0.0);
    for (const StrategyImage& si : r.strategyImages) {
        REQUIRE(si.s + si.t - 1 >= 1);
        REQUIRE(si.s + si.t - 1 <= 3);
        for (size_t i = 0; i < sum.size(); ++i) sum[i] += si.weighted.rgb[i];
    }
    // Float sums per strategy against double sums per pixel: rounding only.
    for (size_t i = 0; i < sum.size(); ++i) REQUIRE(sum[i] == Approx(r.image.rgb[i]).epsilon(1e-4).margin(1e-6));
}

TEST_CASE("BPT strategy images: each unweighted strategy estimates the same per-length image", "[bpt][strategies]") {
    // For path lengths 2 and 3 on the Cornell box, every strategy (s, t) on its own is an
    // unbiased estimator of the length-k image: its unweighted image over K runs against
    // PT's with MinPathLength = MaxPathLength = k (8 x 8 block means, per channel: s = 0
    // hits the small light rarely, so its run means need many samples each to be near normal).
    SceneDesc desc = rstats::cornell64(3);
    desc.settings.width = desc.settings.height = 32;
    const int K = 8, spp = 128, B = 8;
    for (int k = 2; k <= 3; ++k) {
        rstats::RunStats pt;
        std::vector<rstats::RunStats> strat(size_t(k + 1));
        for (int run = 0; run < K; ++run) {
            RenderResult a = render(desc, rstats::renderOptions(TracerKind::PT, spp, 100 + run, k, k));
            std::vector<double> v;
            for (int c = 0; c < 3; ++c) {
                std::vector<double> m = rstats::blockMeans(a.image, B, c);
                v.insert(v.end(), m.begin(), m.end());
            }
            pt.add(v);
            RenderResult b = renderStrategies(desc, spp, 200 + run, k);
            REQUIRE(b.strategyImages.size() == size_t(k + 1));
            for (const StrategyImage& si : b.strategyImages) {
                std::vector<double> u;
                for (int c = 0; c < 3; ++c) {
                    std::vector<double> m = rstats::blockMeans(si.unweighted, B, c);
                    u.insert(u.end(), m.begin(), m.end());
                }
                strat[size_t(si.s)].add(u);
            }
        }
        for (int s = 0; s <= k; ++s) {
            double ratio = 0;
            // p split over the 2 + 3 + 1 comparisons of this test case.
            rstats::ZTestResult z = rstats::compareRuns(strat[size_t(s)], pt, 1e-4 / 7, &ratio);
            INFO("k = " << k << ", s = " << s << ", t = " << k + 1 - s << ": unweighted / PT = " << ratio << "; " << z.describe());
            CHECK(z.pass);
        }
    }
}
