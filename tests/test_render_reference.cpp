// The path tracer against an independent renderer: Bitterli's Cornell box
// (tests/data/scenes/bitterli-cornell, 256 x 256, MaxPathLength 64) against Tungsten's
// reference (reference/tungsten-256-box.pfm: the 1024 x 1024 reference averaged over
// 4 x 4 blocks), compared in 16 x 16-pixel block means, per channel.
//
// Tolerance per block, all from data:
//  - ours: K independent renders (seeds); the standard error of the block mean from their
//    spread (Student t, K - 1 dof);
//  - the reference's own noise: Tungsten importance-samples its tent filter per pixel, so
//    its pixels are independent; a pixel's variance is estimated from the residual of a
//    discrete Laplacian, e = p - mean(4 neighbours), Var(e) = 1.25 sigma^2 for noise. Any
//    image structure (edges, shading gradients) only inflates this estimate: conservative.
//    The block mean's variance is the mean of sigma^2 / 256;
//  - the pixel filter: block means cancel a filter's effect except across the block's
//    border. The reference's 256-pixels carry the 1024-pixel tent (radius 1), i.e. about
//    1/32 of each neighbouring 256-pixel. That correction c (the separable kernel
//    [1/32, 15/16, 1/32] applied to our mean image, minus our box block mean) is
//    not applied but allowed for as a systematic term of size |c| (sub-pixel edge
//    positions make the kernel only a first-order estimate). It matters only at strong
//    edges on block borders (chiefly the light's).
// z = (ours - ref) / sqrt(se^2 + se_ref^2 + c^2), dof by Welch-Satterthwaite, mapped
// exactly to N(0, 1); then rstats::zTest per channel (chi^2 of sum z^2, Bonferroni on
// max |z|, and the mean z) at p = 1e-4 / 3.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "render_stats.h"
#include "wavemmlt/image.h"
#include "wavemmlt/render.h"
#include "wavemmlt/scene_desc.h"

using namespace wmlt;

namespace {

const std::string kDir = std::string(WAVEMMLT_TEST_DATA) + "/scenes/bitterli-cornell/";

// The separable kernel [1/32, 15/16, 1/32] (the reference's tent, at 256 x 256), with
// edge pixels replicated outside the image.
std::vector<double> tentLike(const std::vector<double>& img, int w, int h) {
    std::vector<double> a(img.size()), b(img.size());
    auto clampi = [](int v, int lo, int hi) { return std::min(std::max(v, lo), hi); };
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            a[size_t(y) * w + x] = img[size_t(y) * w + clampi(x - 1, 0, w - 1)] / 32 + img[size_t(y) * w + x] * 15 / 16 +
                                   img[size_t(y) * w + clampi(x + 1, 0, w - 1)] / 32;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            b[size_t(y) * w + x] =
                a[size_t(clampi(y - 1, 0, h - 1)) * w + x] / 32 + a[size_t(y) * w + x] * 15 / 16 + a[size_t(clampi(y + 1, 0, h - 1)) * w + x] / 32;
    return b;
}

std::vector<double> blockMeans(const std::vector<double>& img, int w, int h, int B) {
    int bw = w / B, bh = h / B;
    std::vector<double> m(size_t(bw) * bh, 0.0);
    for (int y = 0; y < bh * B; ++y)
        for (int x = 0; x < bw * B; ++x) m[size_t(y / B) * bw + x / B] += img[size_t(y) * w + x];
    for (double& v : m) v /= double(B) * B;
    return m;
}

}  // namespace

