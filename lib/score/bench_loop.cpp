#include "score/bench_loop.h"

#include <sched.h>

#include <algorithm>
#include <chrono>

#include "util/timer.h"

namespace cdbench {

void pin_to_current_core() {
  cpu_set_t set;
  CPU_ZERO(&set);
  const int cpu = sched_getcpu();
  CPU_SET(cpu >= 0 ? cpu : 0, &set);
  sched_setaffinity(0, sizeof set, &set);
}

ImplScore bench_implementation(CollisionImpl& impl, const TriangleMesh& fixed, const TriangleMesh& mover,
                               const PoseSetManifest& manifest, const std::vector<PoseRow>& rows,
                               const BenchOptions& options, Progress* progress) {
  Timer tb;
  impl.build(fixed, mover);
  const double build_seconds = tb.seconds();
  for (const PoseRow& r : rows) impl.query(r.R, r.t);  // warm caches and branch predictors
  std::vector<std::optional<Answer>> answers(rows.size());
  std::vector<double> times(static_cast<std::size_t>(options.repeat));
  for (std::size_t i = 0; i < rows.size(); ++i) {
    QueryAnswer q;
    for (int k = 0; k < options.repeat; ++k) {
      const auto t0 = std::chrono::steady_clock::now();
      q = impl.query(rows[i].R, rows[i].t);
      times[static_cast<std::size_t>(k)] = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count();
    }
    std::nth_element(times.begin(), times.begin() + options.repeat / 2, times.end());
    Answer a;
    a.collides = q.collides;
    a.distance = q.distance;
    a.time_ns = times[static_cast<std::size_t>(options.repeat / 2)];
    a.bv_tests = static_cast<std::int64_t>(q.bv_tests);
    a.triangle_tests = static_cast<std::int64_t>(q.triangle_tests);
    answers[i] = a;
    if (progress) progress->advance();
  }
  ImplScore s = score_answers(impl.name(), manifest, rows, std::move(answers), !impl.detects_containment());
  s.counts_tests = impl.counts_tests();
  s.build_seconds = build_seconds;
  return s;
}

}  // namespace cdbench
