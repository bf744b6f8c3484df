// Textured mesh lights (scene/mesh_light.h): the sampler follows the texture's luminance,
// its density is the one the hit side computes, it integrates to one, and T / pdfA is an
// unbiased estimate of the texture's integral over the surface.
#include <catch2/catch.hpp>

#include <cmath>

#include "chi2.h"
#include "scene/mesh_light.h"

using namespace wmlt;

namespace {

// A 2 x 1 rectangle in z = 0 (two triangles, uv over [0, 1]^2) under a checkerboard of
// 8 x 8 squares (to_uv scale 4): white (1) where the squares' parities agree, black (0)
// elsewhere; or a bitmap ramp.
TriangleMesh plate() {
    TriangleMesh m;
    m.positions = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {0, 1, 0}};
    m.uvs = {0, 0, 1, 0, 1, 1, 0, 1};
    m.indices = {0, 1, 2, 0, 2, 3};
    return m;
}

TextureDesc checkers() {
    TextureDesc t;
    t.kind = TextureKind::Checkerboard;
    t.colour1 = Vec3(1.0f);
    t.colour2 = Vec3(0.0f);
    t.uvTransform[0] = t.uvTransform[4] = 4;
    return t;
}

TextureDesc ramp() {  // a 64 x 32 bitmap whose texels grow as x^2 (nearest lookup)
    TextureDesc t;
    t.kind = TextureKind::Bitmap;
    t.nearest = true;
    t.image.width = 64;
    t.image.height = 32;
    t.image.rgb.resize(64 * 32 * 3);
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 64; ++x)
            for (int c = 0; c < 3; ++c) t.image.rgb[size_t(y * 64 + x) * 3 + c] = float((x + 1) * (x + 1)) / 4096.0f;
    return t;
}

}  // namespace

TEST_CASE("textured mesh light: sampling follows the luminance, with the density the hit side computes", "[meshlight][texture]") {
    const TriangleMesh m = plate();
    for (const TextureDesc& tex : {checkers(), ramp()}) {
        const MeshLight ml = buildMeshLight(m, &tex);
        REQUIRE(ml.area == Approx(2.0));
        chi2::Pcg32 rng(7);
        const int n = 200000;
        double sumT = 0, sumT2 = 0, black = 0;
        int badPdf = 0, badNormal = 0, mismatched = 0;
        for (int i = 0; i < n; ++i) {
            Vec3 p, nn, T;
            float pdfA;
            sampleTexturedMeshPoint(ml, rng.uniform(), rng.uniform(), p, nn, T, pdfA);
            if (!(pdfA > 0)) ++badPdf;
            if (std::fabs(nn.z - 1.0f) > 1e-6f) ++badNormal;
            // The hit side's density at the same point: the triangle and its barycentrics.
            const int t = p.y <= 0.5f * p.x ? 0 : 1;  // triangle 0 is (0,0), (2,0), (2,1)
            const Vec3 p0 = m.positions[m.indices[3 * t]], p1 = m.positions[m.indices[3 * t + 1]], p2 = m.positions[m.indices[3 * t + 2]];
            const Vec3 e1 = p1 - p0, e2 = p2 - p0, q = p - p0;
            const float det = e1.x * e2.y - e1.y * e2.x;
            const float b1 = (q.x * e2.y - q.y * e2.x) / det, b2 = (e1.x * q.y - e1.y * q.x) / det;
            Vec3 T2;
            float pdfHit;
            texturedEmitterAt(ml, t, b1, b2, p, T2, pdfHit);
            if (std::fabs(pdfHit - pdfA) > 1e-4f * pdfA) ++mismatched;
            const double f = T.y / pdfA;
            sumT += f;
            sumT2 += f * f;
            if (T.y == 0) ++black;
        }
        // Away from cell edges the two densities agree exactly; a point on an edge may be
        // given to the next cell by float rounding: allow that for a few in 10^5.
        CHECK(badPdf == 0);
        CHECK(badNormal == 0);
        INFO("mismatched " << mismatched);
        CHECK(mismatched < n / 10000);
        // E[T / pdfA] = the integral of T over the plate: 1 for the checkers (half of 2),
        // for the ramp 2 * mean_x ((x + 1)^2 / 4096) = 2 * 65 * 129 / (6 * 4096).
        const double integral = tex.kind == TextureKind::Checkerboard ? 1.0 : 2.0 * 65.0 * 129.0 / (6.0 * 4096.0);
        const double mean = sumT / n, var = sumT2 / n - mean * mean, se = std::sqrt(var / n);
        INFO("kind " << int(tex.kind) << ": mean " << mean << " +- " << se << ", expected " << integral);
        CHECK(std::fabs(mean - integral) < 4.5 * se);
        // Importance sampling: the checkers' black half gets few samples (the defensive
        // floor gives a black cell 1 / 20 of a white one's weight, about 5% of the samples,
        // and the cells across square edges are partly white), and T / pdfA varies far less
        // than uniform sampling's (variance 1: 2 T with T in {0, 1}).
        if (tex.kind == TextureKind::Checkerboard) {
            INFO("black " << black / n << ", variance " << var);
            CHECK(black / n < 0.1);
            CHECK(var < 0.25);
        } else {
            // Uniform sampling's variance of 2 T: 4 var(T) with T ~ (x + 1)^2 / 4096 over x.
            double m1 = 0, m2 = 0;
            for (int x = 0; x < 64; ++x) {
                const double v = 2.0 * (x + 1) * (x + 1) / 4096.0;
                m1 += v / 64;
                m2 += v * v / 64;
            }
            INFO("variance " << var << " against uniform " << m2 - m1 * m1);
            CHECK(var < 0.05 * (m2 - m1 * m1));
        }
    }
}

