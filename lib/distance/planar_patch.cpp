#include "distance/planar_patch.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/interval.h"

namespace cdbench {

int projected_side(const Vec3& a, const Vec3& b, const Vec3& x, const Vec3& n) {
  const Vec3 e = b - a, f = x - a;
  const double v = e.cross(n).dot(f);
  // Two differences, the cross product and the dot product: each exact term e_j n_k f_i carries at
  // most ~10 roundings of relative size 2u (directed rounding included), and the six terms sum to
  // at most |e|_1 |n|_1 |f|_1 (which also absorbs the differences' own rounding). 1e-14 covers
  // 10 * 2.2e-16 with a factor of four to spare; the absolute term covers underflow.
  const double err = 1e-14 * (e.cwiseAbs().sum() * n.cwiseAbs().sum() * f.cwiseAbs().sum()) + 1e-300;
  if (v > err) return 1;
  if (v < -err) return -1;
  return 0;
}

namespace {

// The functional m.x with m = e x n, evaluated on the projections along n of the points x (the
// plane {n.x = d}): m.pi(x) = m.x - (n.x - d)(m.n)/|n|^2, computed as m.x with an error bound that
// also covers the second term (m.n is a rounding away from 0). True when the projections of the
// corners and of the segment ab are certainly separated along it.
bool separated_along(const Vec3& e, const Vec3& n, double d, const Vec3& a, const Vec3& b, const Vec3* v, int nv) {
  const Vec3 m = e.cross(n);
  if (!(m.cwiseAbs().maxCoeff() > 0.0)) return false;
  const double mn = std::abs(m.dot(n)) + 2e-15 * m.cwiseAbs().dot(n.cwiseAbs());
  const double tilt = mn / (n.squaredNorm() * (1.0 - 1e-14));  // >= |m.n| / |n|^2
  const auto range = [&](const Vec3& x, double& lo, double& hi) {
    const PlaneOffset f = plane_offset(m, 0.0, x), off = plane_offset(n, d, x);
    const double err = f.error + (std::abs(off.value) + off.error) * tilt * (1.0 + 1e-14) + 1e-300;
    lo = std::min(lo, f.value - err);
    hi = std::max(hi, f.value + err);
  };
  double klo = HUGE_VAL, khi = -HUGE_VAL, slo = HUGE_VAL, shi = -HUGE_VAL;
  for (int k = 0; k < nv; ++k) range(v[k], klo, khi);
  range(a, slo, shi);
  range(b, slo, shi);
  return khi < slo || shi < klo;
}

// pi(segment ab) and pi(conv(corners)) are disjoint, proven by a separating line parallel to the
// segment or to an edge of the cell (the separating-axis theorem in the plane). A box's edges are
// parallel to the coordinate axes; a triangle's are tested against its own edge lines.
bool projected_disjoint(const Vec3& a, const Vec3& b, const Vec3* v, int nv, const Vec3& n, double d) {
  int first = projected_side(a, b, v[0], n);
  bool one_side = first != 0;
  for (int k = 1; k < nv && one_side; ++k) one_side = projected_side(a, b, v[k], n) == first;
  if (one_side) return true;
  if (nv == 8) {
    for (int axis = 0; axis < 3; ++axis)
      if (separated_along(Vec3::Unit(axis), n, d, a, b, v, nv)) return true;
    return false;
  }
  if (nv < 3) {
    // A segment or a point: its own line (for a point, no line: the test above decides).
    if (nv == 2) {
      const int sa = projected_side(v[0], v[1], a, n);
      return sa != 0 && sa == projected_side(v[0], v[1], b, n);
    }
    return false;
  }
  for (int k = 0; k < 3; ++k) {
    const Vec3 &p = v[k], &q = v[(k + 1) % 3], &r = v[(k + 2) % 3];
    const int inner = projected_side(p, q, r, n);
    if (inner == 0) continue;
    if (projected_side(p, q, a, n) == -inner && projected_side(p, q, b, n) == -inner) return true;
  }
  return false;
}

// x's projection strictly inside the projection of triangle abc.
bool projected_inside(const Vec3& x, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& n) {
  const int o = projected_side(a, b, c, n);
  return o != 0 && projected_side(a, b, x, n) == o && projected_side(b, c, x, n) == o &&
         projected_side(c, a, x, n) == o;
}

}  // namespace

bool patch_covers_cell(const TriangleMesh& mesh, const std::vector<std::uint32_t>& ids, const Vec3& n, double d,
                       const Vec3* corners, int n_corners) {
  if (ids.empty() || n_corners < 1 || (n_corners > 3 && n_corners != 8)) return false;
  const auto& V = mesh.vertices;
  bool seeded = false;
  for (std::uint32_t j : ids) {
    const Face& f = mesh.faces[j];
    if (projected_inside(corners[0], V[f[0]], V[f[1]], V[f[2]], n)) {
      seeded = true;
      break;
    }
  }
  if (!seeded) return false;
  // Half-edges of U keyed by their vertex pair; interior edges pair up.
  struct HalfEdge {
    std::uint32_t lo, hi, third, tri;
  };
  thread_local std::vector<HalfEdge> edges;
  edges.clear();
  for (std::uint32_t j : ids) {
    const Face& f = mesh.faces[j];
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t p = f[k], q = f[(k + 1) % 3];
      edges.push_back({std::min(p, q), std::max(p, q), f[(k + 2) % 3], j});
    }
  }
  std::sort(edges.begin(), edges.end(), [](const HalfEdge& x, const HalfEdge& y) {
    return x.lo < y.lo || (x.lo == y.lo && (x.hi < y.hi || (x.hi == y.hi && x.tri < y.tri)));
  });
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t k = i + 1;
    while (k < edges.size() && edges[k].lo == edges[i].lo && edges[k].hi == edges[i].hi) ++k;
    const Vec3 &a = V[edges[i].lo], &b = V[edges[i].hi];
    bool interior = false;
    if (k - i == 2 && edges[i].tri != edges[i + 1].tri) {
      const int s0 = projected_side(a, b, V[edges[i].third], n), s1 = projected_side(a, b, V[edges[i + 1].third], n);
      interior = s0 != 0 && s0 == -s1;
    }
    if (!interior && !projected_disjoint(a, b, corners, n_corners, n, d)) return false;
    i = k;
  }
  return true;
}

double patch_distance_bound(const TrianglePlane& plane, double eta, const Vec3& x) {
  const PlaneOffset o = plane_offset(plane.n, plane.d, x);
  const double n_lo = norm3_lower(plane.n.squaredNorm());
  return round_up(round_up(std::abs(o.value) + o.error + eta) / n_lo * (1.0 + 1e-15));
}

}  // namespace cdbench
