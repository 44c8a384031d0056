#include "distance/slab_cut.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/interval.h"

namespace cdbench {

const std::array<std::array<int, 2>, 12> kBoxEdges{{{0, 1}, {2, 3}, {4, 5}, {6, 7},     // along x
                                                    {0, 2}, {1, 3}, {4, 6}, {5, 7},     // along y
                                                    {0, 4}, {1, 5}, {2, 6}, {3, 7}}};  // along z

namespace {

// |e|_1 hk for a cube, sum |e_k| hk_k for a box; and the largest half side (for the error term).
inline double half_dot(const Vec3& e, double hk) { return hk * e.cwiseAbs().sum(); }
inline double half_dot(const Vec3& e, const Vec3& hk) { return e.cwiseAbs().dot(hk); }
inline double half_max(double hk) { return hk; }
inline double half_max(const Vec3& hk) { return hk.maxCoeff(); }

template <class Half>
Interval span_in_box(const TriangleMesh& mesh, const std::vector<TrianglePlane>& planes, std::uint32_t j, const Vec3& n,
                     const Vec3& c, const Half& hk) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  double vh = -kInf, vl = kInf;
  for (std::uint32_t w : mesh.faces[j]) {
    const PlaneOffset o = plane_offset(n, 0.0, mesh.vertices[w]);
    vh = std::max(vh, round_up(o.value + o.error));
    vl = std::min(vl, round_down(o.value - o.error));
  }
  const TrianglePlane& pl = planes[j];
  const double nn = pl.n.squaredNorm();
  if (std::isfinite(pl.eps) && nn > 0.0) {
    const PlaneOffset on = plane_offset(n, 0.0, c);
    const double mu = n.dot(pl.n) / nn;
    const Vec3 e = n - mu * pl.n;
    const PlaneOffset oj = plane_offset(pl.n, pl.d, c);  // n_j.c - d_j
    const double spread = half_dot(e, hk) + std::abs(mu) * pl.eps;
    const double mid = on.value - mu * oj.value;
    const double err = 1e-13 * (std::abs(on.value) + on.error + std::abs(mu) * (std::abs(oj.value) + oj.error) +
                                spread + half_max(hk) * (n.cwiseAbs().sum() + std::abs(mu) * pl.n.cwiseAbs().sum()));
    vh = std::min(vh, round_up(mid + spread + err));
    vl = std::max(vl, round_down(mid - spread - err));
  }
  return {vl, vh};
}

}  // namespace

Interval triangle_span_in_box(const TriangleMesh& mesh, const std::vector<TrianglePlane>& planes, std::uint32_t j,
                              const Vec3& n, const Vec3& c, double hk) {
  return span_in_box(mesh, planes, j, n, c, hk);
}

Interval triangle_span_in_box(const TriangleMesh& mesh, const std::vector<TrianglePlane>& planes, std::uint32_t j,
                              const Vec3& n, const Vec3& c, const Vec3& hk) {
  return span_in_box(mesh, planes, j, n, c, hk);
}

Interval triangles_span_in_box(const TriangleMesh& mesh, const std::vector<TrianglePlane>& planes,
                               const std::vector<std::uint32_t>& ids, const Vec3& n, const Vec3& c, double hk) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  Interval span{kInf, -kInf};
  for (std::uint32_t j : ids) {
    const Interval s = triangle_span_in_box(mesh, planes, j, n, c, hk);
    span.hi = std::max(span.hi, s.hi);
    span.lo = std::min(span.lo, s.lo);
  }
  return span;
}

bool cut_by_slab(const Vec3* v, const PlaneOffset* ov, int n_corners, const std::array<int, 2>* edges, int n_edges,
                 double hs, double ls, SlabCut& out, int capacity) {
  capacity = std::min(capacity, SlabCut::kCapacity);
  out.n = 0;
  out.err = 0.0;
  for (auto& t : out.cross_t) t = {-1.0, -1.0};
  const auto add = [&](const Vec3& p, int corner) {
    if (out.n >= capacity) return false;
    out.corner_of[static_cast<std::size_t>(out.n)] = corner;
    out.q[static_cast<std::size_t>(out.n++)] = p;
    return true;
  };
  for (int k = 0; k < n_corners; ++k)
    if (!(round_down(ov[k].value - ov[k].error) > hs) && !(round_up(ov[k].value + ov[k].error) < ls))
      if (!add(v[k], k)) return false;
  for (int e = 0; e < n_edges; ++e) {
    const int ka = edges[e][0], kb = edges[e][1];
    const Vec3 &a = v[ka], &b = v[kb];
    const PlaneOffset &oa = ov[ka], &ob = ov[kb];
    for (int side = 0; side < 2; ++side) {
      const double H = side == 0 ? hs : ls;
      if (!std::isfinite(H)) continue;
      // n.a - H and n.b - H enclosed; the crossing's parameter t = A / (A - B) from a.
      Interval A{round_down(round_down(oa.value - oa.error) - H), round_up(round_up(oa.value + oa.error) - H)};
      Interval B{round_down(round_down(ob.value - ob.error) - H), round_up(round_up(ob.value + ob.error) - H)};
      if ((A.lo > 0.0 && B.lo > 0.0) || (A.hi < 0.0 && B.hi < 0.0)) continue;  // no crossing
      if (out.n + 2 > capacity) return false;
      if (!(A.lo > 0.0 || A.hi < 0.0) || !(B.lo > 0.0 || B.hi < 0.0)) {
        // An end on the plane within its error: the crossing may lie anywhere on the edge.
        add(a, ka);
        add(b, kb);
        continue;
      }
      if (A.hi < 0.0) A = {-A.hi, -A.lo}, B = {-B.hi, -B.lo};  // now A > 0 > B: t rises with both
      const double t_lo = std::max(0.0, round_down(A.lo / round_up(A.lo - B.lo)));
      const double t_hi = std::min(1.0, round_up(A.hi / round_down(A.hi - B.hi)));
      const double t = 0.5 * (t_lo + t_hi);
      out.cross_t[static_cast<std::size_t>(e)][static_cast<std::size_t>(side)] = t;
      const Vec3 d = b - a;
      add(a + t * d, -1);
      const double mag = a.cwiseAbs().maxCoeff() + b.cwiseAbs().maxCoeff();
      out.err = std::max(out.err, round_up(round_up(round_up(t_hi - t_lo) * round_up(d.norm() * (1.0 + 1e-12))) +
                                           round_up(4e-15 * mag)));
    }
  }
  return true;
}

}  // namespace cdbench
