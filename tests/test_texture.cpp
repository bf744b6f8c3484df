// Textures: checker cells, bilinear image lookup (exact at pixel centres, wrapping, v = 0
// at the bottom row), Perlin noise and marble (deterministic, bounded, veined).
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "chi2.h"
#include "kernels/texture.h"

using namespace wmlt;

namespace {

TextureDesc checker(float ru = 1, float rv = 1) {
    TextureDesc t;
    t.kind = TextureKind::Checker;
    t.colour1 = Vec3(1, 0, 0);
    t.colour2 = Vec3(0, 0, 1);
    t.repeatU = ru;
    t.repeatV = rv;
    return t;
}

bool same(Vec3 a, Vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

// Pixel (x, row) of a w x h image: a distinct value per pixel and channel.
Vec3 pixelValue(int x, int row) { return Vec3(float(x + 10 * row), float(100 + x * row), float(-x - row)); }

TextureDesc imageTexture(int w, int h, float ru = 1, float rv = 1) {
    TextureDesc t;
    t.kind = TextureKind::ImageFile;
    t.image = Image(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) t.image.set(x, y, pixelValue(x, y));
    t.repeatU = ru;
    t.repeatV = rv;
    return t;
}

TextureDesc marble() {
    TextureDesc t;
    t.kind = TextureKind::Marble;
    t.colour1 = Vec3(0.9f, 0.9f, 0.85f);
    t.colour2 = Vec3(0.4f, 0.35f, 0.3f);
    t.colour3 = Vec3(0.05f, 0.05f, 0.1f);
    return t;
}

}  // namespace

TEST_CASE("Checker: 2 x 2 cells per unit of (u, v) * repeat", "[texture]") {
    TextureDesc t = checker();
    const Vec3 c1 = t.colour1, c2 = t.colour2, p;
    CHECK(same(evalTexture(t, 0.1f, 0.1f, p), c1));
    CHECK(same(evalTexture(t, 0.3f, 0.4f, p), c1));  // still the first cell (cells are 0.5 wide)
    CHECK(same(evalTexture(t, 0.6f, 0.1f, p), c2));
    CHECK(same(evalTexture(t, 0.1f, 0.6f, p), c2));
    CHECK(same(evalTexture(t, 0.6f, 0.6f, p), c1));
    CHECK(same(evalTexture(t, 1.1f, 0.1f, p), c1));   // periodic with period 1
    CHECK(same(evalTexture(t, -0.1f, 0.1f, p), c2));  // floor(-0.2) = -1: odd
    CHECK(same(evalTexture(t, -0.6f, -0.6f, p), c1));
    CHECK(same(evalTexture(t, 0.5f, 0.0f, p), c2));  // cell edges belong to the upper cell
    TextureDesc r = checker(2, 3);
    CHECK(same(evalTexture(r, 0.3f, 0.1f, p), c2));  // u' = 0.6
    CHECK(same(evalTexture(r, 0.3f, 0.2f, p), c1));  // v' = 0.6
    CHECK(textureHeight(t, 0.1f, 0.1f, p) == Approx(0.2126f));
    CHECK(textureHeight(t, 0.6f, 0.1f, p) == Approx(0.0722f));
}

TEST_CASE("Image texture: exact at pixel centres, v = 0 at the bottom row", "[texture]") {
    for (auto [w, h] : {std::pair<int, int>{4, 8}, {3, 5}, {1, 1}, {7, 2}}) {
        TextureDesc t = imageTexture(w, h);
        const bool pow2 = (w & (w - 1)) == 0 && (h & (h - 1)) == 0;
        for (int row = 0; row < h; ++row)
            for (int x = 0; x < w; ++x) {
                const float u = (float(x) + 0.5f) / float(w), v = 1.0f - (float(row) + 0.5f) / float(h);
                Vec3 got = evalTexture(t, u, v, Vec3()), want = pixelValue(x, row);
                INFO(w << "x" << h << " pixel " << x << "," << row);
                if (pow2) {
                    CHECK(same(got, want));
                } else {
                    CHECK(got.x == Approx(want.x).margin(1e-4));
                    CHECK(got.y == Approx(want.y).margin(1e-4));
                    CHECK(got.z == Approx(want.z).margin(1e-4));
                }
            }
    }
    TextureDesc t = imageTexture(4, 8);
    // The bottom-left pixel is at small (u, v).
    CHECK(same(evalTexture(t, 0.125f, 0.0625f, Vec3()), pixelValue(0, 7)));
    CHECK(same(evalTexture(t, 0.125f, 0.9375f, Vec3()), pixelValue(0, 0)));
}

TEST_CASE("Image texture: bilinear between centres and wrapping at the edges", "[texture]") {
    TextureDesc t = imageTexture(4, 8);
    auto near = [](Vec3 a, Vec3 b) {  // values are up to ~100: relative 1e-5
        return std::fabs(a.x - b.x) < 1e-3f && std::fabs(a.y - b.y) < 1e-3f && std::fabs(a.z - b.z) < 1e-3f;
    };
    // Halfway between pixels (1, 3) and (2, 3) in x; a quarter of the way down to row 4.
    const float v3 = 1.0f - 3.5f / 8.0f;
    CHECK(near(evalTexture(t, 0.5f, v3, Vec3()), (pixelValue(1, 3) + pixelValue(2, 3)) * 0.5f));
    const float vq = v3 - 0.25f / 8.0f;
    CHECK(near(evalTexture(t, 0.375f, vq, Vec3()), pixelValue(1, 3) * 0.75f + pixelValue(1, 4) * 0.25f));
    // u = 0: halfway between the last and the first column (wrap).
    CHECK(near(evalTexture(t, 0.0f, v3, Vec3()), (pixelValue(3, 3) + pixelValue(0, 3)) * 0.5f));
    CHECK(near(evalTexture(t, 1.0f, v3, Vec3()), (pixelValue(3, 3) + pixelValue(0, 3)) * 0.5f));
    // v = 0: halfway between the bottom and the top row.
    CHECK(near(evalTexture(t, 0.375f, 0.0f, Vec3()), (pixelValue(1, 7) + pixelValue(1, 0)) * 0.5f));
    // Periodic in u and v, also for negative coordinates.
    for (float u : {0.1f, 0.37f, 0.93f})
        for (float v : {0.05f, 0.5f, 0.77f}) {
            Vec3 base = evalTexture(t, u, v, Vec3());
            CHECK(near(evalTexture(t, u + 2.0f, v - 1.0f, Vec3()), base));
            CHECK(near(evalTexture(t, u - 3.0f, v + 5.0f, Vec3()), base));
        }
    // Repeat tiles: with repeat 2, (u, v) = (0.3, 0.2) looks up (0.6, 0.4).
    TextureDesc r = imageTexture(4, 8, 2, 2);
    CHECK(near(evalTexture(r, 0.3f, 0.2f, Vec3()), evalTexture(t, 0.6f, 0.4f, Vec3())));
    // An empty image is black rather than a crash.
    TextureDesc e;
    e.kind = TextureKind::ImageFile;
    CHECK(isBlack(evalTexture(e, 0.5f, 0.5f, Vec3())));
}

TEST_CASE("Perlin noise: a permutation table, zero on the lattice, bounded", "[texture]") {
    std::vector<int> seen(256, 0);
    for (int i = 0; i < 256; ++i) seen[texture_detail::kPerm[i]]++;
    for (int i = 0; i < 256; ++i) CHECK(seen[i] == 1);
    for (int i = 0; i < 256; ++i) CHECK(texture_detail::kPerm[i] == texture_detail::kPerm[i + 256]);
    CHECK(perlinNoise(Vec3(3, -7, 12)) == 0.0f);
    CHECK(perlinNoise(Vec3(0, 0, 0)) == 0.0f);
    CHECK(perlinNoise(Vec3(NAN, 0, 0)) == 0.0f);
    chi2::Pcg32 rng(7);
    double sum = 0, sumSq = 0, maxAbs = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
        Vec3 p(rng.uniform() * 40 - 20, rng.uniform() * 40 - 20, rng.uniform() * 40 - 20);
        float v = perlinNoise(p);
        sum += v;
        sumSq += double(v) * v;
        maxAbs = std::max(maxAbs, double(std::fabs(v)));
        // Continuous: a tiny step changes little.
        CHECK(std::fabs(perlinNoise(p + Vec3(1e-3f, 0, 0)) - v) < 0.01f);
    }
    CHECK(maxAbs <= 1.1);
    CHECK(maxAbs > 0.5);                // not degenerate
    CHECK(std::fabs(sum / n) < 0.02);   // zero mean
    CHECK(std::sqrt(sumSq / n) > 0.1);  // and some variance
    // Periodic with period 256 (the table), and defined far away.
    CHECK(perlinNoise(Vec3(0.3f, 0.6f, 0.2f)) == Approx(perlinNoise(Vec3(256.3f, 0.6f, 0.2f))).margin(1e-4));
    CHECK(std::isfinite(perlinNoise(Vec3(1e9f, -3e12f, 5e20f))));
}

