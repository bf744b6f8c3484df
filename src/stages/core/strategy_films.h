// BPT's per-strategy images (--strategy-images; Veach 1997, fig. 10.3): for every
// strategy (s, t) of the path lengths k = s + t - 1 in [1, maxLength], the sums of its
// MIS-weighted and of its unweighted contributions. Camera-side strategies (t >= 2) add
// to their slot's pixel as the main film does (tiles own their pixels, so this is race
// free and in sample order); t = 1 splats are merged in tile order after each pass.
// Memory: 24 bytes per pixel per strategy ((L + 1)(L + 2) / 2 - 1 strategies).
#pragma once
#include <cstdint>
#include <vector>

#include "stages/core/film.h"

namespace wmlt {

struct StrategySplat {
    uint32_t pixel;
    uint8_t s;
    Vec3 weighted, unweighted;
};

struct StrategyFilms {
    int width = 0, height = 0, maxLength = 0;
    std::vector<Vec3> weighted, unweighted;  // [strategy][pixel]

    static int count(int maxLength) { return (maxLength + 1) * (maxLength + 2) / 2 - 1; }
    static int index(int s, int k) { return k * (k + 1) / 2 - 1 + s; }
    static size_t bytes(int w, int h, int maxLength) { return size_t(w) * size_t(h) * size_t(count(maxLength)) * 24; }

    StrategyFilms(int w, int h, int maxLen)
        : width(w), height(h), maxLength(maxLen), weighted(size_t(w) * h * size_t(count(maxLen))), unweighted(weighted.size()) {}

    size_t at(int s, int k, uint32_t pixel) const { return size_t(index(s, k)) * size_t(width) * size_t(height) + pixel; }
    void addCamera(uint32_t pixel, int s, int t, Vec3 w, Vec3 u) {
        const size_t i = at(s, s + t - 1, pixel);
        weighted[i] += w;
        unweighted[i] += u;
    }
    void addSplat(const StrategySplat& sp) {  // t = 1: k = s
        const size_t i = at(sp.s, sp.s, sp.pixel);
        weighted[i] += sp.weighted;
        unweighted[i] += sp.unweighted;
    }
};

}  // namespace wmlt
