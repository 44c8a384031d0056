#include "distance/hausdorff.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <initializer_list>
#include <queue>
#include <vector>

#include "distance/point_triangle_distance.h"
#include "util/timer.h"

namespace cdbench {
namespace {

struct Corner {
  Vec3 p;
  Interval d;              // encloses dist(p, B)
  std::uint32_t nearest;   // a triangle of B at the upper end
  double off = 0.0;        // p lies within `off` of a point of A (rounded midpoints drift)
  double lower() const { return std::max(0.0, round_down(d.lo - off)); }  // a valid lower bound of h
};

struct Cell {
  std::array<Corner, 3> c;
  double upper = 0.0;  // >= dist(x, B) for every x of the exact region
  bool operator<(const Cell& o) const { return upper < o.upper; }
};

Corner corner_at(const Vec3& p, const SignedDistance& b) {
  Corner c{p, {}, 0, 0.0};
  c.d = b.unsigned_distance(p, &c.nearest);
  return c;
}

double distance_hi(const Vec3& p, const TriangleMesh& mb, std::uint32_t t) {
  const Face& f = mb.faces[t];
  return sqrt_interval(point_triangle_squared_distance(p, mb.vertices[f[0]], mb.vertices[f[1]], mb.vertices[f[2]])).hi;
}

// Cells whose corners have different nearest triangles (the cell straddles where B's nearest
// point moves from one triangle to the next, e.g. across an edge or around a vertex of a flat-ish
// sheet): a single triangle bounds such a cell badly, by about the cell's size, so that a
// near-constant distance would need cells far below the tolerance. Instead the cell is cut into
// pieces, each bounded by the nearest triangle of its corner: the distance to one triangle is
// convex, so its maximum over a piece is at one of the piece's vertices (a polygon lies in the
// convex hull of its vertices). The cut points are exact points of the cell for the double
// parameters used (any parameters give pieces that cover the cell; the heuristic only places them
// where the two distances cross); the computed points differ from them by a few ulps, added as
// slack (the distance is 1-Lipschitz).
struct CutPoint {
  Vec3 p;
  double s = 0.5;    // p = from + s (to - from)
  double err = 0.0;  // |computed p - exact p|
};

CutPoint cut(const Vec3& from, const Vec3& to, std::uint32_t tf, std::uint32_t tt, const TriangleMesh& mb,
             double good_enough) {
  // g(s) = d(x(s), tf) - d(x(s), tt) changes sign between the corners; the distances are
  // hyperbolic near B, so a few Illinois (regula falsi) steps place the crossing well.
  const auto g = [&](double s) {
    const Vec3 x = from + s * (to - from);
    return distance_hi(x, mb, tf) - distance_hi(x, mb, tt);
  };
  CutPoint c;
  double s0 = 0.0, s1 = 1.0, g0 = g(0.0), g1 = g(1.0);
  if (g0 < 0.0 && g1 > 0.0) {
    int side = 0;
    for (int it = 0; it < 12; ++it) {
      const double s = s0 + (s1 - s0) * (g0 / (g0 - g1));
      if (!(s > s0 && s < s1)) break;
      const double gs = g(s);
      if (std::abs(gs) <= good_enough) {
        s0 = s1 = s;
        break;
      }
      if (gs < 0.0) {
        s0 = s, g0 = gs;
        if (side == -1) g1 *= 0.5;
        side = -1;
      } else {
        s1 = s, g1 = gs;
        if (side == 1) g0 *= 0.5;
        side = 1;
      }
    }
    c.s = s0 + (s1 - s0) * (g0 / (g0 - g1));
  }
  c.s = std::isfinite(c.s) ? std::min(1.0, std::max(0.0, c.s)) : 0.5;  // heuristic only: any s is valid
  c.p = from + c.s * (to - from);
  // Three roundings per coordinate, each of magnitude <= |from| + |to| + |p|.
  c.err = round_up((from.norm() + to.norm() + c.p.norm()) * 0x1p-50);
  return c;
}

double max_distance(std::initializer_list<Vec3> points, const TriangleMesh& mb, std::uint32_t t) {
  double m = 0.0;
  for (const Vec3& p : points) m = std::max(m, distance_hi(p, mb, t));
  return m;
}

// Two labels: the lone corner a (triangle ta) against b and c (triangle tb), cut by x on ab and y
// on ac into the triangle (a, x, y) and the quadrilateral (x, b, c, y).
double two_piece_bound(const std::array<Corner, 3>& c, int lone, const TriangleMesh& mb, double good_enough) {
  const Corner& a = c[lone];
  const Corner& b = c[(lone + 1) % 3];
  const Corner& d = c[(lone + 2) % 3];
  const CutPoint x = cut(a.p, b.p, a.nearest, b.nearest, mb, good_enough);
  const CutPoint y = cut(a.p, d.p, a.nearest, b.nearest, mb, good_enough);
  const double first = max_distance({a.p, x.p, y.p}, mb, a.nearest);
  const double second = max_distance({x.p, b.p, d.p, y.p}, mb, b.nearest);
  return round_up(std::max(first, second) + std::max(x.err, y.err));
}

// Three labels: cut points on the three edges and a point m of the cell (the mean of the cuts in
// barycentric coordinates, m = a + u (b - a) + v (c - a) exactly for the doubles u, v >= 0 with
// u + v <= 1); the segments from m to the cuts split the cell into three quadrilaterals.
double three_piece_bound(const std::array<Corner, 3>& c, const TriangleMesh& mb, double good_enough) {
  const Vec3 &a = c[0].p, &b = c[1].p, &d = c[2].p;
  const CutPoint xab = cut(a, b, c[0].nearest, c[1].nearest, mb, good_enough);
  const CutPoint xbc = cut(b, d, c[1].nearest, c[2].nearest, mb, good_enough);
  const CutPoint xca = cut(d, a, c[2].nearest, c[0].nearest, mb, good_enough);
  // Barycentric weights of b and c in the mean of (1-s1, s1, 0), (0, 1-s2, s2), (s3, 0, 1-s3).
  const double u = (xab.s + (1.0 - xbc.s)) / 3.0;
  const double v = std::min(1.0 - u, (xbc.s + (1.0 - xca.s)) / 3.0);
  const Vec3 m = a + u * (b - a) + v * (d - a);
  const double m_err = round_up((a.norm() + b.norm() + d.norm() + m.norm()) * 0x1p-49);
  const double qa = max_distance({a, xab.p, m, xca.p}, mb, c[0].nearest);
  const double qb = max_distance({b, xbc.p, m, xab.p}, mb, c[1].nearest);
  const double qc = max_distance({d, xca.p, m, xbc.p}, mb, c[2].nearest);
  return round_up(std::max({qa, qb, qc}) + std::max({xab.err, xbc.err, xca.err, m_err}));
}

// An upper bound of dist(., B) over the cell. `target`: a bound at or below it needs no more work
// (the refinement stops there), so the costlier cut bounds are tried only above it.
double bound_of(const Cell& cell, const SignedDistance& b, double target) {
  const TriangleMesh& mb = b.mesh();
  double convex = HUGE_VAL;
  for (int i = 0; i < 3; ++i) {
    const std::uint32_t t = cell.c[i].nearest;
    if ((i > 0 && t == cell.c[0].nearest) || (i > 1 && t == cell.c[1].nearest)) continue;
    convex = std::min(convex, max_distance({cell.c[0].p, cell.c[1].p, cell.c[2].p}, mb, t));
  }
  double edge = 0.0, corner_hi = 0.0, slack = 0.0;
  for (int i = 0; i < 3; ++i) {
    edge = std::max(edge, (cell.c[i].p - cell.c[(i + 1) % 3].p).norm());
    corner_hi = std::max(corner_hi, cell.c[i].d.hi);
    // Every point of the cell's exact region is within the largest corner drift of this triangle.
    slack = std::max(slack, cell.c[i].off);
  }
  // Every point of a triangle is within its longest edge of a corner; norms carry a few ulps.
  const double lipschitz = round_up(corner_hi + round_up(edge * (1.0 + 1e-15)));
  const std::uint32_t n0 = cell.c[0].nearest, n1 = cell.c[1].nearest, n2 = cell.c[2].nearest;
  if ((n0 != n1 || n1 != n2) && round_up(std::min(convex, lipschitz) + slack) > target) {
    // Cut points need not sit exactly at the crossing: an error well inside the tolerance will do.
    const double good_enough = 0.125 * std::max(0.0, target - corner_hi);
    if (n1 == n2) convex = std::min(convex, two_piece_bound(cell.c, 0, mb, good_enough));
    else if (n0 == n2) convex = std::min(convex, two_piece_bound(cell.c, 1, mb, good_enough));
    else if (n0 == n1) convex = std::min(convex, two_piece_bound(cell.c, 2, mb, good_enough));
    else convex = std::min(convex, three_piece_bound(cell.c, mb, good_enough));
  }
  return round_up(std::min(convex, lipschitz) + slack);
}

// Midpoint in doubles: fl(a + b) errs by at most 2^-53 |a + b| per coordinate and halving is exact
// (1e-300 covers underflow); the exact midpoint of the two exact points it stands for is within the
// larger of their drifts of the exact midpoint of a and b, so drifts add up.
Corner midpoint(const Corner& a, const Corner& b, const SignedDistance& to) {
  const Vec3 m = (a.p + b.p) * 0.5;
  Corner c = corner_at(m, to);
  c.off = round_up(std::max(a.off, b.off) + m.norm() * 0x1p-51 + 1e-300);
  return c;
}

struct TriangleOutcome {
  double upper = 0.0, lower = 0.0;
  Vec3 witness = Vec3::Zero();
  std::size_t cells = 0;
  bool converged = true;
};

TriangleOutcome refine(const Cell& root, const SignedDistance& b, double start_lower, const Vec3& start_witness,
                       const HausdorffOptions& opt, double absolute) {
  TriangleOutcome out;
  out.lower = start_lower;  // the root corners are A's vertices, already in start_lower
  out.witness = start_witness;
  std::priority_queue<Cell> heap;
  heap.push(root);
  out.cells = 1;
  while (true) {
    const Cell& top = heap.top();
    const double tol = std::max(opt.relative_tolerance * out.lower, absolute);
    if (top.upper <= out.lower + tol) break;
    if (out.cells >= opt.max_cells_per_triangle) {
      out.converged = false;
      break;
    }
    const Cell cell = top;
    heap.pop();
    const Corner c01 = midpoint(cell.c[0], cell.c[1], b);
    const Corner c12 = midpoint(cell.c[1], cell.c[2], b);
    const Corner c20 = midpoint(cell.c[2], cell.c[0], b);
    for (const Corner* k : {&c01, &c12, &c20})
      if (k->lower() > out.lower) {
        out.lower = k->lower();
        out.witness = k->p;
      }
    const std::array<std::array<Corner, 3>, 4> children = {{{cell.c[0], c01, c20},
                                                            {c01, cell.c[1], c12},
                                                            {c20, c12, cell.c[2]},
                                                            {c12, c20, c01}}};
    for (const auto& corners : children) {
      Cell child;
      child.c = corners;
      child.upper = bound_of(child, b, out.lower + tol);
      heap.push(child);
      ++out.cells;
    }
  }
  out.upper = heap.top().upper;
  return out;
}

}  // namespace

HausdorffResult one_sided_hausdorff(const TriangleMesh& a, const SignedDistance& b, const HausdorffOptions& options) {
  Timer timer;
  HausdorffResult result;
  if (a.faces.empty() || b.mesh().faces.empty()) return result;
  const double absolute =
      options.absolute_tolerance > 0.0 ? options.absolute_tolerance : 1e-9 * std::max(a.bbox().diagonal(), 1e-300);

  // Pass 1: every vertex of A (a deterministic starting lower bound for all triangles).
  std::vector<Corner> corners(a.vertices.size());
  tbb::parallel_for(std::size_t{0}, a.vertices.size(), [&](std::size_t i) { corners[i] = corner_at(a.vertices[i], b); });
  double start = 0.0;
  Vec3 start_witness = Vec3::Zero();
  for (const Corner& c : corners)
    if (c.lower() > start) {
      start = c.lower();
      start_witness = c.p;
    }

  // Pass 2: a few cells per triangle raise the common lower bound, so that pass 3 does not refine
  // triangles far below the maximum down to the absolute tolerance.
  std::vector<TriangleOutcome> outcomes(a.faces.size());
  const auto run = [&](double from, std::size_t cap) {
    HausdorffOptions o = options;
    o.max_cells_per_triangle = cap;
    tbb::parallel_for(std::size_t{0}, a.faces.size(), [&](std::size_t f) {
      Cell root;
      for (int k = 0; k < 3; ++k) root.c[k] = corners[a.faces[f][k]];
      root.upper = bound_of(root, b, HUGE_VAL);
      outcomes[f] = refine(root, b, from, start_witness, o, absolute);
    });
  };
  run(start, 64);
  for (const TriangleOutcome& o : outcomes)
    if (o.lower > start) {
      start = o.lower;
      start_witness = o.witness;
    }
  // Pass 3: each triangle on its own from that common start (deterministic).
  run(start, options.max_cells_per_triangle);

  result.distance = {start, start};
  result.witness = start_witness;
  for (const TriangleOutcome& o : outcomes) {
    result.distance.hi = std::max(result.distance.hi, o.upper);
    result.cells += o.cells;
    result.converged = result.converged && o.converged;
  }
  // The lower end and its witness: the largest certified corner distance over everything evaluated.
  for (const TriangleOutcome& o : outcomes)
    if (o.lower > result.distance.lo) {
      result.distance.lo = o.lower;
      result.witness = o.witness;
    }
  result.distance.hi = std::max(result.distance.hi, result.distance.lo);
  result.seconds = timer.seconds();
  return result;
}

SurfaceDeviation two_sided_hausdorff(const TriangleMesh& first, const TriangleMesh& second,
                                     const HausdorffOptions& options) {
  SurfaceDeviation d;
  const SignedDistance to_second(second);
  d.first_to_second = one_sided_hausdorff(first, to_second, options);
  const SignedDistance to_first(first);
  d.second_to_first = one_sided_hausdorff(second, to_first, options);
  return d;
}

}  // namespace cdbench
