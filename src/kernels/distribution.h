// Piecewise-constant sampling distributions (the method of pbrt-v3, sections 13.6.1 and
// 14.2.4): Distribution1D over [0, 1) from n non-negative values, Distribution2D over
// [0, 1)^2 as a marginal over rows and a conditional per row. Construction allocates;
// sampling and pdf evaluation are const and allocation-free.
// Negative and non-finite values count as 0. When every value is 0 the distribution
// falls back to uniform (so sampling always returns a point of positive pdf).
#pragma once
#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace wmlt {

class Distribution1D {
public:
    std::vector<float> func;  // the values (clamped to >= 0, finite)
    std::vector<float> cdf;   // n + 1 entries, cdf[0] = 0, cdf[n] = 1
    float funcInt = 0;        // integral of func over [0, 1]: sum / n
    bool uniform = true;      // all-zero input: sampled and evaluated as uniform

    Distribution1D() = default;
    explicit Distribution1D(const std::vector<float>& f) { build(f.data(), f.size()); }
    Distribution1D(const float* f, size_t n) { build(f, n); }

    void build(const float* f, size_t n) {
        func.assign(f, f + n);
        for (float& v : func)
            if (!(v > 0) || !std::isfinite(v)) v = 0;
        cdf.assign(n + 1, 0.0f);
        double sum = 0;
        std::vector<double> acc(n + 1, 0.0);
        for (size_t i = 0; i < n; ++i) acc[i + 1] = (sum += func[i]);
        funcInt = n ? float(sum / double(n)) : 0.0f;
        uniform = !(sum > 0);
        for (size_t i = 1; i <= n; ++i) cdf[i] = uniform ? float(double(i) / double(n)) : float(acc[i] / sum);
        if (n) cdf[n] = 1.0f;
    }

    int count() const { return int(func.size()); }

    // Density (with respect to x in [0, 1)) of the bin containing x.
    float pdf(float x) const {
        const int n = count();
        if (n == 0) return 0.0f;
        if (uniform) return 1.0f;
        return func[binOf(x)] / funcInt;
    }
    // Probability of bin i for sampleDiscrete.
    float discretePmf(int i) const {
        const int n = count();
        if (i < 0 || i >= n) return 0.0f;
        return uniform ? 1.0f / float(n) : cdf[i + 1] - cdf[i];
    }

    // x in [0, 1) with density pdf(x); offset: the bin. u in [0, 1).
    float sampleContinuous(float u, float* pdfOut = nullptr, int* offset = nullptr) const {
        const int n = count();
        if (n == 0) {
            if (pdfOut) *pdfOut = 0;
            if (offset) *offset = 0;
            return 0.0f;
        }
        const int o = find(u);
        if (offset) *offset = o;
        float du = u - cdf[o];
        const float width = cdf[o + 1] - cdf[o];
        if (width > 0) du /= width;
        du = std::min(std::max(du, 0.0f), 1.0f);
        if (pdfOut) *pdfOut = uniform ? 1.0f : func[o] / funcInt;
        const float x = (float(o) + du) / float(n);
        return std::min(x, kOneMinusEpsilon);
    }

    // A bin index with probability func[i] / sum; pmf: that probability.
    int sampleDiscrete(float u, float* pmf = nullptr, float* uRemapped = nullptr) const {
        const int n = count();
        if (n == 0) {
            if (pmf) *pmf = 0;
            return 0;
        }
        const int o = find(u);
        if (pmf) *pmf = discretePmf(o);
        if (uRemapped) {
            const float width = cdf[o + 1] - cdf[o];
            *uRemapped = width > 0 ? std::min(std::max((u - cdf[o]) / width, 0.0f), kOneMinusEpsilon) : 0.0f;
        }
        return o;
    }

    static constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;

private:
    // The bin of x in [0, 1) (clamped).
    int binOf(float x) const {
        const int n = count();
        int i = x >= 0 ? int(x * float(n)) : 0;  // NaN -> 0
        return std::min(std::max(i, 0), n - 1);
    }
    // The last i with cdf[i] <= u: a bin of positive width when u in [0, 1). Up to 32 bins
    // (a scene's lights) by counting the entries <= u, upper_bound's index without the
    // branches that random u mispredict; more (an environment map's rows) by its search.
    int find(float u) const {
        const int n = count();
        if (!(u > 0)) u = 0;
        u = std::min(u, kOneMinusEpsilon);
        int i;
        if (n <= 32) {
            i = -1;
            for (int k = 0; k <= n; ++k) i += cdf[size_t(k)] <= u ? 1 : 0;
        } else {
            i = int(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin()) - 1;
        }
        return std::min(std::max(i, 0), n - 1);
    }
};

// func is nu x nv, row-major (row y = v, column x = u). Samples (x, y) in [0, 1)^2 with
// density proportional to func: x from the conditional of y's row, y from the marginal.
class Distribution2D {
public:
    std::vector<Distribution1D> conditional;  // one per row
    Distribution1D marginal;                  // over rows: each row's integral

    Distribution2D() = default;
    Distribution2D(const std::vector<float>& f, int nu, int nv) { build(f.data(), nu, nv); }

    void build(const float* f, int nu, int nv) {
        conditional.clear();
        conditional.reserve(size_t(std::max(nv, 0)));
        std::vector<float> rowInt(size_t(std::max(nv, 0)));
        for (int y = 0; y < nv; ++y) {
            conditional.emplace_back(f + size_t(y) * size_t(nu), size_t(nu));
            rowInt[y] = conditional.back().funcInt;
        }
        marginal = Distribution1D(rowInt);
    }

    int width() const { return conditional.empty() ? 0 : conditional[0].count(); }
    int height() const { return int(conditional.size()); }

    // (x, y) in [0, 1)^2 from (u1, u2) in [0, 1)^2, with its density.
    void sampleContinuous(float u1, float u2, float& x, float& y, float* pdfOut = nullptr) const {
        if (conditional.empty() || width() == 0) {
            x = y = 0;
            if (pdfOut) *pdfOut = 0;
            return;
        }
        float pdfY, pdfX;
        int row;
        y = marginal.sampleContinuous(u2, &pdfY, &row);
        x = conditional[row].sampleContinuous(u1, &pdfX);
        if (pdfOut) *pdfOut = pdfX * pdfY;
    }

    // The same, returning (x, y).
    std::pair<float, float> sampleContinuous(float u1, float u2, float* pdfOut) const {
        std::pair<float, float> xy;
        sampleContinuous(u1, u2, xy.first, xy.second, pdfOut);
        return xy;
    }

    // The density of (x, y), consistent with sampleContinuous.
    float pdf(float x, float y) const {
        if (conditional.empty() || width() == 0) return 0.0f;
        const int nv = height();
        int row = y >= 0 ? int(y * float(nv)) : 0;
        row = std::min(std::max(row, 0), nv - 1);
        return marginal.pdf(y) * conditional[row].pdf(x);
    }
};

}  // namespace wmlt
