// The build-time optimiser of the RGB-to-spectrum table (kernels/spectral.h; Jakob and Hanika
// 2019): for each RGB on the table's grid, the coefficients c of the smooth spectrum
// s(lambda) = S(c0 t^2 + c1 t + c2) whose colour, seen under the colour space's illuminant,
// is that RGB. Run by CMake; reads only Debian's CIE tables (compiled in: cie_tables.cpp).
//
//   wavemmlt_rgb_sigmoid_fit OUT.bin OUT.cpp [--from TABLE.bin]
//
// --from: no fit, TABLE.bin (another build's OUT.bin of the same sources, its size checked)
// written as OUT.bin (scripts/test.sh's sanitizer build takes the release build's: 18 s).
//
// OUT.bin: floats [max channel l][z][y][x][c0 c1 c2], kSigmoidTableRes per axis; the entry
// (l, i, j, k) is rgb[l] = z_i (sigmoidTableZ), rgb[l+1] = z_i x_k, rgb[l+2] = z_i y_j
// (channels mod 3, x_k = k / (res - 1)). OUT.cpp embeds OUT.bin (.incbin) as the symbols
// wmlt_rgb_sigmoid_srgb and wmlt_rgb_sigmoid_srgb_end.
//
// The model (the renderer's own expectation of a reflectance's colour): XYZ = integral of
// s D65 cmf / integral of D65 y-bar over 360..830 nm, by the trapezoid rule on a 1 nm grid of
// the tables made linear between their 5 nm samples; RGB = xyzToSrgbMatrix XYZ (white: that
// D65, so that s = 1 is (1, 1, 1)). The residual is
// the difference in CIELAB (the white: s = 1), made zero by Gauss-Newton with a finite-
// difference Jacobian. Each (l, x, y) column of the grid is solved along z from z_(res/5),
// starting at c = 0, upward and then downward, each solve starting from its neighbour's c
// (the solutions vary smoothly along z). Columns are independent: solved in parallel, the
// table is the same for any thread count. Prints the largest residual (CIELAB units) of the
// colours brighter than 1e-4.
#include <tbb/parallel_for.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "kernels/spectral.h"

namespace {

using wmlt::kSigmoidTableRes;

constexpr int kSamples = 471;  // 360..830 nm, 1 nm apart

struct Model {
    double rgbWeight[kSamples][3];  // the trapezoid weight times D65 times cmf, as RGB, normalised
    double whiteXyz[3];             // of s = 1
    double toRgb[3][3], toXyz[3][3];

    Model() {
        double xyzW[kSamples][3], yD65 = 0;
        for (int j = 0; j < kSamples; ++j) {
            const double l = 360.0 + j, w = (j == 0 || j == kSamples - 1) ? 0.5 : 1.0;
            const double d = wmlt::cieTableAt(wmlt::cie::kD65[0], 107, 300, l);
            for (int k = 0; k < 3; ++k) xyzW[j][k] = w * d * wmlt::cieTableAt(wmlt::cie::kXyz[k], 95, 360, l);
            yD65 += xyzW[j][1];
        }
        for (double& v : whiteXyz) v = 0;
        for (int j = 0; j < kSamples; ++j)
            for (int k = 0; k < 3; ++k) whiteXyz[k] += (xyzW[j][k] /= yD65);
        wmlt::xyzToSrgbMatrix(whiteXyz, toRgb);
        wmlt::invert3(toRgb, toXyz);
        for (int j = 0; j < kSamples; ++j)
            for (int k = 0; k < 3; ++k) {
                rgbWeight[j][k] = 0;
                for (int m = 0; m < 3; ++m) rgbWeight[j][k] += toRgb[k][m] * xyzW[j][m];
            }
    }

    // The RGB of the spectrum of c.
    void rgbOf(const double c[3], double rgb[3]) const {
        rgb[0] = rgb[1] = rgb[2] = 0;
        for (int j = 0; j < kSamples; ++j) {
            const double t = double(j) / double(kSamples - 1), x = (c[0] * t + c[1]) * t + c[2];
            const double s = 0.5 + x / (2.0 * std::sqrt(1.0 + x * x));
            for (int k = 0; k < 3; ++k) rgb[k] += s * rgbWeight[j][k];
        }
    }

    // RGB -> XYZ -> CIELAB (white: whiteXyz).
    void labOf(const double rgb[3], double lab[3]) const {
        double xyz[3];
        for (int k = 0; k < 3; ++k) xyz[k] = toXyz[k][0] * rgb[0] + toXyz[k][1] * rgb[1] + toXyz[k][2] * rgb[2];
        auto f = [](double t) {
            const double d = 6.0 / 29.0;
            return t > d * d * d ? std::cbrt(t) : t / (3 * d * d) + 4.0 / 29.0;
        };
        const double fx = f(xyz[0] / whiteXyz[0]), fy = f(xyz[1] / whiteXyz[1]), fz = f(xyz[2] / whiteXyz[2]);
        lab[0] = 116 * fy - 16;
        lab[1] = 500 * (fx - fy);
        lab[2] = 200 * (fy - fz);
    }

    // CIELAB of c's spectrum minus the target's.
    void residual(const double c[3], const double targetLab[3], double r[3]) const {
        double rgb[3], lab[3];
        rgbOf(c, rgb);
        labOf(rgb, lab);
        for (int k = 0; k < 3; ++k) r[k] = lab[k] - targetLab[k];
    }

