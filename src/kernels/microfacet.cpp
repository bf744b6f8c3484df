// Visible-normal sampling (microfacet.h).
#include "kernels/microfacet.h"
#include "kernels/sampling.h"

#include <algorithm>

namespace wmlt {
namespace {

// erf^-1(y), |y| < 1: Winitzki's approximation (a = 0.147, ~2e-3 relative) refined by
// Newton steps on std::erf in double.
double erfInv(double y) {
    y = std::min(std::max(y, -1.0 + 1e-15), 1.0 - 1e-15);
    const double a = 0.147, l = std::log((1.0 - y) * (1.0 + y)), b = 2.0 / (M_PI * a) + 0.5 * l;
    double x = std::copysign(std::sqrt(std::sqrt(b * b - l / a) - b), y);
    for (int i = 0; i < 3; ++i) {
        const double e = std::erf(x) - y, dx = 2.0 / std::sqrt(M_PI) * std::exp(-x * x);
        if (!(dx > 0)) break;
        x -= e / dx;
    }
    return x;
}

// Beckmann with alpha = 1 seen from angle theta (mu = cot theta > 0): the slope x along the
// azimuth of wo has density (mu - x) exp(-x^2) on x < mu (Heitz and d'Eon 2014, sec. 4:
// the projected area of a facet of slope x is proportional to cos(theta) - x sin(theta)).
// Its CDF is C(x) = mu sqrt(pi)/2 (1 + erf(x)) + exp(-x^2) / 2, inverted by a safeguarded
// Newton iteration.
double beckmannSlopeX(double mu, double u) {
    const double sp = 0.5 * std::sqrt(M_PI);
    auto C = [&](double x) { return mu * sp * (1.0 + std::erf(x)) + 0.5 * std::exp(-x * x); };
    double hi = std::min(mu, 7.0), lo = -7.0;
    const double target = u * C(mu);
    double x = std::max(lo, std::min(hi, 0.0));
    for (int i = 0; i < 60; ++i) {
        const double f = C(x) - target;
        if (f > 0) hi = x;
        else lo = x;
        const double df = (mu - x) * std::exp(-x * x);
        double xn = df > 0 ? x - f / df : 0.5 * (lo + hi);
        if (!(xn > lo && xn < hi)) xn = 0.5 * (lo + hi);  // Newton left the bracket: bisect
        if (std::fabs(xn - x) < 1e-12) {
            x = xn;
            break;
        }
        x = xn;
    }
    return x;
}

// GGX (Heitz 2018, "Sampling the GGX distribution of visible normals", listing 1): the
// view direction stretched by (ax, ay) to the alpha = 1 configuration, its projected
// hemisphere sampled as a disc warped so that its lower part shrinks to the projection of
// the half seen at grazing angles, the normal unstretched. (ax == ay: the isotropic
// arithmetic, the same bits as with one alpha.)
Vec3 sampleGgx(float ax, float ay, Vec3 wo, float u1, float u2) {
    const Vec3 vh = normalize(Vec3(ax * wo.x, ay * wo.y, wo.z));
    const float len2 = vh.x * vh.x + vh.y * vh.y;
    const Vec3 t1 = len2 > 0 ? Vec3(-vh.y, vh.x, 0.0f) / std::sqrt(len2) : Vec3(1, 0, 0);
    const Vec3 t2 = cross(vh, t1);
    const float r = std::sqrt(u1);
    float sinPhi, cosPhi;
    sinCos2Pi(u2, sinPhi, cosPhi);
    const float p1 = r * cosPhi, s = 0.5f * (1.0f + vh.z);
    const float p2 = (1.0f - s) * std::sqrt(std::max(0.0f, 1.0f - p1 * p1)) + s * r * sinPhi;
    const Vec3 nh = t1 * p1 + t2 * p2 + vh * std::sqrt(std::max(0.0f, 1.0f - p1 * p1 - p2 * p2));
    return normalize(Vec3(ax * nh.x, ay * nh.y, std::max(1e-7f, nh.z)));
}

// Beckmann: stretch by (ax, ay) to alpha = 1, sample the slopes (x along the stretched wo's
// azimuth, y across it: a normal of variance 1/2), rotate to that azimuth, unstretch the
// slopes by (ax, ay) (Heitz and d'Eon 2014, sec. 5: the anisotropic distribution is the
// isotropic one stretched).
Vec3 sampleBeckmann(float ax, float ay, Vec3 wo, float u1, float u2) {
    const Vec3 v = normalize(Vec3(ax * wo.x, ay * wo.y, wo.z));
    const double sinT = std::sqrt(std::max(0.0, double(v.x) * v.x + double(v.y) * v.y));
    double sx, sy;
    if (sinT < 1e-7) {  // normal incidence: the slopes are Gaussian, P22 = exp(-x^2 - y^2) / pi
        const double r = std::sqrt(-std::log1p(-double(u1))), phi = 2.0 * M_PI * u2;
        sx = r * std::cos(phi);
        sy = r * std::sin(phi);
    } else {
        const double x = beckmannSlopeX(v.z / sinT, u1), y = erfInv(2.0 * u2 - 1.0);
        const double c = v.x / sinT, s = v.y / sinT;
        sx = c * x - s * y;
        sy = s * x + c * y;
    }
    return normalize(Vec3(float(-ax * sx), float(-ay * sy), 1.0f));
}

}  // namespace

Vec3 sampleVisibleNormal(const Microfacet& d, Vec3 wo, float u1, float u2) {
    if (wo.z < 0) wo = -wo;
    return d.type == MicrofacetType::GGX ? sampleGgx(d.alphaX, d.alphaY, wo, u1, u2) : sampleBeckmann(d.alphaX, d.alphaY, wo, u1, u2);
}

}  // namespace wmlt
