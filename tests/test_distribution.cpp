// Piecewise-constant distributions (1D, 2D) and the environment map's orientation and
// sampling: pdfs integrate to 1, samples follow the pdfs (Pearson's chi-square test at a
// fixed seed, p > 1e-3), sample() and pdf() agree.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "chi2.h"
#include "kernels/distribution.h"
#include "kernels/envmap.h"
#include "kernels/sampling.h"

using namespace wmlt;

namespace {

constexpr double kMinP = 1e-3;

Vec3 dirNear(Vec3 a, Vec3 b) { return a - b; }
bool close(Vec3 a, Vec3 b, float eps = 1e-5f) { return length(dirNear(a, b)) < eps; }

}  // namespace

TEST_CASE("Distribution1D: pdf, integral, continuous sampling", "[distribution]") {
    const std::vector<float> f = {1, 0, 3, 2, 0.5f, 0, 4, 1.5f};
    const int n = int(f.size());
    double sum = 0;
    for (float v : f) sum += v;
    Distribution1D d(f);
    CHECK(d.count() == n);
    CHECK(d.funcInt == Approx(sum / n));
    CHECK_FALSE(d.uniform);
    // The pdf integrates to 1 (it is constant on each bin of width 1/n).
    double integral = 0;
    for (int i = 0; i < n; ++i) integral += d.pdf((i + 0.5f) / n) / n;
    CHECK(integral == Approx(1.0).epsilon(1e-6));
    CHECK(d.pdf(0.3f / n) == Approx(f[0] / (sum / n)));

    // Histogram with 4 sub-bins per bin against the pdf's integral over each.
    const int sub = 4, N = 200000;
    std::vector<double> obs(size_t(n * sub), 0.0), expd(size_t(n * sub));
    for (int i = 0; i < n * sub; ++i) expd[i] = N * f[i / sub] / sum / sub;
    chi2::Pcg32 rng(1234);
    int outside = 0, wrongBin = 0, wrongPdf = 0;
    for (int s = 0; s < N; ++s) {
        float pdf;
        int off;
        float x = d.sampleContinuous(rng.uniform(), &pdf, &off);
        if (!(x >= 0.0f && x < 1.0f)) {
            ++outside;
            continue;
        }
        if (off != std::min(int(x * n), n - 1)) ++wrongBin;
        if (!(pdf > 0) || std::fabs(pdf - d.pdf(x)) > 1e-5f * pdf) ++wrongPdf;
        obs[std::min(int(x * n * sub), n * sub - 1)] += 1;
    }
    CHECK(outside == 0);
    CHECK(wrongBin == 0);
    CHECK(wrongPdf == 0);
    chi2::Result r = chi2::pearson(obs, expd);
    INFO(chi2::describe(r));
    CHECK(r.message.empty());
    CHECK(r.pValue > kMinP);

    // Ends of [0, 1): u = 0 lands in the first non-zero bin, u -> 1 in the last.
    float pdf;
    int off;
    CHECK(d.sampleContinuous(0.0f, &pdf, &off) == 0.0f);
    d.sampleContinuous(std::nextafter(1.0f, 0.0f), &pdf, &off);
    CHECK(off == n - 1);
    CHECK(d.sampleContinuous(1.0f) < 1.0f);
    // The inverse CDF is monotone.
    float prev = -1;
    for (int i = 0; i <= 1000; ++i) {
        float x = d.sampleContinuous(float(i) / 1001.0f);
        CHECK(x >= prev);
        prev = x;
    }
}

