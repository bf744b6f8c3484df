// Comparing images and Monte Carlo renders (wavemmlt-img, the tests, the Python module's
// wavemmlt.diff and wavemmlt.compare_blocks), with tolerances taken from the measured
// variance (never hand-tuned):
//  - RunStats: per-element mean and standard error over K independent renders;
//  - Student t -> standard normal conversion (exact probability-integral transform, so
//    that z from a K-run standard error is N(0,1) when the run means are normal);
//  - zTest: for N independent z values, three checks sharing the false-alarm budget p:
//    sum z^2 ~ chi^2(N) (two-sided bounds; too much scatter, or too little: a wrong se),
//    max |z| below the Bonferroni bound Phi^-1(1 - p / (2N)) (a few bad elements), and
//    sqrt(N) * mean z ~ N(0, 1) (a small bias shared by all elements).
//  - diffImages: rmse, relMSE, mae and max |a - b| of an image against a reference
//    (wavemmlt-img diff).
#pragma once
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "wavemmlt/image.h"

namespace wmlt {

// An image against a reference of the same size, over all pixels and the three channels;
// values where either is NaN or infinite are left out of the means and counted.
struct ImageDiff {
    double rmse = 0;    // sqrt(mean((a - b)^2))
    double relmse = 0;  // mean((a - b)^2 / (b^2 + epsilon))
    double mae = 0;     // mean |a - b|
    double maxAbs = 0;  // max |a - b|
    size_t nonFinite = 0;
};
constexpr double kRelMseEpsilon = 1e-2;
// pixelError, when given: each pixel's squared error summed over its channels (infinite
// where a value was not finite). Throws InputError when the sizes differ.
ImageDiff diffImages(const Image& a, const Image& b, std::vector<double>* pixelError = nullptr);

}  // namespace wmlt

namespace rstats {

// Regularised upper incomplete gamma Q(a, x) = Gamma(a, x) / Gamma(a): series for
// x < a + 1, Lentz continued fraction otherwise (Numerical Recipes, 2nd ed., 6.2).
inline double gammaQ(double a, double x) {
    if (x <= 0) return 1.0;
    double lnPre = -x + a * std::log(x) - std::lgamma(a);
    if (x < a + 1) {
        double ap = a, del = 1.0 / a, sum = del;
        for (int n = 0; n < 100000 && std::fabs(del) > std::fabs(sum) * 1e-15; ++n) {
            ap += 1;
            del *= x / ap;
            sum += del;
        }
        return 1.0 - sum * std::exp(lnPre);
    }
    const double tiny = 1e-300;
    double b = x + 1 - a, c = 1 / tiny, d = 1 / b, h = d;
    for (int i = 1; i < 100000; ++i) {
        double an = -i * (i - a);
        b += 2;
        d = an * d + b;
        if (std::fabs(d) < tiny) d = tiny;
        c = b + an / c;
        if (std::fabs(c) < tiny) c = tiny;
        d = 1 / d;
        double del = d * c;
        h *= del;
        if (std::fabs(del - 1) < 1e-15) break;
    }
    return std::exp(lnPre) * h;
}

// ---- distributions -------------------------------------------------------------------

inline double normalCdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

// Phi^-1(p) for 0 < p < 1: Acklam's rational approximation refined by two Newton steps
// (relative error ~1e-15 well into the tails).
inline double normalQuantile(double p) {
    if (p <= 0) return -std::numeric_limits<double>::infinity();
    if (p >= 1) return std::numeric_limits<double>::infinity();
    static const double a[] = {-3.969683028665376e+01, 2.209460984245205e+02,  -2.759285104469687e+02,
                               1.383577518672690e+02,  -3.066479806614716e+01, 2.506628277459239e+00};
    static const double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02, 6.680131188771972e+01, -1.328068155288572e+01};
    static const double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                               -2.549732539343734e+00, 4.374664141464968e+00,  2.938163982698783e+00};
    static const double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00, 3.754408661907416e+00};
    const double pl = 0.02425;
    double x;
    if (p < pl) {
        double q = std::sqrt(-2 * std::log(p));
        x = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) / ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
    } else if (p <= 1 - pl) {
        double q = p - 0.5, r = q * q;
        x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
            (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1);
    } else {
        double q = std::sqrt(-2 * std::log(1 - p));
        x = -(((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) / ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
    }
    for (int i = 0; i < 2; ++i) {  // Newton on Phi(x) = p (Halley would be overkill)
        double e = normalCdf(x) - p;
        double pdf = std::exp(-0.5 * x * x) / std::sqrt(2 * M_PI);
        if (pdf > 0) x -= e / pdf;
    }
    return x;
}

// Regularised incomplete beta I_x(a, b) (Numerical Recipes 6.4, Lentz continued fraction).
inline double betaCf(double a, double b, double x) {
    const double tiny = 1e-300;
    double qab = a + b, qap = a + 1, qam = a - 1, c = 1, d = 1 - qab * x / qap;
    if (std::fabs(d) < tiny) d = tiny;
    d = 1 / d;
    double h = d;
    for (int m = 1; m <= 10000; ++m) {
        int m2 = 2 * m;
        double aa = m * (b - m) * x / ((qam + m2) * (a + m2));
        d = 1 + aa * d;
        if (std::fabs(d) < tiny) d = tiny;
        c = 1 + aa / c;
        if (std::fabs(c) < tiny) c = tiny;
        d = 1 / d;
        h *= d * c;
        aa = -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2));
        d = 1 + aa * d;
        if (std::fabs(d) < tiny) d = tiny;
        c = 1 + aa / c;
        if (std::fabs(c) < tiny) c = tiny;
        d = 1 / d;
        double del = d * c;
        h *= del;
        if (std::fabs(del - 1) < 1e-15) break;
    }
    return h;
}
inline double betaI(double a, double b, double x) {
    if (x <= 0) return 0;
    if (x >= 1) return 1;
    double lbt = std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log(1 - x);
    if (x < (a + 1) / (a + b + 2)) return std::exp(lbt) * betaCf(a, b, x) / a;
    return 1 - std::exp(lbt) * betaCf(b, a, 1 - x) / b;
}

