#include "distance/depth_plane.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

#include "core/interval.h"
#include "distance/depth_bound.h"
#include "distance/exact_predicates.h"
#include "distance/point_triangle_distance.h"
#include "distance/slab_cut.h"

namespace cdbench {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kMaxFaces = DepthRegion::kMaxFaces;
constexpr int kMaxCandidates = kMaxFaces + kMaxFaces * (kMaxFaces - 1) / 2 + 4;
// Beyond this many triangles near the box the neighbourhood is not a wall's few faces.
constexpr std::size_t kMaxNear = 48;
// Conditioning asked of two or three planes' common line or point (unit normals' Gram
// determinant): their projections then stay near the cell.
constexpr double kMinGram = 1e-12;
// The computed projections on a line or point of planes whose Gram determinant is g are within
// about 10 u (|x| + |levels|) / g of the exact ones; this factor covers that with margin.
constexpr double kProjectionError = 1e-12;

// Faces from which regions are grown as members (distance/depth_plane.h): the nearest few
// distinct planes, and the nearest facing the other way (a wall's other side).
constexpr std::size_t kNearFaces = 2;
constexpr std::size_t kRegionFaces = 6;
// Triangle members with them (minimax_bound takes at most 16 members).
constexpr std::size_t kRegionTriangles = 16 - kRegionFaces;
// Faces a region grows to at first; those that stopped there are grown again up to
// DepthRegion::kMaxFaces where the bound does not set the cube aside (most regions need at most
// four faces, and each face costs every later triangle's test).
constexpr int kFirstFaces = 4;

inline double norm_lower(const Vec3& n) { return norm3_lower(n.squaredNorm()); }
inline double norm_upper(const Vec3& n) { return norm3_upper(n.squaredNorm()); }

// An upper end of (H - n.x) / |n|, of either sign.
double plane_excess_up(const Vec3& nv, double level, const Vec3& x) {
  const PlaneOffset o = plane_offset(nv, 0.0, x);
  const double num = round_up(level - round_down(o.value - o.error));
  return num < 0.0 ? round_up(num / norm_upper(nv)) : round_up(num / norm_lower(nv));
}

// The point nearest to x of the line common to the planes n_i.y = H_i and n_j.y = H_j.
Vec3 line_point(const Vec3& ni, double hi, double nni, const Vec3& nj, double hj, double nnj, const Vec3& x) {
  const double g = ni.dot(nj), det = nni * nnj - g * g;
  const double ri = hi - ni.dot(x), rj = hj - nj.dot(x);
  return x + ((ri * nnj - rj * g) / det) * ni + ((rj * nni - ri * g) / det) * nj;
}

// W's planes at their levels, and the projections (plain doubles: they place boxes and pick points,
// whose use is checked rigorously).
struct Region : DepthRegionPlanes {
  Region() = default;
  explicit Region(const DepthRegionPlanes& p) : DepthRegionPlanes(p) {}

