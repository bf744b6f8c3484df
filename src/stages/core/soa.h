// Structure-of-arrays records are declared once as a field list X(type, name); these
// macros make the arrays and resize them all to n (WMLT_SOA_ZERO: to n zeros), so that no
// array can be forgotten:
//   #define MY_ARRAYS(X) X(uint32_t, pixel) X(Vec3, L)
//   struct S { MY_ARRAYS(WMLT_SOA_ARRAY) void resize(size_t n) { MY_ARRAYS(WMLT_SOA_RESIZE) } };
#pragma once
#include <vector>

#define WMLT_SOA_ARRAY(type, name) std::vector<type> name;
#define WMLT_SOA_RESIZE(type, name) name.resize(n);
#define WMLT_SOA_ZERO(type, name) name.assign(n, type());
