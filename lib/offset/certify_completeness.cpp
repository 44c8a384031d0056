#include "offset/certify_completeness.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "distance/point_triangle_distance.h"
#include "util/timer.h"

namespace cdbench {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Cells are boxes with exact double corners; children split at the rounded midpoint, so they tile
// exactly. Each keeps its parent's centre and that centre's sides of F and of S_d (0: unknown): a
// centre's side is then the crossing parity of the short segment from it instead of a ray out of
// the bounding box (SignedDistance::side with a reference point; exact either way).
struct Cell : Aabb {
  Vec3 ref = Vec3::Zero();
  std::int8_t ref_side_f = 0, ref_side_s = 0;
};

enum class Verdict : unsigned char { Discard, Split, Missed, Unresolved };

// Whether s has no critical point (local extremum) in the cell: every point x of the cell has its
// nearest surface points on the triangles `ids` (all triangles within radius = dist(c) + 2r of c),
// within radius of c, and some direction w satisfies w.(x - p) > 0 for all x in the cell and such
// p (w.(x - c) is least at a corner; max_towards bounds w.(p - c)), so dist strictly increases
// along w at every x.
bool no_critical_point(const SignedDistance& sdf, const Cell& cell, const Vec3& c, double radius,
                       std::vector<std::uint32_t>& ids) {
  // Far from F the possibly-nearest set is a thin shell holding many triangles: allow a few hundred.
  if (!sdf.triangles_within(c, radius, 256, ids) || ids.empty()) return false;
  const TriangleMesh& m = sdf.mesh();
  // Heuristic direction: min-norm point of the hull of the nearest-point directions (Frank-Wolfe).
  std::vector<Vec3> g(ids.size());
  for (std::size_t j = 0; j < ids.size(); ++j) {
    const Face& f = m.faces[ids[j]];
    const Vec3 v = c - closest_point_on_triangle(c, m.vertices[f[0]], m.vertices[f[1]], m.vertices[f[2]]);
    if (!(v.norm() > 0)) return false;
    g[j] = v.normalized();
  }
  std::vector<double> lambda;
  const Vec3 x = min_norm_combination(g, lambda, 60);
  if (!(x.norm() > 1e-6)) return false;
  const Vec3 w = x.normalized();
  double nearest_corner = kInf, corner_size = 0.0;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 v = cell.corner(corner);
    nearest_corner = std::min(nearest_corner, w.dot(v - c));
    corner_size = std::max(corner_size, v.cwiseAbs().sum());
  }
  for (std::uint32_t id : ids) {
    const Face& f = m.faces[id];
    const Vec3 &a = m.vertices[f[0]], &b = m.vertices[f[1]], &q = m.vertices[f[2]];
    // Margin far above the rounding of the 3-term dot products and differences of these magnitudes.
    const double margin =
        1e-12 * (corner_size + c.cwiseAbs().sum() + a.cwiseAbs().sum() + b.cwiseAbs().sum() + q.cwiseAbs().sum());
    if (!(nearest_corner - max_towards(w, c, radius, a, b, q) > margin)) return false;
  }
  return true;
}

}  // namespace

