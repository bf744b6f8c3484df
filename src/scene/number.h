// Numbers in scene files (the thesis' XML, Mitsuba's XML, PLY text): a finite number that
// fits a float, the whole text (trimmed of white space) consumed, one leading '+'
// allowed. "1.5x", "nan", "inf", "1e39", "+-1" and "" are rejected. from_chars is
// locale-independent.
#pragma once
#include <cfloat>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <string>
#include <string_view>

namespace wmlt {

inline bool parseNumber(std::string_view t, bool integer, double& out) {
    const size_t b = t.find_first_not_of(" \t\r\n"), e = t.find_last_not_of(" \t\r\n");
    t = b == std::string_view::npos ? std::string_view() : t.substr(b, e - b + 1);
    const char* p = t.data();
    const char* end = p + t.size();
    if (p != end && *p == '+' && p + 1 != end && p[1] != '-') ++p;
    double v = 0;
    std::from_chars_result r{};
    if (integer) {
        long long i = 0;
        r = std::from_chars(p, end, i);
        v = double(i);
    } else {
        r = std::from_chars(p, end, v);
    }
    if (r.ec != std::errc() || r.ptr != end || p == end || !std::isfinite(v) || std::fabs(v) > FLT_MAX) return false;
    out = v;
    return true;
}

// Whether a product computed in double still fits a float (finite, at most FLT_MAX in
// magnitude): finite parameters whose product is not are refused where they are multiplied.
inline bool fitsFloat(double x) { return std::fabs(x) <= FLT_MAX; }  // (false for NaN)

// A number in a message, as a person writes it: 1e+38, 0.5, 63.
inline std::string numberText(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.6g", v);
    return b;
}

}  // namespace wmlt