TEST_CASE("Distribution1D: sampleDiscrete and its pmf", "[distribution]") {
    const std::vector<float> f = {0, 5, 1, 0, 2, 2, 0.25f};
    double sum = 0;
    for (float v : f) sum += v;
    Distribution1D d(f);
    double pmfSum = 0;
    for (int i = 0; i < d.count(); ++i) {
        CHECK(d.discretePmf(i) == Approx(f[i] / sum).margin(1e-7));
        pmfSum += d.discretePmf(i);
    }
    CHECK(pmfSum == Approx(1.0));
    const int N = 100000;
    std::vector<double> obs(f.size(), 0.0), expd(f.size());
    for (size_t i = 0; i < f.size(); ++i) expd[i] = N * f[i] / sum;
    chi2::Pcg32 rng(99);
    int outside = 0, wrongPmf = 0;
    for (int s = 0; s < N; ++s) {
        float pmf;
        int i = d.sampleDiscrete(rng.uniform(), &pmf);
        if (i < 0 || i >= d.count()) {
            ++outside;
            continue;
        }
        if (std::fabs(pmf - f[i] / sum) > 1e-7) ++wrongPmf;
        obs[i] += 1;
    }
    CHECK(outside == 0);
    CHECK(wrongPmf == 0);
    chi2::Result r = chi2::pearson(obs, expd);
    INFO(chi2::describe(r));
    CHECK(r.message.empty());
    CHECK(r.pValue > kMinP);
}

// find's count of the cdf entries <= u (tables of up to 32 bins: a scene's lights) must
// give the bin of the plain search, upper_bound(cdf, u) - 1 clamped to the bins, bit for
// bit with its pmf: short tables with zero-width bins and all-zero input, and long ones
// (the search itself), at random u, on every cdf entry and at 0, 1 - eps, 1, NaN, -1.
TEST_CASE("Distribution1D: sampleDiscrete's bin is the search's, without branches", "[distribution]") {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    for (const std::vector<float>& f :
         std::vector<std::vector<float>>{{1}, {3, 1}, {0.2f, 0, 5, 0, 1.5f}, {0, 0, 0}, std::vector<float>(32, 1), std::vector<float>(40, 0.5f)}) {
        std::vector<float> g = f;
        for (size_t i = 0; i < g.size(); ++i) g[i] += float(i % 3);  // uneven (the all-zero one kept below)
        for (const std::vector<float>* in : std::initializer_list<const std::vector<float>*>{&f, &g}) {
            const Distribution1D d(*in);
            std::vector<float> u(4099);
            for (float& x : u) x = u01(rng);
            u[0] = 0.0f;
            u[1] = Distribution1D::kOneMinusEpsilon;
            u[2] = 1.0f;
            u[3] = std::nanf("");
            u[4] = -1.0f;
            for (size_t k = 0; k < d.cdf.size(); ++k) u[5 + k] = d.cdf[k];  // on the bins' edges
            const int n = d.count();
            size_t differ = 0;
            for (float x : u) {
                float p;
                const int i = d.sampleDiscrete(x, &p);
                const float c = std::isnan(x) || x < 0 ? 0.0f : std::min(x, Distribution1D::kOneMinusEpsilon);
                const int ref = std::min(std::max(int(std::upper_bound(d.cdf.begin(), d.cdf.end(), c) - d.cdf.begin()) - 1, 0), n - 1);
                const float pRef = d.uniform ? 1.0f / float(n) : d.cdf[size_t(ref) + 1] - d.cdf[size_t(ref)];
                differ += i != ref || std::memcmp(&p, &pRef, sizeof p) != 0;
            }
            INFO("bins " << in->size());
            CHECK(differ == 0);
        }
    }
}

TEST_CASE("Distribution1D: all-zero, negative and non-finite input", "[distribution]") {
    Distribution1D z(std::vector<float>{0, 0, 0, 0});
    CHECK(z.uniform);
    CHECK(z.pdf(0.3f) == 1.0f);
    float pdf, pmf;
    int off;
    CHECK(z.sampleContinuous(0.6f, &pdf, &off) == Approx(0.6f));
    CHECK(pdf == 1.0f);
    CHECK(off == 2);
    CHECK(z.sampleDiscrete(0.9f, &pmf) == 3);
    CHECK(pmf == 0.25f);
    Distribution1D bad(std::vector<float>{-1, NAN, 2, INFINITY});
    CHECK(bad.pdf(0.1f) == 0.0f);
    CHECK(bad.pdf(0.6f) == Approx(4.0f));  // all the mass in bin 2: density 1 / (1/4)
    for (float u : {0.0f, 0.3f, 0.99f}) {
        bad.sampleContinuous(u, &pdf, &off);
        CHECK(off == 2);
    }
    Distribution1D empty;
    CHECK(empty.pdf(0.5f) == 0.0f);
    CHECK(empty.sampleContinuous(0.5f, &pdf) == 0.0f);
    CHECK(pdf == 0.0f);
}