// The vertex bound: a linear function on a triangle peaks at a vertex. The disc bound: with n* the
// exact unit normal and h* = (c - a).n*, every such p has p - c = u - h* n*, u orthogonal to n*,
// |u|^2 <= rho^2 - h*^2, so w.(p - c) <= |w - (w.n*) n*| sqrt(rho^2 - h*^2) - h* (w.n*). The
// computed normal n is within kappa of n* (cross-product rounding relative to |b - a| |q - a|,
// divided by |N|: large for slivers, where the vertex bound serves); h and w.n are widened by it.
// -inf when the ball misses the plane (no point of the triangle can be nearest).
double max_towards(const Vec3& w, const Vec3& c, double rho, const Vec3& a, const Vec3& b, const Vec3& q) {
  double vertices = -kInf;  // each with its rounding (a difference and a 3-term dot product)
  for (const Vec3* v : {&a, &b, &q})
    vertices = std::max(vertices, w.dot(*v - c) + 1e-14 * ((*v - c).cwiseAbs().sum() + v->cwiseAbs().sum()));
  const Vec3 e1 = b - a, e2 = q - a, N = e1.cross(e2);
  const double len = N.norm();
  if (!(len > 0.0)) return vertices;
  const double kappa = 1e-14 * e1.norm() * e2.norm() / len;
  if (!(kappa < 1e-3)) return vertices;
  const Vec3 n = N / len;
  const double ca = (c - a).norm();
  const double h = (c - a).dot(n), eh = ca * (kappa + 1e-15);
  const double wn = w.dot(n), ewn = kappa + 1e-15;
  const double h_lo = std::max(0.0, std::abs(h) - eh);
  if (h_lo > rho) return -kInf;
  const double wn_lo = std::max(0.0, std::abs(wn) - ewn);
  // rho^2 - h_lo^2 may cancel: its absolute rounding (below 3 u rho^2) is added before the root,
  // where it would otherwise grow to sqrt(u) rho; likewise |w|^2 <= 1 + 4 u.
  const double chord2 = rho * rho - h_lo * h_lo + 1e-15 * rho * rho;
  const double along = std::sqrt(std::max(0.0, 1.0 + 1e-14 - wn_lo * wn_lo)) * std::sqrt(std::max(0.0, chord2));
  const double across = -h * wn + std::abs(h) * ewn + std::abs(wn) * eh + eh * ewn;
  // The other roundings of these terms stay far below 1e-12 (rho + |c - a|).
  const double disc = along + across + 1e-12 * (rho + ca);
  return std::min(vertices, disc);
}