// P(T > |t|) for Student's t with nu degrees of freedom (one tail).
inline double studentTail(double t, double nu) { return 0.5 * betaI(0.5 * nu, 0.5, nu / (nu + t * t)); }

// The standard normal z with the same tail probability as t under t(nu): exact
// probability-integral transform, computed from the tail to keep precision.
inline double tToZ(double t, double nu) {
    if (!std::isfinite(t)) return t;
    if (nu > 1e7) return t;
    double tail = studentTail(t, nu);
    double z = -normalQuantile(tail);
    return t < 0 ? -z : z;
}

// Two-sided Student t quantile: the t with P(|T| > t) = p.
inline double studentQuantileTwoSided(double p, double nu) {
    double lo = 0, hi = 1;
    while (2 * studentTail(hi, nu) > p) hi *= 2;
    for (int i = 0; i < 200; ++i) {
        double m = 0.5 * (lo + hi);
        (2 * studentTail(m, nu) > p ? lo : hi) = m;
    }
    return 0.5 * (lo + hi);
}

// x with P(chi^2(k) > x) = p (upper) by bisection on gammaQ.
inline double chiSquareUpperQuantile(double k, double p) {
    double lo = 0, hi = k + 10 * std::sqrt(2 * k) + 100;
    while (gammaQ(0.5 * k, 0.5 * hi) > p) hi *= 2;
    for (int i = 0; i < 200; ++i) {
        double m = 0.5 * (lo + hi);
        (gammaQ(0.5 * k, 0.5 * m) > p ? lo : hi) = m;
    }
    return 0.5 * (lo + hi);
}

// ---- per-element mean and standard error over K runs ---------------------------------

struct RunStats {
    std::vector<double> sum, sumSq;
    int runs = 0;
    void add(const std::vector<double>& v) {
        if (sum.empty()) {
            sum.assign(v.size(), 0.0);
            sumSq.assign(v.size(), 0.0);
        }
        for (size_t i = 0; i < v.size(); ++i) {
            sum[i] += v[i];
            sumSq[i] += v[i] * v[i];
        }
        ++runs;
    }
    size_t size() const { return sum.size(); }
    double mean(size_t i) const { return sum[i] / runs; }
    // Sample variance of one run's value (unbiased), then the standard error of the mean.
    double variance(size_t i) const {
        double m = mean(i);
        return std::max(0.0, (sumSq[i] - runs * m * m) / (runs - 1));
    }
    double se(size_t i) const { return std::sqrt(variance(i) / runs); }
    double dof() const { return runs - 1; }
};

// The image as doubles, channel c only (c < 0: all three interleaved).
inline std::vector<double> channel(const wmlt::Image& im, int c) {
    std::vector<double> v;
    size_t n = size_t(im.width) * im.height;
    for (size_t i = 0; i < n; ++i)
        if (c < 0)
            for (int k = 0; k < 3; ++k) v.push_back(im.rgb[i * 3 + k]);
        else v.push_back(im.rgb[i * 3 + c]);
    return v;
}

// Means over b x b blocks (the image size must be a multiple of b), channel c.
inline std::vector<double> blockMeans(const wmlt::Image& im, int b, int c) {
    int bw = im.width / b, bh = im.height / b;
    std::vector<double> v(size_t(bw) * bh, 0.0);
    for (int y = 0; y < bh * b; ++y)
        for (int x = 0; x < bw * b; ++x) v[size_t(y / b) * bw + x / b] += im.rgb[(size_t(y) * im.width + x) * 3 + c];
    for (double& x : v) x /= double(b) * b;
    return v;
}

// ---- the test -------------------------------------------------------------------------

