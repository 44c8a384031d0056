#include "distance/max_penetration.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

#include "distance/depth_bound.h"
#include "distance/point_triangle_distance.h"
#include "util/progress.h"
#include "util/timer.h"

namespace cdbench {
namespace {

struct Cell {
  Vec3 center;
  signed char sign;    // -1 inside, +1 outside, 0 unknown (a certified fact about the centre)
  double parent_upper;  // certified depth bound over the parent cell (covers this one)
  std::int64_t near = -1;  // a triangle near the parent's centre: the first guess of the queries
};

struct Outcome {
  bool keep = false;
  bool full = false;
  bool side_query = false;
  signed char sign = 0;
  double lower = -1.0;     // certified depth of `point` (inside only), else -1
  Vec3 point = Vec3::Zero();
  double upper = 0.0;      // certified upper bound of the depth over the cell's interior points
  double child_margin = 0.0;  // dist lower bound at the centre: children closer than it share the sign
  std::uint32_t near = 0;      // the triangle found nearest to the centre (or one proving the bound)
};

// The convexity bound over a cube: its 8 corners (see distance/depth_bound.h).
// Near-coplanar triangles within coplanar_slack of a plane count as one planar patch where they
// cover the cube's projection (distance/planar_patch.h): machined parts' plateaus between parallel
// faces tiled by many triangles.
// When that bound still exceeds `enough`, the weights minimising it over the corners are tried too
// (minimax_depth_bound: the seams of faceted walls).
double convexity_bound(const SignedDistance& sdf, const Vec3& c, double h, double radius,
                       std::vector<std::uint32_t>& ids, Vec3& candidate, double coplanar_slack, double enough) {
  std::array<Vec3, 8> corners;
  for (int corner = 0; corner < 8; ++corner)
    corners[corner] = c + Vec3((corner & 1) ? h : -h, (corner & 2) ? h : -h, (corner & 4) ? h : -h);
  double bound = depth_upper_bound(sdf, c, radius, corners.data(), 8, ids, &candidate, nullptr, nullptr, nullptr,
                                   coplanar_slack);
  if (bound > enough) bound = std::min(bound, minimax_depth_bound(sdf, ids, corners.data(), 8));
  return bound;
}

// Candidates of a deep point refined from the previous candidate, per kept cell (see the loop).
constexpr int kCandidateRounds = 6;

// sqrt(3) rounded up to a double (the nearest double is below sqrt(3)).
constexpr double kSqrt3Up = 1.7320508075688774;

}  // namespace

MaxPenetrationResult certified_max_penetration(const SignedDistance& sdf, const MaxPenetrationOptions& options) {
  Timer timer;
  MaxPenetrationResult result;
  const Aabb box = sdf.bbox();
  const double diag = box.diagonal();
  // A hair below the requested width, so that the outward rounding of the bounds stays within it.
  const double eps = options.relative_tolerance * diag * (1.0 - 1e-9);
  const Vec3 extent = box.extent();
  double half = 0.5 * extent.maxCoeff() / std::max(1, options.initial_resolution);

  std::vector<Cell> frontier;
  {
    const int nx = std::max(1, static_cast<int>(std::ceil(extent.x() / (2 * half))));
    const int ny = std::max(1, static_cast<int>(std::ceil(extent.y() / (2 * half))));
    const int nz = std::max(1, static_cast<int>(std::ceil(extent.z() / (2 * half))));
    // Grow the cells a little so that they cover the box despite rounding of the centres.
    half *= 1.0 + 1e-9;
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
          frontier.push_back({box.lo + Vec3((2 * i + 1) * half, (2 * j + 1) * half, (2 * k + 1) * half), 0,
                              std::numeric_limits<double>::infinity()});
  }

  double best = 0.0;             // certified: some interior point has depth >= best
  Vec3 best_point = box.center();
  double upper_left = 0.0;  // max certified upper bound over the discarded cells and those a stop left
  bool stopped = false;     // a safety stop after a level: its next level was not built
  Progress progress("max penetration", 0);

  while (!frontier.empty()) {  // (a stop leaves it empty: the next level is not built)
    if (result.cells + frontier.size() > options.max_cells || frontier.size() > options.max_frontier) break;
    const double r = round_up(half * kSqrt3Up);  // covering radius of a cell around its centre
    const double snapshot = best;
    std::vector<Outcome> out(frontier.size());
    // Grain 1: after the first level the frontier holds 8-600 cells of 10 us to 1 ms each (armadillo),
    // which chunks of 64 gave to at most 9 threads (one below 65 cells).
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, frontier.size(), 1), [&](const auto& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        const Cell& cell = frontier[i];
        Outcome& o = out[i];
        // Discard without a full query when some triangle is close enough to the centre:
        // depth over the cell <= dist(c) + r <= snapshot + eps.
        const double theta = snapshot + eps - r;
        Interval d;
        if (sdf.distance_at_most(cell.center, theta, &d, &o.near, cell.near)) {
          o.upper = round_up(theta + r);
          if (options.progress) progress.advance();
          continue;
        }
        o.full = true;
        o.sign = cell.sign;
        if (o.sign == 0) {
          o.side_query = true;
          const int s = sdf.side(cell.center, d);
          o.sign = static_cast<signed char>(s == 0 ? 1 : s);  // on the surface: depth 0, treat as outside
        }
        o.child_margin = d.lo;
        if (o.sign < 0) {
          o.lower = d.lo;
          o.point = cell.center;
          o.upper = round_up(d.hi + r);
          // The Lipschitz bound cannot discard a cell on a plateau or near a medial point; the
          // convexity bound can. Worth its cost only for cells well inside.
          if (o.upper > snapshot + eps && r <= d.lo) {
            thread_local std::vector<std::uint32_t> ids;
            Vec3 candidate;
            o.upper = std::min(o.upper,
                               convexity_bound(sdf, cell.center, half, round_up(d.hi + 2 * r), ids, candidate, 0.25 * eps,
                                               snapshot + eps));
            // The candidate (the weighted mean of the nearest points) is a medial point only along
            // the directions its weights balance: on a bar, weights on two opposite faces give a
            // point on the mid-plane between them, not on the axis. Candidates from the candidate
            // (up to kCandidateRounds, while the cell is still kept) balance the others; each is a
            // heuristic only, certified below like the first.
            for (int round = 0; round <= kCandidateRounds; ++round) {
              if (!((candidate - cell.center).cwiseAbs().array() <= half).all()) break;
              // Within the ball of radius d.lo about the centre (inside F), which holds no point of
              // F: the candidate is inside too, and needs no ray test.
              const bool in_ball = (candidate - cell.center).norm() * (1.0 + 1e-12) < d.lo;
              const Interval sc = in_ball ? with_side(sdf.unsigned_distance(candidate, nullptr, o.near), -1)
                                          : sdf.signed_distance(candidate);
              if (-sc.hi > o.lower) {
                o.lower = -sc.hi;
                o.point = candidate;
              }
              if (round == kCandidateRounds || !(o.upper > std::max(snapshot, o.lower) + eps)) break;
              const Vec3 from = candidate;
              depth_upper_bound_among(sdf, from, ids, &from, 1, &candidate);
            }
          }
        } else {
          o.upper = round_up(r - d.lo);  // a point inside at distance <= r crosses the surface first
        }
        o.keep = o.upper > snapshot + eps;
        if (options.progress) progress.advance();
      }
    });

    // The next level (eight cells for each kept one) is counted before it is built: one past the
    // safety stops is never built (its cells would only carry their parents' bounds, which the stop
    // reports from the kept cells themselves: the same interval), so that the memory stays within
    // them; a level that is built takes one allocation.
    std::uint64_t kept = 0;
    for (const Outcome& o : out) kept += o.keep;
    const std::uint64_t next_cells = 8 * kept;
    const bool stop = next_cells > 0 && (next_cells > options.max_frontier ||
                                         result.cells + frontier.size() + next_cells > options.max_cells);
    std::vector<Cell> next;
    if (!stop) next.reserve(next_cells);
    const double child_half = 0.5 * half;
    const double child_offset = round_up(child_half * kSqrt3Up);  // distance from a centre to a child's centre
    for (std::size_t i = 0; i < frontier.size(); ++i) {
      const Outcome& o = out[i];
      ++result.cells;
      result.full_queries += o.full;
      result.side_queries += o.side_query;
      if (o.lower > best) {
        best = o.lower;
        best_point = o.point;
      }
      if (!o.keep || stop) {  // discarded, or left unexplored by the stop: its bound covers it
        upper_left = std::max(upper_left, o.upper);
        continue;
      }
      const signed char child_sign = o.child_margin > child_offset ? o.sign : 0;
      for (int k = 0; k < 8; ++k) {
        const Vec3 offset((k & 1) ? child_half : -child_half, (k & 2) ? child_half : -child_half,
                          (k & 4) ? child_half : -child_half);
        next.push_back({frontier[i].center + offset, child_sign, o.upper, o.near});
      }
    }
    // Kept cells whose children were computed are replaced by them; the children cover the parent
    // (same centre spacing), so every point of space stays covered by a live or discarded cell.
    frontier = std::move(next);
    half = child_half;
    ++result.levels;
    stopped = stop;
    if (options.progress) {
      std::ostringstream os;
      os.precision(9);
      os << "level " << result.levels << ", " << (stop ? next_cells : frontier.size()) << " cells"
         << (stop ? " (past the safety stop)" : "") << ", depth >= " << best;
      progress.set_detail(os.str());
    }
  }
  progress.finish();

  result.tolerance_reached = frontier.empty() && !stopped;
  double upper = std::max(best, upper_left);
  // Cells of the first level left unexplored by a safety stop are bounded by their parents' bounds.
  for (const Cell& c : frontier) upper = std::max(upper, c.parent_upper);
  result.depth = {best, upper};
  result.point = best_point;
  result.seconds = timer.seconds();
  return result;
}

}  // namespace cdbench
