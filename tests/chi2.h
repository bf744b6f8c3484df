// Test helpers: a small PCG32, adaptive Simpson quadrature, the regularised incomplete
// gamma function and Pearson's chi-square goodness-of-fit test of a direction sampler
// against its pdf (the method of Mitsuba's `chi2` test: histogram on the sphere, expected
// counts by numerical integration of the pdf, sparse bins pooled, p-value from Q(k/2, x/2)).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

#include "image/compare.h"
#include "wavemmlt/math.h"

namespace chi2 {

// Degrees to radians, and the unit direction at polar angle theta from +z and azimuth phi
// from +x (degrees): the BSDF tests' incident directions.
constexpr double kDeg = M_PI / 180;
inline wmlt::Vec3 dirAt(double thetaDeg, double phiDeg) {
    double t = thetaDeg * kDeg, p = phiDeg * kDeg;
    return wmlt::Vec3(float(std::sin(t) * std::cos(p)), float(std::sin(t) * std::sin(p)), float(std::cos(t)));
}
// a and b agree to rel of the larger, plus abs (for values near 0).
inline bool close(double a, double b, double rel = 1e-4, double abs = 1e-7) {
    return std::fabs(a - b) <= rel * std::max(std::fabs(a), std::fabs(b)) + abs;
}

// PCG32 (O'Neill 2014), XSH-RR output.
struct Pcg32 {
    uint64_t state = 0x853c49e6748fea9bULL, inc = 0xda3e39cb94b95bdbULL;
    explicit Pcg32(uint64_t seed, uint64_t seq = 1) {
        state = 0;
        inc = (seq << 1u) | 1u;
        next();
        state += seed;
        next();
    }
    uint32_t next() {
        uint64_t old = state;
        state = old * 6364136223846793005ULL + inc;
        uint32_t xs = uint32_t(((old >> 18u) ^ old) >> 27u), rot = uint32_t(old >> 59u);
        return (xs >> rot) | (xs << ((32 - rot) & 31));
    }
    // Midpoints of a 2^24 grid: a discretised U(0, 1) that never returns 0 exactly (the
    // endpoints u = 0, 1 are measure-zero edge cases, tested separately).
    float uniform() { return (float(next() >> 8) + 0.5f) * 0x1p-24f; }
};

// Adaptive Simpson on [a, b] (Lyness 1969), absolute tolerance eps, depth-limited.
template <class F>
double simpsonRec(const F& f, double a, double b, double fa, double fm, double fb, double whole, double eps, int depth) {
    double m = 0.5 * (a + b), lm = 0.5 * (a + m), rm = 0.5 * (m + b);
    double flm = f(lm), frm = f(rm);
    double left = (m - a) / 6 * (fa + 4 * flm + fm), right = (b - m) / 6 * (fm + 4 * frm + fb);
    double delta = left + right - whole;
    if (depth <= 0 || std::fabs(delta) <= 15 * eps) return left + right + delta / 15;
    return simpsonRec(f, a, m, fa, flm, fm, left, eps / 2, depth - 1) + simpsonRec(f, m, b, fm, frm, fb, right, eps / 2, depth - 1);
}
template <class F>
double adaptiveSimpson(const F& f, double a, double b, double eps = 1e-9, int depth = 14, int pieces = 4) {
    double sum = 0, h = (b - a) / pieces;  // a few initial pieces so that no lobe is missed
    for (int i = 0; i < pieces; ++i) {
        double x0 = a + i * h, x1 = x0 + h, fa = f(x0), fm = f(0.5 * (x0 + x1)), fb = f(x1);
        sum += simpsonRec(f, x0, x1, fa, fm, fb, h / 6 * (fa + 4 * fm + fb), eps / pieces, depth);
    }
    return sum;
}
// Nested 2D version: integral of f(x, y) over [x0, x1] x [y0, y1].
template <class F>
double adaptiveSimpson2D(const F& f, double x0, double x1, double y0, double y1, double eps = 1e-9, int depth = 8) {
    auto inner = [&](double x) { return adaptiveSimpson([&](double y) { return f(x, y); }, y0, y1, eps / (x1 - x0 + 1e-300), depth); };
    return adaptiveSimpson(inner, x0, x1, eps, depth);
}

using rstats::gammaQ;  // (image/compare.h)

struct Result {
    double stat = 0, pValue = 0;
    int dof = 0;
    std::string message;  // why the test failed outright, if it did
};

// Pearson's test. Bins are sorted by expected count and pooled from the smallest up
// until each pooled cell expects >= minExpected. A sample in a bin of zero expected
// count is a failure (p = 0): the sampler produced a direction its pdf says is impossible.
inline Result pearson(const std::vector<double>& obs, const std::vector<double>& expd, double minExpected = 5) {
    Result r;
    std::vector<size_t> idx(obs.size());
    std::iota(idx.begin(), idx.end(), size_t(0));
    std::sort(idx.begin(), idx.end(), [&](size_t a, size_t b) { return expd[a] < expd[b]; });
    std::vector<std::pair<double, double>> cells;
    double po = 0, pe = 0;
    for (size_t i : idx) {
        if (expd[i] <= 0) {
            if (obs[i] > 0) {
                std::ostringstream s;
                s << "bin " << i << " has " << obs[i] << " samples but expected count 0";
                r.message = s.str();
                return r;
            }
            continue;
        }
        po += obs[i];
        pe += expd[i];
        if (pe >= minExpected) {
            cells.emplace_back(po, pe);
            po = pe = 0;
        }
    }
    if (pe > 0) {
        if (cells.empty()) cells.emplace_back(po, pe);
        else {
            cells.back().first += po;
            cells.back().second += pe;
        }
    }
    for (auto& c : cells) r.stat += (c.first - c.second) * (c.first - c.second) / c.second;
    r.dof = int(cells.size()) - 1;
    r.pValue = r.dof > 0 ? gammaQ(0.5 * r.dof, 0.5 * r.stat) : 1.0;
    return r;
}

// Bins on the sphere in spherical coordinates (theta, phi) about frame.n.
struct SphereBins {
    wmlt::Frame frame = wmlt::Frame::fromNormal({0, 0, 1});
    double s[3] = {1, 0, 0}, t[3] = {0, 1, 0}, n[3] = {0, 0, 1};
    std::vector<double> thetaEdges;  // increasing, 0 .. pi
    int nPhi = 20;