TEST_CASE("Distribution2D: pdf integrates to 1 and sampling follows it", "[distribution]") {
    const int nu = 6, nv = 5;
    std::vector<float> f(nu * nv);
    for (int y = 0; y < nv; ++y)
        for (int x = 0; x < nu; ++x) f[y * nu + x] = float((x * 3 + y * 5) % 7);  // includes zeros
    f[2 * nu + 0] = 20;                                                           // a bright cell
    for (int x = 0; x < nu; ++x) f[4 * nu + x] = 0;                               // an empty row
    double sum = 0;
    for (float v : f) sum += v;
    Distribution2D d(f, nu, nv);
    CHECK(d.width() == nu);
    CHECK(d.height() == nv);
    double integral = 0;
    for (int y = 0; y < nv; ++y)
        for (int x = 0; x < nu; ++x) {
            float p = d.pdf((x + 0.5f) / nu, (y + 0.5f) / nv);
            CHECK(p == Approx(f[y * nu + x] / sum * nu * nv).margin(1e-5));
            integral += p / (nu * nv);
        }
    CHECK(integral == Approx(1.0).epsilon(1e-6));

    const int sub = 2, N = 300000;
    const int bx = nu * sub, by = nv * sub;
    std::vector<double> obs(size_t(bx * by), 0.0), expd(size_t(bx * by));
    for (int j = 0; j < by; ++j)
        for (int i = 0; i < bx; ++i) expd[j * bx + i] = N * f[(j / sub) * nu + i / sub] / sum / (sub * sub);
    chi2::Pcg32 rng(42);
    int outside = 0, wrongPdf = 0;
    for (int s = 0; s < N; ++s) {
        float x, y, pdf;
        d.sampleContinuous(rng.uniform(), rng.uniform(), x, y, &pdf);
        if (!(x >= 0.0f && x < 1.0f && y >= 0.0f && y < 1.0f)) {
            ++outside;
            continue;
        }
        if (!(pdf > 0) || std::fabs(pdf - d.pdf(x, y)) > 1e-5f * pdf) ++wrongPdf;
        obs[std::min(int(y * by), by - 1) * bx + std::min(int(x * bx), bx - 1)] += 1;
    }
    CHECK(outside == 0);
    CHECK(wrongPdf == 0);
    chi2::Result r = chi2::pearson(obs, expd);
    INFO(chi2::describe(r));
    CHECK(r.message.empty());
    CHECK(r.pValue > kMinP);
    float pdf, x, y;
    d.sampleContinuous(0.3f, 0.7f, x, y, &pdf);
    auto xy = d.sampleContinuous(0.3f, 0.7f, &pdf);
    CHECK(xy.first == x);
    CHECK(xy.second == y);
    CHECK(pdf == Approx(d.pdf(x, y)));
}

