// MMLT's target function c(x) (mmlt.md, step 4; docs/mmlt-levers.md, "The relative
// target"). The luminance of the path's contribution F (Hachisuka et al. 2014), or
// with a target map (RenderOptions::mmltTarget = Relative, from the second pass on) that
// luminance over a smoothed estimate of the brightness B of the film tile the path lands on,
// with a floor (Hoberock and Hart 2010, "Arbitrary importance functions for Metropolis light
// transport", sec. 4: I(x) / B(pixel(x))): the chains then spread their mutations over the
// image as the relative error asks, not in proportion to brightness. Any c > 0 wherever
// F != 0 keeps the estimator unbiased (the splats divide by c: F / c * b_k), so the map
// only moves effort. With an exponent beta < 1 (RenderOptions::mmltTargetExponent, a tempered
// target) c = luminance(F)^beta: the chains spend fewer iterations on the brightest paths and
// leave them sooner (the ratio of two paths' c is the ratio of their luminances to the beta),
// each visit weighing more (F / c). Pure: the driver builds the map (stages/mmlt/mmlt_learn.cpp).
#pragma once
#include <algorithm>
#include <cmath>

#include "wavemmlt/math.h"

namespace wmlt {

// A view of the map: scale[tile] = the mean brightness over the tile's (floored, smoothed)
// brightness, tiles of tileSize x tileSize pixels, row by row. scale == nullptr: the
// luminance target.
struct TargetMap {
    const float* scale = nullptr;
    int tilesX = 1, tilesY = 1;
    float invTileSize = 1;  // 1 / pixels per tile side
    float exponent = 1;     // beta: c = luminance^beta (1: the luminance itself)
};

// The tile holding film point (px, py) in pixels; a point off the film (or NaN) is clamped
// to the nearest edge tile (its F is 0 anyway: a light subpath that misses the film).
inline int targetTileOf(const TargetMap& m, float px, float py) {
    const float fx = px * m.invTileSize, fy = py * m.invTileSize;
    const int tx = fx > 0 ? std::min(int(std::min(fx, 1e9f)), m.tilesX - 1) : 0;
    const int ty = fy > 0 ? std::min(int(std::min(fy, 1e9f)), m.tilesY - 1) : 0;
    return ty * m.tilesX + tx;
}

// c = luminance(F)^beta (times the tile's scale with a map), 0 when anything is not finite.
inline float targetOf(const Vec3& F, float px, float py, const TargetMap& m) {
    float c = luminance(F);
    if (m.exponent != 1.0f && c > 0) c = std::pow(c, m.exponent);
    if (m.scale) c *= m.scale[targetTileOf(m, px, py)];
    return std::isfinite(c) && isFinite(F) ? c : 0.0f;
}
// The luminance target (PSSMLT's whole samples; MMLT's first pass).
inline float targetOf(const Vec3& F) { return targetOf(F, 0, 0, TargetMap{}); }

}  // namespace wmlt