TEST_CASE("Marble: deterministic, within its colours' hull, veined", "[texture]") {
    TextureDesc t = marble();
    chi2::Pcg32 rng(11);
    float tMin = 1, tMax = 0;
    for (int i = 0; i < 5000; ++i) {
        Vec3 p(rng.uniform() - 0.5f, rng.uniform() - 0.5f, rng.uniform() - 0.5f);  // a unit cube
        Vec3 c = evalTexture(t, 0.3f, 0.7f, p);
        Vec3 again = evalTexture(t, 0.9f, 0.1f, p);  // (u, v) do not matter
        CHECK(same(c, again));
        // On the segment colour1-colour2 or colour2-colour3.
        float m = marbleParameter(p);
        CHECK(m >= 0.0f);
        CHECK(m <= 1.0f);
        tMin = std::min(tMin, m);
        tMax = std::max(tMax, m);
        Vec3 expect = m < 0.5f ? t.colour1 * (1 - 2 * m) + t.colour2 * (2 * m) : t.colour2 * (2 - 2 * m) + t.colour3 * (2 * m - 1);
        CHECK(c.x == Approx(expect.x).margin(1e-5));
        CHECK(c.y == Approx(expect.y).margin(1e-5));
        CHECK(c.z == Approx(expect.z).margin(1e-5));
        for (int k = 0; k < 3; ++k) {
            float lo = std::min({t.colour1[k], t.colour2[k], t.colour3[k]});
            float hi = std::max({t.colour1[k], t.colour2[k], t.colour3[k]});
            CHECK(c[k] >= lo - 1e-6f);
            CHECK(c[k] <= hi + 1e-6f);
        }
        CHECK(textureHeight(t, 0, 0, p) == Approx(luminance(c)));
    }
    // Veins: over one unit the parameter sweeps (nearly) the whole range.
    CHECK(tMin < 0.05f);
    CHECK(tMax > 0.95f);
    // A fixed value pins the table and the constants down (so that a change is noticed).
    CHECK(marbleParameter(Vec3(0.25f, 0.5f, 0.75f)) == Approx(0.736898363).margin(1e-5));
    CHECK(same(evalTexture(t, 0, 0, Vec3(0.1f, 0.2f, 0.3f)), evalTexture(marble(), 1, 1, Vec3(0.1f, 0.2f, 0.3f))));
}