  Vec3 onto_plane(int i, const Vec3& x) const { return x + ((level[i] - n[i].dot(x)) / nn[i]) * n[i]; }
  Vec3 onto_line(int i, int j, const Vec3& x) const {
    return line_point(n[i], level[i], nn[i], n[j], level[j], nn[j], x);
  }
  Vec3 corner(int a, int b, int c) const {  // the common point of three planes (Cramer)
    const Vec3 cbc = n[b].cross(n[c]), cca = n[c].cross(n[a]), cab = n[a].cross(n[b]);
    return (level[a] * cbc + level[b] * cca + level[c] * cab) / n[a].dot(cbc);
  }
  // The points among which the nearest point of W to x lies (x outside int W): its projections on
  // the faces' planes, on their common lines (all pairs' lines, or only W's edges' once `edges` is
  // set: a line that misses W holds no point of it), and the triples' common points.
  int candidates(const Vec3& x, std::array<Vec3, kMaxCandidates>& out, bool edges_only) const {
    int m = 0;
    for (int i = 0; i < nf; ++i) out[m++] = onto_plane(i, x);
    if (edges_only) {
      for (int e = 0; e < ne; ++e) out[m++] = onto_line(edges[e][0], edges[e][1], x);
    } else {
      for (int i = 0; i < nf; ++i)
        for (int j = i + 1; j < nf; ++j) out[m++] = onto_line(i, j, x);
    }
    for (int k = 0; k < nt; ++k) {
      int idx[3], c = 0;
      for (int i = 0; i < nf; ++i)
        if (triples[k] >> i & 1u) idx[c++] = i;
      out[m++] = corner(idx[0], idx[1], idx[2]);
    }
    return m;
  }
  // The pairs whose common line meets W, up to a relative slack (a heuristic: the candidates only
  // pick points, each proven in W before it bounds anything).
  void find_edges(const Vec3& x) {
    ne = 0;
    for (int i = 0; i < nf; ++i)
      for (int j = i + 1; j < nf; ++j) {
        const Vec3 p = onto_line(i, j, x), d = n[i].cross(n[j]);
        double lo = -kInf, hi = kInf;
        bool meets = p.allFinite();
        for (int k = 0; k < nf && meets; ++k) {
          if (k == i || k == j) continue;
          // n_k.(p + t d) >= H_k
          const double a = n[k].dot(d), b = level[k] - n[k].dot(p);
          const double slack = 1e-9 * std::sqrt(nn[k]) * (1.0 + p.norm());
          if (a > 0.0)
            lo = std::max(lo, (b - slack) / a);
          else if (a < 0.0)
            hi = std::min(hi, (b - slack) / a);
          else
            meets = b <= slack;
        }
        if (meets && lo <= hi) edges[ne++] = {static_cast<std::uint8_t>(i), static_cast<std::uint8_t>(j)};
      }
  }
  // y in W (strict: in its interior), rigorously.
  bool inside(const Vec3& y, bool strict) const {
    for (int i = 0; i < nf; ++i) {
      const PlaneOffset o = plane_offset(n[i], 0.0, y);
      const double lo = round_down(o.value - o.error);
      if (strict ? !(lo > level[i]) : !(lo >= level[i])) return false;
    }
    return true;
  }
  // y moved a hair into W (along the sum of the unit normals, which raises every n_i.y: the normals
  // are within a right angle of each other).
  Vec3 pushed(const Vec3& y, double delta) const {
    Vec3 s = Vec3::Zero();
    for (int i = 0; i < nf; ++i) s += u[i];
    return y + delta * s;
  }
  // Adds the plane n.y = level if it keeps the projections well defined. False: not added.
  bool add(const Vec3& nv, double lv) {
    const double q = nv.squaredNorm();
    if (nf >= kMaxFaces || !(q > 0.0) || !std::isfinite(lv)) return false;
    const Vec3 unit = nv / std::sqrt(q);
    for (int i = 0; i < nf; ++i) {
      const double c = unit.dot(u[i]);
      if (!(c > 0.0) || !(1.0 - c * c > kMinGram)) return false;  // within a right angle, not parallel
    }
    double least = gram;
    for (int i = 0; i < nf; ++i) least = std::min(least, 1.0 - unit.dot(u[i]) * unit.dot(u[i]));
    // Three planes whose normals are exactly dependent have no single common point; otherwise the
    // point must be well placed.
    std::array<unsigned, 4> more{};
    int nm = 0;
    for (int i = 0; i < nf; ++i)
      for (int j = i + 1; j < nf; ++j) {
        if (vectors_coplanar(n[i], n[j], nv)) continue;
        const double g = std::abs(u[i].dot(u[j].cross(unit)));
        if (!(g * g > kMinGram)) return false;
        least = std::min(least, g * g);
        if (nt + nm >= 4) return false;  // more than four common points
        more[nm++] = (1u << i) | (1u << j) | (1u << nf);
      }
    for (int k = 0; k < nm; ++k) triples[nt++] = more[k];
    n[nf] = nv, u[nf] = unit, nn[nf] = q, level[nf] = lv;
    ++nf;
    gram = least;
    return true;
  }
};

// |x - y| rounded up (any rounding mode: a few ulps, covered with margin).
inline double distance_up(const Vec3& x, const Vec3& y) {
  return std::sqrt((x - y).squaredNorm()) * (1.0 + 1e-14) + 1e-15 * (x.cwiseAbs().maxCoeff() + y.cwiseAbs().maxCoeff());
}

}  // namespace