struct ZTestResult {
    size_t n = 0;
    double meanZ2 = 0, lowMeanZ2 = 0, highMeanZ2 = 0;  // sum z^2 / n and its chi^2 bounds / n
    double maxAbsZ = 0, bonferroni = 0;
    size_t worst = 0;
    double worstValue = 0, worstExpected = 0, worstSe = 0;
    double meanZ = 0, meanZBound = 0;  // sqrt(N) mean z ~ N(0, 1): a shared bias
    bool pass = false;
    std::string describe() const {
        std::ostringstream o;
        o << "n=" << n << " mean z^2=" << meanZ2 << " (allowed [" << lowMeanZ2 << ", " << highMeanZ2 << "]) mean z=" << meanZ << " (allowed +-"
          << meanZBound << ") max|z|=" << maxAbsZ << " (allowed " << bonferroni << ") at element " << worst << ": value " << worstValue
          << " expected " << worstExpected << " se " << worstSe;
        return o.str();
    }
};

// z_i = tToZ((value_i - expected_i) / se_i, dof_i): N(0, 1) under the null. Checks, each
// at p / 3: sum z^2 inside the two-sided chi^2(n) interval, max |z| below
// Phi^-1(1 - p / (6 n)), |mean z| below Phi^-1(1 - p / 6) / sqrt(n). Elements with
// se == 0 must match exactly (up to relTol).
inline ZTestResult zTest(const std::vector<double>& value, const std::vector<double>& expected, const std::vector<double>& se,
                         const std::vector<double>& dof, double p = 1e-4, double exactRelTol = 1e-5) {
    ZTestResult r;
    // Elements with se == 0 (no variance: e.g. pixels that see only a constant sky) are
    // checked for an exact match and left out of the statistics of z.
    r.n = 0;
    double sumZ2 = 0, sumZ = 0;
    bool exactOk = true;
    for (size_t i = 0; i < value.size(); ++i) {
        double z;
        if (se[i] > 0) {
            z = tToZ((value[i] - expected[i]) / se[i], dof[i]);
            ++r.n;
        } else {
            bool ok = std::fabs(value[i] - expected[i]) <= exactRelTol * std::max(1e-30, std::fabs(expected[i]));
            exactOk = exactOk && ok;
            if (ok) continue;
            z = std::numeric_limits<double>::infinity();
            ++r.n;
        }
        if (!std::isfinite(value[i])) z = std::numeric_limits<double>::infinity();
        sumZ2 += z * z;
        sumZ += z;
        if (!(std::fabs(z) <= r.maxAbsZ)) {
            r.maxAbsZ = std::fabs(z);
            r.worst = i;
            r.worstValue = value[i];
            r.worstExpected = expected[i];
            r.worstSe = se[i];
        }
    }
    double n = double(std::max<size_t>(r.n, 1));
    r.meanZ2 = sumZ2 / n;
    r.meanZ = sumZ / n;
    const double q = p / 3;  // each of the three checks
    r.lowMeanZ2 = chiSquareUpperQuantile(n, 1 - q / 2) / n;
    r.highMeanZ2 = chiSquareUpperQuantile(n, q / 2) / n;
    r.bonferroni = -normalQuantile(q / (2 * n));
    r.meanZBound = -normalQuantile(q / 2) / std::sqrt(n);
    r.pass = exactOk && r.meanZ2 >= r.lowMeanZ2 && r.meanZ2 <= r.highMeanZ2 && r.maxAbsZ <= r.bonferroni && std::fabs(r.meanZ) <= r.meanZBound;
    return r;
}

// The common case: values are RunStats means, se from the same runs.
inline ZTestResult zTest(const RunStats& s, const std::vector<double>& expected, double p = 1e-4) {
    std::vector<double> v(s.size()), se(s.size()), dof(s.size(), s.dof());
    for (size_t i = 0; i < s.size(); ++i) {
        v[i] = s.mean(i);
        se[i] = s.se(i);
    }
    return zTest(v, expected, se, dof, p);
}

// z test of the difference of two sets of K-run means: se^2 = se_a^2 + se_b^2,
// Welch-Satterthwaite degrees of freedom.
inline ZTestResult compareRuns(const RunStats& a, const RunStats& b, double p, double* ratio = nullptr) {
    const size_t n = a.size();
    const double K = a.runs;
    std::vector<double> v(n), e(n), se(n), dof(n);
    double sumV = 0, sumE = 0;
    for (size_t i = 0; i < n; ++i) {
        v[i] = a.mean(i);
        e[i] = b.mean(i);
        double x = a.variance(i) / K, y = b.variance(i) / K;
        se[i] = std::sqrt(x + y);
        double den = x * x / (K - 1) + y * y / (K - 1);
        dof[i] = den > 0 ? (x + y) * (x + y) / den : K - 1;
        sumV += v[i];
        sumE += e[i];
    }
    if (ratio) *ratio = sumV / sumE;
    return zTest(v, e, se, dof, p);
}

}  // namespace rstats
