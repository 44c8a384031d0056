#include "score/verdict.h"

namespace cdbench {

const char* to_string(Verdict v) {
  switch (v) {
    case Verdict::Ok: return "ok";
    case Verdict::FalsePositive: return "false-positive";
    case Verdict::FalseNegative: return "false-negative";
    case Verdict::MissedOrContained: return "missed-or-contained";
    case Verdict::Ambiguous: return "ambiguous";
  }
  return "?";
}

Verdict classify(double lo, double hi, bool collides, bool surface_only) {
  if (hi < 0.0) return collides ? Verdict::Ok : surface_only ? Verdict::MissedOrContained : Verdict::FalseNegative;
  if (lo > 0.0) return collides ? Verdict::FalsePositive : Verdict::Ok;
  return Verdict::Ambiguous;
}

}  // namespace cdbench