bool prove_depth_region(const SignedDistance& sdf, std::uint32_t face, const Vec3* points, int n, const Vec3& ref,
                        int ref_side, DepthRegion* out, std::vector<std::uint32_t>& scratch, int max_faces) {
  if (n <= 0 || n > 16) return false;
  max_faces = std::clamp(max_faces, 1, kMaxFaces);
  bool capped = false;
  // Whether a face was kept out by max_faces, on failure too (a caller may try again with more).
  struct Report {
    DepthRegion* out;
    const bool& capped;
    ~Report() { out->capped = capped; }
  } report{out, capped};
  const TrianglePlane& pl = sdf.planes()[face];
  if (!std::isfinite(pl.eps)) return false;
  Region w;
  DepthRegion r;
  double mag = 0.0;
  Vec3 mean = Vec3::Zero();
  for (int k = 0; k < n; ++k) {
    mean += points[k];
    mag = std::max(mag, points[k].cwiseAbs().maxCoeff());
  }
  mean /= n;
  // top(n) >= n.x over P.
  const auto top = [&](const Vec3& nv) {
    double t = -kInf;
    for (int k = 0; k < n; ++k) {
      const PlaneOffset o = plane_offset(nv, 0.0, points[k]);
      t = std::max(t, round_up(o.value + o.error));
    }
    return t;
  };
  // The first face at its own level (its points have n.y <= d + eps): P lies below it, or crosses it.
  const double own_level = round_up(pl.d + pl.eps);
  const bool crossing = top(pl.n) > own_level;
  if (!w.add(pl.n, own_level)) return false;
  r.face[0] = face;
  r.n = 1;
  r.crossing = crossing;
  // The box of the projections of P's corners (and of the corners, for a crossing region).
  const auto projections_box = [&](Vec3& lo, Vec3& hi) {
    lo = Vec3::Constant(kInf), hi = Vec3::Constant(-kInf);
    std::array<Vec3, kMaxCandidates> q;
    for (int k = 0; k < n; ++k) {
      const int m = w.candidates(points[k], q, false);
      for (int j = 0; j < m; ++j) lo = lo.cwiseMin(q[j]), hi = hi.cwiseMax(q[j]);
      if (crossing) lo = lo.cwiseMin(points[k]), hi = hi.cwiseMax(points[k]);
    }
  };
  Vec3 lo, hi;
  projections_box(lo, hi);
  if (!lo.allFinite() || !hi.allFinite()) return false;
  // B: the box of the projections, a half side per axis (on a curved wall a cube's sides along the
  // wall and across it differ, and every facet B meets joins the region).
  Vec3 cb = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
  // The projections' rounding (a few ulps of the coordinates and of the distances moved) is far
  // below m0; a sixteenth of the box's largest half side (of each axis' own, and of the largest)
  // leaves room for the region to change without a new box.
  const double m0 = 1e-9 * (mag + half.maxCoeff()) + 1e-300;
  bool proven = false;
  Vec3 hk = Vec3::Zero();
  for (int attempt = 0; attempt < 4 && !proven; ++attempt) {
    const double room = m0 + 0.015625 * half.maxCoeff();
    hk = (half + 0.0625 * half + Vec3::Constant(room)).unaryExpr([](double v) { return round_up(v); });
    // Every triangle that may meet the box (a ball about it reaches about 1.7 times as far, and on a
    // finely faceted curved wall each facet meeting the ball would join the region).
    const Aabb bk{(cb - hk).unaryExpr([](double v) { return round_down(v); }),
                  (cb + hk).unaryExpr([](double v) { return round_up(v); })};
    if (!sdf.triangles_meeting_box(bk, kMaxNear, scratch)) return false;
    // Each triangle meeting the box cb +- hk must lie, over its part there, below some face's level.
    // Where none holds, its face joins the region (at its own level), or else the level it exceeds
    // least rises to it (faces joining and levels rising only shrink W: the triangles passed
    // before still pass).
    for (std::uint32_t j : scratch) {
      std::array<double, kMaxFaces> s;
      s.fill(-kInf);
      bool below = false;
      // A face of the region first: its own level holds it (its plane's slab, up to rounding).
      const int own_index = static_cast<int>(std::find(r.face.begin(), r.face.begin() + r.n, j) - r.face.begin());
      if (own_index < r.n) {
        s[own_index] = triangle_span_in_box(sdf.mesh(), sdf.planes(), j, w.n[own_index], cb, hk).hi;
        below = s[own_index] <= w.level[own_index];
      }
      for (int i = 0; i < w.nf && !below; ++i) {
        if (i == own_index) continue;
        s[i] = triangle_span_in_box(sdf.mesh(), sdf.planes(), j, w.n[i], cb, hk).hi;
        below = s[i] <= w.level[i];
      }
      if (below) continue;
      const TrianglePlane& pj = sdf.planes()[j];
      capped = capped || w.nf >= max_faces;
      if (std::isfinite(pj.eps) && w.nf < max_faces) {
        // At the level of its own part in the box (its plane's, up to rounding): it passes.
        const double own = triangle_span_in_box(sdf.mesh(), sdf.planes(), j, pj.n, cb, hk).hi;
        if (w.add(pj.n, own)) {
          r.face[r.n++] = j;
          continue;
        }
      }
      int raise = 0;
      for (int i = 1; i < w.nf; ++i)
        if ((s[i] - w.level[i]) / std::sqrt(w.nn[i]) < (s[raise] - w.level[raise]) / std::sqrt(w.nn[raise])) raise = i;
      if (!std::isfinite(s[raise])) return false;
      w.level[raise] = s[raise];
    }
    // P must lie below some face's level (then no point of it is inside W), unless it is crossing
    // (then B holds P: its interior points of the solid are not in int W).
    bool below_one = crossing;
    for (int i = 0; i < w.nf && !below_one; ++i) below_one = top(w.n[i]) <= w.level[i];
    if (!below_one) return false;
    // The projections for the region reached must lie in the box checked, m0 inside it.
    projections_box(lo, hi);
    if (!lo.allFinite() || !hi.allFinite()) return false;
    // The exact projections are within m0 of the computed ones (and within the conditioning's
    // error where lines or points are involved): they lie in the box checked.
    const Vec3 inner =
        hk - Vec3::Constant(std::max(m0, kProjectionError * (mag + half.maxCoeff() + hk.maxCoeff()) / w.gram));
    if (((lo - cb).array() >= -inner.array()).all() && ((hi - cb).array() <= inner.array()).all()) {
      proven = true;
    } else {
      cb = 0.5 * (lo + hi);
      half = 0.5 * (hi - lo);
    }
  }
  if (!proven) return false;
  // A point of R: the nearest point of W to the mean of P (approximately), pushed into W's interior.
  std::array<Vec3, kMaxCandidates> q;
  const int m = w.candidates(mean, q, false);
  Vec3 z = Vec3::Zero();
  double best = kInf;
  for (int j = 0; j < m; ++j) {
    const Vec3 y = w.pushed(q[j], 0.5 * m0);
    if (!w.inside(y, true) || !((y - cb).cwiseAbs().array() < hk.array() * (1.0 - 1e-9)).all()) continue;
    const double dist = (y - mean).squaredNorm();
    if (dist < best) best = dist, z = y;
  }
  if (!(best < kInf)) return false;
  const Interval off_f{std::numeric_limits<double>::min(), kInf};  // z is in R, which holds no point of F
  const int side = ref_side != 0 ? sdf.side(z, off_f, ref, ref_side) : sdf.side(z, off_f);
  if (side <= 0) return false;
  w.find_edges(mean);
  r.planes = w;
  *out = r;
  return true;
}

