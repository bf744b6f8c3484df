// EnvMapSampler::prepare: the sampling distribution and the mean luminance of the map.
#include "kernels/envmap.h"

#include <vector>

namespace wmlt {

void EnvMapSampler::prepare() {
    meanLuminance = 0;
    dist = Distribution2D();
    if (!valid()) return;
    const int w = image.width, h = image.height;
    std::vector<float> f(size_t(w) * size_t(h));
    double total = 0;
    for (int y = 0; y < h; ++y) {
        const double theta0 = M_PI * y / h, theta1 = M_PI * (y + 1) / h;
        const float sinCentre = float(std::sin(M_PI * (y + 0.5) / h));
        // Solid angle of one pixel of this row.
        const double omega = 2.0 * M_PI / w * (std::cos(theta0) - std::cos(theta1));
        for (int x = 0; x < w; ++x) {
            float lum = luminance(image.at(x, y));
            if (!(lum > 0) || !std::isfinite(lum)) lum = 0;  // negative, NaN, Inf: not sampled
            f[size_t(y) * w + x] = lum * sinCentre;
            total += double(lum) * omega;
        }
    }
    dist.build(f.data(), w, h);
    meanLuminance = float(total / (4.0 * M_PI));
}

}  // namespace wmlt
