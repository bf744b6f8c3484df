#include "scene/filter_desc.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "kernels/filter.h"

namespace wmlt {

bool namedFilter(const std::string& name, FilterDesc& f) {
    f = FilterDesc();
    if (name == "box") {
        f.kind = FilterKind::Box;
    } else if (name == "tent" || name == "triangle") {
        f.kind = FilterKind::Tent;
        f.radius = 1;
    } else if (name == "gaussian") {
        f.kind = FilterKind::Gaussian;
        f.stddev = 0.5f;
        f.radius = 2;
    } else if (name == "mitchell" || name == "catmullrom") {  // Catmull-Rom: B = 0, C = 1/2
        f.kind = FilterKind::Mitchell;
        f.radius = 2;
        if (name == "catmullrom") {
            f.B = 0;
            f.C = 0.5f;
        }
    } else if (name == "lanczos") {
        f.kind = FilterKind::Lanczos;
        f.radius = f.tau = 3;
    } else {
        return false;
    }
    return true;
}

std::string setFilterParameter(FilterDesc& f, const std::string& param, double v) {
    if (!std::isfinite(v)) return param + " must be a finite number";
    if (param == "radius") {
        if (!(v > 0 && v <= kMaxFilterRadius)) return "radius must be > 0 and at most 16 pixels";
        f.radius = float(v);
    } else if (param == "stddev") {
        if (f.kind != FilterKind::Gaussian) return "stddev applies to gaussian only";
        if (!(v > 0 && 4 * v <= kMaxFilterRadius)) return "stddev must be > 0 and at most 4 pixels";
        f.stddev = float(v);
        f.radius = float(4 * v);
    } else if (param == "B" || param == "C") {
        if (f.kind != FilterKind::Mitchell) return param + " applies to mitchell and catmullrom only";
        (param == "B" ? f.B : f.C) = float(v);
    } else if (param == "lobes") {
        if (f.kind != FilterKind::Lanczos) return "lobes applies to lanczos only";
        if (!(v >= 1 && v <= kMaxFilterRadius && v == std::floor(v))) return "lobes must be a whole number from 1 to 16";
        f.radius = f.tau = float(v);
    } else if (param == "tau") {
        if (f.kind != FilterKind::Lanczos) return "tau applies to lanczos only";
        if (!(v > 0)) return "tau must be > 0";
        f.tau = float(v);
    } else {
        return "unknown filter parameter \"" + param + "\"";
    }
    return "";
}

std::string describeFilter(const FilterDesc& f) {
    std::ostringstream o;
    switch (f.kind) {
        case FilterKind::Box: o << "box"; break;
        case FilterKind::Tent: o << "tent"; break;
        case FilterKind::Gaussian: o << "gaussian"; break;
        case FilterKind::Mitchell: o << (f.B == 0 && f.C == 0.5f ? "catmullrom" : "mitchell"); break;
        case FilterKind::Lanczos: o << "lanczos"; break;
    }
    o << " (radius " << f.radius;
    if (f.kind == FilterKind::Gaussian) o << ", stddev " << f.stddev;
    if (f.kind == FilterKind::Mitchell) o << ", B " << f.B << ", C " << f.C;
    if (f.kind == FilterKind::Lanczos) o << ", tau " << f.tau;
    o << ")";
    return o.str();
}

}  // namespace wmlt