double depth_region_value(const SignedDistance& sdf, const DepthRegion& region, const Vec3& x) {
  if (region.n == 1) {
    const double v = plane_excess_up(sdf.planes()[region.face[0]].n, region.planes.level[0], x);
    return region.crossing && v < 0.0 ? v : std::max(1e-300, v);
  }
  const Region w(region.planes);
  if (w.nf != region.n) return kInf;
  if (region.crossing && w.inside(x, false)) {
    // Inside W: the signed distance, -(the distance to W's boundary) = max_i (H_i - n_i.x) / |n_i|.
    double v = -kInf;
    for (int i = 0; i < w.nf; ++i) v = std::max(v, plane_excess_up(w.n[i], w.level[i], x));
    return v;
  }
  // Any point of W bounds the distance to it; the nearest candidate proven in W is tight (the
  // candidates nearest first: the first in W is the nearest point, up to the push).
  std::array<Vec3, kMaxCandidates> q;
  std::array<std::pair<double, int>, kMaxCandidates> order;
  const int m = w.candidates(x, q, true);
  for (int j = 0; j < m; ++j) order[j] = {(q[j] - x).squaredNorm(), j};
  std::sort(order.begin(), order.begin() + m);
  const double delta = 1e-12 * x.cwiseAbs().maxCoeff() + 1e-300;
  // The least push first over all candidates: a nearer candidate just outside W (a line of two
  // faces that meets W only beyond the others) is taken with a large push only when no candidate
  // is in W with a small one.
  for (double push = delta; push <= 1e6 * delta; push *= 1e3)
    for (int k = 0; k < m; ++k) {
      const Vec3 y = w.pushed(q[order[k].second], push);
      if (w.inside(y, false)) return std::max(1e-300, distance_up(x, y));
    }
  return kInf;
}

