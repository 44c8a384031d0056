#pragma once
// Verdicts of a collision answer against a pose's certified clearance interval [lo, hi]
// (doc/benchmark.md): hi < 0 (the mover penetrates) must collide, lo > 0 (apart) must not; an
// interval containing 0 cannot decide.
#include <string>

namespace cdbench {

enum class Verdict {
  Ok,
  FalsePositive,      // apart, answered "collides"
  FalseNegative,      // penetrating, answered "free"
  MissedOrContained,  // penetrating, answered "free" by a surface-only implementation: a mover
                      // wholly inside the solid has no surface contact, so this is not proof of a miss
  Ambiguous,          // the certificate contains 0 (a touching pose): any answer is accepted
};

const char* to_string(Verdict v);

// `surface_only`: the implementation tests the two surfaces only (most libraries), so a miss on a
// penetrating pose is reported as MissedOrContained rather than FalseNegative.
Verdict classify(double clearance_lo, double clearance_hi, bool collides, bool surface_only);

}  // namespace cdbench