TEST_CASE("textureMean: checkers, images and the marble's approximation", "[texture]") {
    TextureDesc t;
    t.kind = TextureKind::Checkerboard;
    t.colour1 = Vec3(0.9f, 0.6f, 0.3f);
    t.colour2 = Vec3(0.1f, 0.2f, 0.3f);
    CHECK(textureMean(t).x == Approx(0.5f));
    CHECK(textureMean(t).y == Approx(0.4f));
    CHECK(textureMean(t).z == 0.3f);  // (c + c) / 2 = c exactly: a constant texture's mean is its value
    t.kind = TextureKind::Checker;
    CHECK(textureMean(t).x == Approx(0.5f));
    t.kind = TextureKind::Bitmap;
    t.image = Image(2, 1);
    t.image.set(0, 0, Vec3(1, 0, 0.5f));
    t.image.set(1, 0, Vec3(0, 1, 0.5f));
    CHECK(textureMean(t).x == 0.5f);
    CHECK(textureMean(t).y == 0.5f);
    CHECK(textureMean(t).z == 0.5f);
    t.kind = TextureKind::Marble;
    t.colour1 = Vec3(0.0f);
    t.colour2 = Vec3(1.0f);
    t.colour3 = Vec3(2.0f);
    CHECK(textureMean(t).x == 1.0f);
}

