#pragma once
// The work of the slowest tests in the sanitizer build. Under AddressSanitizer and
// UndefinedBehaviorSanitizer (CDBENCH_SANITIZE, which defines CDBENCH_SANITIZED_TESTS) every case
// costs 3-10x more, and that run looks for memory and undefined-behaviour errors on the code paths
// the cases reach; the optimised build of the same CI job (scripts/test.sh) runs the full counts
// and tolerances. A test that scales its work scales the thresholds that depend on it.
#include <algorithm>

namespace cdbench::test_scale {

#ifdef CDBENCH_SANITIZED_TESTS
inline constexpr bool kSanitized = true;
#else
inline constexpr bool kSanitized = false;
#endif

// Cases of a randomised loop: all n, or half of them (at least one) under the sanitizers.
constexpr int cases(int n) { return kSanitized ? std::max(1, n / 2) : n; }

// A value for the optimised build and one for the sanitizer build (a tolerance, a resolution).
template <class T>
constexpr T pick(T optimised, T sanitized) {
  return kSanitized ? sanitized : optimised;
}

}  // namespace cdbench::test_scale
