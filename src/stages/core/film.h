// The film: per-pixel sums (double) and sample counts, box filter. Each pixel's samples
// are added in a fixed order by the stages, so the image is the same for any threads.
#pragma once
#include <cstdint>
#include <vector>

#include "wavemmlt/image.h"
#include "wavemmlt/render.h"

namespace wmlt {

struct Film {
    int width = 0, height = 0;
    std::vector<double> sum;      // 3 per pixel
    std::vector<uint32_t> count;  // samples per pixel

    Film(int w, int h) : width(w), height(h), sum(size_t(w) * h * 3, 0.0), count(size_t(w) * h, 0) {}
    void add(uint32_t pixel, Vec3 L) {
        double* s = &sum[size_t(pixel) * 3];
        s[0] += L.x;
        s[1] += L.y;
        s[2] += L.z;
        ++count[pixel];
    }
    // Mean of each pixel's samples (black where a pixel has none).
    Image resolve() const {
        Image img(width, height);
        for (size_t i = 0; i < count.size(); ++i) {
            double inv = count[i] ? 1.0 / count[i] : 0.0;
            for (int c = 0; c < 3; ++c) img.rgb[i * 3 + c] = float(sum[i * 3 + c] * inv);
        }
        return img;
    }
};

// Luminance sums of contributions by path length, kept per batch and merged in a fixed
// order (RenderStats::lengthMeanLuminance).
struct PathLengthSums {
    double lum[kMaxPathLength + 1] = {};
    void add(int length, Vec3 c) { lum[length] += double(luminance(c)); }
    void add(const PathLengthSums& o) {
        for (int k = 0; k <= kMaxPathLength; ++k) lum[k] += o.lum[k];
    }
    // Means over an image of `pixels` pixels with `spp` samples each.
    std::vector<double> means(double pixels, double spp) const {
        std::vector<double> m(lum, lum + kMaxPathLength + 1);
        for (double& v : m) v = pixels * spp > 0 ? v / (pixels * spp) : 0.0;
        return m;
    }
};

// What every tracer's batch counts besides its film: NaN or Inf contributions (left out)
// and the luminance of the others by path length.
struct ContributionTally {
    uint64_t nonfinite = 0;
    PathLengthSums lengths;
    // Whether a contribution v of path length `length` is to be added (finite and not
    // black); counts it either way.
    bool take(Vec3 v, int length) {
        if (!isFinite(v)) {
            ++nonfinite;
            return false;
        }
        if (isBlack(v)) return false;
        lengths.add(length, v);
        return true;
    }
    void add(const ContributionTally& o) {
        nonfinite += o.nonfinite;
        lengths.add(o.lengths);
    }
};

// One light-tracing contribution to a pixel.
struct Splat {
    uint32_t pixel;
    Vec3 value;
};
// A splat's target that is no pixel but a film point, to be spread over the pixels whose
// filter footprint holds it (pushSplat, wave.h).
constexpr uint32_t kFilmPoint = ~0u;
// A light-side contribution at a film point (raster coordinates), kept as one entry and
// spread over the filter's footprint only when added to the film (addPointSplats, wave.h):
// a footprint holds up to (2 radius + 1)^2 pixels.
struct PointSplat {
    float px, py;
    Vec3 value;
};

// The light tracer's film: per-pixel sums of splats (double). Batches' splat lists are
// added in batch order after each pass, so the image is the same for any threads.
// resolve(spp): the sums divided by the samples per pixel (camera.h, "Importance":
// W H spp light paths estimate W H times each pixel's box-filtered mean).
struct SplatFilm {
    int width = 0, height = 0;
    std::vector<double> sum;  // 3 per pixel

    SplatFilm(int w, int h) : width(w), height(h), sum(size_t(w) * h * 3, 0.0) {}
    void add(const Splat& s) {
        double* d = &sum[size_t(s.pixel) * 3];
        d[0] += s.value.x;
        d[1] += s.value.y;
        d[2] += s.value.z;
    }
    // Adds splats [0, n) in order, loading the pixels a few splats ahead: splats land
    // anywhere and a large film is not in cache (MMLT's serial merge stalled on it).
    void addAll(const Splat* s, size_t n) {
        constexpr size_t kAhead = 64;
        for (size_t i = 0; i < n; ++i) {
            if (i + kAhead < n) __builtin_prefetch(&sum[size_t(s[i + kAhead].pixel) * 3], 1);
            add(s[i]);
        }
    }
    Image resolve(uint64_t spp) const {
        Image img(width, height);
        double inv = spp ? 1.0 / double(spp) : 0.0;
        for (size_t i = 0; i < sum.size(); ++i) img.rgb[i] = float(sum[i] * inv);
        return img;
    }
};

}  // namespace wmlt
