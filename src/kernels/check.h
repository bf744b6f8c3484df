// WMLT_DCHECK(cond, what): an invariant whose failure would bias the estimator silently (a
// replayed seed that evaluates differently from its pool entry, a probability outside
// [0, 1], a weight that is not finite). Checked in debug builds and in the sanitizer build
// (-DWMLT_DCHECKS, scripts/test.sh): a failure throws InvariantError naming the file, the
// line, the condition and `what`, which fails the render. Compiled away in release builds
// (neither evaluated): `what` is built only on failure.
#pragma once
#include <stdexcept>
#include <string>

namespace wmlt {

struct InvariantError : std::logic_error {
    using std::logic_error::logic_error;
};

[[noreturn]] inline void invariantFailed(const char* cond, const std::string& what, const char* file, int line) {
    throw InvariantError(std::string(file) + ":" + std::to_string(line) + ": invariant " + cond + " failed: " + what);
}

}  // namespace wmlt

#if !defined(NDEBUG) || defined(WMLT_DCHECKS)
#define WMLT_DCHECKS_ON 1
#define WMLT_DCHECK(cond, what) ((cond) ? void(0) : ::wmlt::invariantFailed(#cond, (what), __FILE__, __LINE__))
#else
#define WMLT_DCHECKS_ON 0
#define WMLT_DCHECK(cond, what) ((void)sizeof((cond) ? 1 : 0))
#endif
