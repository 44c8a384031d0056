#pragma once
// Certified maximum penetration of a closed solid: max over interior points x of dist(x, F), the
// radius of the largest inscribed ball, as an interval of prescribed width, by branch and bound
// over an octree with the 1-Lipschitz bound of the signed distance. See doc/distance.md.
#include <cstdint>

#include "core/interval.h"
#include "distance/signed_distance.h"

namespace cdbench {

struct MaxPenetrationOptions {
  double relative_tolerance = 1e-6;  // target width of the interval, relative to the bbox diagonal
  int initial_resolution = 32;       // cells along the longest bbox side at the first level
  // Safety stops (the result then says the tolerance was not reached, with a valid wider interval):
  std::uint64_t max_cells = 200000000;   // cells evaluated in all
  // Cells alive at one level: 48 bytes each, and 64 for each one's outcome while a level is
  // evaluated; a next level past it is not built, so the search holds at most about 3.2 GB.
  std::uint64_t max_frontier = 20000000;
  bool progress = true;              // progress on stderr (only when it is a terminal)
};

struct MaxPenetrationResult {
  Interval depth;               // contains the exact maximum penetration
  Vec3 point = Vec3::Zero();    // interior point whose depth is at least depth.lo
  bool tolerance_reached = false;
  std::uint64_t cells = 0;             // octree cells evaluated
  std::uint64_t full_queries = 0;      // cells that needed a complete distance query
  std::uint64_t side_queries = 0;      // exact inside/outside tests
  int levels = 0;
  double seconds = 0.0;
};

// Uses TBB; the result does not depend on the number of threads.
MaxPenetrationResult certified_max_penetration(const SignedDistance& sdf, const MaxPenetrationOptions& options = {});

}  // namespace cdbench