    // Gauss-Newton from c (in place); returns the final residual's norm.
    double fit(const double rgb[3], double c[3]) const {
        double target[3], r[3];
        labOf(rgb, target);
        double norm = 0;
        for (int it = 0; it < 40; ++it) {
            residual(c, target, r);
            norm = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
            if (norm < 1e-6) break;
            double J[3][3];
            for (int i = 0; i < 3; ++i) {
                double cp[3] = {c[0], c[1], c[2]}, rp[3];
                const double h = 1e-5 * std::max(1.0, std::abs(c[i]));
                cp[i] += h;
                residual(cp, target, rp);
                for (int k = 0; k < 3; ++k) J[k][i] = (rp[k] - r[k]) / h;
            }
            // Solve J d = r by Cramer's rule (3 x 3).
            const double det = J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) - J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
                               J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
            if (!(std::abs(det) > 1e-300)) break;
            double d[3];
            for (int i = 0; i < 3; ++i) {
                double A[3][3];
                for (int a = 0; a < 3; ++a)
                    for (int b = 0; b < 3; ++b) A[a][b] = b == i ? r[a] : J[a][b];
                d[i] = (A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) - A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) +
                        A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0])) /
                       det;
            }
            for (int i = 0; i < 3; ++i) c[i] -= d[i];
            // Keep the polynomial's range sane (a step past it is a divergence, not a fit).
            const double big = std::max({std::abs(c[0]), std::abs(c[1]), std::abs(c[2])});
            if (big > 1e4)
                for (int i = 0; i < 3; ++i) c[i] *= 1e4 / big;
        }
        return norm;
    }
};

// The table as OUT.bin and OUT.cpp, which embeds it (.incbin) for the renderer.
bool writeTable(const std::vector<float>& table, const char* binPath, const char* cppPath) {
    std::ofstream bin(binPath, std::ios::binary);
    bin.write(reinterpret_cast<const char*>(table.data()), std::streamsize(table.size() * sizeof(float)));
    std::ofstream cpp(cppPath);
    cpp << "// Generated by cmake/rgb_sigmoid_fit.cpp: do not edit. The RGB-to-spectrum table (kernels/spectral.h).\n"
           "asm(\".section .rodata\\n.balign 16\\n.global wmlt_rgb_sigmoid_srgb\\nwmlt_rgb_sigmoid_srgb:\\n.incbin \\\""
        << binPath << "\\\"\\n.global wmlt_rgb_sigmoid_srgb_end\\nwmlt_rgb_sigmoid_srgb_end:\\n.previous\\n\");\n";
    if (bin && cpp) return true;
    std::fprintf(stderr, "rgb_sigmoid_fit: could not write %s or %s\n", binPath, cppPath);
    return false;
}

}  // namespace

int main(int argc, char** argv) {
    const bool from = argc == 5 && std::string(argv[3]) == "--from";
    if (argc != 3 && !from) {
        std::fprintf(stderr, "usage: %s OUT.bin OUT.cpp [--from TABLE.bin]\n", argv[0]);
        return 2;
    }
    constexpr size_t kEntries = size_t(3) * kSigmoidTableRes * kSigmoidTableRes * kSigmoidTableRes * 3;
    if (from) {
        std::vector<float> table(kEntries);
        std::ifstream in(argv[4], std::ios::binary);
        in.read(reinterpret_cast<char*>(table.data()), std::streamsize(table.size() * sizeof(float)));
        if (!in || in.peek() != std::ifstream::traits_type::eof()) {
            std::fprintf(stderr, "rgb_sigmoid_fit: %s is not a table of %zu floats\n", argv[4], kEntries);
            return 1;
        }
        return writeTable(table, argv[1], argv[2]) ? 0 : 1;
    }
    const Model model;
    constexpr int res = kSigmoidTableRes;
    std::vector<float> table(kEntries);
    std::vector<double> worst(size_t(3) * res * res, 0.0);
    tbb::parallel_for(0, 3 * res * res, [&](int column) {
        const int l = column / (res * res), j = column / res % res, k = column % res;  // channel, y, x
        const double x = double(k) / (res - 1), y = double(j) / (res - 1);
        const int start = res / 5;
        double c[3] = {0, 0, 0}, cStart[3] = {0, 0, 0};
        auto solve = [&](int i) {
            const double z = wmlt::sigmoidTableZ(i);
            double rgb[3];
            rgb[l] = z;
            rgb[(l + 1) % 3] = x * z;
            rgb[(l + 2) % 3] = y * z;
            const double r = model.fit(rgb, c);
            // Colours darker than 1e-4 (the first 3 nodes of z) are left out of the figure: the
            // Lab residual there is large (Lab's a and b amplify tiny errors near black), the
            // RGB error below 1e-4.
            if (z >= 1e-4) worst[size_t(column)] = std::max(worst[size_t(column)], r);
            float* out = &table[((size_t(l) * res + size_t(i)) * res * res + size_t(j) * res + size_t(k)) * 3];
            for (int m = 0; m < 3; ++m) out[m] = float(c[m]);
        };
        for (int i = start; i < res; ++i) {
            solve(i);
            if (i == start)
                for (int m = 0; m < 3; ++m) cStart[m] = c[m];
        }
        for (int m = 0; m < 3; ++m) c[m] = cStart[m];
        for (int i = start - 1; i >= 0; --i) solve(i);
    });
    double most = 0;
    for (double w : worst) most = std::max(most, w);
    if (!writeTable(table, argv[1], argv[2])) return 1;
    std::printf("rgb_sigmoid_fit: %d^3 x 3 entries, largest CIELAB residual %.3g (colours of max(rgb) >= 1e-4)\n", res, most);
    return 0;
}
