// Pixel reconstruction filters (docs/filters.md): pixel (x, y) of the image is
//   I(x, y) = int_film f(p - c) L(p) dp / int_film f(p - c) dp,   c = (x + 1/2, y + 1/2),
// the filter-weighted mean of the image plane about the pixel's centre, the filter cut at
// the film's edge and renormalised there (Mitsuba 3's hdrfilm; inside the film the
// denominator is int f). Every filter is separable, f(x, y) = f(x) f(y), so the
// normalisation of pixel (x, y) is normX[x] normY[y] (filterNorm).
// Camera-side samples (PT, BPT's t >= 2, LT's directly seen environment) use filter
// importance sampling: the pixel's sample lands at c + (dx, dy), dx drawn from |f|
// tabulated and restricted to the film (sampleFilterInFilm), and carries
// f(dx) f(dy) / (pdf(dx) pdf(dy)) normX normY, negative in a negative lobe. Light-side contributions (LT,
// BPT's t = 1, every MMLT splat) land at a film point p and are spread over the pixels
// whose footprint holds it, weighted f(p - c) normX normY (forEachFilterPixel). Both
// estimate I(x, y): every tracer converges to the same image for every filter. The box
// filter of radius 1/2 is the pixel's plain mean, computed as before (`box`).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "kernels/sampling.h"
#include "wavemmlt/scene_desc.h"

