#pragma once
// The timing harness of `cdbench bench`: each implementation is built once, every pose queried once
// to warm caches, then `repeat` times with the median kept; the caller pins the thread.
#include <string>
#include <vector>

#include "collide/collision_impl.h"
#include "score/scoring.h"
#include "util/progress.h"

namespace cdbench {

struct BenchOptions {
  int repeat = 5;
};

// Times `impl` over the placed rows and scores its answers (build time, verdicts, per level).
ImplScore bench_implementation(CollisionImpl& impl, const TriangleMesh& fixed, const TriangleMesh& mover,
                               const PoseSetManifest& manifest, const std::vector<PoseRow>& rows,
                               const BenchOptions& options, Progress* progress);

// Pins the calling thread to the core it runs on (no migration in the middle of a measurement).
void pin_to_current_core();

}  // namespace cdbench