CompletenessResult certify_completeness(const SignedDistance& sdf, const TriangleMesh& offset, double d, double eps,
                                        const CompletenessOptions& options) {
  Timer timer;
  CompletenessResult result;
  std::unique_ptr<SignedDistance> surface;
  if (!offset.faces.empty()) surface = std::make_unique<SignedDistance>(offset);
  // Every bounded component of {s < d - eps} or {s > d + eps} lies in the input's box grown by
  // max(d, 0): sublevel points are within d of the solid, exterior pockets within its hull.
  Aabb domain = sdf.bbox();
  const double grow = std::max(d, 0.0) + eps + 1e-3 * domain.diagonal();
  domain.lo -= Vec3::Constant(grow);
  domain.hi += Vec3::Constant(grow);
  const double min_size = options.min_cell_relative * domain.diagonal();

  std::vector<Cell> frontier;
  {
    const int n = 8;
    const Vec3 step = domain.extent() / n;
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          Cell c;
          c.lo = domain.lo + Vec3(i * step.x(), j * step.y(), k * step.z());
          c.hi = domain.lo + Vec3((i + 1) * step.x(), (j + 1) * step.y(), (k + 1) * step.z());
          if (i == n - 1) c.hi.x() = domain.hi.x();
          if (j == n - 1) c.hi.y() = domain.hi.y();
          if (k == n - 1) c.hi.z() = domain.hi.z();
          frontier.push_back(c);
        }
  }
  while (!frontier.empty() && result.cells < options.max_cells) {
    std::vector<Verdict> verdict(frontier.size(), Verdict::Split);
    std::vector<std::int8_t> side_f(frontier.size(), 0), side_s(frontier.size(), 0);  // of each centre
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, frontier.size(), 32), [&](const auto& range) {
      thread_local std::vector<std::uint32_t> ids;
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        const Cell& cell = frontier[i];
        const Vec3 c = 0.5 * (cell.lo + cell.hi);
        // Covering radius around the rounded centre, rounded up generously.
        const double r = round_up(0.5 * (cell.hi - cell.lo).norm() * (1 + 1e-12) +
                                  4 * std::numeric_limits<double>::epsilon() * c.cwiseAbs().maxCoeff());
        const Interval du = sdf.unsigned_distance(c);
        const int sf = sdf.side(c, du, cell.ref, cell.ref_side_f);
        side_f[i] = static_cast<std::int8_t>(sf);
        const Interval s = with_side(du, sf);
        const double s_min = s.lo - r, s_max = s.hi + r;  // s over the cell (1-Lipschitz)
        // (1) the cell holds no point of A = {s < d - eps} nor of B = {s > d + eps}.
        if (s_min >= d - eps && s_max <= d + eps) {
          verdict[i] = Verdict::Discard;
          continue;
        }
        // (2) the cell misses S_d: all of it is on one side of S_d.
        const Interval to_surface = surface ? surface->unsigned_distance(c) : Interval{kInf, kInf};
        // The centre's side of S_d whenever it is off S_d: the children's reference even when this
        // cell touches S_d (most split cells do).
        const int ss = !surface ? 1 : (to_surface.lo > 0.0 ? surface->side(c, to_surface, cell.ref, cell.ref_side_s) : 0);
        side_s[i] = static_cast<std::int8_t>(ss);
        if (to_surface.lo > r) {  // c is off S_d: the cell lies on the side of its centre
          const bool inside = ss < 0;
          if (inside ? s_max <= d + eps : s_min >= d - eps) {
            verdict[i] = Verdict::Discard;
            continue;
          }
          if (inside ? s.lo - r > d + eps : s.hi + r < d - eps) {
            verdict[i] = Verdict::Missed;  // wholly in B inside S_d, or wholly in A outside S_d
            continue;
          }
        }
        // (3) no extremum of s in the cell (it avoids the surface, where s is not smooth).
        if (std::abs(s.lo) > r && std::abs(s.hi) > r && std::signbit(s.lo) == std::signbit(s.hi) &&
            no_critical_point(sdf, cell, c, round_up(std::max(std::abs(s.lo), std::abs(s.hi)) + 2 * r), ids)) {
          verdict[i] = Verdict::Discard;
          continue;
        }
        if ((cell.hi - cell.lo).maxCoeff() < min_size) verdict[i] = Verdict::Unresolved;
      }
    });
    std::vector<Cell> next;
    for (std::size_t i = 0; i < frontier.size(); ++i) {
      ++result.cells;
      const Cell& cell = frontier[i];
      switch (verdict[i]) {
        case Verdict::Discard: break;
        case Verdict::Missed:
          if (result.missed.size() < 64) result.missed.push_back(0.5 * (cell.lo + cell.hi));
          break;
        case Verdict::Unresolved:
          if (result.unresolved.size() < 64) result.unresolved.push_back(0.5 * (cell.lo + cell.hi));
          break;
        case Verdict::Split: {
          const Vec3 mid = 0.5 * (cell.lo + cell.hi);
          for (int k = 0; k < 8; ++k) {
            Cell child;
            child.ref = mid;
            child.ref_side_f = side_f[i];
            child.ref_side_s = side_s[i];
            for (int a = 0; a < 3; ++a) {
              const bool upper = (k >> a) & 1;
              child.lo[a] = upper ? mid[a] : cell.lo[a];
              child.hi[a] = upper ? cell.hi[a] : mid[a];
            }
            next.push_back(child);
          }
          break;
        }
      }
    }
    frontier = std::move(next);
    // A certain violation settles the answer; its points are the seeds the caller needs.
    if (!result.missed.empty()) break;
  }
  if (result.missed.empty())
    for (const Cell& cell : frontier)
      if (result.unresolved.size() < 64) result.unresolved.push_back(0.5 * (cell.lo + cell.hi));
  result.complete = frontier.empty() && result.missed.empty() && result.unresolved.empty();
  result.seconds = timer.seconds();
  return result;
}

}  // namespace cdbench
