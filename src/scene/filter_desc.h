// Pixel filters by name and parameter, shared by the scene formats and the command line
// (docs/filters.md): the names and defaults are Mitsuba 3's rfilters (pbrt-v4's triangle
// is tent, its sinc is lanczos).
#pragma once
#include <string>

#include "wavemmlt/scene_desc.h"

namespace wmlt {

constexpr const char* kFilterNames = "box, tent, gaussian, mitchell, catmullrom, lanczos";

// The filter of that name with its defaults (box: radius 1/2; tent: 1; gaussian: stddev
// 1/2, radius 4 stddev; mitchell: B = C = 1/3, radius 2; catmullrom: B = 0, C = 1/2, radius
// 2; lanczos: 3 lobes, radius 3). False for an unknown name.
bool namedFilter(const std::string& name, FilterDesc& f);

// Sets parameter `param` (radius, stddev, B, C, lobes, tau) of f to v: "" when done, else
// what is wrong ("radius must be > 0 and at most 16 pixels", "stddev applies to gaussian
// only", ...). stddev also sets the radius to 4 stddev (a radius given after it wins);
// lobes sets both the radius and tau.
std::string setFilterParameter(FilterDesc& f, const std::string& param, double v);

// "gaussian (radius 2, stddev 0.5)", for --describe and messages.
std::string describeFilter(const FilterDesc& f);

}  // namespace wmlt
