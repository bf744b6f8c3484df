// Comparing a tracer's images with a reference tracer's, with stated power.
//
// K independent renders per side (different seeds: every random number is hashed from the
// seed, so runs are independent however correlated the samples inside a run are). Each
// property is one test at the suite's significance p (never a share of it):
//  - brightness: the image's mean luminance, one Welch z;
//  - blocks: b x b block means of each channel, max |z| against Bonferroni's bound (valid
//    whatever the blocks' correlation, e.g. an error of b_k that all pixels share);
//  - scatter: the blocks' shape (block luminance over the run's mean luminance, which
//    removes the shared brightness error) as sum z^2 ~ chi^2(n - 1), two-sided: an error spread
//    thinly over many blocks, or standard errors that are wrong;
//  - lengths: the mean luminance of each path length's image (RenderOptions::lengthImages),
//    max |z| over the lengths (each length's normalisation), and the lengths' blocks.
// Every test also states its power: the bias it detects with probability 0.9, printed as
// a relative error ("fails a brightness error of 0.8%"), and the tests that claim a power
// check it (a test that lost its power by a change of K or samples fails).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "render_stats.h"
#include "wavemmlt/render.h"
#include "wavemmlt/scene_desc.h"

namespace power {

inline double lum(double r, double g, double b) { return 0.2126 * r + 0.7152 * g + 0.0722 * b; }

inline double meanLuminance(const wmlt::Image& im) {
    double s = 0;
    const size_t n = size_t(im.width) * im.height;
    for (size_t i = 0; i < n; ++i) s += lum(im.rgb[i * 3], im.rgb[i * 3 + 1], im.rgb[i * 3 + 2]);
    return n ? s / double(n) : 0.0;
}

// Luminance means over b x b blocks.
inline std::vector<double> blockLuminance(const wmlt::Image& im, int b) {
    std::vector<double> r = rstats::blockMeans(im, b, 0), g = rstats::blockMeans(im, b, 1), bl = rstats::blockMeans(im, b, 2);
    for (size_t i = 0; i < r.size(); ++i) r[i] = lum(r[i], g[i], bl[i]);
    return r;
}

// z beyond which a two-sided test at false-alarm probability p rejects, and the bias
// (in standard errors) that such a test detects with probability `power`.
inline double zCritical(double p) { return -rstats::normalQuantile(p / 2); }
inline double detectableInSe(double zCrit, double power = 0.9) { return zCrit + rstats::normalQuantile(power); }

// K renders of one tracer on one scene, reduced to what the tests compare.
struct Runs {
    int block = 4;
    int kMin = 1, kMax = 0;  // path lengths with images (none when kMax < kMin)
    rstats::RunStats brightness, blocks, shape, lengthBrightness, lengthBlocks;
    explicit Runs(int b, int minLength = 1, int maxLength = 0) : block(b), kMin(minLength), kMax(maxLength) {}
    int runs() const { return brightness.runs; }
    void add(const wmlt::RenderResult& r) {
        const double m = meanLuminance(r.image);
        brightness.add({m});
        std::vector<double> v;
        for (int c = 0; c < 3; ++c) {
            std::vector<double> x = rstats::blockMeans(r.image, block, c);
            v.insert(v.end(), x.begin(), x.end());
        }
        blocks.add(v);
        std::vector<double> s = blockLuminance(r.image, block);
        for (double& x : s) x = m > 0 ? x / m : 0.0;
        shape.add(s);
        if (kMax < kMin) return;
        REQUIRE(r.lengthImages.size() > size_t(kMax));
        std::vector<double> lb, lbl;
        for (int k = kMin; k <= kMax; ++k) {
            lb.push_back(meanLuminance(r.lengthImages[size_t(k)]));
            std::vector<double> x = blockLuminance(r.lengthImages[size_t(k)], block);
            lbl.insert(lbl.end(), x.begin(), x.end());
        }
        lengthBrightness.add(lb);
        lengthBlocks.add(lbl);
    }
};

// Element i of a against b: difference, Welch standard error and degrees of freedom.
struct Diff {
    double a = 0, b = 0, se = 0, dof = 1, z = 0;
};
inline Diff welch(const rstats::RunStats& a, const rstats::RunStats& b, size_t i) {
    Diff d;
    d.a = a.mean(i);
    d.b = b.mean(i);
    const double x = a.variance(i) / a.runs, y = b.variance(i) / b.runs;
    d.se = std::sqrt(x + y);
    const double den = x * x / (a.runs - 1) + y * y / (b.runs - 1);
    d.dof = den > 0 ? (x + y) * (x + y) / den : double(std::min(a.runs, b.runs) - 1);
    if (d.se > 0) d.z = rstats::tToZ((d.a - d.b) / d.se, d.dof);
    else d.z = std::fabs(d.a - d.b) <= 1e-5 * std::max(1e-30, std::fabs(d.b)) ? 0.0 : INFINITY;  // no variance: exact
    if (!std::isfinite(d.a)) d.z = INFINITY;
    return d;
}

struct Verdict {
    bool pass = false;
    double detectable = 0;  // relative bias detected with probability 0.9 (brightness, lengths)
    std::string text;
};

// The image's mean luminance: one z at p. `detectable` is relative to the reference.
inline Verdict brightness(const Runs& a, const Runs& ref, double p) {
    const Diff d = welch(a.brightness, ref.brightness, 0);
    Verdict v;
    const double zc = zCritical(p);
    v.pass = std::fabs(d.z) <= zc;
    v.detectable = detectableInSe(zc) * d.se / d.b;
    std::ostringstream o;
    o << "brightness: " << d.a << " vs " << d.b << " (ratio " << d.a / d.b << "), z " << d.z << " (allowed +-" << zc
      << "); fails a brightness error of " << 100 * v.detectable << "% (power 0.9)";
    v.text = o.str();
    return v;
}

// Max |z| over the elements of x (a's against ref's) below Bonferroni's bound at p. The
// text names the worst element and the median relative bias one element must have to fail.
inline Verdict worstOf(const rstats::RunStats& a, const rstats::RunStats& ref, double p, const std::string& what) {
    const size_t n = a.size();
    const double zc = zCritical(p / double(std::max<size_t>(n, 1)));
    double worst = 0;
    size_t at = 0;
    std::vector<double> rel;
    Diff dw;
    for (size_t i = 0; i < n; ++i) {
        const Diff d = welch(a, ref, i);
        if (d.b > 0 && d.se > 0) rel.push_back(detectableInSe(zc) * d.se / d.b);
        if (!(std::fabs(d.z) <= worst)) {
            worst = std::fabs(d.z);
            at = i;
            dw = d;
        }
    }
    std::sort(rel.begin(), rel.end());
    Verdict v;
    v.pass = worst <= zc;
    v.detectable = rel.empty() ? 0 : rel[rel.size() / 2];
    std::ostringstream o;
    o << what << ": max |z| " << worst << " (allowed " << zc << " over " << n << ") at " << at << ": " << dw.a << " vs " << dw.b << " se " << dw.se
      << "; the median " << what << " fails an error of " << 100 * v.detectable << "% (power 0.9)";
    v.text = o.str();
    return v;
}

inline Verdict blocks(const Runs& a, const Runs& ref, double p) { return worstOf(a.blocks, ref.blocks, p, "block"); }

// Sum of z^2 over the shape's blocks inside the two-sided chi^2(n - 1) interval at p.
inline Verdict scatter(const Runs& a, const Runs& ref, double p) {
    double sum = 0;
    size_t n = 0;
    for (size_t i = 0; i < a.shape.size(); ++i) {
        const Diff d = welch(a.shape, ref.shape, i);
        if (d.se == 0 && d.z == 0) continue;  // exact on both sides
        sum += d.z * d.z;
        ++n;
    }
    // The shapes of a run sum to the number of blocks (each is a block over the blocks' mean),
    // so the blocks that vary carry n - 1 degrees of freedom: with 2 such blocks (a light seen
    // directly, nothing else lit) their z are one z twice, and chi^2(2)'s lower tail failed an
    // unbiased render (sum 1.4e-5, which chi^2(1) puts at p = 0.003).
    const double df = double(n > 1 ? n - 1 : n);
    const double lo = rstats::chiSquareUpperQuantile(df, 1 - p / 2), hi = rstats::chiSquareUpperQuantile(df, p / 2);
    Verdict v;
    v.pass = n <= 1 || (sum >= lo && sum <= hi);
    std::ostringstream o;
    o << "shape scatter: sum z^2 " << sum << " over " << n << " blocks, chi^2(" << df << ") (allowed [" << lo << ", " << hi << "])";
    v.text = o.str();
    return v;
}

// Each length's mean luminance: max |z| over the lengths (Bonferroni at p). `detectable`
// is the largest relative error the test could miss (power 0.9) among the lengths that
// carry at least `minShare` of the reference's brightness.
inline Verdict lengths(const Runs& a, const Runs& ref, double p, double minShare = 0.1) {
    const size_t n = a.lengthBrightness.size();
    const double zc = zCritical(p / double(std::max<size_t>(n, 1)));
    const double total = ref.brightness.mean(0);
    Verdict v;
    v.pass = true;
    std::ostringstream o;
    o << "lengths (allowed |z| " << zc << "):";
    for (size_t i = 0; i < n; ++i) {
        const Diff d = welch(a.lengthBrightness, ref.lengthBrightness, i);
        const double rel = d.b > 0 ? detectableInSe(zc) * d.se / d.b : 0.0;
        if (d.b >= minShare * total) v.detectable = std::max(v.detectable, rel);
        v.pass = v.pass && std::fabs(d.z) <= zc;
        o << "\n  k = " << a.kMin + int(i) << ": " << d.a << " vs " << d.b << " (" << 100 * d.b / total << "% of the image), z " << d.z
          << ", fails an error of " << 100 * rel << "%";
    }
    v.text = o.str();
    return v;
}

inline Verdict lengthBlocks(const Runs& a, const Runs& ref, double p) { return worstOf(a.lengthBlocks, ref.lengthBlocks, p, "length block"); }

// K renders of desc with options o and seeds seed0 + i, reduced to one Runs per entry of
// kMinImage (0: the image as rendered): with length images (BPT, MMLT), the image of an
// entry kMin > o.minPathLength is the sum of the length images from kMin on (BPT's image
// restricted to those lengths: its lengths do not depend on MinPathLength). Every run must
// discard nothing and, for MMLT and PSSMLT, replay every checked seed exactly.
inline std::vector<Runs> tracerRuns(const wmlt::SceneDesc& desc, wmlt::RenderOptions o, int K, uint64_t seed0, int block,
                                    const std::vector<int>& kMinImage = {0}) {
    const bool lengthImages = o.tracer == wmlt::TracerKind::BPT || o.tracer == wmlt::TracerKind::MMLT;
    std::vector<Runs> r;
    for (int kMin : kMinImage) r.emplace_back(block, std::max(kMin, o.minPathLength), lengthImages ? o.maxPathLength : 0);
    o.lengthImages = lengthImages;
    for (int i = 0; i < K; ++i) {
        o.seed = seed0 + uint64_t(i);
        const wmlt::RenderResult res = wmlt::render(desc, o);
        REQUIRE(res.stats.samplesNonfiniteDiscarded == 0);
        REQUIRE(res.stats.mmlt.replayMismatches == 0);
        for (Runs& x : r) {
            if (x.kMin == o.minPathLength) {
                x.add(res);
                continue;
            }
            wmlt::RenderResult part = res;
            part.image = wmlt::Image(res.image.width, res.image.height);
            for (int k = x.kMin; k <= o.maxPathLength; ++k)
                for (size_t j = 0; j < part.image.rgb.size(); ++j) part.image.rgb[j] += res.lengthImages[size_t(k)].rgb[j];
            x.add(part);
        }
    }
    return r;
}

// The power a comparison claims: the brightness error it detects with probability 0.9,
// and a length's (in lengths carrying >= 25% of the image; 0: not claimed).
struct Claims {
    double brightness = 0.01;
    double length = 0;
};

// Every property of a's runs against the reference's at p (the lengths' when both have
// length images), and the claimed power; the power is printed under `label`
// ("MMLT vs BPT"), every statistic too with WMLT_TEST_VERBOSE=1.
inline void compare(const Runs& a, const Runs& ref, const std::string& label, const std::string& what, double p, Claims claims) {
    const bool withLengths = a.kMax >= a.kMin && ref.kMax >= ref.kMin;
    const Verdict br = brightness(a, ref, p), bl = blocks(a, ref, p), sc = scatter(a, ref, p);
    std::cout << label << ", " << what << " (K = " << a.runs() << ", p = " << p << "): fails a brightness error of " << 100 * br.detectable
              << "%, a block error of " << 100 * bl.detectable << "% (median block)";
    std::vector<Verdict> all = {br, bl, sc};
    if (withLengths) {
        all.push_back(lengths(a, ref, p, 0.25));
        all.push_back(lengthBlocks(a, ref, p));
        std::cout << ", a length's error of " << 100 * all[3].detectable << "% (lengths with >= 25% of the image)";
    }
    std::cout << "\n";
    if (std::getenv("WMLT_TEST_VERBOSE"))
        for (const Verdict& v : all) std::cout << "  " << v.text << "\n";
    INFO(label << ", " << what);
    for (size_t i = 0; i < all.size(); ++i) {
        INFO(all[i].text);
        CHECK(all[i].pass);
        if (i == 0) CHECK(all[i].detectable <= claims.brightness);
        if (i == 3 && claims.length > 0) CHECK(all[i].detectable <= claims.length);
    }
}

}  // namespace power