TEST_CASE("Environment map orientation: +z at the centre, +y at the top, -x to the right", "[envmap]") {
    CHECK(close(envDirection(0.5f, 0.5f), Vec3(0, 0, 1)));
    CHECK(close(envDirection(0.3f, 0.0f), Vec3(0, 1, 0)));
    CHECK(close(envDirection(0.8f, 1.0f), Vec3(0, -1, 0)));
    CHECK(close(envDirection(0.75f, 0.5f), Vec3(-1, 0, 0)));  // right of centre: -x
    CHECK(close(envDirection(0.25f, 0.5f), Vec3(1, 0, 0)));
    CHECK(close(envDirection(0.0f, 0.5f), Vec3(0, 0, -1)));
    CHECK(envDirection(0.55f, 0.5f).x < 0);
    float u, v;
    envUv(Vec3(0, 0, 1), u, v);
    CHECK(u == Approx(0.5f));
    CHECK(v == Approx(0.5f));
    envUv(Vec3(-1, 0, 0), u, v);
    CHECK(u == Approx(0.75f));
    envUv(Vec3(0, 1, 0), u, v);
    CHECK(v == 0.0f);
    envUv(Vec3(0, -2, 0), u, v);  // not normalised
    CHECK(v == 1.0f);
    envUv(Vec3(0, 3, 3), u, v);
    CHECK(v == Approx(0.25f));
    // Exact inverses (away from the poles, where u is arbitrary).
    for (int i = 0; i < 64; ++i)
        for (int j = 1; j < 32; ++j) {
            const float uu = (i + 0.37f) / 64.0f, vv = (j + 0.1f) / 32.0f;
            Vec3 d = envDirection(uu, vv);
            CHECK(length(d) == Approx(1.0f).epsilon(1e-6));
            envUv(d, u, v);
            CHECK(u == Approx(uu).margin(2e-6));
            CHECK(v == Approx(vv).margin(2e-6));
            CHECK(close(envDirection(u, v), d, 2e-6f));
        }
    // u stays in [0, 1) at the seam (-z).
    envUv(Vec3(0.0f, 0.0f, -1.0f), u, v);
    CHECK(u >= 0.0f);
    CHECK(u < 1.0f);
    envUv(Vec3(-0.0f, 0.0f, -1.0f), u, v);
    CHECK(u >= 0.0f);
    CHECK(u < 1.0f);
}

namespace {

// 32 x 16 map: a dim gradient, a black band, a bright pixel near the top, one at the seam.
Image testMap() {
    Image img(32, 16);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 32; ++x) img.set(x, y, Vec3(0.1f + 0.02f * x, 0.2f, 0.05f * (y + 1)));
    for (int x = 0; x < 32; ++x) img.set(x, 10, Vec3(0.0f));
    img.set(20, 2, Vec3(50, 40, 30));
    img.set(31, 7, Vec3(8, 8, 8));
    img.set(5, 0, Vec3(-3, -3, -3));  // negative radiance: never sampled
    return img;
}

}  // namespace

TEST_CASE("EnvMapSampler: Le is the nearest pixel, sample and pdf agree", "[envmap]") {
    Image img = testMap();
    EnvMapSampler env;
    env.build(img);
    REQUIRE(env.valid());
    // Le at pixel centres.
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 32; ++x) {
            Vec3 d = envDirection((x + 0.5f) / 32, (y + 0.5f) / 16);
            Vec3 le = env.Le(d), want = img.at(x, y);
            CHECK((le.x == want.x && le.y == want.y && le.z == want.z));
        }
    chi2::Pcg32 rng(5);
    int notUnit = 0, noPdf = 0, disagree = 0, impossible = 0;
    for (int s = 0; s < 20000; ++s) {
        float pdf;
        Vec3 d = env.sample(rng.uniform(), rng.uniform(), pdf);
        if (std::fabs(length(d) - 1.0f) > 1e-5f) ++notUnit;
        if (!(pdf > 0)) {
            ++noPdf;
            continue;
        }
        if (std::fabs(env.pdf(d) - pdf) > 2e-3f * pdf) ++disagree;
        float u, v;
        envUv(d, u, v);
        int x, y;
        env.pixelOf(u, v, x, y);
        if (y == 10 || (x == 5 && y == 0)) ++impossible;  // the black row, the negative pixel
    }
    CHECK(notUnit == 0);
    CHECK(noPdf == 0);
    CHECK(disagree == 0);
    CHECK(impossible == 0);
    // The pdf is proportional to luminance where the map is piecewise constant.
    Vec3 dBright = envDirection(20.5f / 32, 2.5f / 16), dDim = envDirection(3.5f / 32, 2.5f / 16);
    CHECK(env.pdf(dBright) / env.pdf(dDim) == Approx(luminance(img.at(20, 2)) / luminance(img.at(3, 2))).epsilon(1e-4));
    CHECK(env.pdf(envDirection(0.3f, 10.5f / 16)) == 0.0f);
    CHECK(env.pdf(Vec3(0, 1, 0)) == 0.0f);  // the pole: sin(theta) = 0
}