TEST_CASE("Bitterli's Cornell box matches Tungsten's reference in 16x16 block means", "[render][reference]") {
    const Image ref = readImage(kDir + "reference/tungsten-256-box.pfm");
    const SceneDesc desc = loadScene(kDir + "bitterli-cornell-256.xml");
    REQUIRE(desc.settings.width == 256);
    REQUIRE(desc.settings.height == 256);
    REQUIRE(desc.settings.maxPathLength == 64);
    REQUIRE(desc.settings.minPathLength == 1);
    REQUIRE(ref.width == 256);
    REQUIRE(ref.height == 256);
    const int W = 256, H = 256, B = 16, nb = (W / B) * (H / B);
    const int K = 8, spp = 16;

    rstats::RunStats blocks[3];        // our block means per run
    std::vector<double> meanImage[3];  // our mean image over the runs
    for (int c = 0; c < 3; ++c) meanImage[c].assign(size_t(W) * H, 0.0);
    for (int k = 0; k < K; ++k) {
        RenderOptions o;
        o.tracer = TracerKind::PT;
        o.spp = spp;
        o.strataPerAxis = strataForSpp(spp);
        o.threads = 2;
        o.seed = 500 + k;
        o.minPathLength = desc.settings.minPathLength;
        o.maxPathLength = desc.settings.maxPathLength;
        RenderResult r = render(desc, o);
        REQUIRE(r.image.width == W);
        REQUIRE(r.stats.samplesNonfiniteDiscarded == 0);
        for (int c = 0; c < 3; ++c) {
            std::vector<double> ch = rstats::channel(r.image, c);
            blocks[c].add(blockMeans(ch, W, H, B));
            for (size_t i = 0; i < ch.size(); ++i) meanImage[c][i] += ch[i] / K;
        }
    }

    double imageOurs[3] = {0, 0, 0}, imageRef[3] = {0, 0, 0};
    for (int c = 0; c < 3; ++c) {
        const std::vector<double> refCh = rstats::channel(ref, c);
        const std::vector<double> refBlocks = blockMeans(refCh, W, H, B);
        // Filter allowance: first-order tent correction of each block.
        const std::vector<double> tentBlocks = blockMeans(tentLike(meanImage[c], W, H), W, H, B);
        const std::vector<double> boxBlocks = blockMeans(meanImage[c], W, H, B);
        // Reference noise: Laplacian residuals, per block.
        std::vector<double> refVarSum(nb, 0.0), refCount(nb, 0.0);
        for (int y = 1; y < H - 1; ++y)
            for (int x = 1; x < W - 1; ++x) {
                size_t i = size_t(y) * W + x;
                double e = refCh[i] - 0.25 * (refCh[i - 1] + refCh[i + 1] + refCh[i - W] + refCh[i + W]);
                size_t b = size_t(y / B) * (W / B) + x / B;
                refVarSum[b] += e * e / 1.25;
                refCount[b] += 1;
            }
        std::vector<double> value(nb), expected(nb), se(nb), dof(nb);
        double worstFilterRatio = 0;
        for (int b = 0; b < nb; ++b) {
            double a = blocks[c].se(b) * blocks[c].se(b);             // ours
            double r = refVarSum[b] / refCount[b] / (double(B) * B);  // reference
            double f = tentBlocks[b] - boxBlocks[b];                  // filter
            double nuRef = refCount[b] - 1;
            value[b] = blocks[c].mean(b);
            expected[b] = refBlocks[b];
            se[b] = std::sqrt(a + r + f * f);
            dof[b] = (a + r + f * f) * (a + r + f * f) / (a * a / blocks[c].dof() + r * r / nuRef);
            worstFilterRatio = std::max(worstFilterRatio, std::fabs(f) / std::sqrt(a));
            imageOurs[c] += value[b] / nb;
            imageRef[c] += expected[b] / nb;
        }
        rstats::ZTestResult z = rstats::zTest(value, expected, se, dof, 1e-4 / 3);
        INFO("channel " << c << ": image mean ours " << imageOurs[c] << " reference " << imageRef[c] << " (ratio " << imageOurs[c] / imageRef[c]
                        << "); largest filter allowance " << worstFilterRatio << " x our se; block " << z.worst % (W / B) << "," << z.worst / (W / B)
                        << "; " << z.describe());
        CHECK(z.pass);
    }
}