    static SphereBins uniform(wmlt::Vec3 axis, int nTheta, int nPhi) {
        SphereBins b;
        b.setAxis(axis);
        for (int i = 0; i <= nTheta; ++i) b.thetaEdges.push_back(M_PI * i / nTheta);
        b.nPhi = nPhi;
        return b;
    }
    // Theta edges at the quantiles of a power-cosine lobe of exponent n about axis
    // (nLobe bins in the upper hemisphere, nLower uniform bins below): any partition is
    // valid for the test, this one keeps sharp lobes resolved.
    static SphereBins lobe(wmlt::Vec3 axis, double n, int nLobe, int nLower, int nPhi) {
        SphereBins b;
        b.setAxis(axis);
        for (int i = 0; i < nLobe; ++i) b.thetaEdges.push_back(std::acos(std::pow(1.0 - double(i) / nLobe, 1.0 / (n + 1))));
        for (int i = 0; i <= nLower; ++i) b.thetaEdges.push_back(0.5 * M_PI * (1.0 + double(i) / nLower));
        b.nPhi = nPhi;
        return b;
    }
    int count() const { return int(thetaEdges.size() - 1) * nPhi; }
    // theta from atan2 of the components in the double frame: exact for small angles too
    // (acos of a z rounded near 1 would bin a narrow cone in rings).
    void local(wmlt::Vec3 w, double l[3]) const {
        const double v[3] = {w.x, w.y, w.z};
        l[0] = l[1] = l[2] = 0;
        for (int i = 0; i < 3; ++i) {
            l[0] += s[i] * v[i];
            l[1] += t[i] * v[i];
            l[2] += n[i] * v[i];
        }
    }
    double theta(wmlt::Vec3 w) const {
        double l[3];
        local(w, l);
        return std::atan2(std::sqrt(l[0] * l[0] + l[1] * l[1]), l[2]);
    }
    int index(wmlt::Vec3 w) const {
        double l[3];
        local(w, l);
        double th = std::atan2(std::sqrt(l[0] * l[0] + l[1] * l[1]), l[2]), ph = std::atan2(l[1], l[0]);
        if (ph < 0) ph += 2 * M_PI;
        int it = int(std::upper_bound(thetaEdges.begin(), thetaEdges.end(), th) - thetaEdges.begin()) - 1;
        it = std::min(std::max(it, 0), int(thetaEdges.size()) - 2);
        int ip = std::min(int(ph / (2 * M_PI) * nPhi), nPhi - 1);
        return it * nPhi + ip;
    }
    // In double, rounded once to float: a float frame would make the directions
    // systematically non-unit by ~1e-7, which biases cos^n for n ~ 1e4 by ~1e-3.
    wmlt::Vec3 dir(double th, double ph) const {
        double l[3] = {std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)}, w[3];
        for (int i = 0; i < 3; ++i) w[i] = s[i] * l[0] + t[i] * l[1] + n[i] * l[2];
        return wmlt::Vec3(float(w[0]), float(w[1]), float(w[2]));
    }
    void setAxis(wmlt::Vec3 axis) {  // frame for binning (float) and an orthonormal double one
        double len = std::sqrt(double(axis.x) * axis.x + double(axis.y) * axis.y + double(axis.z) * axis.z);
        n[0] = axis.x / len;
        n[1] = axis.y / len;
        n[2] = axis.z / len;
        double a[3] = {0, 0, 0};
        a[std::fabs(n[2]) < 0.9 ? 2 : 0] = 1;
        s[0] = a[1] * n[2] - a[2] * n[1];
        s[1] = a[2] * n[0] - a[0] * n[2];
        s[2] = a[0] * n[1] - a[1] * n[0];
        double sl = std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
        for (double& x : s) x /= sl;
        t[0] = n[1] * s[2] - n[2] * s[1];
        t[1] = n[2] * s[0] - n[0] * s[2];
        t[2] = n[0] * s[1] - n[1] * s[0];
        // bin in the same (double) frame
        frame.s = wmlt::Vec3(float(s[0]), float(s[1]), float(s[2]));
        frame.t = wmlt::Vec3(float(t[0]), float(t[1]), float(t[2]));
        frame.n = wmlt::Vec3(float(n[0]), float(n[1]), float(n[2]));
    }
    // Integral of pdf(w) over each bin (solid angle measure: sin(theta) dtheta dphi).
    template <class Pdf>
    std::vector<double> integrate(const Pdf& pdf, double eps = 1e-7, int depth = 8) const {
        std::vector<double> out(count());
        // Simpson samples the bin's edges; nudge them inwards by 1e-9 of the bin so that a
        // pdf discontinuous on an edge (the horizon) is sampled on the bin's own side.
        auto in = [](double a, double b, double& a2, double& b2) {
            a2 = a + 1e-9 * (b - a);
            b2 = b - 1e-9 * (b - a);
        };
        for (size_t it = 0; it + 1 < thetaEdges.size(); ++it)
            for (int ip = 0; ip < nPhi; ++ip) {
                double t0, t1, p0, p1;
                in(thetaEdges[it], thetaEdges[it + 1], t0, t1);
                in(2 * M_PI * ip / nPhi, 2 * M_PI * (ip + 1) / nPhi, p0, p1);
                out[it * nPhi + ip] =
                    adaptiveSimpson2D([&](double th, double ph) { return double(pdf(dir(th, ph))) * std::sin(th); }, t0, t1, p0, p1, eps, depth);
            }
        return out;
    }
};

// Draws nSamples directions with sample(rng, w) (returns false for a rejected sample,
// counted in an extra bin whose expected probability is missingMass) and compares
// the histogram with the integral of pdf over the bins.
template <class Sample, class Pdf>
Result sphereTest(const Sample& sample, const Pdf& pdf, const SphereBins& bins, int nSamples, double missingMass = 0, uint64_t seed = 1) {
    std::vector<double> expd = bins.integrate(pdf), obs(expd.size() + 1, 0.0);
    for (double& e : expd) e *= nSamples;
    expd.push_back(missingMass * nSamples);
    Pcg32 rng(seed);
    wmlt::Vec3 w;
    for (int i = 0; i < nSamples; ++i) {
        if (sample(rng, w)) obs[bins.index(w)] += 1;
        else obs.back() += 1;
    }
    return pearson(obs, expd);
}

inline std::string describe(const Result& r) {
    std::ostringstream s;
    s << "chi2 = " << r.stat << ", dof = " << r.dof << ", p = " << r.pValue << " " << r.message;
    return s.str();
}

}  // namespace chi2
