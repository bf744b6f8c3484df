// diffImages (compare.h): the figures of wavemmlt-img diff and wavemmlt.diff.
#include "image/compare.h"

#include "wavemmlt/error.h"

namespace wmlt {

ImageDiff diffImages(const Image& a, const Image& b, std::vector<double>* pixelError) {
    if (a.width != b.width || a.height != b.height)
        throw InputError("size mismatch: " + std::to_string(a.width) + " x " + std::to_string(a.height) + " against " + std::to_string(b.width) +
                         " x " + std::to_string(b.height));
    const size_t nPix = size_t(a.width) * size_t(a.height);
    ImageDiff d;
    double se = 0, rel = 0, ae = 0;
    size_t n = 0;
    if (pixelError) pixelError->assign(nPix, 0.0);
    for (size_t i = 0; i < nPix; ++i)
        for (int c = 0; c < 3; ++c) {
            const double x = a.rgb[3 * i + c], r = b.rgb[3 * i + c];
            if (!std::isfinite(x) || !std::isfinite(r)) {
                ++d.nonFinite;
                if (pixelError) (*pixelError)[i] = INFINITY;
                continue;
            }
            const double e = x - r;
            se += e * e;
            rel += e * e / (r * r + kRelMseEpsilon);
            ae += std::fabs(e);
            d.maxAbs = std::max(d.maxAbs, std::fabs(e));
            if (pixelError) (*pixelError)[i] += e * e;
            ++n;
        }
    if (n) {
        d.rmse = std::sqrt(se / double(n));
        d.relmse = rel / double(n);
        d.mae = ae / double(n);
    }
    return d;
}

}  // namespace wmlt