TEST_CASE("textured mesh light: the density integrates to one over the surface", "[meshlight][texture]") {
    const TriangleMesh m = plate();
    const TextureDesc tex = ramp();
    const MeshLight ml = buildMeshLight(m, &tex);
    // Stratified barycentrics over each triangle: sum pdfA dA = 1.
    double total = 0;
    const int k = 400;
    for (int t = 0; t < 2; ++t)
        for (int j = 0; j < k; ++j)
            for (int i = 0; i < k; ++i) {
                float b0, b1;
                sampleUniformTriangle((float(i) + 0.5f) / k, (float(j) + 0.5f) / k, b0, b1);
                Vec3 T;
                float pdfA;
                texturedEmitterAt(ml, t, b1, 1.0f - b0 - b1, Vec3(0.0f), T, pdfA);
                total += double(pdfA) * 1.0 / (double(k) * k);  // each triangle's area is 1
            }
    CHECK(total == Approx(1.0).epsilon(1e-3));
}

TEST_CASE("textured mesh light: a mesh of many triangles (one cell each) is sampled by their luminance", "[meshlight][texture]") {
    // The 2 x 1 plate as a 64 x 36 grid of quads (4608 triangles, over the 4096 of one cell
    // each), uv over [0, 1]^2, under the ramp.
    TriangleMesh m;
    const int nx = 64, ny = 36;
    for (int j = 0; j <= ny; ++j)
        for (int i = 0; i <= nx; ++i) {
            m.positions.push_back(Vec3(2.0f * float(i) / nx, float(j) / ny, 0.0f));
            m.uvs.push_back(float(i) / nx);
            m.uvs.push_back(float(j) / ny);
        }
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            const uint32_t v = uint32_t(j * (nx + 1) + i);
            for (uint32_t k : {v, v + 1, v + uint32_t(nx) + 2, v, v + uint32_t(nx) + 2, v + uint32_t(nx) + 1}) m.indices.push_back(k);
        }
    const TextureDesc tex = ramp();
    const MeshLight ml = buildMeshLight(m, &tex);
    REQUIRE(ml.grids.empty());
    chi2::Pcg32 rng(11);
    const int n = 200000;
    double sum = 0, sum2 = 0;
    for (int i = 0; i < n; ++i) {
        Vec3 p, nn, T;
        float pdfA;
        sampleTexturedMeshPoint(ml, rng.uniform(), rng.uniform(), p, nn, T, pdfA);
        const double f = T.y / pdfA;
        sum += f;
        sum2 += f * f;
    }
    const double integral = 2.0 * 65.0 * 129.0 / (6.0 * 4096.0), mean = sum / n, var = sum2 / n - mean * mean;
    INFO("mean " << mean << " +- " << std::sqrt(var / n) << ", expected " << integral << ", variance " << var);
    CHECK(std::fabs(mean - integral) < 4.5 * std::sqrt(var / n));
    CHECK(var < 0.05 * 0.366);  // uniform sampling's: 0.366 (the test above)
}