int depth_region_edge_points(const SignedDistance&, const DepthRegion& region, const Vec3& x,
                             std::array<Vec3, DepthRegion::kMaxEdges>& out) {
  const Region w(region.planes);
  if (region.n < 2 || w.nf != region.n) return 0;
  int m = 0;
  for (int e = 0; e < w.ne && m < DepthRegion::kMaxEdges; ++e)
    out[m++] = w.onto_line(w.edges[e][0], w.edges[e][1], x);
  return m;
}

bool crossing_regions_edge_point(const SignedDistance& sdf, const DepthRegion& a, const DepthRegion& b, const Vec3& x,
                                 Vec3* out) {
  if (!a.crossing || !b.crossing || a.n != 1 || b.n != 1) return false;
  const Vec3 &na = sdf.planes()[a.face[0]].n, &nb = sdf.planes()[b.face[0]].n;
  if (!((na.normalized().cross(nb.normalized())).squaredNorm() > 1e-12)) return false;  // (nearly) parallel
  *out = line_point(na, a.planes.level[0], na.squaredNorm(), nb, b.planes.level[0], nb.squaredNorm(), x);
  return out->allFinite();
}

bool region_seeds(const SignedDistance& sdf, const Vec3& c, double reach, std::size_t max_count,
                  const std::vector<std::uint32_t>* candidates, std::vector<std::uint32_t>& out) {
  if (candidates) {
    sdf.triangles_within_among(c, reach, *candidates, out);
    if (out.size() > max_count) return false;
  } else if (!sdf.triangles_within(c, reach, max_count, out)) {
    return false;
  }
  sort_nearest_first(sdf, c, out);
  return true;
}

void sort_nearest_first(const SignedDistance& sdf, const Vec3& c, std::vector<std::uint32_t>& ids) {
  thread_local std::vector<std::pair<double, std::uint32_t>> by;
  by.clear();
  for (const std::uint32_t t : ids) by.emplace_back(point_triangle_distance_upper_near(c, sdf.mesh(), t), t);
  std::sort(by.begin(), by.end());
  for (std::size_t i = 0; i < by.size(); ++i) ids[i] = by[i].second;
}