// Scale and Mix (pbrt's): operand 0 times operand 1; (1 - a) operand 0 + a operand 1 with a
// operand 2's luminance or the constant amount; an absent operand is colour1 / colour2.
// At points in each checker cell, against the closed forms; nested (a mix of a scale); and
// their means.
TEST_CASE("Scale and Mix textures combine their operands", "[texture]") {
    std::vector<TextureDesc> all;
    all.push_back(checker());          // 0: red / blue cells
    TextureDesc grey = checker(2, 2);  // 1: cells of 0.2 and 0.8 (twice as many)
    grey.colour1 = Vec3(0.2f);
    grey.colour2 = Vec3(0.8f);
    all.push_back(grey);
    TextureDesc scale;  // 2: checker 0 times (0.5, 2, 1)
    scale.kind = TextureKind::Scale;
    scale.operand[0] = 0;
    scale.colour2 = Vec3(0.5f, 2.0f, 1.0f);
    all.push_back(scale);
    TextureDesc mix;  // 3: (1 - a) scale + a (0, 1, 0), a = grey's luminance
    mix.kind = TextureKind::Mix;
    mix.operand[0] = 2;
    mix.colour2 = Vec3(0, 1, 0);
    mix.operand[2] = 1;
    all.push_back(mix);
    TextureDesc fixed = mix;  // 4: the same with a constant amount 0.25
    fixed.operand[2] = -1;
    fixed.amount = 0.25f;
    all.push_back(fixed);
    for (float u : {0.1f, 0.3f, 0.6f, 0.9f})
        for (float v : {0.15f, 0.35f, 0.65f, 0.85f}) {
            const Vec3 c = evalTexture(all[0], u, v, Vec3(0.0f)), g = evalTexture(all[1], u, v, Vec3(0.0f));
            const Vec3 s = c * Vec3(0.5f, 2.0f, 1.0f);
            CHECK(same(evalTextureOf(all, 2, u, v, Vec3(0.0f), Vec3(0, 0, 1)), s));
            const float a = luminance(g);
            CHECK(same(evalTextureOf(all, 3, u, v, Vec3(0.0f), Vec3(0, 0, 1)), s * (1.0f - a) + Vec3(0, 1, 0) * a));
            CHECK(same(evalTextureOf(all, 4, u, v, Vec3(0.0f), Vec3(0, 0, 1)), s * 0.75f + Vec3(0, 1, 0) * 0.25f));
            CHECK(same(evalTextureOf(all, 0, u, v, Vec3(0.0f), Vec3(0, 0, 1)), c));  // a plain texture as evalTexture
        }
    const Vec3 m = textureMeanOf(all, 4), s = Vec3(0.5f, 0.0f, 0.5f) * Vec3(0.5f, 2.0f, 1.0f);
    CHECK(m.x == Approx(s.x * 0.75f));
    CHECK(m.y == Approx(0.25f));
    CHECK(m.z == Approx(s.z * 0.75f));
}