TEST_CASE("EnvMapSampler: samples follow the pixel probabilities (chi-square)", "[envmap]") {
    Image img = testMap();
    EnvMapSampler env;
    env.build(img);
    const int w = img.width, h = img.height, N = 200000;
    std::vector<double> weight(size_t(w * h));
    double total = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double l = std::max(0.0f, luminance(img.at(x, y))) * std::sin(M_PI * (y + 0.5) / h);
            weight[y * w + x] = l;
            total += l;
        }
    std::vector<double> obs(weight.size(), 0.0), expd(weight.size());
    for (size_t i = 0; i < weight.size(); ++i) expd[i] = N * weight[i] / total;
    chi2::Pcg32 rng(77);
    for (int s = 0; s < N; ++s) {
        float pdf, u, v;
        Vec3 d = env.sample(rng.uniform(), rng.uniform(), pdf);
        envUv(d, u, v);
        int x, y;
        env.pixelOf(u, v, x, y);
        obs[y * w + x] += 1;
    }
    chi2::Result r = chi2::pearson(obs, expd);
    INFO(chi2::describe(r));
    CHECK(r.message.empty());
    CHECK(r.pValue > kMinP);
}

TEST_CASE("EnvMapSampler: the pdf integrates to 1 over the sphere, and the mean luminance", "[envmap]") {
    Image img = testMap();
    EnvMapSampler env;
    env.build(img);
    // Monte Carlo with uniform directions: E[pdf(d) / (1 / 4 pi)] = integral of pdf = 1.
    const int N = 400000;
    chi2::Pcg32 rng(2024);
    double s1 = 0, s2 = 0, l1 = 0;
    for (int i = 0; i < N; ++i) {
        Vec3 d = sampleUniformSphere(rng.uniform(), rng.uniform());
        double e = double(env.pdf(d)) / kUniformSpherePdf;
        s1 += e;
        s2 += e * e;
        l1 += std::max(0.0f, luminance(env.Le(d)));
    }
    const double mean = s1 / N, stderr_ = std::sqrt((s2 / N - mean * mean) / (N - 1));
    INFO("integral " << mean << " +- " << stderr_);
    CHECK(std::fabs(mean - 1.0) < 5 * stderr_);
    CHECK(stderr_ < 0.05);
    // meanLuminance = (1 / 4 pi) * integral of luminance(Le) over the sphere.
    CHECK(env.meanLuminance == Approx(l1 / N).epsilon(0.03));

    // A constant map: mean luminance exact, and importance sampling is close to uniform.
    Image flat(64, 32);
    for (float& v : flat.rgb) v = 2.0f;
    EnvMapSampler c;
    c.build(std::move(flat));
    CHECK(c.meanLuminance == Approx(2.0f).epsilon(1e-5));
    CHECK(c.pdf(Vec3(0.3f, 0.2f, 0.9f)) == Approx(kUniformSpherePdf).epsilon(0.03));
    // An empty map is harmless.
    EnvMapSampler none;
    none.build(Image());
    float pdf;
    none.sample(0.5f, 0.5f, pdf);
    CHECK(pdf == 0.0f);
    CHECK(isBlack(none.Le(Vec3(0, 0, 1))));
    CHECK(none.pdf(Vec3(0, 0, 1)) == 0.0f);
}
