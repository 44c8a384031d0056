#pragma once
// Internal to the two mesher translation units (mesh_level_set.cpp, mesh_level_set_mesh3.cpp): the
// implicit function as the meshers see it, with a cache of exact repeats and signs known from a
// nearby value by the Lipschitz bound. One Evaluator per thread: it is not thread-safe.
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <unordered_map>
#include <vector>

#include "offset/mesh_level_set.h"

namespace cdbench::detail {

// CGAL's oracle evaluates many points more than once (about 40 % of the calls on armadillo
// offsets: shared segment endpoints), so values are cached by exact coordinates, in each Evaluator
// (one per mesher call, and per thread for Mesh_3 in parallel mode).
struct PointHash {
  std::size_t operator()(const std::array<double, 3>& p) const {
    std::size_t h = 1469598103934665603ull;
    for (double x : p) h = (h ^ std::hash<double>()(x)) * 1099511628211ull;
    return h;
  }
};
using Cache = std::unordered_map<std::array<double, 3>, double, PointHash>;

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
  Cache cache;
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
    const std::array<double, 3> key{p.x(), p.y(), p.z()};
    const auto it = cache.find(key);
    double value;
    if (it != cache.end()) {
      value = it->second;
    } else {
      if (cache.size() > 20000000) cache.clear();  // bound the memory (about 1.5 GB at most)
      value = (*f)(p);
      ++stats.evaluations;
      cache.emplace(key, value);
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