namespace wmlt {

constexpr float kMaxFilterRadius = 16;  // pixels (the footprint's weights fit a fixed array)

// f(x) of one axis (Mitsuba 3's rfilters, pbrt-v4's Filter::Evaluate; 0 beyond the radius).
inline float filterValue(const FilterDesc& d, float x) {
    const float a = std::fabs(x);
    if (!(a < d.radius)) return 0.0f;
    switch (d.kind) {
        case FilterKind::Box: return 1.0f;
        case FilterKind::Tent: return 1.0f - a / d.radius;
        case FilterKind::Gaussian: {
            const float k = -0.5f / (d.stddev * d.stddev);
            return std::max(0.0f, std::exp(k * a * a) - std::exp(k * d.radius * d.radius));
        }
        case FilterKind::Mitchell: {  // Mitchell and Netravali 1988, at t = 2 |x| / radius in [0, 2)
            const float t = 2.0f * a / d.radius, t2 = t * t, t3 = t2 * t, B = d.B, C = d.C;
            return (1.0f / 6.0f) * (t < 1 ? (12 - 9 * B - 6 * C) * t3 + (-18 + 12 * B + 6 * C) * t2 + (6 - 2 * B)
                                          : (-B - 6 * C) * t3 + (6 * B + 30 * C) * t2 + (-12 * B - 48 * C) * t + (8 * B + 24 * C));
        }
        case FilterKind::Lanczos: {  // sinc(x) sinc(x / tau)
            if (a < 1e-5f) return 1.0f;
            const float x1 = kPi * a, x2 = x1 / d.tau;
            return std::sin(x1) * std::sin(x2) / (x1 * x2);
        }
    }
    return 0.0f;
}

// The filter with its sampling table: |f| over [-radius, radius) in kBins equal bins,
// piecewise constant (each bin's mean |f|, at least 1e-4 of the mean bin so that the
// density is positive wherever f may be non-zero).
struct PixelFilter {
    static constexpr int kBins = 256;
    FilterDesc desc;
    bool box = true;  // box of radius 1/2: each sample in its pixel, weight 1
    float radius = 0.5f;
    double integral = 1;  // int f over one axis
    float cdf[kBins + 1] = {};
    float binPdf[kBins] = {};  // the density (per pixel of x) in bin i
    // guide[j]: the last bin i with cdf[i] <= j / kGuide, where sampleFilter's search for
    // u in [j / kGuide, (j + 1) / kGuide) starts (a binary search's unpredictable branches
    // were most of a filtered camera ray's cost).
    static constexpr int kGuide = 1024;
    uint16_t guide[kGuide] = {};
    // Gaussian: filterValue's exponent factor and its value at the radius, made once.
    float gaussK = 0, gaussBias = 0;
};

// filterValue(f.desc, x), bit for bit, with the Gaussian's constants made once (the
// per-sample and per-splat evaluations).
inline float filterValue(const PixelFilter& f, float x) {
    if (f.desc.kind != FilterKind::Gaussian) return filterValue(f.desc, x);
    const float a = std::fabs(x);
    if (!(a < f.desc.radius)) return 0.0f;
    return std::max(0.0f, std::exp(f.gaussK * a * a) - f.gaussBias);
}

// int_a^b f(x) dx by 3-point Gauss-Legendre on 256 panels per piece, the pieces split at
// the filters' kinks (0, +-radius/2); no end point is evaluated (the box jumps there).
inline double integrateFilter(const FilterDesc& d, double a, double b) {
    if (!(b > a)) return 0.0;
    double cuts[5] = {a, b, b, b, b};
    int n = 1;
    for (double k : {-0.5 * d.radius, 0.0, 0.5 * d.radius})
        if (k > a && k < b) cuts[n++] = k;
    cuts[n] = b;
    const double node = std::sqrt(0.6);
    double sum = 0;
    for (int s = 0; s < n; ++s) {
        const double h = (cuts[s + 1] - cuts[s]) / 256;
        for (int i = 0; i < 256; ++i) {
            const double m = cuts[s] + (i + 0.5) * h, r = 0.5 * h * node;
            sum +=
                h * (5 * double(filterValue(d, float(m - r))) + 8 * double(filterValue(d, float(m))) + 5 * double(filterValue(d, float(m + r)))) / 18;
        }
    }
    return sum;
}

inline PixelFilter makePixelFilter(const FilterDesc& d) {
    PixelFilter f;
    f.desc = d;
    f.radius = d.radius;
    f.box = d.kind == FilterKind::Box && d.radius == 0.5f;
    if (d.kind == FilterKind::Gaussian) {  // filterValue's expressions, evaluated once
        f.gaussK = -0.5f / (d.stddev * d.stddev);
        f.gaussBias = std::exp(f.gaussK * d.radius * d.radius);
    }
    f.integral = integrateFilter(d, -double(d.radius), double(d.radius));
    double mass[PixelFilter::kBins], total = 0;
    const double width = 2.0 * double(d.radius) / PixelFilter::kBins;
    for (int i = 0; i < PixelFilter::kBins; ++i) {
        double m = 0;
        for (int j = 0; j < 16; ++j) m += std::fabs(double(filterValue(d, float(-double(d.radius) + (i + (j + 0.5) / 16) * width))));
        total += mass[i] = m / 16;
    }
    double acc = 0;
    const double floor = 1e-4 * total / PixelFilter::kBins;
    for (double& m : mass) m = std::max(m, floor);
    total = 0;
    for (double m : mass) total += m;
    for (int i = 0; i < PixelFilter::kBins; ++i) {
        f.cdf[i] = float(acc / total);
        acc += mass[i];
        f.binPdf[i] = float(mass[i] / total / width);
    }
    f.cdf[PixelFilter::kBins] = 1.0f;
    for (int j = 0, i = 0; j < PixelFilter::kGuide; ++j) {
        const float u = float(j) / float(PixelFilter::kGuide);
        while (i + 1 < PixelFilter::kBins && f.cdf[i + 1] <= u) ++i;
        f.guide[j] = uint16_t(i);
    }
    return f;
}

// A point x in [-radius, radius) drawn with density pdf from u in [0, 1); returns
// f(x) / pdf(x) (negative in a negative lobe).
inline float sampleFilter(const PixelFilter& f, float u, float& x) {
    // The last bin i < kBins with cdf[i] <= u (upper_bound's answer), from the guide (u kGuide
    // is exact: kGuide is a power of two, so the guide's bin never starts past it).
    int i = f.guide[std::clamp(int(u * float(PixelFilter::kGuide)), 0, PixelFilter::kGuide - 1)];
    while (i + 1 < PixelFilter::kBins && f.cdf[i + 1] <= u) ++i;
    const float lo = f.cdf[i], hi = f.cdf[i + 1];
    const float t = hi > lo ? std::clamp((u - lo) / (hi - lo), 0.0f, 1.0f) : 0.5f;
    const float width = 2.0f * f.radius / float(PixelFilter::kBins);
    x = std::min(-f.radius + (float(i) + t) * width, std::nextafter(f.radius, 0.0f));
    return filterValue(f, x) / f.binPdf[i];
}

// The table's cdf at x in [-radius, radius] (linear within a bin, as sampleFilter inverts it).
inline float filterCdf(const PixelFilter& f, float x) {
    const float t = (x + f.radius) / (2.0f * f.radius) * float(PixelFilter::kBins);
    const int i = std::clamp(int(t), 0, PixelFilter::kBins - 1);
    const float frac = std::clamp(t - float(i), 0.0f, 1.0f);
    return f.cdf[i] + frac * (f.cdf[i + 1] - f.cdf[i]);
}

// A camera sample's offset from the centre of pixel i of n along one axis, drawn from the
// table restricted to the film (u in [0, 1) mapped into the cdf's range over
// [-min(radius, i + 1/2), min(radius, n - i - 1/2)]), so that no sample falls outside it;
// returns f(x) / pdf(x) of the restricted density (f / pdf times the range's mass).
inline float sampleFilterInFilm(const PixelFilter& f, float u, int i, int n, float& x) {
    const float c = float(i) + 0.5f;
    if (c - f.radius >= 0 && c + f.radius <= float(n)) return sampleFilter(f, u, x);
    const float a = filterCdf(f, std::max(-f.radius, -c)), b = filterCdf(f, std::min(f.radius, float(n) - c));
    return sampleFilter(f, a + u * (b - a), x) * (b - a);
}

// The normalisation of pixel i of n along one axis: 1 / int_0^n f(t - i - 1/2) dt (the
// filter's part inside the film; 1 / integral for a pixel whose footprint is inside).
inline double filterNorm(const PixelFilter& f, int i, int n) {
    const double c = double(i) + 0.5, r = double(f.radius);
    if (c - r >= 0 && c + r <= double(n)) return 1.0 / f.integral;
    const double inside = integrateFilter(f.desc, std::max(-r, -c), std::min(r, double(n) - c));
    return inside > 0 ? 1.0 / inside : 0.0;
}

// The pixels [x0, x1] x [y0, y1] whose centres are within the radius of (px, py) (a film point
// of a filter that is not the box of radius 1/2).
inline void filterFootprint(const PixelFilter& f, int width, int height, float px, float py, int& x0, int& x1, int& y0, int& y1) {
    const float r = f.radius;
    x0 = std::max(0, int(std::ceil(px - 0.5f - r)));
    x1 = std::min(width - 1, int(std::floor(px - 0.5f + r)));
    y0 = std::max(0, int(std::ceil(py - 0.5f - r)));
    y1 = std::min(height - 1, int(std::floor(py - 0.5f + r)));
}

// Calls add(pixel, weight) for every pixel of a width x height film whose filter footprint
// holds the film point (px, py), 0 <= px <= width, 0 <= py <= height (weight f(px - cx)
// normX[x] f(py - cy) normY[y]; zero weights are left out). The box filter of radius 1/2:
// the pixel holding the point, weight 1 (the far edges belong to the last pixels).
template <class Add>
inline void forEachFilterPixel(const PixelFilter& f, const float* normX, const float* normY, int width, int height, float px, float py, Add&& add) {
    if (f.box) {
        const int x = std::min(int(px), width - 1), y = std::min(int(py), height - 1);
        add(uint32_t(y) * uint32_t(width) + uint32_t(x), 1.0f);
        return;
    }
    int x0, x1, y0, y1;
    filterFootprint(f, width, height, px, py, x0, x1, y0, y1);
    constexpr int kMax = 2 * int(kMaxFilterRadius) + 2;
    float wx[kMax];
    for (int x = x0; x <= x1 && x - x0 < kMax; ++x) wx[x - x0] = filterValue(f, px - (float(x) + 0.5f)) * normX[x];
    for (int y = y0; y <= y1; ++y) {
        const float wy = filterValue(f, py - (float(y) + 0.5f)) * normY[y];
        if (wy == 0) continue;
        for (int x = x0; x <= x1 && x - x0 < kMax; ++x) {
            const float w = wx[x - x0] * wy;
            if (w != 0) add(uint32_t(y) * uint32_t(width) + uint32_t(x), w);
        }
    }
}

}  // namespace wmlt