double region_depth_bound(const SignedDistance& sdf, const Vec3& ref, int ref_side, const Vec3* points, int n,
                          const std::vector<std::uint32_t>& ids, const RegionBoundOptions& options,
                          RegionBoundStats* stats) {
  if (n != 8) return kInf;
  const double enough = options.enough;
  thread_local std::vector<std::uint32_t> scratch;
  std::array<std::uint32_t, kRegionFaces> tried{};
  std::array<DepthRegion, kRegionFaces> regions;
  std::array<std::uint32_t, kRegionFaces> capped_out{};  // faces whose proof failed at kFirstFaces
  std::size_t nt = 0, nr = 0, ncapped = 0;
  // (Heuristic: a face's region is seldom worth proving again from a face in the same plane.)
  const auto coplanar = [&](std::uint32_t f, std::uint32_t g) {
    const TrianglePlane &pf = sdf.planes()[f], &pg = sdf.planes()[g];
    const double lf = pf.n.norm(), lg = pg.n.norm();
    if (!(lf > 0.0) || !(lg > 0.0)) return false;
    return (pf.n / lf - pg.n / lg).cwiseAbs().maxCoeff() <= 1e-12 &&
           std::abs(pf.d / lf - pg.d / lg) <= 1e-12 * (1.0 + std::abs(pf.d / lf));
  };
  const auto try_face = [&](std::uint32_t f) {
    for (std::size_t j = 0; j < nt; ++j)
      if (coplanar(f, tried[j])) return false;  // the other half of a quad
    for (std::size_t j = 0; j < nr; ++j)       // a face a region grew to
      for (int i = 1; i < regions[j].n; ++i)
        if (coplanar(f, regions[j].face[static_cast<std::size_t>(i)])) return false;
    tried[nt++] = f;
    if (prove_depth_region(sdf, f, points, n, ref, ref_side, &regions[nr], scratch, kFirstFaces)) ++nr;
    else if (regions[nr].capped) capped_out[ncapped++] = f;
    return true;
  };
  std::size_t ntri = std::min(ids.size(), kRegionTriangles);
  // The minimax bound over points q[0..nq) (nq <= 16), plus err. Crossing regions' members are
  // negative above their faces: all members are raised by `shift` (at least their most negative
  // value's size) for minimax_bound, whose weighted means are of positive values, and lowered after.
  const auto bound_over = [&](const Vec3* q, int nq, double err) {
    const std::size_t M = ntri + nr;  // (nr grows when regions are grown again)
    std::array<double, 16 * 16> D;
    double least = 0.0;
    for (int k = 0; k < nq; ++k) {
      for (std::size_t j = 0; j < ntri; ++j) D[k * M + j] = point_triangle_distance_upper_near(q[k], sdf.mesh(), ids[j]);
      for (std::size_t j = 0; j < nr; ++j) {
        D[k * M + ntri + j] = depth_region_value(sdf, regions[j], q[k]);
        least = std::min(least, D[k * M + ntri + j]);
      }
    }
    if (!(least < 0.0)) return round_up(minimax_bound(D.data(), nq, static_cast<int>(M)) + err);
    const double shift = round_up(-least * (1.0 + 1e-12) + 1e-300);
    for (int i = 0; i < nq * static_cast<int>(M); ++i) D[i] = round_up(D[i] + shift);
    return round_up(round_up(minimax_bound(D.data(), nq, static_cast<int>(M)) - shift) + err);
  };
  // The bound over the cube, its slices where regions' edges cross it.
  const auto cube_bound = [&]() {
    const double bound = bound_over(points, n, 0.0);
    if (!(bound > enough) || !options.slices) return bound;
    // A region's distance is convex across its edges, where the depth may peak (a tube's seam, the
    // outer faces' edge above it): the cube is cut into slices by planes through those edges, normal
    // to the first edge's bisector (any planes are valid; these make each slice's region distances
    // nearly affine), and the slices (cut_by_slab: their points within err) are bounded apart, each
    // with the same members (proven for the whole cube).
    const Vec3 centre = 0.5 * (points[0] + points[7]);
    Vec3 b = Vec3::Zero();
    std::array<double, DepthRegion::kMaxEdges + 4> t;
    std::size_t ncut = 0;
    t[ncut++] = -kInf;
    for (std::size_t j = 0; j < nr; ++j) {
      std::array<Vec3, DepthRegion::kMaxEdges> edge;
      const int m = depth_region_edge_points(sdf, regions[j], centre, edge);
      if (m == 0) continue;
      if (b == Vec3::Zero()) {
        const Vec3 n0 = sdf.planes()[regions[j].face[0]].n, n1 = sdf.planes()[regions[j].face[1]].n;
        b = n0 / n0.norm() - n1 / n1.norm();
      }
      for (int e = 0; e < m && ncut < t.size() - 1; ++e) t[ncut++] = b.dot(edge[static_cast<std::size_t>(e)]);
    }
    // Two crossing regions' planes meeting along an edge of F across the cube: cut there too.
    for (std::size_t i = 0; i < nr; ++i)
      for (std::size_t j = i + 1; j < nr && ncut < t.size() - 1; ++j) {
        Vec3 p;
        if (!crossing_regions_edge_point(sdf, regions[i], regions[j], centre, &p) ||
            !((p - centre).cwiseAbs().maxCoeff() <= 0.5 * (points[7] - points[0]).maxCoeff()))
          continue;
        if (b == Vec3::Zero()) {
          const Vec3 n0 = sdf.planes()[regions[i].face[0]].n, n1 = sdf.planes()[regions[j].face[0]].n;
          b = n0 / n0.norm() - n1 / n1.norm();
        }
        t[ncut++] = b.dot(p);
      }
    if (ncut == 1) return bound;
    t[ncut++] = kInf;
    std::sort(t.begin(), t.begin() + static_cast<std::ptrdiff_t>(ncut));
    std::array<PlaneOffset, 8> ov;
    for (int k = 0; k < 8; ++k) ov[k] = plane_offset(b, 0.0, points[k]);
    double split = 0.0;
    for (std::size_t i = 0; i + 1 < ncut; ++i) {
      SlabCut cut;
      if (!cut_by_slab(points, ov.data(), 8, kBoxEdges.data(), 12, t[i + 1], t[i], cut, 16)) return bound;
      if (cut.n == 0) continue;
      split = std::max(split, bound_over(cut.q.data(), cut.n, cut.err));
      if (!(split < bound)) return bound;
    }
    return std::min(bound, split);
  };
  // The nearest face, then (staged: the bound from these two first) the nearest facing the other
  // way (a wall's other side), then the next nearest and more facing the other way.
  const auto facing_back = [&](std::uint32_t f) { return sdf.planes()[f].n.dot(sdf.planes()[tried[0]].n) < 0.0; };
  if (options.staged && !ids.empty()) {
    try_face(ids[0]);
    for (std::size_t i = 1; i < ids.size() && nt < 2; ++i)
      if (facing_back(ids[i])) try_face(ids[i]);
    if (nr > 0) {
      // The regions alone: the triangles' distances seldom help where two sides' regions do not
      // (the repaired shark's octree: 6 % fewer instructions without them, the same cubes).
      const std::size_t all = ntri;
      ntri = 0;
      const double two = cube_bound();
      ntri = all;
      if (!(two > enough)) return two;
    }
  }
  // (A face tried by the staged first step counts where the unstaged order would have met it.)
  const auto was_tried = [&](std::uint32_t f) { return std::find(tried.begin(), tried.begin() + nt, f) != tried.begin() + nt; };
  for (std::size_t i = 0, near = 0; i < ids.size() && i < 8 && near < kNearFaces; ++i)
    if (was_tried(ids[i]) || try_face(ids[i])) ++near;
  if (nt > 0)
    for (std::size_t i = 0; i < ids.size() && nt < kRegionFaces; ++i)
      if (facing_back(ids[i])) try_face(ids[i]);
  if (nr == 0 && ncapped == 0) return kInf;
  const double first = nr > 0 ? cube_bound() : kInf;
  if (!(first > enough) || !options.regrow) return first;
  // Regions whose growth stopped at kFirstFaces (a curved wall's cube spanning more facets than
  // that: a level rose instead) grown again up to kMaxFaces.
  bool again = false;
  for (std::size_t j = 0; j < nr; ++j) {
    if (!regions[j].capped) continue;
    DepthRegion more;
    if (prove_depth_region(sdf, regions[j].face[0], points, n, ref, ref_side, &more, scratch, DepthRegion::kMaxFaces)) {
      regions[j] = more;
      again = true;
    }
  }
  for (std::size_t j = 0; j < ncapped; ++j)
    if (prove_depth_region(sdf, capped_out[j], points, n, ref, ref_side, &regions[nr], scratch, DepthRegion::kMaxFaces)) {
      ++nr;
      again = true;
    }
  const double fin = again ? std::min(first, cube_bound()) : first;
  if (stats) {
    stats->regrown = again;
    stats->regrown_won = again && !(fin > enough);
  }
  return fin;
}

}  // namespace cdbench
