#pragma once
// Internal to the two mesher translation units (mesh_level_set.cpp, mesh_level_set_mesh3.cpp): the
// implicit function as the meshers see it, with a cache of exact repeats and signs known from a
// nearby value by the Lipschitz bound. One Evaluator per thread: it is not thread-safe.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <vector>

#include "offset/mesh_level_set.h"

namespace cdbench::detail {

// CGAL's oracle evaluates many points more than once (shared segment endpoints, mostly soon after
// each other), so recent values are kept by exact coordinates, in each Evaluator (one per mesher
// call, and per thread for Mesh_3 in parallel mode): a direct-mapped table of 2^18 entries (8 MB),
// a newer point replacing an older one in its slot. f depends on the point alone, so what the
// table forgets only costs an evaluation: the values, hence the meshes, are those of a cache that
// forgets nothing. (An unordered_map of every value was a fifth of Surface_mesher's time on boeing
// -20 %, its lookups cache misses; doc/offsets.md, "The mesher's value cache, direct-mapped".)
class RecentValues {
 public:
  RecentValues() : table_(std::size_t{1} << kLog2, Entry{kEmpty, 0.0, 0.0, 0.0}) {}
  bool find(const Vec3& p, double& value) const {
    const Entry& e = table_[slot(p)];
    if (!(e.x == p.x() && e.y == p.y() && e.z == p.z())) return false;  // an empty slot's NaN never matches
    value = e.value;
    return true;
  }
  void put(const Vec3& p, double value) { table_[slot(p)] = Entry{p.x(), p.y(), p.z(), value}; }

 private:
  static constexpr int kLog2 = 18;
  static constexpr double kEmpty = std::numeric_limits<double>::quiet_NaN();
  struct Entry {
    double x, y, z, value;
  };
  static std::uint64_t bits(double x) {
    x += 0.0;  // -0 and +0 compare equal: one slot for both
    std::uint64_t b;
    std::memcpy(&b, &x, sizeof b);
    return b;
  }
  std::size_t slot(const Vec3& p) const {
    std::uint64_t h = bits(p.x()) * 0x9E3779B97F4A7C15ull;
    h = (h ^ bits(p.y())) * 0xC2B2AE3D27D4EB4Full;
    h = (h ^ bits(p.z())) * 0x165667B19E3779F9ull;
    return static_cast<std::size_t>((h ^ (h >> 31)) >> (64 - kLog2));
  }
  std::vector<Entry> table_;
};

// The oracle uses only the sign of f (Implicit_surface_oracle_3 applies Sgn). During a bisection
// the segment's ends were just evaluated, so a midpoint within |f(q)| / L of such a point q has
// q's sign: the value returned is then the bound sign(f(q)) (|f(q)| - L |p - q|), smaller in
// magnitude than f(p) and of the same sign, which later points may use in turn. Dual Voronoi edges
// of a good surface sample are nearly normal to the surface, where f changes almost at rate L, so
// most bisection steps need no evaluation. Deterministic: the answers depend only on the calls.
struct Evaluator {
  Evaluator(const std::function<double(const Vec3&)>& f, double lipschitz, double margin)
      : f(&f), lipschitz(lipschitz), margin(margin) {}
  const std::function<double(const Vec3&)>* f;
  double lipschitz;
  double margin;  // absolute, on top of the rounding relative to the magnitudes (below)
  RecentValues cache;
  struct Known {
    Vec3 p;
    double value;
  };
  static constexpr int kRecent = 16;
  std::array<Known, kRecent> recent{};
  int recent_count = 0, recent_next = 0;
  LevelSetMeshStats stats;

  void remember(const Vec3& p, double value) {
    recent[recent_next] = Known{p, value};
    recent_next = (recent_next + 1) % kRecent;
    recent_count = std::min(recent_count + 1, kRecent);
  }
  double operator()(const Vec3& p) {
    ++stats.calls;
    if (lipschitz > 0.0) {
      double bound = 0.0;  // the largest magnitude known to keep its sign at p
      const double p_size = p.cwiseAbs().maxCoeff();
      for (int k = 0; k < recent_count; ++k) {
        // b below is at most v - margin: a point that cannot beat the bound costs no norm.
        if (std::abs(recent[k].value) - margin <= std::abs(bound)) continue;
        const double v = std::abs(recent[k].value), step = lipschitz * (p - recent[k].p).norm();
        // The rounding of f and of this difference is relative to the magnitudes involved: the
        // mesher asks about circumcentres of flat tetrahedra as far out as 1e15.
        const double rounding = 1e-13 * (v + step + p_size + recent[k].p.cwiseAbs().maxCoeff());
        const double b = v - step - margin - rounding;
        if (b > std::abs(bound)) bound = std::copysign(b, recent[k].value);
      }
      if (bound != 0.0) {
        ++stats.lipschitz;
        remember(p, bound);
        return bound;
      }
    }
    double value;
    if (!cache.find(p, value)) {
      value = (*f)(p);
      ++stats.evaluations;
      cache.put(p, value);
    }
    remember(p, value);
    return value;
  }
};

// The seeds without any within 10^-3 x the mesher's distance bound of an earlier one. Seeds from
// neighbouring missed regions may coincide, and nearly coincident vertices let a refinement point
// round onto a vertex (CGAL's constructions are inexact), which both meshers refuse with an
// assertion ("already inserted on surface": Surface_mesher on dino -20 %, Mesh_3 on two balls);
// seeds that close add nothing the refinement would not add.
inline std::vector<Vec3> distinct_seeds(const std::vector<Vec3>& seeds, double distance_bound) {
  const double spacing = 1e-3 * distance_bound;
  std::vector<Vec3> kept;
  kept.reserve(seeds.size());
  for (const Vec3& s : seeds)
    if (std::none_of(kept.begin(), kept.end(), [&](const Vec3& k) { return (k - s).norm() <= spacing; }))
      kept.push_back(s);
  return kept;
}

}  // namespace cdbench::detail
